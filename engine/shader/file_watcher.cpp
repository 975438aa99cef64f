#include "shader/file_watcher.hpp"

#include <algorithm>
#include <set>
#include <system_error>

#ifdef __linux__
#include <sys/inotify.h>
#include <unistd.h>
#endif

namespace candela {
namespace fs = std::filesystem;

FileWatcher::FileWatcher(fs::path root, bool force_polling) : root_(fs::absolute(root).lexically_normal()) {
#ifdef __linux__
    if (!force_polling) {
        fd_ = inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
        if (fd_ >= 0) add_watches(root_);
        if (fd_ >= 0 && watches_.empty()) {
            close(fd_);
            fd_ = -1;
        }
    }
#else
    (void)force_polling;
#endif
    if (fd_ < 0) stamps_ = scan();
}

FileWatcher::~FileWatcher() {
#ifdef __linux__
    if (fd_ >= 0) close(fd_);
#endif
}

void FileWatcher::add_watches(const fs::path& dir) {
#ifdef __linux__
    const int wd = inotify_add_watch(fd_, dir.c_str(), IN_CLOSE_WRITE | IN_MODIFY | IN_MOVED_TO | IN_MOVED_FROM | IN_CREATE | IN_DELETE);
    if (wd < 0) return;
    watches_[wd] = dir;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec))
        if (e.is_directory(ec)) add_watches(e.path());
#else
    (void)dir;
#endif
}

std::map<fs::path, FileWatcher::Stamp> FileWatcher::scan() const {
    std::map<fs::path, Stamp> out;
    std::error_code ec;
    for (auto it = fs::recursive_directory_iterator(root_, ec); !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
        if (!it->is_regular_file(ec)) continue;
        Stamp s;
        s.time = it->last_write_time(ec);
        s.size = it->file_size(ec);
        out[it->path().lexically_normal()] = s;
    }
    return out;
}

std::vector<fs::path> FileWatcher::poll() {
    std::set<fs::path> changed;
#ifdef __linux__
    if (fd_ >= 0) {
        alignas(inotify_event) char buffer[16384];
        for (;;) {
            const ssize_t n = read(fd_, buffer, sizeof buffer);
            if (n <= 0) break;
            for (ssize_t at = 0; at < n;) {
                const auto* ev = reinterpret_cast<const inotify_event*>(buffer + at);
                at += static_cast<ssize_t>(sizeof(inotify_event) + ev->len);
                auto dir = watches_.find(ev->wd);
                if (dir == watches_.end() || ev->len == 0) continue;
                const fs::path p = (dir->second / ev->name).lexically_normal();
                std::error_code ec;
                if (ev->mask & IN_ISDIR) {
                    if (ev->mask & (IN_CREATE | IN_MOVED_TO)) add_watches(p);
                    continue;
                }
                changed.insert(p);
            }
        }
        return {changed.begin(), changed.end()};
    }
#endif
    auto now = scan();
    for (const auto& [p, s] : now) {
        auto old = stamps_.find(p);
        if (old == stamps_.end() || old->second != s) changed.insert(p);
    }
    for (const auto& [p, s] : stamps_)
        if (!now.count(p)) changed.insert(p);
    stamps_ = std::move(now);
    return {changed.begin(), changed.end()};
}

}  // namespace candela
