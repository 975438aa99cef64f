#pragma once
// Whole-file text reads and writes for tests that edit shader sources on disk (hot reload).
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace candela::test {

inline std::string read_text(const std::filesystem::path& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

inline void write_text(const std::filesystem::path& p, const std::string& s) { std::ofstream(p, std::ios::trunc) << s; }

}  // namespace candela::test
