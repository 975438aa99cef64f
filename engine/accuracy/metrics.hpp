#pragma once
// The accuracy engine's measures (internal to engine/accuracy): a row's error against the ray
// tracer's reference, and the Pareto front of a section's rows (time against error). CPU only.
#include <cstddef>
#include <vector>

#include "accuracy/results.hpp"
#include "image/image.hpp"

namespace candela::accuracy {

// The mean of two seeds, and its noise: RMSE(a, b) / 2 (each seed has sigma = RMSE / sqrt 2; the
// mean of two has sigma / sqrt 2).
struct Reference {
    ImageF image;
    ImageF half_diff;  // (seed 1 - seed 2) / 2: the mean's noise, per pixel
    double noise = 0.0;
    double ms = 0.0;  // the tracer's time for this reference (both seeds)
    int spp = 0;
};

// The row's errors (RMSE, relative MSE, max, share over 2/255) of `img` against the reference,
// and the reference's noise; radiance and indirect light are judged after tone mapping.
void measure_errors(Row& row, const ImageF& img, const Reference& ref, Buffer buffer);

// The same errors over the edge pixels only (AccuracySweep::Region::edges: those whose 3x3
// neighbourhood in the reference spans more than a tenth of its largest luminance), and the
// reference's noise there.
void measure_edge_errors(Row& row, const ImageF& img, const Reference& ref);

// Row::pareto of rows[first, end): no other row with a time and an error is both faster and more
// accurate.
void mark_pareto(std::vector<Row>& rows, std::size_t first);

// The Pareto row of rows[first, last) nearest the utopia point (least time and least error) in
// log-log; -1: none.
int knee(const std::vector<Row>& rows, std::size_t first, std::size_t last);

}  // namespace candela::accuracy
