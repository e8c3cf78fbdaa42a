// Hot reload through the real pieces: files on disk, inotify, LiveProgram, llvmpipe.
// Each test works on a copy of shaders/ in a temp folder (SDFVJ_ROOT points there).
#include <catch2/catch.hpp>
#include <epoxy/gl.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <thread>

#include "gl_fixture.h"
#include "render/compile_worker.h"
#include "render/live_program.h"
#include "shader/watch.h"

using namespace sdfvj;
using namespace sdfvj::test;
namespace fs = std::filesystem;

namespace {

// A compile thread on a context of its own, set as PendingProgram's worker while it lives.
// binary = false: that context shares programs with the test's; true: the worker hands over
// program binaries instead.
struct WorkerOn {
    HeadlessContext shared;
    std::unique_ptr<CompileWorker> worker;
    explicit WorkerOn(bool binary = false) {
        RequireGl();
        std::string err;
        REQUIRE(shared.CreateShared(*TestContext(), &err, !binary));
        worker = std::make_unique<CompileWorker>([this] { return shared.MakeCurrent(); }, binary,
                                                 [this] { shared.ReleaseCurrent(); });
        REQUIRE(worker->Ok());
        PendingProgram::SetWorker(worker.get());
    }
    ~WorkerOn() {
        PendingProgram::SetWorker(nullptr);
        worker.reset();   // before the context it uses
    }
};

struct ReloadRig {
    fs::path root;
    FolderWatcher watcher;
    LiveProgram live;
    FrameRenderer fr;
    VariantKey key;

    explicit ReloadRig(const std::string& name) {
        RequireGl();
        root = fs::temp_directory_path() / ("sdfvj-reload-" + name + "-" + std::to_string(::getpid()));
        fs::remove_all(root);
        fs::create_directories(root);
        fs::copy(fs::path(SDFVJ_SOURCE_ROOT) / "shaders", root / "shaders", fs::copy_options::recursive);
        setenv("SDFVJ_ROOT", root.c_str(), 1);
        std::string err;
        for (const char* d : {"shaders/lib", "shaders/scenes", "shaders/render"})
            REQUIRE(watcher.Watch((root / d).string(), &err));
        // A scene of our own, so the edits below are known: a sphere whose radius and colour
        // come from an included helper file.
        Save("shaders/lib/test_helper.glsl", "float testRadius() { return 1.0f; }\n");
        Save("shaders/scenes/reloadme.glsl", SceneText("vec3(0.9f, 0.2f, 0.1f)"));
        REQUIRE(fr.Resize(64, 48, &err));
        key = VariantKey{(root / "shaders/scenes/reloadme.glsl").string(), EffectSet{}, RenderPath::Fragment};
        live.Request(key);
        live.Wait();
        INFO(live.Error());
        REQUIRE(live.Current() != nullptr);
        watcher.Poll();   // our own set-up writes are not edits
    }
    ~ReloadRig() {
        unsetenv("SDFVJ_ROOT");
        fs::remove_all(root);
    }
    static std::string SceneText(const std::string& colour) {
        return "/*{ \"NAME\": \"reloadme\", \"CAMERA\": {\"POSITION\": [0, 0, -4], \"TARGET\": [0, 0, 0]} }*/\n"
               "#include \"lib/test_helper.glsl\"\n"
               "vec4 map(vec3 p) {\n"
               "    return vec4(" + colour + ", length(p) - testRadius());\n"
               "}\n"
               "float sceneLipschitz() { return 1.0f; }\n";
    }
    // Saves like an editor does: write a temp file, rename it over the original.
    void Save(const std::string& rel, const std::string& text) {
        fs::path tmp = root / (rel + ".tmp~");
        std::ofstream(tmp) << text;
        fs::rename(tmp, root / rel);
    }
    Image Frame() {
        live.Update(watcher.Poll());
        if (live.Current()) {
            FrameInputs in;
            fr.Draw(*live.Current(), live.Scene(), in);
        }
        return Image{fr.Width(), fr.Height(), fr.ReadPixels()};
    }
    // Renders frames until the image differs from `before` (or a few seconds pass).
    int FramesUntilChange(const Image& before, Image* after) {
        for (int frame = 1; frame <= 300; ++frame) {
            *after = Frame();
            if (CompareImages(before, *after, 8).fractionOver > 0.01) return frame;
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        return -1;
    }
    // Renders frames until no compile is pending.
    void Settle() {
        for (int i = 0; i < 300 && (live.Pending() || i < 3); ++i) {
            Frame();
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
    }
};

}  // namespace

TEST_CASE("reload: an edited scene file shows within a few frames", "[reload]") {
    ReloadRig rig("edit");
    Image before = rig.Frame(), after;
    rig.Save("shaders/scenes/reloadme.glsl", ReloadRig::SceneText("vec3(0.1f, 0.3f, 0.9f)"));
    int frames = rig.FramesUntilChange(before, &after);
    INFO("frames until the new program showed: " << frames);
    CHECK(frames > 0);
    CHECK(rig.live.Error().empty());
    // The sphere turned from red to blue in the middle of the frame.
    const uint8_t* centre = &after.rgba[((size_t)24 * 64 + 32) * 4];
    CHECK(centre[2] > centre[0]);
}

TEST_CASE("reload: a broken save keeps the last good program and names file and line, a fix recovers", "[reload]") {
    ReloadRig rig("broken");
    Image good = rig.Frame();
    const int compiles = rig.live.CompilesStarted();

    // Broken in the scene file itself, line 4.
    rig.Save("shaders/scenes/reloadme.glsl",
             "/*{ \"NAME\": \"reloadme\", \"CAMERA\": {\"POSITION\": [0, 0, -4], \"TARGET\": [0, 0, 0]} }*/\n"
             "#include \"lib/test_helper.glsl\"\nvec4 map(vec3 p) {\n    return vec4(1.0f, 0.0f, 0.0f, fBx(p));\n}\n"
             "float sceneLipschitz() { return 1.0f; }\n");
    rig.Settle();
    INFO(rig.live.Error());
    CHECK(rig.live.CompilesStarted() > compiles);
    CHECK(rig.live.Error().find("shaders/scenes/reloadme.glsl:4:") != std::string::npos);
    Image during = rig.Frame();
    CHECK(CompareImages(good, during, 0).maxAbs == 0);   // frames keep coming from the old program

    // Broken inside the included file, line 2.
    rig.Save("shaders/scenes/reloadme.glsl", ReloadRig::SceneText("vec3(0.9f, 0.2f, 0.1f)"));
    rig.Save("shaders/lib/test_helper.glsl", "// helper\nfloat testRadius() { return 1.0f +; }\n");
    rig.Settle();
    INFO(rig.live.Error());
    CHECK(rig.live.Error().find("shaders/lib/test_helper.glsl:2:") != std::string::npos);
    CHECK(CompareImages(good, rig.Frame(), 0).maxAbs == 0);

    // Fixed: the error clears and the new radius shows.
    rig.Save("shaders/lib/test_helper.glsl", "// helper\nfloat testRadius() { return 1.4f; }\n");
    Image fixed;
    CHECK(rig.FramesUntilChange(good, &fixed) > 0);
    CHECK(rig.live.Error().empty());

    // A broken scene header is reported the same way and also keeps the picture.
    rig.Save("shaders/scenes/reloadme.glsl", "/*{ \"NAME\": \"reloadme\", \"INPUTS\": 7 }*/\n");
    rig.Settle();
    CHECK(rig.live.Error().find("reloadme.glsl:1: INPUTS is") != std::string::npos);
    CHECK(CompareImages(fixed, rig.Frame(), 0).maxAbs == 0);
}

TEST_CASE("reload: a no-op save compiles nothing, an included file rebuilds its owners", "[reload]") {
    ReloadRig rig("noop");
    Image before = rig.Frame();
    const int compiles = rig.live.CompilesStarted();
    rig.Save("shaders/scenes/reloadme.glsl", ReloadRig::SceneText("vec3(0.9f, 0.2f, 0.1f)"));   // same bytes
    rig.Save("shaders/lib/test_helper.glsl", "float testRadius() { return 1.0f; }\n");
    rig.Settle();
    CHECK(rig.live.CompilesStarted() == compiles);

    rig.Save("shaders/lib/test_helper.glsl", "float testRadius() { return 0.5f; }\n");
    Image after;
    CHECK(rig.FramesUntilChange(before, &after) > 0);
    CHECK(rig.live.CompilesStarted() == compiles + 1);
}

TEST_CASE("variant: switching effects compiles once, then comes from the cache", "[variant]") {
    ReloadRig rig("variants");
    VariantKey shadowed = rig.key;
    shadowed.effects.shadows = 2;
    shadowed.effects.ao = true;
    const int compiles = rig.live.CompilesStarted();
    rig.live.Request(shadowed);
    rig.Settle();
    CHECK(rig.live.CompilesStarted() == compiles + 1);
    CHECK(rig.live.Key() == shadowed);
    rig.live.Request(rig.key);      // back: cached, no compile
    rig.live.Request(shadowed);     // and again
    CHECK(rig.live.CompilesStarted() == compiles + 1);
    REQUIRE(rig.live.Current() != nullptr);
    auto active = rig.live.Current()->ActiveUniforms();
    CHECK(std::find(active.begin(), active.end(), "u_aoSamples") != active.end());
}

TEST_CASE("variant: the cache keeps the most recently used variants and rebuilds one it dropped", "[variant]") {
    // A show toggling effects for hours reaches many variants; each holds the driver's code.
    ReloadRig rig("variant-lru");
    rig.live.SetCacheLimit(2);
    VariantKey ao = rig.key, shadows = rig.key, fog = rig.key;
    ao.effects.ao = true;
    shadows.effects.shadows = 1;
    fog.effects.fog = !rig.key.effects.fog;
    for (const VariantKey* k : {&ao, &shadows}) {
        rig.live.Request(*k);
        rig.Settle();
    }
    CHECK(rig.live.CachedVariants() == 2);
    CHECK(!rig.live.IsCached(rig.key));      // the first, least recently used, went
    CHECK(rig.live.IsCached(ao));
    rig.live.Request(ao);                    // from the cache: now the most recent
    const int compiles = rig.live.CompilesStarted();
    rig.live.Request(fog);
    rig.Settle();
    CHECK(rig.live.CompilesStarted() == compiles + 1);
    CHECK(rig.live.CachedVariants() == 2);
    CHECK(rig.live.IsCached(ao));            // used after shadows, so shadows went
    CHECK(!rig.live.IsCached(shadows));
    REQUIRE(rig.live.Current() != nullptr);
    CHECK(rig.live.Key() == fog);
    rig.live.Request(rig.key);               // dropped: compiles again, and draws as it did
    rig.Settle();
    CHECK(rig.live.CompilesStarted() == compiles + 2);
    CHECK(rig.live.Error().empty());
    CHECK(rig.live.Key() == rig.key);
}

TEST_CASE("variant: a library save while an effect toggle compiles keeps the program on screen alive", "[variant]") {
    // Issue 10, defect 3: the reload evicted every owner of the saved file except the variant
    // asked for, so the program still on screen was deleted while the toggled variant compiled
    // on the compile thread (as in `live` on Mesa), and the next draw used freed memory.
    WorkerOn on;
    ReloadRig rig("toggle-save");
    Image before = rig.Frame();
    const unsigned onScreen = rig.live.Current()->Id();
    VariantKey toggled = rig.key;
    toggled.effects.ao = true;
    rig.live.Request(toggled);                 // compiles to the side; the old program stays up
    REQUIRE(rig.live.Pending());
    rig.Save("shaders/lib/test_helper.glsl", "float testRadius() { return 1.0f; } // saved\n");
    std::vector<std::string> changed;
    for (int i = 0; i < 200 && changed.empty(); ++i) {
        changed = rig.watcher.Poll();
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    REQUIRE(!changed.empty());
    rig.live.Update(changed);                  // the save arrives while the toggle compiles
    REQUIRE(rig.live.Pending());
    // The program on screen was not deleted. (glDeleteProgram only flags a program that is still
    // bound, so its delete status is what tells; the possibly freed C++ object is not read.)
    GLint deleted = GL_TRUE;
    glGetProgramiv(onScreen, GL_DELETE_STATUS, &deleted);
    CHECK(deleted == GL_FALSE);
    if (deleted == GL_FALSE) {
        REQUIRE(rig.live.Current() != nullptr);
        CHECK(rig.live.Current()->Id() == onScreen);
        FrameInputs in;
        rig.fr.Draw(*rig.live.Current(), rig.live.Scene(), in);
        CHECK(CompareImages(before, Image{rig.fr.Width(), rig.fr.Height(), rig.fr.ReadPixels()}, 0).maxAbs == 0);
    }
    rig.Settle();
    CHECK(rig.live.Error().empty());
    CHECK(rig.live.Key() == toggled);
}

namespace {
// binary = false: the worker's context shares programs with the test's context; true: it has
// its own context and hands over program binaries.
void WorkerReload(bool binary) {
    WorkerOn on(binary);
    ReloadRig rig(binary ? "worker-binary" : "worker");
    Image good = rig.Frame(), after;
    rig.Save("shaders/scenes/reloadme.glsl", ReloadRig::SceneText("vec3(0.1f, 0.3f, 0.9f)"));
    int frames = rig.FramesUntilChange(good, &after);
    INFO("frames until the new program showed: " << frames);
    CHECK(frames > 0);
    CHECK(rig.live.Error().empty());

    rig.Save("shaders/lib/test_helper.glsl", "// helper\nfloat testRadius() { return 1.0f +; }\n");
    rig.Settle();
    INFO(rig.live.Error());
    CHECK(rig.live.Error().find("shaders/lib/test_helper.glsl:2:") != std::string::npos);
    CHECK(CompareImages(after, rig.Frame(), 0).maxAbs == 0);
    // Undoing the broken save brings back the cached program and clears the error.
    rig.Save("shaders/lib/test_helper.glsl", "float testRadius() { return 1.0f; }\n");
    rig.Settle();
    CHECK(rig.live.Error().empty());
    rig.Save("shaders/lib/test_helper.glsl", "float testRadius() { return 0.6f; }\n");
    Image fixed;
    CHECK(rig.FramesUntilChange(after, &fixed) > 0);
    CHECK(rig.live.Error().empty());
}
}  // namespace

TEST_CASE("reload: on a compile thread, edits, errors and fixes behave the same and frames keep coming", "[reload]") {
    WorkerReload(false);
}

TEST_CASE("reload: a compile thread with its own context hands over program binaries that render the same", "[reload]") {
    WorkerReload(true);
}

// A compile frees tens of MB on llvmpipe, which glibc keeps mapped unless trimmed. The trim ran on
// the render thread after each build, holding the frame that showed it 8-22 ms; on a compile
// thread it runs there, once no compile came for half a second (not beside the frame that first
// draws the new program, which it slowed).
TEST_CASE("reload: on a compile thread the heap is trimmed there, after the build, while frames go on", "[reload]") {
    WorkerOn on;
    CompileWorker& worker = *on.worker;
    CHECK_FALSE(worker.TrimAfterJobs());
    ReloadRig rig("worker-trim");
    CHECK(worker.TrimAfterJobs());   // LiveProgram hands its trims to the compile thread
    Image good = rig.Frame(), after;
    const int trimsBefore = worker.Trims();
    rig.Save("shaders/scenes/reloadme.glsl", ReloadRig::SceneText("vec3(0.9f, 0.3f, 0.1f)"));
    REQUIRE(rig.FramesUntilChange(good, &after) > 0);
    int frames = 0;
    const auto t0 = std::chrono::steady_clock::now();
    while (worker.Trims() == trimsBefore && std::chrono::steady_clock::now() - t0 < std::chrono::seconds(5)) {
        rig.Frame();   // the show goes on meanwhile
        ++frames;
    }
    INFO("frames drawn while waiting for the trim: " << frames);
    CHECK(worker.Trims() == trimsBefore + 1);
    CHECK(frames > 0);
    CHECK(rig.live.Error().empty());
}
