#pragma once
// The accuracy run's outputs (internal to engine/accuracy): results.csv, the plots, the strips
// and report.md, from the sections and their rows. CPU only.
#include <chrono>
#include <filesystem>
#include <vector>

#include "accuracy/accuracy.hpp"
#include "accuracy/results.hpp"

namespace candela::accuracy {

// OUT and the report's folder (made before a run, so that a bad path fails at once); the report.
std::filesystem::path make_output_dirs(const Options& o);

// results.csv, the plots, the strips and report.md from the sections and their rows: the one
// writer of the accuracy outputs, whether the sections ran in this process or were assembled
// from saved ones (so the two outputs cannot drift apart). Needs no GL context. `start`: when
// the work began, for Written::seconds.
Written write_outputs(const Options& o, const std::vector<Section>& sections, const std::vector<Row>& rows,
                      const std::vector<Device>& devices, std::chrono::steady_clock::time_point start);

}  // namespace candela::accuracy
