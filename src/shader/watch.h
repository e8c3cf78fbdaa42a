// FolderWatcher: which files under some folders changed since the last Poll().
//
// Watches folders, not files: editors save by writing a temp file and renaming it over the
// original, which a per-file watch loses. Linux inotify, non-blocking; Poll() never waits, so the
// render thread can call it every frame. No GL here.
#pragma once
#include <map>
#include <string>
#include <vector>

namespace sdfvj {

class FolderWatcher {
public:
    FolderWatcher() = default;
    ~FolderWatcher();
    FolderWatcher(const FolderWatcher&) = delete;
    FolderWatcher& operator=(const FolderWatcher&) = delete;
    // Adds a folder (not recursive). False with a reason when it cannot be watched.
    bool Watch(const std::string& folder, std::string* error);
    // Absolute paths of files created, written or renamed into a watched folder since last call.
    std::vector<std::string> Poll();
private:
    int fd_ = -1;
    std::map<int, std::string> folders_;   // watch descriptor -> folder
};

}  // namespace sdfvj
