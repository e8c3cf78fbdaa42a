// `sdfvj live` as a user runs it: a real GLFW window on Xvfb (ctest fixture `xvfb`), OSC from
// the `oscsend` tool, a screenshot, a recorded take. The frame values come from the
// --log-params log ("time name=value ..." per frame).
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "accuracy/accuracy.h"
#include "app/replay_driver.h"
#include "app/show.h"
#include "gl_fixture.h"
#include "live_util.h"
#include "take/take.h"

using namespace sdfvj;
using namespace sdfvj::test;
namespace fs = std::filesystem;

namespace {

const int kW = 240, kH = 136;

struct LiveRun {
    std::string dir, log, shot, params;
    pid_t pid = -1;
    int oscPort = 0;
    LiveRun(const std::string& name, std::vector<std::string> extra = {}, bool overlay = true, std::vector<EnvChange> env = {}) {
        dir = FreshDir(SDFVJ_LIVE_OUT, name);
        log = dir + "/live.log";
        shot = dir + "/shot.png";
        params = dir + "/params.txt";
        oscPort = FreeUdpPort();
        std::vector<std::string> argv = {SDFVJ_BIN, "live", "--scene", "midi", "--size", std::to_string(kW) + "x" + std::to_string(kH),
                                         "--seconds", "3", "--path", "fragment", "--effects", "none", "--osc-port", std::to_string(oscPort),
                                         "--midi", "no-such-controller", "--screenshot", shot, "--log-params", params};
        for (const char* option : {"--scene", "--seconds", "--size"})   // given in `extra`: its default goes
            if (std::find(extra.begin(), extra.end(), option) != extra.end()) {
                auto at = std::find(argv.begin(), argv.end(), option);
                argv.erase(at, at + 2);
            }
        if (!overlay) argv.push_back("--hide-overlay");
        argv.insert(argv.end(), extra.begin(), extra.end());
        env.insert(env.begin(), {{"DISPLAY", Display()}, {"JACK_NO_START_SERVER", "1"}});
        pid = Spawn(argv, log, env);
    }
    // Waits until the log holds `text` (the program got that far).
    bool WaitForLog(const std::string& text, double seconds) const {
        for (double t = 0; t < seconds; t += 0.01) {
            if (ReadText(log).find(text) != std::string::npos) return true;
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        return false;
    }
    // Waits until the show has logged its first frame (--log-params): a message sent before it would
    // move the first frame's value, which the tests read as the value before the message.
    bool WaitForFirstFrame(double seconds) const {
        for (double t = 0; t < seconds; t += 0.01) {
            if (ReadText(params).find('\n') != std::string::npos) return true;
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        return false;
    }
    void Osc(const std::string& address, const std::string& type, const std::string& value) const {
        int rc = Run({"oscsend", "localhost", std::to_string(oscPort), address, type, value}, dir + "/oscsend.log", 10);
        INFO(ReadText(dir + "/oscsend.log"));
        REQUIRE(rc == 0);
    }
    int Wait() { return WaitExit(pid, 40); }
};

// Standard deviation of luma over the image: a flat colour (nothing drawn) gives 0.
double LumaSpread(const Image& img) {
    double sum = 0, sum2 = 0;
    int n = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const uint8_t* p = &img.rgba[((size_t)y * img.width + x) * 4];
            double l = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
            sum += l;
            sum2 += l * l;
            ++n;
        }
    double mean = sum / n;
    return std::sqrt(std::max(0.0, sum2 / n - mean * mean));
}

}  // namespace

TEST_CASE("live osc: oscsend /sdfvj/param/twist moves the running scene (window under Xvfb)") {
    // Two runs side by side: one gets the OSC message half a second after its first frame, the other nothing.
    // The overlay is hidden (--hide-overlay) so the screenshots show only the scene.
    // The scene's spin is stopped (spin=0), so twist is the only thing that differs between them.
    LiveRun with("osc-twist", {"--param", "spin=0"}, false), without("no-osc", {"--param", "spin=0"}, false);
    INFO(ReadText(with.log));
    REQUIRE(with.WaitForLog("OSC: listening on UDP port " + std::to_string(with.oscPort), 20));
    REQUIRE(with.WaitForFirstFrame(20));
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    with.Osc("/sdfvj/param/twist", "f", "1.0");
    const int rcWith = with.Wait(), rcWithout = without.Wait();
    INFO("with OSC:\n" << ReadText(with.log) << "without:\n" << ReadText(without.log));
    REQUIRE(rcWith == 0);
    REQUIRE(rcWithout == 0);

    // Parameter log: twist starts at the scene default 0.5 and ends at 3 (1.0 of [-3, 3]).
    std::vector<Frame> a = ReadParamLog(with.params), b = ReadParamLog(without.params);
    REQUIRE(a.size() >= 5);   // software GL under load: a few frames per second is enough
    REQUIRE(b.size() >= 5);
    CHECK(a.front().second["twist"] == Approx(0.5f));
    CHECK(a.back().second["twist"] == Approx(3.0f).margin(1e-3));
    CHECK(a.back().first == Approx(3.0).margin(0.5));
    double changedAt = -1;
    for (const Frame& f : a)
        if (changedAt < 0 && f.second.at("twist") != a.front().second.at("twist")) changedAt = f.first;
    INFO("twist started to move at " << changedAt << " s of the live clock");
    CHECK(changedAt > 0.3);
    CHECK(changedAt < 2.7);
    for (const Frame& f : b) CHECK(f.second.at("twist") == 0.5f);

    // Screenshots: the size of the window, a real scene (not one flat colour), and the twisted
    // scene differs from the untouched one.
    Image sa, sb;
    REQUIRE(LoadPng(with.shot, &sa));
    REQUIRE(LoadPng(without.shot, &sb));
    CHECK(sa.width == kW);
    CHECK(sa.height == kH);
    CHECK(LumaSpread(sa) > 5.0);
    CHECK(LumaSpread(sb) > 5.0);
    ImageDiff d = CompareImages(sa, sb, 8);
    INFO("twist 3 vs 0.5: " << d.fractionOver * 100 << "% of pixels differ by more than 8/255");
    CHECK(d.fractionOver > 0.01);
}

// Five seconds of show, so that on a loaded machine (the sanitizer pass runs two of these at once)
// the third message still lands before the end; the recorded gaps are held to the gaps the
// messages were actually sent at (each oscsend is a process start), not to the sleeps.
TEST_CASE("live record: OSC messages during `live --record` read back from the .mid and replay") {
    LiveRun run("record", {"--record", std::string(SDFVJ_LIVE_OUT) + "/record/take.mid", "--seconds", "5"});
    const std::string take = run.dir + "/take.mid";
    INFO(ReadText(run.log));
    REQUIRE(run.WaitForLog("OSC: listening on UDP port " + std::to_string(run.oscPort), 20));
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    std::vector<double> sentAt;
    auto send = [&](const char* address, const char* value) {
        run.Osc(address, "f", value);
        sentAt.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count());
    };
    send("/sdfvj/param/twist", "1.0");
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    send("/sdfvj/raw/scale", "1.5");
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    send("/sdfvj/param/displacement", "0.5");
    REQUIRE(run.Wait() == 0);
    CHECK(run.WaitForLog("recorded 3 events to", 1));

    Take t;
    TakeReadResult r = ReadTake(take, &t);
    INFO(r.error);
    REQUIRE(r.ok);
    REQUIRE(t.events.size() == 3);
    const char* addresses[] = {"/sdfvj/param/twist", "/sdfvj/raw/scale", "/sdfvj/param/displacement"};
    const float sent[] = {1.0f, 1.5f, 0.5f};
    for (int i = 0; i < 3; ++i) {
        INFO("event " << i);
        CHECK(t.events[i].source == EventSource::Osc);
        CHECK(t.events[i].address == addresses[i]);
        REQUIRE(t.events[i].args.size() == 1);
        CHECK(t.events[i].args[0].type == 'f');
        CHECK(t.events[i].args[0].f == sent[i]);
        if (i > 0) {
            CHECK(t.events[i].time - t.events[i - 1].time == Approx(sentAt[i] - sentAt[i - 1]).margin(0.1));
            CHECK(t.events[i].time - t.events[i - 1].time >= 0.25);   // the 300 ms sleeps, less the take's tick
        }
    }
    CHECK(t.events[0].time > 0.2);
    CHECK(t.duration >= 4.9);   // End-of-Track at the clock when the loop ended: --seconds plus the last frame
    CHECK(t.duration < 8.0);

    // The take drives `render --replay` to the values the live run ended with.
    std::vector<Frame> live = ReadParamLog(run.params);
    REQUIRE(!live.empty());
    ShowOptions opts;
    opts.scene = "midi";
    Show show;
    std::string error;
    REQUIRE(PrepareShow(opts, &show, &error));
    auto driver = MakeReplayDriver(show, take, "", &error);
    INFO(error);
    REQUIRE(driver);
    std::vector<std::pair<std::string, float>> values;
    for (int i = 0; i <= 90; ++i) driver->Advance(i / 30.0, 1 / 30.0, &values);
    for (const auto& [name, v] : values) {
        INFO(name);
        CHECK(v == Approx(live.back().second.at(name)).margin(1e-3));
    }
    CHECK(live.back().second.at("twist") == Approx(3.0f).margin(1e-3));
    CHECK(live.back().second.at("scale") == Approx(1.5f).margin(1e-3));
    CHECK(live.back().second.at("displacement") == Approx(0.125f).margin(1e-3));
}

TEST_CASE("live without a display exits 2 with one clear line") {
    const std::string dir = FreshDir(SDFVJ_LIVE_OUT, "no-display");
    int rc = Run({SDFVJ_BIN, "live", "--scene", "midi", "--seconds", "1"}, dir + "/live.log", 20,
                 {{"DISPLAY", "", true}, {"WAYLAND_DISPLAY", "", true}, {"JACK_NO_START_SERVER", "1"}});
    const std::string out = ReadText(dir + "/live.log");
    INFO(out);
    CHECK(rc == 2);
    CHECK(std::count(out.begin(), out.end(), '\n') == 1);
    CHECK(out.find("no display") != std::string::npos);
}

TEST_CASE("command line: a negative or non-finite --seconds or --frame-budget, --frames 0, a --budget-floor without a budget or that does not parse exit 2 with what was expected") {
    const std::string dir = FreshDir(SDFVJ_LIVE_OUT, "bad-numbers");
    // Checked before the window opens: no display is needed, and none is given, so a check that
    // let one through would fail on "no display" instead.
    const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
        {{"--seconds=-1"}, "--seconds: '-1', expected a finite number >= 0"},
        {{"--seconds=nan"}, "--seconds: 'nan', expected a finite number >= 0"},
        {{"--frame-budget=-5"}, "--frame-budget: '-5', expected a finite number >= 0"},
        {{"--frame-budget=inf"}, "--frame-budget: 'inf', expected a finite number >= 0"},
        {{"--budget-floor", "scale=0.5"}, "--budget-floor scale=0.5 without --frame-budget MS"},
        {{"--frame-budget", "8", "--budget-floor", "bogus"}, "'bogus' is not NAME=NUMBER"},
        {{"--frame-budget", "8", "--budget-floor", "scale=9"}, "'scale=9' unknown or out of range"},
    };
    for (const auto& [extra, expected] : cases) {
        std::vector<std::string> argv = {SDFVJ_BIN, "live", "--scene", "midi"};
        argv.insert(argv.end(), extra.begin(), extra.end());
        int rc = Run(argv, dir + "/live.log", 20, {{"DISPLAY", "", true}, {"WAYLAND_DISPLAY", "", true}, {"JACK_NO_START_SERVER", "1"}});
        const std::string out = ReadText(dir + "/live.log");
        INFO(extra.front() << ": " << out);
        CHECK(rc == 2);
        CHECK(out.find(expected) != std::string::npos);
        CHECK(out.find("no display") == std::string::npos);
    }
    // The benches and learn: a table of zeros for --frames 0, a wait of -1 s, before.
    for (const auto& [argv, expected] : std::vector<std::pair<std::vector<std::string>, std::string>>{
             {{SDFVJ_BIN, "bench", "--scenes", "midi", "--frames", "0"}, "--frames: '0', expected a finite number >= 1"},
             {{SDFVJ_BIN, "bench", "accuracy", "--warmup=-1"}, "--warmup: '-1', expected a finite number >= 0"},
             {{SDFVJ_BIN, "bench", "reload", "--fps=nan"}, "--fps: 'nan', expected a finite number >= 0"},
             {{SDFVJ_BIN, "learn", "--param", "scale", "--timeout=-1"}, "--timeout: '-1', expected a finite number > 0"}}) {
        int rc = Run(argv, dir + "/cli.log", 20, {{"JACK_NO_START_SERVER", "1"}});
        const std::string out = ReadText(dir + "/cli.log");
        INFO(argv[1] << ": " << out);
        CHECK(rc == 2);
        CHECK(out.find(expected) != std::string::npos);
    }
}

TEST_CASE("live with a display that does not answer asks again for 3 s then exits 2 with GLFW's reason") {
    const std::string dir = FreshDir(SDFVJ_LIVE_OUT, "dead-display");
    int n = 90;   // a display number with no X server behind it
    while (std::filesystem::exists("/tmp/.X11-unix/X" + std::to_string(n))) ++n;
    const auto start = std::chrono::steady_clock::now();
    int rc = Run({SDFVJ_BIN, "live", "--scene", "midi", "--seconds", "1"}, dir + "/live.log", 30,
                 {{"DISPLAY", ":" + std::to_string(n)}, {"WAYLAND_DISPLAY", "", true}, {"JACK_NO_START_SERVER", "1"}});
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const std::string out = ReadText(dir + "/live.log");
    INFO(out);
    CHECK(rc == 2);
    CHECK(seconds >= 2.5);
    CHECK(out.find("did not answer") != std::string::npos);
    CHECK(out.find("no display (GLFW could not start: X11: ") != std::string::npos);   // GLFW's own reason
}

// Two shows run at once, the second with another --render-scale: both end well, and their
// screenshots (the second window-sized) go to a and b.
void ScaledPair(LiveRun& full, LiveRun& scaled, Image* a, Image* b) {
    const int rcFull = full.Wait(), rcScaled = scaled.Wait();
    INFO(ReadText(full.log) << ReadText(scaled.log));
    REQUIRE(rcFull == 0);
    REQUIRE(rcScaled == 0);
    REQUIRE(LoadPng(full.shot, a));
    REQUIRE(LoadPng(scaled.shot, b));
    REQUIRE(b->width == kW);
    REQUIRE(b->height == kH);
}

TEST_CASE("live render scale: --render-scale 0.25 fills the window with the scene rendered at a quarter of its size") {
    LiveRun full("scale-full", {"--param", "spin=0"}, false), quarter("scale-quarter", {"--param", "spin=0", "--render-scale", "0.25"}, false);
    Image a, b;
    ScaledPair(full, quarter, &a, &b);
    CHECK(LumaSpread(b) > 5.0);                    // the scene, not a blank window
    ImageDiff d = CompareImages(a, b, 24);
    INFO("quarter against full: mean " << d.meanAbs << ", " << d.fractionOver * 100 << "% of pixels over 24/255");
    CHECK(d.meanAbs < 12.0);                       // the same picture, softer
    CHECK(d.maxAbs > 0);                           // but not the full-size render
}

TEST_CASE("live render scale: --render-scale 2 supersamples and the window shows each pixel as the mean of 2x2 samples") {
    // primitives with spin and bob at 0 is still (midi pulses with the show's beat), with a checker floor to alias
    const std::vector<std::string> still = {"--scene", "primitives", "--param", "spin=0", "--param", "bob=0"};
    std::vector<std::string> superArgs = still;
    superArgs.insert(superArgs.end(), {"--render-scale", "2"});
    LiveRun full("super-full", still, false), super("super-2", superArgs, false);
    Image a, b;
    ScaledPair(full, super, &a, &b);
    // The truth it should show: the same frame rendered offline at twice the size, averaged 2x2
    // (the scene is still, so the time a screenshot is taken at does not matter).
    const std::string dir = FreshDir(SDFVJ_LIVE_OUT, "super-truth");
    REQUIRE(Run({SDFVJ_BIN, "render", "--scene", "primitives", "--size", std::to_string(2 * kW) + "x" + std::to_string(2 * kH),
                 "--path", "fragment", "--effects", "none", "--param", "spin=0", "--param", "bob=0", "--quiet", "--out", dir},
                dir + "/render.log", 60) == 0);
    Image big, truth;
    REQUIRE(LoadPng(dir + "/frame_00000.png", &big));
    REQUIRE(big.width == 2 * kW);
    truth.width = kW;
    truth.height = kH;
    truth.rgba = accuracy::DownsampleRgba8x2(big.rgba, big.width, big.height);
    ImageDiff superVsTruth = CompareImages(b, truth, 8), fullVsTruth = CompareImages(a, truth, 8), superVsFull = CompareImages(a, b, 8);
    INFO("supersampled against the truth: mean " << superVsTruth.meanAbs << ", max " << superVsTruth.maxAbs << ", "
         << superVsTruth.fractionOver * 100 << "% over 8/255; one sample against it: mean " << fullVsTruth.meanAbs << ", "
         << fullVsTruth.fractionOver * 100 << "%");
    CHECK(superVsTruth.fractionOver < 0.002);                 // the mean of 2x2 (a dither level or two apart)
    CHECK(fullVsTruth.fractionOver > 0.01);                   // one sample a pixel has stairs on every edge
    CHECK(superVsTruth.fractionOver < 0.2 * fullVsTruth.fractionOver);
    CHECK(superVsFull.meanAbs < 6.0);                         // the same picture
}

TEST_CASE("live frame budget: --frame-budget starts supersampled at the front's best and drops to the cheapest when nothing fits") {
    // 0.05 ms is far below any frame llvmpipe draws (even a quarter of the width is predicted over
    // it): after its first second the budget takes the
    // cheapest setting above the default floor, a quarter of the width.
    // 6 s, not 3: on a loaded machine the first frame came after 3 s once, and the budget had no
    // second of frames left to move in.
    // SDFVJ_SCALES_AHEAD=1: the sizes drawn ahead as on a GPU (llvmpipe skips it: a new texture costs it nothing).
    LiveRun run("budget", {"--param", "spin=0", "--frame-budget", "0.05", "--seconds", "6"}, false, {{"SDFVJ_SCALES_AHEAD", "1"}});
    const int rc = run.Wait();
    const std::string log = ReadText(run.log);
    INFO(log);
    REQUIRE(rc == 0);
    const size_t start = log.find("frame budget 0.05 ms: starts at ");
    REQUIRE(start != std::string::npos);
    CHECK(log.substr(start, log.find('\n', start) - start).find("@ 2.00") != std::string::npos);   // 2x2 supersampled
    // The sizes its moves reach drawn once ahead, nearest first: 1 is the nearest to 2 on the front.
    const size_t ahead = log.find("frame budget: the targets of render scales 1.00, ");
    CHECK(ahead != std::string::npos);
    CHECK(ahead < log.find("frame budget 0.05 ms: median "));
    const size_t move = log.find("frame budget 0.05 ms: median ");
    REQUIRE(move != std::string::npos);
    CHECK(log.substr(move, log.find('\n', move) - move).find("@ 0.25") != std::string::npos);
    Image shot;
    REQUIRE(LoadPng(run.shot, &shot));
    CHECK(shot.width == kW);
    CHECK(LumaSpread(shot) > 5.0);   // the scene, upscaled from a quarter of the window
}

TEST_CASE("live screenshot: a show whose --seconds end before its first frame runs on until one is drawn and writes it") {
    // 0.05 s is shorter than a first compile on llvmpipe that no cache serves: without the grace the
    // show ended with no frame and no screenshot (a loaded machine may do the same to a 3 s show).
    LiveRun run("shot-late", {"--seconds", "0.05", "--param", "spin=0", "--no-program-cache"}, false,
                {{"MESA_SHADER_CACHE_DISABLE", "true"}});
    const int rc = run.Wait();
    const std::string log = ReadText(run.log);
    INFO(log);
    REQUIRE(rc == 0);
    CHECK(log.find("running on until one is, for --screenshot") != std::string::npos);
    Image shot;
    REQUIRE(LoadPng(run.shot, &shot));
    CHECK(shot.width == kW);
    CHECK(LumaSpread(shot) > 5.0);   // the scene, not the clear colour shown while it compiled
}

TEST_CASE("live post: --post mirror filters the window's frame, and its input answers OSC like a scene's") {
    // mirror's `mode` input (0 left onto right ... 3 top onto bottom) becomes a show parameter. In this
    // process, and with --render-process drawn by the render server over each frame (its parameters
    // go with the frame's inputs).
    const bool servers = GENERATE(false, true);
    std::vector<std::string> args = {"--post", "mirror", "--param", "spin=0"};
    if (servers) args.insert(args.end(), {"--render-process", "--seconds", "5"});   // its first frame comes later (1.8 s under ASan)
    LiveRun run(servers ? "post-mirror-servers" : "post-mirror", args, false, {{"SDFVJ_POST_IN_SERVER", servers ? "1" : "0"}});
    INFO(ReadText(run.log));
    REQUIRE(run.WaitForLog("OSC: listening on UDP port " + std::to_string(run.oscPort), 20));
    REQUIRE(run.WaitForLog(servers ? "post: mirror, drawn by the render process" : "post: mirror", 20));
    REQUIRE(run.WaitForFirstFrame(20));
    std::this_thread::sleep_for(std::chrono::milliseconds(800));
    run.Osc("/sdfvj/param/mode", "f", "1.0");   // 0..1 over the input's range [0, 3]: 3, top onto bottom
    REQUIRE(run.Wait() == 0);
    const std::vector<Frame> frames = ReadParamLog(run.params);
    REQUIRE(frames.size() >= 3);
    CHECK(frames.front().second.at("mode") == Approx(0.0f));
    CHECK(frames.back().second.at("mode") == Approx(3.0f));
    CHECK(frames.back().second.at("twist") == Approx(0.5f));   // the scene's own inputs are still there

    // The last frame: mode 3 (top onto bottom) makes row y the mirror of row H-1-y (within 2/255:
    // the upscale to the window samples both halves alike, the mirror line may round).
    Image shot;
    REQUIRE(LoadPng(run.shot, &shot));
    REQUIRE(shot.width == kW);
    CHECK(LumaSpread(shot) > 5.0);
    int worst = 0;
    for (int y = 0; y < kH / 2 - 1; ++y)
        for (int x = 0; x < kW; ++x)
            for (int c = 0; c < 3; ++c) {
                const int a = shot.rgba[((size_t)y * kW + x) * 4 + c], b = shot.rgba[((size_t)(kH - 1 - y) * kW + x) * 4 + c];
                worst = std::max(worst, std::abs(a - b));
            }
    CHECK(worst <= 2);
}

TEST_CASE("live post: a preset's post chain loads with it, and an unknown effect keeps the preset on stage") {
    const std::string dir = FreshDir(SDFVJ_LIVE_OUT, "post-preset");
    const fs::path root = fs::path(dir) / "root";
    fs::create_directories(root);
    for (const char* sub : {"shaders", "presets", "mappings"})
        fs::copy(fs::path(SDFVJ_SOURCE_ROOT) / sub, root / sub, fs::copy_options::recursive);
    std::ofstream(root / "presets" / "split.json") << R"({"scene": "midi", "post": "rgb_split", "params": {"amount": 10}})";
    std::ofstream(root / "presets" / "broken.json") << "{\"scene\": \"midi\",\n \"post\": \"no_such_effect\"}";
    const std::string log = dir + "/live.log", params = dir + "/params.txt";
    const int port = FreeUdpPort();
    const pid_t pid = Spawn({SDFVJ_BIN, "live", "--preset", "split", "--size", "160x90", "--seconds", "4", "--path", "fragment",
                             "--osc-port", std::to_string(port), "--midi", "no-such-controller", "--log-params", params,
                             "--hide-overlay"},
                            log, {{"DISPLAY", Display()}, {"JACK_NO_START_SERVER", "1"}, {"SDFVJ_ROOT", root.string()}});
    REQUIRE(PollFor(20, [&] { return ReadText(log).find("post: rgb_split") != std::string::npos; }));
    REQUIRE(Run({"oscsend", "localhost", std::to_string(port), "/sdfvj/preset", "s", "broken"}, dir + "/oscsend.log", 10) == 0);
    REQUIRE(WaitExit(pid, 40) == 0);
    const std::string out = ReadText(log);
    INFO(out);
    CHECK(out.find("broken.json: post:") != std::string::npos);
    CHECK(out.find("keeping the current preset") != std::string::npos);
    const std::vector<Frame> frames = ReadParamLog(params);
    REQUIRE(!frames.empty());
    CHECK(frames.front().second.at("amount") == Approx(10.0f));   // the preset set the post input
    CHECK(frames.back().second.at("amount") == Approx(10.0f));
}

TEST_CASE("live isf scene: --scene x.fs runs an ISF generator in the window, its inputs answer OSC") {
    const std::string dir = FreshDir(SDFVJ_LIVE_OUT, "isf-scene");
    const std::string fs = dir + "/grey.fs";
    std::ofstream(fs) << R"(/*{
    "DESCRIPTION": "a flat grey of the input's level, for the live test",
    "ISFVSN": "2",
    "INPUTS": [{"NAME": "level", "TYPE": "float", "DEFAULT": 0.25, "MIN": 0.0, "MAX": 1.0}]
}*/
void main() { gl_FragColor = vec4(vec3(level), 1.0); }
)";
    LiveRun run("isf-scene-run", {"--scene", fs}, false);
    INFO(ReadText(run.log));
    REQUIRE(run.WaitForLog("OSC: listening on UDP port " + std::to_string(run.oscPort), 20));
    REQUIRE(run.WaitForLog("post: " + fs, 20));
    REQUIRE(run.WaitForFirstFrame(20));
    std::this_thread::sleep_for(std::chrono::milliseconds(800));
    run.Osc("/sdfvj/param/level", "f", "0.75");
    REQUIRE(run.Wait() == 0);
    const std::vector<Frame> frames = ReadParamLog(run.params);
    REQUIRE(frames.size() >= 3);
    CHECK(frames.front().second.at("level") == Approx(0.25f));
    CHECK(frames.back().second.at("level") == Approx(0.75f));
    // The last frame is the generator's flat grey at 0.75 (sRGB-free: 191 of 255, within 2).
    Image shot;
    REQUIRE(LoadPng(run.shot, &shot));
    REQUIRE(shot.width == kW);
    CHECK(MeanLuma(shot, 0, 0, 1, 1) == Approx(191.0).margin(2.0));
    CHECK(ReadText(run.log).find("error") == std::string::npos);
}

TEST_CASE("live envelope: oscsend /sdfvj/env/drop i 1 fires the scripted preset's envelope, 0 releases it") {
    // bulb_breath: power = 8 + 3 env_hit - 1.5 env_drop; drop attacks in 0.5 s, decays to 0.6.
    // A small frame: the envelope's peak (power < 7) lasts about 0.6 s, and the Mandelbulb on
    // llvmpipe beside a parallel test run once drew too few frames at 240x136 to land in it.
    LiveRun run("osc-env", {"--scene", "mandelbulb", "--preset", "bulb_breath", "--seconds", "6", "--size", "96x54"}, false);
    INFO(ReadText(run.log));
    REQUIRE(run.WaitForLog("OSC: listening on UDP port " + std::to_string(run.oscPort), 20));
    REQUIRE(run.WaitForFirstFrame(20));
    std::this_thread::sleep_for(std::chrono::milliseconds(800));
    run.Osc("/sdfvj/env/drop", "i", "1");
    std::this_thread::sleep_for(std::chrono::milliseconds(2000));
    run.Osc("/sdfvj/env/drop", "i", "0");
    REQUIRE(run.Wait() == 0);
    const std::string log = ReadText(run.log);
    CHECK(log.find("unknown address") == std::string::npos);
    std::vector<Frame> a = ReadParamLog(run.params);
    REQUIRE(a.size() >= 5);
    CHECK(a.front().second.at("power") == Approx(8.0f).margin(1e-3));
    float lowest = 99.0f;
    for (const Frame& f : a) lowest = std::min(lowest, f.second.at("power"));
    // The attack's peak: power 8 - 1.5 = 6.5, then the decay to sustain 0.6 (7.1) while held.
    CHECK(lowest < 7.0f);
    CHECK(lowest > 6.45f);
    // Released 1.5 s before the end, with a 1.5 s release: on its way back to 8.
    CHECK(a.back().second.at("power") > lowest + 0.2f);
}
