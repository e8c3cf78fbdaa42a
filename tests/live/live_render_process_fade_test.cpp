// `sdfvj live --render-process` during a preset's scene change (issue 12): the scene before is drawn
// by its own render process for the whole fade, and a frame of it that is late is not waited for,
// as the scene on screen's is not (live_render_process_test.cpp). Real window under Xvfb, real
// llvmpipe in every process, real OSC from `oscsend`.
#include <signal.h>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "live_show.h"

using namespace sdfvj::test;

TEST_CASE("live render process: in a crossfade, a render process that stops answering for 0.8 s stops neither the frames nor the fade") {
    const std::string dir = FreshDir(SDFVJ_LIVE_OUT, "render-process-fade-late");
    const std::string root = CopyDataRoot(dir);
    WriteCrossfadePreset(root, "6.0");
    LiveShow show(dir, {"--scene", "midi", "--render-process"}, root);
    StartCrossfade(show, dir, "6.00");
    REQUIRE_LIVE(show, show.WaitForFramesAfter(show.Frames().size(), 5, kDeadline));   // fading

    // Every render process stopped (alive, silent) for 0.8 s, under the 1 s after which one is taken
    // for dead: the scene before's frame used to be waited for, each frame, up to that second.
    const std::vector<pid_t> servers = Children(show.pid);
    INFO("render processes: " << servers.size());
    REQUIRE(servers.size() >= 3);   // the scene on screen, the scene before, a spare
    const size_t before = show.Frames().size();   // the first frame after the stop began has this index
    REQUIRE(before >= 1);
    for (pid_t p : servers) kill(p, SIGSTOP);
    std::this_thread::sleep_for(std::chrono::milliseconds(800));
    for (pid_t p : servers) kill(p, SIGCONT);
    REQUIRE_LIVE(show, show.WaitForFramesAfter(before, 30, kDeadline));
    const std::vector<Frame> frames = show.Frames();
    size_t during = 0;   // frames logged in the 0.8 s from the last before the stop
    for (size_t i = before; i < frames.size() && frames[i].first < frames[before - 1].first + 0.8; ++i) ++during;
    const double gap = LongestGap(frames, before - 1, frames.size() - 1);   // from the last frame before the stop
    INFO("frames in the 0.8 s stop: " << during << ", longest gap after it began " << gap << " s");
    CHECK(gap < 0.5);      // the loop went on with the last images of both scenes
    CHECK(during >= 3);
    // The fade went on: the scene before's process was neither dropped nor taken for dead; it ends
    // with the fade, 6 s after it began.
    const std::string log = show.Log();
    CHECK(log.find("the render server on screen ended") == std::string::npos);
    CHECK(Children(show.pid).size() >= 3);
    REQUIRE_LIVE(show, PollFor(20, [&] { return Children(show.pid).size() == 2; }));
    CHECK(show.Running());
}
