#pragma once
// A saved section (internal to engine/accuracy; written by run_section, read by assemble):
// DIR/section.json holds the section's fields and its rows' (every double as "%.17g" text, which
// reads back to the same bits, NaN included; JSON numbers have no NaN), DIR/reference.exr and
// DIR/row_NNN.exr the images as float32 EXR (lossless). section.json is written last, by a
// rename: a task that died leaves no section.json, and a directory with one is complete.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "accuracy/accuracy.hpp"
#include "accuracy/results.hpp"
#include "effects/accuracy_sweep.hpp"

namespace candela::accuracy {

inline constexpr const char* kSectionFile = "section.json";

// section.json's content for section `index` (rows[sec.first, sec.last)).
nlohmann::ordered_json section_json(int index, const std::string& label, const Options& o, const Section& sec,
                                    const std::vector<Row>& rows);

// Writes the images and then `j` (from section_json) into DIR, each under a temporary name first.
void save_section(const std::filesystem::path& dir, const nlohmann::ordered_json& j, const Section& sec, const std::vector<Row>& rows);

// DIR/section.json if DIR holds a complete result of this section (sweep `s` on `scene`, run
// with o.quick); else std::nullopt and why not (in `problem`).
std::optional<nlohmann::json> complete_section(const std::filesystem::path& dir, const Options& o, const AccuracySweep& s,
                                               const std::string& scene, std::string& problem);

// The section saved in DIR (its json from complete_section), its rows appended to `rows`.
Section load_section(const std::filesystem::path& dir, const nlohmann::json& j, const AccuracySweep& s, std::vector<Row>& rows);

// What differs between a section and its reloaded copy, bit for bit ("" when nothing).
std::string round_trip_difference(const Section& a, const std::vector<Row>& ar, const Section& b, const std::vector<Row>& br);

}  // namespace candela::accuracy
