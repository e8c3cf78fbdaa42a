// Loads a show sends its render processes (part of test_render_process, whose main makes this
// binary its own `render-server`): a quick tier's load whose optimized program is in the program
// cache shows that one and nothing follows; `live`'s servers send no quick tier for a program whose
// optimized build was on screen once the cache serves; a newer load waits for the build in flight
// instead of ending it before it was shown (a storm of pads and presets on 2 cores: docs/reliability.md);
// a spare makes its hand-over images for the show's size while it waits; the inputs a show streams
// to a build never block it, and the first frame is drawn with the last that went.
#include <catch2/catch.hpp>
#include <epoxy/gl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "app/live_servers.h"
#include "gl_fixture.h"
#include "render/program_cache.h"
#include "render/server_show.h"
#include "render_process_fixture.h"
#include "scene/scene.h"

using namespace sdfvj;
using namespace sdfvj::test;
namespace fs = std::filesystem;

namespace {

// The program cache on, in a folder of its own, for the servers spawned while it lives (they
// inherit the environment); the fixture's "cache off" after.
struct CacheOn {
    fs::path folder;
    bool binaries = false;   // the driver gives program binaries (Mesa: only with its disk cache on)
    explicit CacheOn(const std::string& name) {
        RequireGl();
        folder = fs::temp_directory_path() / ("sdfvj-loads-" + name + "-" + std::to_string(::getpid()));
        fs::remove_all(folder);
        setenv("XDG_CACHE_HOME", folder.c_str(), 1);
        setenv("SDFVJ_PROGRAM_CACHE", "1", 1);
        GLint formats = 0;
        glGetIntegerv(GL_NUM_PROGRAM_BINARY_FORMATS, &formats);
        binaries = formats > 0;
        if (!binaries) WARN("the driver gives no program binaries (Mesa with MESA_SHADER_CACHE_DISABLE): nothing to cache");
    }
    ~CacheOn() {
        setenv("SDFVJ_PROGRAM_CACHE", "0", 1);
        unsetenv("XDG_CACHE_HOME");
        std::error_code ec;
        fs::remove_all(folder, ec);
    }
};

// Polls until nothing builds (the optimized program on screen, or a failure), up to 120 s.
bool PollUntilSettled(ServerShow* show, std::string* error) {
    for (int i = 0; i < 60000; ++i) {
        show->Poll(error);
        if (!error->empty()) return false;
        if (!show->Building()) return true;
        ::usleep(2000);
    }
    return false;
}

}  // namespace

TEST_CASE("render process: a quick tier's load whose optimized program is in the program cache shows that program, and no optimized build follows", "[render_process]") {
    CacheOn cache("quick");
    if (!cache.binaries) return;
    SceneInfo scene;
    std::string error;
    REQUIRE(FindScene("midi", &scene, &error));
    ServerShow show(FrameTransport::Shm, false, true);   // tiered
    show.SetTiersInTurn(true);                           // the quick tier alone first, the optimized build once it is on screen
    const ServerLoad none{scene.path, false, EffectSet{}, RenderPath::Fragment, kW, kH};
    INFO(error);
    REQUIRE(show.Start(none, &error));
    CHECK(show.OnScreenQuick());   // nothing cached yet: the quick tier
    REQUIRE(PollUntilSettled(&show, &error));
    CHECK_FALSE(show.OnScreenQuick());   // its optimized program followed, and went to the cache
    CHECK_FALSE(show.Shown().back().fromCache);
    // Another variant, then the first again: its optimized program is in the cache now.
    REQUIRE(show.Load(ServerLoad{scene.path, false, scene.effects, RenderPath::Fragment, kW, kH}, &error));
    REQUIRE(PollUntilSettled(&show, &error));
    REQUIRE(show.Load(none, &error));
    CHECK(show.BuildingQuick());   // sent as a quick tier
    REQUIRE(PollUntilChange(&show, &error));
    const RenderProcess::Ready r = show.Shown().back();
    CHECK(r.optimized);
    CHECK(r.fromCache);
    CHECK_FALSE(show.OnScreenQuick());
    CHECK_FALSE(show.Building());   // no optimized build follows: it is on screen
    REQUIRE(show.Frame(Inputs(scene, 1.0)));
    CHECK(CompareImages(ReadTexture(show.Texture()), RenderScene("midi", EffectSet{}, RenderPath::Fragment, kW, kH, 1.0), 1).fractionOver == 0.0);
}

TEST_CASE("render process: live's servers send no quick tier for a program whose optimized build was on screen, once the cache serves", "[render_process]") {
    CacheOn cache("live");
    if (!cache.binaries) return;
    SceneInfo scene;
    std::string error;
    REQUIRE(FindScene("midi", &scene, &error));
    const VariantKey own{scene.path, scene.effects, RenderPath::Fragment}, none{scene.path, EffectSet{}, RenderPath::Fragment};
    LiveServers servers(true, false);   // tiered, as on NVIDIA
    INFO(error);
    REQUIRE(servers.Start(own, kW, kH, &error));
    std::vector<std::string> say;
    auto settle = [&](const VariantKey& key) {
        for (int i = 0; i < 60000; ++i) {
            servers.Update(key, {}, kW, kH, &say);
            if (!servers.Building() && servers.Key() == key && !servers.Servers().OnScreenQuick()) return true;
            ::usleep(2000);
        }
        return false;
    };
    servers.Update(none, {}, kW, kH, &say);
    CHECK(servers.Servers().BuildingQuick());   // a program not seen: its quick tier beside it
    REQUIRE(settle(none));
    // Back to the first variant, from the cache (its build put it there): the cache serves. Mesa
    // writes its own disk cache, which llvmpipe's program binaries lean on, on a thread of its own:
    // on CI's two loaded cores a load right after the store once found it unwritten and compiled.
    // So the two variants take turns until a load comes from the cache (a few turns at most).
    bool served = false;
    for (int turn = 0; turn < 4 && !served; ++turn) {
        if (turn > 0) {
            servers.Update(none, {}, kW, kH, &say);
            REQUIRE(settle(none));
        }
        servers.Update(own, {}, kW, kH, &say);
        REQUIRE(servers.Building());
        REQUIRE(settle(own));
        served = servers.Servers().Shown().back().fromCache;
    }
    REQUIRE(served);
    servers.Update(none, {}, kW, kH, &say);
    REQUIRE(servers.Building());
    CHECK_FALSE(servers.Servers().BuildingQuick());   // its optimized build was on screen: no quick tier
    REQUIRE(settle(none));
    CHECK(servers.Servers().Shown().back().fromCache);
}

TEST_CASE("render process: a newer load waits for the build in flight, which goes on screen, then the newest is sent", "[render_process]") {
    SceneInfo scene;
    std::string error;
    RequireGl();
    REQUIRE(FindScene("midi", &scene, &error));
    const VariantKey own{scene.path, scene.effects, RenderPath::Fragment}, none{scene.path, EffectSet{}, RenderPath::Fragment};
    EffectSet fog;
    fog.fog = true;
    const VariantKey fogOnly{scene.path, fog, RenderPath::Fragment};
    LiveServers servers(false, false);
    INFO(error);
    REQUIRE(servers.Start(own, kW, kH, &error));
    std::vector<std::string> say;
    servers.Update(none, {}, kW, kH, &say);   // sent at once: nothing in flight
    REQUIRE(servers.Building());
    REQUIRE(servers.Servers().BuildingLoad().effects == EffectSet{});
    // Two more asks while it builds (a pad hit twice): the one in flight goes on, the newest waits.
    servers.Update(own, {}, kW, kH, &say);
    servers.Update(fogOnly, {}, kW, kH, &say);
    CHECK(servers.Servers().BuildingLoad().effects == EffectSet{});
    bool noneShown = false;
    for (int i = 0; i < 60000 && !(servers.Key() == fogOnly && !servers.Building()); ++i) {
        servers.Update(fogOnly, {}, kW, kH, &say);
        noneShown = noneShown || servers.Key() == none;
        ::usleep(2000);
    }
    CHECK(noneShown);                     // the build in flight reached the screen
    CHECK(servers.Key() == fogOnly);      // then the newest asked for, not the one between
    CHECK_FALSE(servers.Building());
    int w = 0, h = 0;
    REQUIRE(servers.Frame(Inputs(scene, 1.0), &w, &h) != 0);
    const Image fogImage = RenderScene("midi", fog, RenderPath::Fragment, kW, kH, 1.0);
    CHECK(CompareImages(ReadTexture(servers.Servers().Texture()), fogImage, 1).fractionOver == 0.0);
}

TEST_CASE("render process: a spare makes its hand-over images for the show's size while it waits, so a load of that size only hands its first frame over, and a load of another size makes its own", "[render_process]") {
    const SceneInfo midi = ShippedScene("midi"), character = ShippedScene("character");
    std::string error;
    for (const bool ahead : {true, false}) {
        ServerShow show(FrameTransport::VkMemory, false, false);   // the GPU's images where the drivers can, else shared memory
        if (!ahead) show.SetServerEnv({"SDFVJ_SERVER_PREPARE_IMAGES=0"});
        INFO((ahead ? "made ahead" : "SDFVJ_SERVER_PREPARE_IMAGES=0") << ": " << error);
        REQUIRE(show.Start(ServerLoad{midi.path, true, {}, RenderPath::Fragment, kW, kH}, &error));
        CHECK_FALSE(show.Shown().back().imagesAhead);   // the first server was spawned for this load, told nothing before it
        auto loadOnASpare = [&](const SceneInfo& scene, int w, int h) {
            for (int i = 0; i < 30000 && show.SparesReady() == 0; ++i) ::usleep(2000);   // one that waited, as a save finds it
            REQUIRE(show.SparesReady() > 0);
            REQUIRE(show.Load(ServerLoad{scene.path, true, {}, RenderPath::Fragment, w, h}, &error));
            REQUIRE(PollUntilChange(&show, &error));
            REQUIRE(show.Frame(Inputs(scene, 1.0)));
            INFO(scene.name << " at " << w << "x" << h << ", " << FrameTransportName(show.Shown().back().transport));
            const Image want = RenderScene(scene.name, scene.effects, RenderPath::Fragment, w, h, 1.0);
            CHECK(CompareImages(ReadTexture(show.Texture(), w, h), want, 1).fractionOver == 0.0);
            return show.Shown().back();
        };
        // The spares were told kW x kH: a load of that size hands over in the images made ahead.
        CHECK(loadOnASpare(character, kW, kH).imagesAhead == ahead);
        // Another size: the spare's images are for the old one, so it makes its own, of the new size.
        CHECK_FALSE(loadOnASpare(midi, 2 * kW, kH + 16).imagesAhead);
        // And the spares started after that load were told its size.
        CHECK(loadOnASpare(character, 2 * kW, kH + 16).imagesAhead == ahead);
    }
}

TEST_CASE("render process: the inputs a show streams to a build stop at 16 KB unread, no send waits for the build, and its first frame is drawn with the last that went, shared memory too", "[render_process]") {
    const SceneInfo midi = ShippedScene("midi"), character = ShippedScene("character");
    std::string error;
    auto timeOf = [](uint32_t seq) { return 0.5 + 0.05 * seq; };
    {
        RenderProcess proc;   // shared memory: the frame reaches the texture only when copied in
        REQUIRE(proc.Start(&error));
        REQUIRE(proc.Load(ServerLoad{character.path, true, {}, RenderPath::Fragment, kW, kH}, FrameTransport::Shm));
        // The server reads nothing while it starts and builds (seconds on llvmpipe): the show's sends
        // pile up in the socket until the cap, and none of them waits.
        int tried = 0;
        double longestMs = 0;
        for (bool sent = true; sent && tried < 100000; ++tried) {
            const auto t0 = std::chrono::steady_clock::now();
            sent = proc.SendInputsOfNow(Inputs(character, timeOf(proc.LastInputsSent() + 1)));
            longestMs = std::max(longestMs, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
        }
        INFO(tried << " sends tried, " << proc.LastInputsSent() << " went, the longest " << longestMs << " ms");
        CHECK(tried < 100000);                   // the cap stopped them
        CHECK(proc.LastInputsSent() >= 10);      // 16 KB of the socket's memory: some 20 frames' inputs
        CHECK(longestMs < 50.0);                 // a send that waited would wait for the build
        RenderProcess::Ready ready;
        bool answered = false;
        for (int i = 0; i < 1200 && !answered; ++i) answered = proc.PollReady(&ready, 100);
        REQUIRE(answered);
        REQUIRE(ready.ok);
        CHECK(ready.firstSeq == proc.LastInputsSent());   // every one read after the build, the last drawn
        REQUIRE(proc.ShowFirstFrame());
        const Image want = RenderScene("character", character.effects, RenderPath::Fragment, kW, kH, timeOf(ready.firstSeq));
        CHECK(CompareImages(ReadTexture(proc.Texture()), want, 1).fractionOver == 0.0);
        CHECK(CompareImages(ReadTexture(proc.Texture()), RenderScene("character", character.effects, RenderPath::Fragment, kW, kH, timeOf(1)), 1)
                  .fractionOver > 0.0);   // not the first inputs: the times differ on screen
    }
    // A show on shared memory swaps in the frame that reads the answer too, with that frame's image.
    ServerShow show(FrameTransport::Shm, true, false);
    REQUIRE(show.Start(ServerLoad{midi.path, true, {}, RenderPath::Fragment, kW, kH}, &error));
    double time = 1.0;
    auto frame = [&](const SceneInfo& scene) {
        const bool swapped = show.Poll(&error);
        REQUIRE(show.Frame(Inputs(scene, time)));
        ReadFramebufferImage(show.ReadFramebuffer());
        show.AfterRead(Inputs(scene, time));
        show.FrameDone();
        ::usleep(100000);
        return swapped;
    };
    for (int i = 0; i < 30 && show.SparesReady() == 0; ++i) frame(midi), time += 0.25;
    REQUIRE(show.Load(ServerLoad{character.path, true, {}, RenderPath::Fragment, kW, kH}, &error));
    bool swapped = false;
    double swapTime = 0;
    for (int i = 0; i < 600 && !swapped; ++i) swapTime = time, swapped = frame(character), time += 0.25;
    REQUIRE(swapped);
    INFO("polls from the answer to the swap: " << show.LastSwapPolls());
    CHECK(show.LastSwapPolls() <= 1);
    const Image want = RenderScene("character", character.effects, RenderPath::Fragment, kW, kH, swapTime - 0.25);
    CHECK(CompareImages(ReadFramebufferImage(show.ReadFramebuffer()), want, 1).fractionOver == 0.0);
}
