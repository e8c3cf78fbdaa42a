#include "shader/watch.h"

#include <sys/inotify.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <set>

namespace sdfvj {

FolderWatcher::~FolderWatcher() {
    if (fd_ >= 0) close(fd_);
}

bool FolderWatcher::Watch(const std::string& folder, std::string* error) {
    if (fd_ < 0) fd_ = inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
    if (fd_ < 0) {
        *error = std::string("cannot watch files: ") + std::strerror(errno);
        return false;
    }
    std::string abs = std::filesystem::absolute(folder).lexically_normal().string();
    // Not IN_CREATE or IN_MODIFY: both fire while a file is still being written, and a half-
    // written shader would be compiled (and fail) before the complete one arrives.
    int wd = inotify_add_watch(fd_, abs.c_str(), IN_CLOSE_WRITE | IN_MOVED_TO | IN_ONLYDIR);
    if (wd < 0) {
        *error = "cannot watch " + folder + ": " + std::strerror(errno);
        return false;
    }
    folders_[wd] = abs;
    return true;
}

std::vector<std::string> FolderWatcher::Poll() {
    std::vector<std::string> changed;   // in event order, each path once
    std::set<std::string> seen;
    auto addOnce = [&](const std::string& path) {
        if (seen.insert(path).second) changed.push_back(path);
    };
    if (fd_ < 0) return changed;
    bool overflow = false;
    alignas(struct inotify_event) char buf[16384];
    for (;;) {
        ssize_t n = read(fd_, buf, sizeof buf);
        if (n <= 0) break;
        for (char* p = buf; p < buf + n;) {
            auto* ev = reinterpret_cast<struct inotify_event*>(p);
            p += sizeof(struct inotify_event) + ev->len;
            if (ev->mask & IN_Q_OVERFLOW) {
                overflow = true;
                continue;
            }
            if (ev->mask & IN_IGNORED) {   // the folder itself went away
                folders_.erase(ev->wd);
                continue;
            }
            auto it = folders_.find(ev->wd);
            if (it != folders_.end() && ev->len > 0 && !(ev->mask & IN_ISDIR)) addOnce(it->second + "/" + ev->name);
        }
    }
    if (overflow) {
        // Lost events cannot be recovered: every file may have changed.
        ++overflows_;
        for (const auto& [wd, folder] : folders_) {
            std::error_code ec;
            for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
                std::error_code fec;
                if (!entry.is_directory(fec)) addOnce(entry.path().string());
            }
        }
        std::fprintf(stderr, "sdfvj: the file watch queue overflowed (too many file events at once), "
                             "reloading every file in the %zu watched folders\n", folders_.size());
    }
    return changed;
}

}  // namespace sdfvj
