#pragma once
// A disk cache for data derived deterministically from inputs that a run can name exactly: today
// the prefiltered environment cube (render/environment.hpp), which costs llvmpipe about 75 ms of
// compute per run and is the same for every scene lit by the same environment (the default rig's
// sky lights most of them). The idea is the derived-data cache of game engines: the key is a hash
// of every input (texels, shader sources after #include, sizes, sample counts, the GL driver, a
// format version), so a changed input is a different entry, never a stale one.
//
// Where: $CANDELA_CACHE_DIR; "off" (or empty) turns the cache off. Unset: $XDG_CACHE_HOME/candela,
// else $HOME/.cache/candela. Entries are written to a temporary file and renamed, so concurrent
// runs never read half an entry; each carries its key, size and a checksum, and an entry that
// fails any check is a miss (and is replaced). Failing to read or write is never an error: the
// data is computed as without the cache. At most kMaxEntries entries are kept (the oldest go).
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace candela {

// 64-bit hash of byte strings for cache keys (not cryptographic): four lanes of multiply-rotate
// over 8-byte words, so that hashing an environment map's texels costs little next to the work
// it saves (about 5 GB/s here).
class Hasher {
public:
    Hasher& bytes(const void* data, std::size_t size);
    Hasher& text(const std::string& s);
    Hasher& integer(std::int64_t v);
    std::uint64_t value() const;

private:
    std::uint64_t lanes_[4] = {0x9e3779b97f4a7c15ull, 0xc2b2ae3d27d4eb4full, 0x165667b19e3779f9ull, 0x27d4eb2f165667c5ull};
    std::uint64_t length_ = 0;
};

class DerivedCache {
public:
    static constexpr int kMaxEntries = 64;
    // The cache directory from the environment (see above); nullopt: off.
    static std::optional<std::filesystem::path> default_directory();
    // `directory` nullopt: every lookup misses and nothing is stored.
    explicit DerivedCache(std::optional<std::filesystem::path> directory = default_directory());

    // The entry `kind`-`key`, if it exists, is intact and holds exactly `size` bytes.
    std::optional<std::vector<std::uint8_t>> load(const std::string& kind, std::uint64_t key, std::size_t size) const;
    // Stores (replaces) the entry; false if it could not be written (the reason goes to the debug log).
    bool store(const std::string& kind, std::uint64_t key, const std::vector<std::uint8_t>& data) const;
    std::optional<std::filesystem::path> entry_path(const std::string& kind, std::uint64_t key) const;

private:
    void prune() const;
    std::optional<std::filesystem::path> directory_;
};

}  // namespace candela
