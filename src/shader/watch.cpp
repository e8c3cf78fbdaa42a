#include "shader/watch.h"

#include <sys/inotify.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>

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
    int wd = inotify_add_watch(fd_, abs.c_str(), IN_CLOSE_WRITE | IN_MOVED_TO | IN_CREATE | IN_DELETE | IN_MODIFY);
    if (wd < 0) {
        *error = "cannot watch " + folder + ": " + std::strerror(errno);
        return false;
    }
    folders_[wd] = abs;
    return true;
}

std::vector<std::string> FolderWatcher::Poll() {
    std::vector<std::string> changed;
    if (fd_ < 0) return changed;
    alignas(struct inotify_event) char buf[16384];
    for (;;) {
        ssize_t n = read(fd_, buf, sizeof buf);
        if (n <= 0) break;
        for (char* p = buf; p < buf + n;) {
            auto* ev = reinterpret_cast<struct inotify_event*>(p);
            auto it = folders_.find(ev->wd);
            if (it != folders_.end() && ev->len > 0) {
                std::string path = it->second + "/" + ev->name;
                if (std::find(changed.begin(), changed.end(), path) == changed.end()) changed.push_back(path);
            }
            p += sizeof(struct inotify_event) + ev->len;
        }
    }
    return changed;
}

}  // namespace sdfvj
