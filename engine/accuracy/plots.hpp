#pragma once
// The accuracy report's pictures (internal to engine/accuracy): a section's SVG plot of time
// against error, and the image strips of a row against the reference. CPU only.
#include <filesystem>
#include <string>
#include <vector>

#include "accuracy/results.hpp"
#include "image/image.hpp"

namespace candela::accuracy {

// log ms (x) against log RMSE (y): every row, the Pareto front, the reference's noise floor and
// the ray tracer's time. Nothing is written when no row has both a time and an error.
void write_plot(const std::filesystem::path& path, const std::string& title, const std::vector<Row>& rows, double noise,
                double rt_ms);

// raster | reference | difference (red at 0.1), display values (radiance and indirect light
// tone mapped).
void write_strip(const std::filesystem::path& path, const ImageF& raster, const ImageF& reference, Buffer buffer);

}  // namespace candela::accuracy
