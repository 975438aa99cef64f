#include "core/derived_cache.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <random>
#include <system_error>

#include <unistd.h>

#include "core/log.hpp"

namespace candela {
namespace {
namespace fs = std::filesystem;

constexpr std::uint64_t kPrime1 = 0x9e3779b185ebca87ull, kPrime2 = 0xc2b2ae3d27d4eb4full;
std::uint64_t rotl(std::uint64_t v, int r) { return (v << r) | (v >> (64 - r)); }
std::uint64_t mix(std::uint64_t lane, std::uint64_t word) { return rotl(lane ^ (word * kPrime2), 31) * kPrime1; }
std::uint64_t avalanche(std::uint64_t h) {
    h ^= h >> 33;
    h *= kPrime2;
    h ^= h >> 29;
    h *= kPrime1;
    return h ^ (h >> 32);
}

// File layout: magic, key, payload size, payload, hash of the payload (all little-endian u64 but
// the payload).
constexpr char kMagic[8] = {'C', 'N', 'D', 'L', 'D', 'C', '0', '1'};
constexpr std::size_t kHeader = 8 + 8 + 8, kTrailer = 8;

std::uint64_t payload_hash(const std::uint8_t* data, std::size_t size) { return Hasher().bytes(data, size).value(); }

void put_u64(std::vector<std::uint8_t>& out, std::size_t at, std::uint64_t v) {
    for (int i = 0; i < 8; ++i) out[at + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(v >> (8 * i));
}
std::uint64_t get_u64(const std::uint8_t* p) {
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= static_cast<std::uint64_t>(p[i]) << (8 * i);
    return v;
}
}  // namespace

Hasher& Hasher::bytes(const void* data, std::size_t size) {
    const auto* p = static_cast<const std::uint8_t*>(data);
    std::size_t i = 0;
    for (; i + 32 <= size; i += 32)
        for (int lane = 0; lane < 4; ++lane) {
            std::uint64_t w;
            std::memcpy(&w, p + i + 8 * static_cast<std::size_t>(lane), 8);
            lanes_[lane] = mix(lanes_[lane], w);
        }
    // The tail, a byte at a time, into lane 0; the length (in value()) separates "ab"+"c" from "a"+"bc".
    for (; i < size; ++i) lanes_[0] = mix(lanes_[0], p[i] + 0x100ull);
    length_ += size;
    lanes_[1] = mix(lanes_[1], size);  // where one call's bytes end
    return *this;
}

Hasher& Hasher::text(const std::string& s) { return bytes(s.data(), s.size()); }

Hasher& Hasher::integer(std::int64_t v) { return bytes(&v, sizeof v); }

std::uint64_t Hasher::value() const {
    std::uint64_t h = rotl(lanes_[0], 1) + rotl(lanes_[1], 7) + rotl(lanes_[2], 12) + rotl(lanes_[3], 18);
    for (const std::uint64_t lane : lanes_) h = (h ^ mix(0, lane)) * kPrime1;
    return avalanche(h ^ length_);
}

std::optional<fs::path> DerivedCache::default_directory() {
    if (const char* dir = std::getenv("CANDELA_CACHE_DIR")) {
        const std::string d = dir;
        if (d.empty() || d == "off") return std::nullopt;
        return fs::path(d);
    }
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg == '/') return fs::path(xdg) / "candela";
    if (const char* home = std::getenv("HOME"); home && *home == '/') return fs::path(home) / ".cache" / "candela";
    return std::nullopt;
}

DerivedCache::DerivedCache(std::optional<fs::path> directory) : directory_(std::move(directory)) {}

std::optional<fs::path> DerivedCache::entry_path(const std::string& kind, std::uint64_t key) const {
    if (!directory_) return std::nullopt;
    char name[17];
    std::snprintf(name, sizeof name, "%016llx", static_cast<unsigned long long>(key));
    return *directory_ / (kind + "-" + name + ".bin");
}

std::optional<std::vector<std::uint8_t>> DerivedCache::load(const std::string& kind, std::uint64_t key, std::size_t size) const {
    const std::optional<fs::path> path = entry_path(kind, key);
    if (!path) return std::nullopt;
    std::error_code ec;
    if (!fs::is_regular_file(*path, ec)) return std::nullopt;  // not there, or a directory or FIFO (reading one would block)
    std::ifstream in(*path, std::ios::binary);
    if (!in) return std::nullopt;
    std::vector<std::uint8_t> file(kHeader + size + kTrailer);
    in.read(reinterpret_cast<char*>(file.data()), static_cast<std::streamsize>(file.size()));
    const bool complete = in.gcount() == static_cast<std::streamsize>(file.size()) && in.peek() == std::char_traits<char>::eof();
    const std::uint8_t* payload = file.data() + kHeader;
    if (!complete || std::memcmp(file.data(), kMagic, 8) != 0 || get_u64(file.data() + 8) != key || get_u64(file.data() + 16) != size ||
        get_u64(payload + size) != payload_hash(payload, size)) {
        log::debug("cache: " + path->string() + " is damaged or of another version; computing it again");
        return std::nullopt;
    }
    return std::vector<std::uint8_t>(payload, payload + size);
}

bool DerivedCache::store(const std::string& kind, std::uint64_t key, const std::vector<std::uint8_t>& data) const {
    const std::optional<fs::path> path = entry_path(kind, key);
    if (!path) return false;
    std::error_code ec;
    fs::create_directories(*directory_, ec);
    std::vector<std::uint8_t> file(kHeader + data.size() + kTrailer);
    std::memcpy(file.data(), kMagic, 8);
    put_u64(file, 8, key);
    put_u64(file, 16, data.size());
    std::copy(data.begin(), data.end(), file.begin() + static_cast<std::ptrdiff_t>(kHeader));
    put_u64(file, kHeader + data.size(), payload_hash(data.data(), data.size()));
    // A name no other process uses, renamed into place: readers see the old entry or the new one.
    std::random_device rd;
    const fs::path tmp = path->string() + ".tmp" + std::to_string(::getpid()) + "-" + std::to_string(rd());
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(file.data()), static_cast<std::streamsize>(file.size()));
        out.close();
        if (!out) {
            log::debug("cache: cannot write " + tmp.string() + "; not cached");
            fs::remove(tmp, ec);
            return false;
        }
    }
    fs::rename(tmp, *path, ec);
    if (ec) {
        log::debug("cache: cannot rename " + tmp.string() + ": " + ec.message() + "; not cached");
        fs::remove(tmp, ec);
        return false;
    }
    prune();
    return true;
}

void DerivedCache::prune() const {
    std::error_code ec;
    std::vector<std::pair<fs::file_time_type, fs::path>> entries;
    for (fs::directory_iterator it(*directory_, ec), end; !ec && it != end; it.increment(ec))
        if (it->path().extension() == ".bin") entries.emplace_back(it->last_write_time(ec), it->path());
    if (entries.size() <= static_cast<std::size_t>(kMaxEntries)) return;
    std::sort(entries.begin(), entries.end());
    for (std::size_t i = 0; i + kMaxEntries < entries.size(); ++i) fs::remove(entries[i].second, ec);
}

}  // namespace candela
