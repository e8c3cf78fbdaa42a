// FolderWatcher on a real folder: a save is reported once it is complete (closed or renamed in),
// never half-written; a lost inotify queue (overflow) reports every watched file.
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>

#include "shader/watch.h"

namespace fs = std::filesystem;
using sdfvj::FolderWatcher;

namespace {

struct WatchRig {
    fs::path dir;
    FolderWatcher watcher;
    explicit WatchRig(const std::string& name) {
        dir = fs::temp_directory_path() / ("sdfvj-watch-" + name + "-" + std::to_string(::getpid()));
        fs::remove_all(dir);
        fs::create_directories(dir);
        dir = fs::canonical(dir);
        std::string error;
        REQUIRE(watcher.Watch(dir.string(), &error));
    }
    ~WatchRig() { fs::remove_all(dir); }
    std::string Path(const std::string& name) const { return (dir / name).string(); }
    void Save(const std::string& name, const std::string& text) const {
        std::ofstream(dir / name, std::ios::binary) << text;
    }
};

bool Has(const std::vector<std::string>& v, const std::string& s) { return std::find(v.begin(), v.end(), s) != v.end(); }

int MaxQueuedEvents() {
    std::ifstream f("/proc/sys/fs/inotify/max_queued_events");
    int n = 16384;
    f >> n;
    return n;
}

}  // namespace

TEST_CASE("reload: watcher reports a file written in chunks only once it is closed", "[reload][watch]") {
    WatchRig rig("chunks");
    int fd = ::open(rig.Path("scene.glsl").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    REQUIRE(fd >= 0);
    const std::string first = "/*{ \"NAME\": \"half\" }*/\n", second = "vec4 map(vec3 p) { return vec4(1.0); }\n";
    REQUIRE(::write(fd, first.data(), first.size()) == ssize_t(first.size()));
    CHECK(rig.watcher.Poll().empty());    // created and half written: not a save yet
    REQUIRE(::write(fd, second.data(), second.size()) == ssize_t(second.size()));
    CHECK(rig.watcher.Poll().empty());
    ::close(fd);
    std::vector<std::string> changed = rig.watcher.Poll();
    REQUIRE(changed.size() == 1);
    CHECK(changed[0] == rig.Path("scene.glsl"));
    CHECK(rig.watcher.Poll().empty());
}

TEST_CASE("reload: watcher reports a temp file renamed over the original, not the temp file's writes", "[reload][watch]") {
    WatchRig rig("rename");
    fs::path other = rig.dir.parent_path() / ("sdfvj-watch-tmp-" + std::to_string(::getpid()));
    std::ofstream(other) << "saved elsewhere\n";
    fs::rename(other, rig.dir / "scene.glsl");
    std::vector<std::string> changed = rig.watcher.Poll();
    REQUIRE(changed.size() == 1);
    CHECK(changed[0] == rig.Path("scene.glsl"));
    CHECK(rig.watcher.Overflows() == 0);
}

TEST_CASE("reload: watcher answers an inotify queue overflow with every file in every watched folder", "[reload][watch]") {
    WatchRig rig("overflow");
    fs::create_directories(rig.dir / "lib");
    rig.Save("untouched.glsl", "// never written after the watch starts\n");
    rig.Save("lib/untouched.glsl", "// in a second watched folder\n");
    std::string error;
    REQUIRE(rig.watcher.Watch((rig.dir / "lib").string(), &error));
    rig.Save("a.glsl", "a");
    rig.Save("b.glsl", "b");
    CHECK(rig.watcher.Poll().size() == 3);   // the set-up writes in the first folder, drained
    // Alternate two files so inotify cannot merge consecutive identical events: every close
    // is one queued event, and the queue holds max_queued_events of them.
    const int events = MaxQueuedEvents() + 100;
    int failedOpens = 0;
    for (int i = 0; i < events; ++i) {
        int fd = ::open(rig.Path(i % 2 ? "a.glsl" : "b.glsl").c_str(), O_WRONLY | O_APPEND);
        if (fd < 0) ++failedOpens;
        else ::close(fd);
    }
    REQUIRE(failedOpens == 0);
    std::vector<std::string> changed = rig.watcher.Poll();
    CHECK(rig.watcher.Overflows() == 1);
    CHECK(Has(changed, rig.Path("untouched.glsl")));
    CHECK(Has(changed, rig.Path("lib/untouched.glsl")));
    CHECK(Has(changed, rig.Path("a.glsl")));
    CHECK(Has(changed, rig.Path("b.glsl")));
    CHECK_FALSE(Has(changed, rig.Path("lib")));            // folders are not files
    CHECK(changed.size() == 4);                             // each once
    CHECK(rig.watcher.Poll().empty());
}
