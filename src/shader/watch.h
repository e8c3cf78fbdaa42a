// FolderWatcher: which files under some folders changed since the last Poll().
//
// Watches folders, not files: editors save by writing a temp file and renaming it over the
// original, which a per-file watch loses. Linux inotify, non-blocking; Poll() never waits, so the
// render thread can call it every frame. No GL here.
//
// A file is reported when a writer closes it (IN_CLOSE_WRITE) or when it is renamed into the
// folder (IN_MOVED_TO), never while it is being written: a save that arrives in several chunks
// is one change, seen once, complete. When the kernel's event queue overflows (more than
// /proc/sys/fs/inotify/max_queued_events unread events) the events in it are lost, so Poll()
// reports every file of every watched folder and logs one line; consumers are idempotent (a
// file whose content did not change compiles nothing).
#pragma once
#include <cstddef>
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
    // Absolute paths of files closed after writing or renamed into a watched folder since the
    // last call (each once); after a queue overflow, every file in every watched folder.
    std::vector<std::string> Poll();
    // How many queue overflows Poll() has seen (each one logged and answered with every file).
    size_t Overflows() const { return overflows_; }
private:
    int fd_ = -1;
    size_t overflows_ = 0;
    std::map<int, std::string> folders_;   // watch descriptor -> folder
};

}  // namespace sdfvj
