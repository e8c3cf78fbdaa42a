// Reloads measured as a performer sees them, on llvmpipe: every save is a source no cache has
// seen (a constant nudged by a per-run nonce), compiled on the compile worker as `live` does on
// Mesa. Frame times are compared with the compile's own duration (a ratio, never a time: a
// loaded machine slows both alike), and the tiered compile's hand-over is checked image to image.
#include <catch2/catch.hpp>
#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "gl_fixture.h"
#include "render/compile_worker.h"
#include "render/live_program.h"
#include "shader/literals.h"

using namespace sdfvj;
using namespace sdfvj::test;
namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

double MsSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

// A copy of shaders/ in a temp folder, a compile worker on a shared context (live's set-up on
// Mesa) and a LiveProgram showing `scene`.
struct WorkerRig {
    fs::path root, sceneFile;
    std::string original;
    HeadlessContext shared;
    std::unique_ptr<CompileWorker> worker;
    LiveProgram live;
    FrameRenderer fr;
    VariantKey key;
    uint64_t nonce;

    WorkerRig(const std::string& name, const std::string& scene, bool tiered, bool literalTier = false) {
        RequireGl();
        nonce = (uint64_t)Clock::now().time_since_epoch().count();
        root = fs::temp_directory_path() / ("sdfvj-tiered-" + name + "-" + std::to_string(::getpid()));
        fs::remove_all(root);
        fs::create_directories(root);
        fs::copy(fs::path(SDFVJ_SOURCE_ROOT) / "shaders", root / "shaders", fs::copy_options::recursive);
        setenv("SDFVJ_ROOT", root.c_str(), 1);
        sceneFile = root / "shaders" / "scenes" / (scene + ".glsl");
        std::ifstream in(sceneFile);
        std::stringstream ss;
        ss << in.rdbuf();
        original = ss.str();
        std::string err;
        REQUIRE(shared.CreateShared(*TestContext(), &err, true));
        worker = std::make_unique<CompileWorker>([this] { return shared.MakeCurrent(); }, false,
                                                 [this] { shared.ReleaseCurrent(); });
        REQUIRE(worker->Ok());
        PendingProgram::SetWorker(worker.get());
        live.SetTiered(tiered);
        live.SetLiteralTier(literalTier);
        REQUIRE(fr.Resize(64, 48, &err));
        Save(0);
        key = VariantKey{sceneFile.string(), EffectSet{}, RenderPath::Fragment};
        live.Request(key);
        live.Wait();
        INFO(live.Error());
        REQUIRE(live.Current() != nullptr);
    }
    ~WorkerRig() {
        PendingProgram::SetWorker(nullptr);
        worker.reset();
        unsetenv("SDFVJ_ROOT");
        fs::remove_all(root);
    }
    // Saves the scene with its first constant after the header nudged: a source no cache holds.
    void Save(int round) {
        bool found = false;
        const std::string text = NudgeFirstConstant(original, 1e-9 * (double)(1 + (nonce + (uint64_t)round) % 999999), &found);
        REQUIRE(found);
        std::ofstream(sceneFile) << text;
    }
    void SaveText(const std::string& text) { std::ofstream(sceneFile) << text; }
    // One frame as live draws it: reload step, draw, wait for the pixels. Returns its wall time.
    double Frame(bool* swapped, bool saved = false) {
        const auto t0 = Clock::now();
        *swapped = live.Update(saved ? std::vector<std::string>{sceneFile.string()} : std::vector<std::string>{});
        FrameInputs in;
        fr.Draw(*live.Current(), live.Scene(), in);
        glFinish();
        const double ms = MsSince(t0);
        // Paced like a 100 Hz display: a loop drawing flat out would starve the compile of CPU.
        if (ms < 10) std::this_thread::sleep_for(std::chrono::microseconds((int)((10 - ms) * 1000)));
        return ms;
    }
    Image Pixels() { return Image{fr.Width(), fr.Height(), fr.ReadPixels()}; }
};

}  // namespace

TEST_CASE("reload: on llvmpipe no frame waits for the compile (longest frame well under the compile)", "[reload][tiered]") {
    WorkerRig rig("nowait", "midi", false);
    bool swapped = false;
    std::vector<double> steady;
    for (int i = 0; i < 10; ++i) steady.push_back(rig.Frame(&swapped));
    const double steadyMedian = MedianMs(steady);

    // Three saves; the median ratio is asserted. Mesa writes its disk cache from an idle-priority
    // thread, and now and then (about 1 reload in 10 on a loaded 2-core machine) the render
    // context looks the worker's JIT up before it is written and JITs itself: that reload shows
    // in the printout and in docs/performance.md, a systematic stall fails the median.
    std::vector<double> ratios;
    for (int round = 1; round <= 3; ++round) {
        rig.Save(round);
        std::vector<double> frames;
        const auto saved = Clock::now();
        swapped = false;
        while (!swapped && MsSince(saved) < 60000) frames.push_back(rig.Frame(&swapped, frames.empty()));
        REQUIRE(swapped);
        REQUIRE(rig.live.Error().empty());
        // The first frame drawn with the new program counts too: a JIT there would be a stall.
        const double compileMs = rig.live.Current()->Origin().buildMs;
        const double longest = *std::max_element(frames.begin(), frames.end());
        std::printf("reload on llvmpipe: compile %.0f ms on the worker, save -> screen %.0f ms, %zu frames, "
                    "longest %.1f ms (frame %zu, the last draws the new program), steady median %.1f ms\n",
                    compileMs, MsSince(saved), frames.size(), longest,
                    (size_t)(std::max_element(frames.begin(), frames.end()) - frames.begin()) + 1, steadyMedian);
        CHECK(frames.size() >= 3);
        ratios.push_back(longest / std::max(compileMs, 1.0));
    }
    GLint binaryFormats = 0;
    glGetIntegerv(GL_NUM_PROGRAM_BINARY_FORMATS, &binaryFormats);
    if (IsSoftwareRenderer() && binaryFormats == 0) {
        // Mesa with MESA_SHADER_CACHE_DISABLE: llvmpipe's shaders are per context, so the render
        // context JITs the new program at its first draw whatever the worker primed; the worker's
        // JIT reaches it only through Mesa's disk cache (docs/performance.md, reload).
        WARN("Mesa's disk cache is off: the first draw of a new program JITs on the render thread; not asserted");
        return;
    }
    INFO("longest frame / compile, per save: " << ratios[0] << ", " << ratios[1] << ", " << ratios[2]);
    CHECK(MedianMs(ratios) < 0.25);
}

TEST_CASE("tiered: the quick tier shows first, then the optimized program takes over with the same image", "[tiered]") {
    WorkerRig rig("tiers", "mandelbulb", true);
    bool swapped = false;
    rig.Frame(&swapped);
    rig.Save(1);
    bool sawQuick = false;
    Image quick;
    const auto saved = Clock::now();
    rig.Frame(&swapped, true);
    while (rig.live.Pending() && MsSince(saved) < 60000) {
        rig.Frame(&swapped);
        if (swapped && rig.live.Current()->QuickTier() && !sawQuick) {
            sawQuick = true;
            quick = rig.Pixels();
        }
    }
    REQUIRE(!rig.live.Pending());
    CHECK(rig.live.Error().empty());
    CHECK(sawQuick);
    REQUIRE(rig.live.Current() != nullptr);
    CHECK_FALSE(rig.live.Current()->QuickTier());
    if (sawQuick) {
        // Mesa ignores the NVIDIA hint, so the tiers are the same program here: exact. (On the
        // NVIDIA H200 the issue measured 45 of 518,400 pixels off by 1/255.)
        const ImageDiff d = CompareImages(quick, rig.Pixels(), 1);
        CHECK(d.maxAbs <= 1);
        CHECK(d.fractionOver == 0.0);
    }
}

TEST_CASE("reload: NudgeFirstConstant changes the first literal in a function body, not comments or names", "[tiered]") {
    bool found = false;
    const std::string scene = "/*{ \"NAME\": \"x\", \"DEFAULT\": 1.0 }*/\n// 2.5f in a comment\nconst float a = 3.0f;\n"
                              "vec4 map(vec3 p) { /* 4.0f */ float v2 = p.x * 0.25f; return vec4(1.0f); }\n";
    const std::string out = NudgeFirstConstant(scene, 0.000123, &found);
    CHECK(found);
    CHECK(out.find("p.x * (0.25f+0.000123000f);") != std::string::npos);
    CHECK(out.find("3.0f;") != std::string::npos);
    NudgeFirstConstant("vec4 map(vec3 p) { return vec4(1); }", 0.1, &found);
    CHECK_FALSE(found);
}

TEST_CASE("tiered: the quick tier's source has the NVIDIA hint right after #version, no cone pre-pass, the one-site renderer and QUICK_TIER for the scene", "[tiered]") {
    const std::string text = "#version 450 core\n#define X 1\n#line 1 1\nvoid main() {}\n";
    if (QuickTierOneSite()) {   // the default
        CHECK(QuickTierText(text) == "#version 450 core\n#pragma optionNV(unroll none)\n#define CONE_PREPASS 0\n#define ONE_SITE 1\n"
                                     "#define QUICK_TIER 1\n#define X 1\n#line 1 1\nvoid main() {}\n");
    } else {   // SDFVJ_QUICK_ONE_SITE=0 (ctest tiered_inline_none)
        CHECK(QuickTierText(text) ==
              "#version 450 core\n#pragma optionNV(inline none)\n#define CONE_PREPASS 0\n#define QUICK_TIER 1\n#define X 1\n#line 1 1\nvoid main() {}\n");
    }
    CHECK(QuickTierText("no version line") == "no version line");
}

TEST_CASE("literal tier: a save that only retunes numbers is on screen in its first reload step, and the optimized program follows with the same image", "[tiered][literals]") {
    WorkerRig rig("literals", "midi", false, true);
    rig.SaveText(rig.original);   // the scene as shipped (the rig starts from a nudged copy)
    rig.live.Update({rig.sceneFile.string()});
    REQUIRE(rig.live.WaitLiteralTier());
    bool swapped = false;
    rig.Frame(&swapped);
    const Image before = rig.Pixels();
    const int compiles = rig.live.CompilesStarted();

    // The sphere's colour and the box's place: numbers only, so the lifted skeleton is unchanged.
    std::string text = rig.original;
    for (auto [from, to] : {std::pair<std::string, std::string>{"vec4(0.95f, 0.30f, 0.12f,", "vec4(0.10f, 0.30f, 0.95f,"},
                           {"vec3(0.75f, -0.1f, 0.0f)", "vec3(0.95f, -0.3f, 0.0f)"}}) {
        const size_t at = text.find(from);
        REQUIRE(at != std::string::npos);
        text.replace(at, from.size(), to);
    }
    REQUIRE(LiftLiterals(text).text == LiftLiterals(rig.original).text);
    rig.SaveText(text);
    rig.Frame(&swapped, true);
    CHECK(swapped);
    REQUIRE(rig.live.Current() != nullptr);
    CHECK(rig.live.Current()->Origin().literalTier);
    CHECK(rig.live.LiteralSwaps() == 1);
    CHECK(rig.live.Error().empty());
    const Image retuned = rig.Pixels();
    // A person sees the edit: a blue sphere where the orange one was.
    CHECK(CompareImages(before, retuned, 8).fractionOver > 0.01);

    rig.live.Wait();   // the optimized program of the same save
    CHECK(rig.live.CompilesStarted() == compiles + 1);
    rig.Frame(&swapped);
    REQUIRE(rig.live.Current() != nullptr);
    CHECK_FALSE(rig.live.Current()->QuickTier());
    // Same numbers, folded by the compiler or read from uniforms: within the accuracy report's 8/255.
    const ImageDiff d = CompareImages(retuned, rig.Pixels(), 8);
    INFO("retuned vs optimized: max " << d.maxAbs << ", mean " << d.meanAbs << ", over 8/255 " << d.fractionOver);
    CHECK(d.fractionOver < 0.001);
    CHECK(d.meanAbs < 0.1);

    // A structural edit (the nudge wraps a literal in a sum) is not a retune: it compiles as before.
    rig.Save(7);
    rig.Frame(&swapped, true);
    CHECK(rig.live.LiteralSwaps() == 1);
    rig.live.Wait();
    CHECK(rig.live.Error().empty());
}


TEST_CASE("prefetch: variants built ahead are on screen at once when asked for, and a save drops them", "[tiered][prefetch]") {
    WorkerRig rig("prefetch", "midi", false);
    bool swapped = false;
    rig.Frame(&swapped);
    const Image plain = rig.Pixels();
    VariantKey withAo = rig.key, withShadows = rig.key;
    withAo.effects.ao = true;
    withShadows.effects.shadows = 2;
    rig.live.Prefetch({withAo, withShadows, rig.key});   // the variant on screen is not built again
    CHECK(rig.live.PrefetchQueued() == 2);
    const auto t0 = Clock::now();
    while (rig.live.PrefetchQueued() > 0 && MsSince(t0) < 60000) rig.Frame(&swapped);
    REQUIRE(rig.live.PrefetchQueued() == 0);
    CHECK(rig.live.Prefetched() == 2);
    CHECK(rig.live.IsCached(withAo));
    CHECK(rig.live.IsCached(withShadows));
    CHECK(rig.live.Current()->Source().hash != 0);
    // An effect pad hit: the variant is on screen in that call, nothing compiles.
    const int compiles = rig.live.CompilesStarted();
    rig.live.Request(withShadows);
    CHECK_FALSE(rig.live.Pending());
    CHECK(rig.live.CompilesStarted() == compiles);
    rig.Frame(&swapped);
    CHECK(rig.live.Key() == withShadows);
    // A person sees the shadows: the frame is not the unshadowed one.
    CHECK(CompareImages(plain, rig.Pixels(), 8).fractionOver > 0.005);
    // A save of the scene drops the variants built from the old text.
    rig.Save(5);
    rig.Frame(&swapped, true);
    CHECK_FALSE(rig.live.IsCached(withAo));
    rig.live.Wait();
    CHECK(rig.live.Error().empty());
}

TEST_CASE("evaluator tier: a structural save is on screen in its first reload step with no build, and the optimized program follows with the same image", "[tiered][evaluator]") {
    WorkerRig rig("evaluator", "midi", false);
    rig.SaveText(rig.original);
    rig.live.Update({rig.sceneFile.string()});
    rig.live.SetEvaluatorTier(true);
    INFO(rig.live.EvaluatorError());
    REQUIRE(rig.live.WaitEvaluatorTier());
    bool swapped = false;
    rig.Frame(&swapped);
    const Image before = rig.Pixels();
    const int compiles = rig.live.CompilesStarted();

    // A structural edit inside a helper (midiBlob): the box becomes a sphere, the torus goes.
    std::string text = rig.original;
    for (auto [from, to] : {std::pair<std::string, std::string>{"fRoundBox(pTranslate(q, vec3(0.75f, -0.1f, 0.0f)), vec3(0.4f), 0.05f)",
                                                                "fSphere(pTranslate(q, vec3(0.75f, 0.1f, 0.0f)), 0.5f)"},
                           {"res = fOpUnionSmoothColor(res, vec4(0.95f, 0.80f, 0.15f,", "if (u_time < -1.0f) res = fOpUnionSmoothColor(res, vec4(0.95f, 0.80f, 0.15f,"}}) {
        const size_t at = text.find(from);
        REQUIRE(at != std::string::npos);
        text.replace(at, from.size(), to);
    }
    rig.SaveText(text);
    rig.Frame(&swapped, true);
    CHECK(swapped);
    REQUIRE(rig.live.Current() != nullptr);
    CHECK(rig.live.Current()->Origin().evaluatorTier);
    CHECK(rig.live.EvaluatorSwaps() == 1);
    CHECK(rig.live.Error().empty());
    const Image evaluated = rig.Pixels();
    // A person sees the edit: a sphere where the box was, no torus.
    CHECK(CompareImages(before, evaluated, 8).fractionOver > 0.01);

    rig.live.Wait();   // the optimized program of the same save
    CHECK(rig.live.CompilesStarted() == compiles + 1);
    rig.Frame(&swapped);
    REQUIRE(rig.live.Current() != nullptr);
    CHECK_FALSE(rig.live.Current()->QuickTier());
    // The same field, interpreted or compiled (and the one-site renderer): within the accuracy report's 8/255.
    const ImageDiff d = CompareImages(evaluated, rig.Pixels(), 8);
    INFO("evaluated vs optimized: max " << d.maxAbs << ", mean " << d.meanAbs << ", over 8/255 " << d.fractionOver);
    CHECK(d.fractionOver < 0.005);
    CHECK(d.meanAbs < 0.5);

    // A save that changes the header (a new input) changes the evaluator program: it compiles as before.
    std::string header = text;
    const size_t at = header.find("{\"NAME\": \"spin\"");
    REQUIRE(at != std::string::npos);
    header.insert(at, "{\"NAME\": \"extra\", \"TYPE\": \"float\", \"DEFAULT\": 0.5, \"MIN\": 0.0, \"MAX\": 1.0},\n    ");
    rig.SaveText(header);
    rig.Frame(&swapped, true);
    CHECK(rig.live.EvaluatorSwaps() == 1);
    rig.live.Wait();
    CHECK(rig.live.Error().empty());
}
