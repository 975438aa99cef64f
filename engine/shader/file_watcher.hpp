#pragma once
// Notices changed files under a directory tree: inotify on Linux, else (or when asked) polling
// of modification times and sizes. poll() never blocks.
#include <chrono>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace candela {

class FileWatcher {
public:
    explicit FileWatcher(std::filesystem::path root, bool force_polling = false);
    ~FileWatcher();
    FileWatcher(const FileWatcher&) = delete;
    FileWatcher& operator=(const FileWatcher&) = delete;

    // Regular files created, written, moved in or removed since the last call (normalized
    // absolute paths, sorted, no duplicates).
    std::vector<std::filesystem::path> poll();
    bool uses_inotify() const { return fd_ >= 0; }

private:
    struct Stamp {
        std::filesystem::file_time_type time;
        std::uintmax_t size = 0;
        bool operator!=(const Stamp& o) const { return time != o.time || size != o.size; }
    };
    void add_watches(const std::filesystem::path& dir);
    std::map<std::filesystem::path, Stamp> scan() const;

    std::filesystem::path root_;
    int fd_ = -1;
    std::map<int, std::filesystem::path> watches_;   // inotify watch descriptor -> directory
    std::map<std::filesystem::path, Stamp> stamps_;  // polling
};

}  // namespace candela
