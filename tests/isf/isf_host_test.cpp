// IsfHost on llvmpipe: a post chain built and first drawn in a context of its own while the
// render thread keeps drawing the chain on screen; broken saves keep each stage's last good file;
// feedback survives a rebuild.
#include <catch2/catch.hpp>
#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <thread>
#include <cstdlib>
#include <cmath>
#include <fstream>
#include <iterator>
#include <set>

#include "isf/isf_host.h"
#include "render/render.h"
#include "isf_test_util.h"

using namespace sdfvj;
using namespace sdfvj::isftest;

namespace {

constexpr int kW = 64, kH = 36;

void WriteText(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

IsfFile Parse(const std::string& path) {
    IsfFile f;
    std::string error;
    if (!LoadIsfFile(path, &f, &error)) FAIL(error);
    return f;
}

// A filter that draws `rgb` over a black input, with `taps` reads of the input: enough code that
// llvmpipe's compile at the first draw takes tens of milliseconds.
std::string Tint(const std::string& rgb, int taps) {
    std::string s = "/*{ \"ISFVSN\": \"2.0\", \"INPUTS\": [{\"NAME\": \"inputImage\", \"TYPE\": \"image\"}] }*/\n"
                    "void main() {\n    vec4 sum = vec4(0.0);\n";
    for (int i = 0; i < taps; ++i)
        s += "    sum += IMG_NORM_PIXEL(inputImage, isf_FragNormCoord + vec2(" + std::to_string(0.001 * i) + ", " +
             std::to_string(0.002 * (i % 7)) + ")) * " + std::to_string(1.0 + 0.01 * i) + ";\n";
    // A text no earlier run compiled, so the drivers' disk caches cannot serve it.
    static const long long run = std::chrono::steady_clock::now().time_since_epoch().count();
    return s + "    gl_FragColor = vec4(" + rgb + ", 1.0) + sum * 0.001;\n}\n// run " + std::to_string(run) + "\n";
}

// A filter that multiplies its input by `rgb`.
std::string Multiply(const std::string& rgb) {
    return "/*{ \"ISFVSN\": \"2.0\", \"INPUTS\": [{\"NAME\": \"inputImage\", \"TYPE\": \"image\"}] }*/\n"
           "void main() { gl_FragColor = IMG_THIS_PIXEL(inputImage) * vec4(" + rgb + ", 1.0); }\n";
}

// The test thread's context and two that share objects with it, for an IsfHost of its own.
struct Gl {
    HeadlessContext& main = MainContext();
    HeadlessContext a, b;
    Gl() {
        std::string error;
        REQUIRE(a.CreateShared(main, &error, true));
        REQUIRE(b.CreateShared(main, &error, true));
        REQUIRE(main.MakeCurrent());
    }
    ~Gl() { main.MakeCurrent(); }
    std::array<IsfHostContext, 2> Own() {
        auto hooks = [](HeadlessContext& c) { return IsfHostContext{[&c] { return c.MakeCurrent(); }, [&c] { c.ReleaseCurrent(); }}; };
        return {hooks(a), hooks(b)};
    }
};

struct Px {
    int r = 0, g = 0, b = 0;
};

// One frame on the render thread: the chain over `input`, read back; its time in ms.
struct Frames {
    IsfHost& host;
    unsigned input;
    IsfFrameInputs in;
    double Draw(Px* px) {
        const auto t = std::chrono::steady_clock::now();
        const unsigned out = host.Render(input, kW, kH, in);
        const Img img = ReadBack(out, kW, kH);
        *px = {img.At(kW / 2, kH / 2, 0), img.At(kW / 2, kH / 2, 1), img.At(kW / 2, kH / 2, 2)};
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
    }
    // Frames until a build finishes (at most 30 s); the longest frame meanwhile and their count.
    // pauseMs: a pause after each frame (a bound on their count however long a busy machine builds).
    IsfHost::Done UntilBuilt(double* longest = nullptr, int* count = nullptr, std::vector<Px>* seen = nullptr, int pauseMs = 0) {
        IsfHost::Done done;
        const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(30);
        while (!host.Poll(&done)) {
            if (std::chrono::steady_clock::now() > end) FAIL("the build did not finish in 30 s");
            Px px;
            const double ms = Draw(&px);
            if (longest) *longest = std::max(*longest, ms);
            if (count) ++*count;
            if (seen) seen->push_back(px);
            if (pauseMs > 0) std::this_thread::sleep_for(std::chrono::milliseconds(pauseMs));
        }
        return done;
    }
};

bool Is(const Px& p, int r, int g, int b) { return std::abs(p.r - r) <= 1 && std::abs(p.g - g) <= 1 && std::abs(p.b - b) <= 1; }

// A white kW x kH input.
unsigned White() {
    return MakeTexture(kW, kH, [](int, int) { return std::array<uint8_t, 4>{255, 255, 255, 255}; });
}

// The output textures `frames` frames of the chain at w x h return: its targets, seen from outside.
std::set<unsigned> Outputs(IsfHost& host, unsigned input, int w, int h, const IsfFrameInputs& in, int frames) {
    std::set<unsigned> seen;
    for (int i = 0; i < frames; ++i) seen.insert(host.Render(input, w, h, in));
    glFinish();
    return seen;
}

}  // namespace

TEST_CASE("isf host: a saved effect is built and first drawn in a context of its own so no frame waits for its compile", "[isf][gl]") {
    Gl gl;
    const std::string path = TempDir() + "/host_tint.fs";
    WriteText(path, Tint("1.0, 0.0, 0.0", 48));
    const unsigned input = MakeTexture(kW, kH, [](int, int) { return std::array<uint8_t, 4>{0, 0, 0, 255}; });
    {
        IsfHost host(gl.Own(), IsfDrawIn::OwnContexts);   // drawn there: on llvmpipe no frame compiles
        REQUIRE(host.OwnContexts());
        Frames f{host, input, {}};
        host.Request({Parse(path)}, kW, kH);
        IsfHost::Done first = f.UntilBuilt();
        REQUIRE(first.adopted);
        Px px;
        f.Draw(&px);
        CHECK(Is(px, 255, 0, 0));

        // A save: a new program (green). The frames drawn while it builds show the red one and
        // none of them waits for the build (a ratio of the build's own time, so a slow machine
        // does not fail it: drawn in the render thread's context the build holds its frame whole).
        WriteText(path, Tint("0.0, 1.0, 0.0", 48));
        std::vector<std::string> errors;
        REQUIRE(host.Reload(&errors));
        CHECK(errors.empty());
        double longest = 0.0;
        int during = 0;
        std::vector<Px> seen;
        const IsfHost::Done done = f.UntilBuilt(&longest, &during, &seen);
        REQUIRE(done.adopted);
        CHECK(done.errors.empty());
        f.Draw(&px);
        CHECK(Is(px, 0, 255, 0));
        INFO("build and first draw " << done.buildMs << " ms on the worker; " << during << " frames meanwhile, the longest " << longest << " ms");
        REQUIRE(done.buildMs > 20.0);   // the test effect is heavy enough to measure against
        CHECK(during >= 2);
        CHECK(longest < 0.5 * done.buildMs);
        CHECK(std::count_if(seen.begin(), seen.end(), [](const Px& p) { return !Is(p, 255, 0, 0); }) == 0);
    }
    {
        // Without contexts of its own the same save holds the frame that asks for it.
        IsfHost host;
        REQUIRE_FALSE(host.OwnContexts());
        Frames f{host, input, {}};
        WriteText(path, Tint("0.0, 0.0, 1.0", 48));
        host.Request({Parse(path)}, kW, kH);
        REQUIRE(f.UntilBuilt().adopted);
        WriteText(path, Tint("1.0, 1.0, 0.0", 48));
        std::vector<std::string> errors;
        const auto t = std::chrono::steady_clock::now();
        REQUIRE(host.Reload(&errors));
        IsfHost::Done done;
        REQUIRE(host.Poll(&done));
        Px px;
        f.Draw(&px);
        const double frameMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
        CHECK(Is(px, 255, 255, 0));
        INFO("build " << done.buildMs << " ms, the frame " << frameMs << " ms");
        CHECK(frameMs >= done.buildMs);
    }
    DeleteTexture(input);
}

TEST_CASE("isf host: a broken save keeps its stage's last good file and a save of the GLSL on screen builds nothing", "[isf][gl]") {
    const IsfDrawIn drawIn = GENERATE(IsfDrawIn::OwnContexts, IsfDrawIn::RenderThread);
    INFO((drawIn == IsfDrawIn::OwnContexts ? "drawn in its own contexts" : "drawn by the render thread"));
    Gl gl;
    const std::string first = TempDir() + "/host_first.fs", second = TempDir() + "/host_second.fs";
    const std::string tint = Tint("1.0, 0.5, 1.0", 4);
    WriteText(first, tint);
    WriteText(second, Multiply("1.0, 1.0, 0.5"));
    const unsigned input = MakeTexture(kW, kH, [](int, int) { return std::array<uint8_t, 4>{0, 0, 0, 255}; });
    {
        IsfHost host(gl.Own(), drawIn);
        Frames f{host, input, {}};
        host.Request({Parse(first), Parse(second)}, kW, kH);
        REQUIRE(f.UntilBuilt().adopted);
        Px px;
        f.Draw(&px);
        CHECK(Is(px, 255, 128, 128));
        const int built = host.ChainsBuilt();

        // A header cut in half: its file and line, nothing built, the chain on screen draws on.
        WriteText(first, "/*{ \"INPUTS\": [\n");
        std::vector<std::string> errors;
        CHECK_FALSE(host.Reload(&errors));
        REQUIRE(errors.size() == 1);
        CHECK(errors[0].find("host_first.fs:") != std::string::npos);
        f.Draw(&px);
        CHECK(Is(px, 255, 128, 128));
        // The last good file put back: its GLSL is the program's, nothing is built.
        WriteText(first, tint);
        errors.clear();
        CHECK_FALSE(host.Reload(&errors));
        CHECK(errors.empty());
        CHECK(host.ChainsBuilt() == built);
        CHECK_FALSE(host.Busy());

        // A GLSL error in the first stage and a new factor in the second, saved together: the
        // second's change goes on screen, the first keeps its last good program.
        WriteText(first, "/*{ \"ISFVSN\": \"2.0\", \"INPUTS\": [{\"NAME\": \"inputImage\", \"TYPE\": \"image\"}] }*/\n"
                         "void main() {\n    gl_FragColor = undeclaredThing;\n}\n");
        WriteText(second, Multiply("0.5, 1.0, 1.0"));
        errors.clear();
        REQUIRE(host.Reload(&errors));
        CHECK(errors.empty());   // both parse: the compile error comes from the build
        const IsfHost::Done done = f.UntilBuilt();
        REQUIRE(done.adopted);
        REQUIRE(done.errors.size() == 1);
        CHECK(done.errors[0].find("host_first.fs:3:") != std::string::npos);
        f.Draw(&px);
        CHECK(Is(px, 128, 128, 255));
        // What the next save edits is the stage's last good file, not the broken one.
        WriteText(TempDir() + "/host_good.fs", tint);
        CHECK(host.Wanted()[0].body == Parse(TempDir() + "/host_good.fs").body);

        // A new chain whose file does not compile: said, and the chain on screen stays.
        const std::string bad = TempDir() + "/host_bad.fs";
        WriteText(bad, "/*{ \"ISFVSN\": \"2.0\" }*/\nvoid main() {\n    gl_FragColor = vec4(nothing);\n}\n");
        host.Request({Parse(bad)}, kW, kH);
        const IsfHost::Done refused = f.UntilBuilt();
        CHECK_FALSE(refused.adopted);
        REQUIRE(refused.errors.size() == 1);
        CHECK(refused.errors[0].find("host_bad.fs:3:") != std::string::npos);
        f.Draw(&px);
        CHECK(Is(px, 128, 128, 255));
        CHECK(host.Wanted().size() == 2);
    }
    DeleteTexture(input);
}

TEST_CASE("isf host: a rebuilt effect keeps its PERSISTENT feedback", "[isf][gl]") {
    const IsfDrawIn drawIn = GENERATE(IsfDrawIn::OwnContexts, IsfDrawIn::RenderThread);
    INFO((drawIn == IsfDrawIn::OwnContexts ? "drawn in its own contexts" : "drawn by the render thread"));
    Gl gl;
    std::ifstream src(TestFile("persistent.fs"));
    const std::string text((std::istreambuf_iterator<char>(src)), {});
    const std::string path = TempDir() + "/host_persistent.fs";
    WriteText(path, text);
    {
        IsfHost host(gl.Own(), drawIn);
        Frames f{host, 0, {}};
        f.in.params = {{"step", 0.0002f}};   // a frame adds 0.051 of an 8-bit level: 5000 frames to saturate
        host.Request({Parse(path)}, kW, kH);
        REQUIRE(f.UntilBuilt().adopted);
        Px px;
        int frames = 0;
        for (; frames < 200; ++frames) f.Draw(&px);
        CHECK(px.r == (int)std::lround(frames * 0.0002 * 255));   // and not the first draw's (the build's) worth more
        WriteText(path, text + "\n// saved\n");   // new GLSL: a new program, the same targets
        std::vector<std::string> errors;
        REQUIRE(host.Reload(&errors));
        int during = 0;
        REQUIRE(f.UntilBuilt(nullptr, &during, nullptr, 5).adopted);   // paced: a build of 20 s is 4000 frames, short of saturating
        frames += during;
        REQUIRE(frames < 4500);
        f.Draw(&px);
        ++frames;
        INFO(frames << " frames drawn in all");
        CHECK(std::abs(px.r - (int)std::lround(frames * 0.0002 * 255)) <= 1);   // not 1 frame's worth: the sum went on
    }
}

// On NVIDIA a texture's first draws cost about 1 ms of CPU per MB and hold every context's frames
// (docs/performance.md, "Session 32"), so a rebuilt chain draws into the targets of the chain it
// replaced. Each chain's targets are seen as the output textures Render returns.
TEST_CASE("isf host: a rebuilt chain draws into the render targets of the chain it replaced", "[isf][gl]") {
    const int form = GENERATE(0, 1, 2);
    INFO((form == 0 ? "drawn in its own contexts" : form == 1 ? "built in its own contexts, drawn by the render thread" : "the window's context"));
    const bool own = form < 2;
    Gl gl;
    const std::string path = TempDir() + "/host_pool.fs";
    WriteText(path, Multiply("1.0, 0.5, 0.25"));
    const unsigned white = White();   // so each chain's colour is its own
    {
        IsfHost host = own ? IsfHost(gl.Own(), form == 0 ? IsfDrawIn::OwnContexts : IsfDrawIn::RenderThread) : IsfHost();
        CHECK(host.DrawIn() == (form == 0 ? IsfDrawIn::OwnContexts : IsfDrawIn::RenderThread));
        REQUIRE(host.OwnContexts() == own);
        Frames f{host, white, {}};
        auto outputs = [&](int frames) { return Outputs(host, white, kW, kH, f.in, frames); };
        host.Request({Parse(path)}, kW, kH);
        REQUIRE(f.UntilBuilt().adopted);
        const std::set<unsigned> first = outputs(4);
        REQUIRE(first.size() == 2);   // the output's two buffers, by turns
        std::vector<std::string> errors;
        WriteText(path, Multiply("0.25, 1.0, 0.5"));   // built while the first chain is on screen: targets of its own
        REQUIRE(host.Reload(&errors));
        REQUIRE(f.UntilBuilt().adopted);
        const std::set<unsigned> second = outputs(4);
        CHECK(std::none_of(second.begin(), second.end(), [&](unsigned t) { return first.count(t) > 0; }));
        WriteText(path, Multiply("0.5, 0.25, 1.0"));   // built once the first chain was retired: its targets
        REQUIRE(host.Reload(&errors));
        REQUIRE(f.UntilBuilt().adopted);
        const std::set<unsigned> third = outputs(4);
        CHECK(third == first);
        Px px;
        f.Draw(&px);
        CHECK(Is(px, 128, 64, 255));   // the third chain's image, on targets cleared and drawn anew
        CHECK(errors.empty());
    }
    DeleteTexture(white);
}

TEST_CASE("isf host: by default a chain is drawn in its own contexts where the renderer compiles again in each context", "[isf][gl]") {
    Gl gl;
    {
        IsfHost host(gl.Own());
        CHECK(host.DrawIn() == (IsSoftwareRenderer() ? IsfDrawIn::OwnContexts : IsfDrawIn::RenderThread));
    }
    setenv("SDFVJ_POST_DRAW", "render", 1);
    {
        IsfHost host(gl.Own());
        CHECK(host.DrawIn() == IsfDrawIn::RenderThread);
    }
    setenv("SDFVJ_POST_DRAW", "own", 1);
    {
        IsfHost host(gl.Own());
        CHECK(host.DrawIn() == IsfDrawIn::OwnContexts);
    }
    unsetenv("SDFVJ_POST_DRAW");
    IsfHost none;
    CHECK(none.DrawIn() == IsfDrawIn::RenderThread);
}

// A chain's first build makes a second set of targets and draws both sets twice (each target is
// two textures drawn in turn), so neither the show's first frames nor the first save's build draw
// into a texture never drawn before (what holds NVIDIA's frames). Without the spare set (as on
// llvmpipe by default) the first save's build makes new targets.
TEST_CASE("isf host: a chain's first build draws a spare set of targets so the first save makes none", "[isf][gl]") {
    const int form = GENERATE(0, 1, 2);
    const bool spare = GENERATE(true, false);
    INFO((form == 0 ? "drawn in its own contexts" : form == 1 ? "built in its own contexts, drawn by the render thread" : "the window's context"));
    INFO((spare ? "spare targets on" : "spare targets off"));
    Gl gl;
    const std::string path = TempDir() + "/host_spare.fs";
    WriteText(path, Multiply("1.0, 0.5, 0.25"));
    const unsigned white = White();
    {
        IsfHost host = form < 2 ? IsfHost(gl.Own(), form == 0 ? IsfDrawIn::OwnContexts : IsfDrawIn::RenderThread) : IsfHost();
        host.SetSpareTargets(spare);
        Frames f{host, white, {}};
        auto outputs = [&](int frames) { return Outputs(host, white, kW, kH, f.in, frames); };
        host.Request({Parse(path)}, kW, kH);
        REQUIRE(f.UntilBuilt().adopted);
        const std::set<unsigned> first = outputs(4);
        REQUIRE(first.size() == 2);
        const int made = host.TargetsMade();
        CHECK(made == (spare ? 4 : 2));   // the output's two textures, and as many spare
        std::vector<std::string> errors;
        WriteText(path, Multiply("0.25, 1.0, 0.5"));
        REQUIRE(host.Reload(&errors));
        REQUIRE(f.UntilBuilt().adopted);
        const std::set<unsigned> second = outputs(4);
        CHECK(std::none_of(second.begin(), second.end(), [&](unsigned t) { return first.count(t) > 0; }));
        CHECK(host.TargetsMade() == (spare ? made : made + 2));   // the spare set, or new ones
        Px px;
        f.Draw(&px);
        CHECK(Is(px, 64, 255, 128));   // the second chain's image on the spare set, cleared first
        WriteText(path, Multiply("0.5, 0.25, 1.0"));
        REQUIRE(host.Reload(&errors));
        REQUIRE(f.UntilBuilt().adopted);
        CHECK(outputs(4) == first);
        CHECK(host.TargetsMade() == (spare ? made : made + 2));
        f.Draw(&px);
        CHECK(Is(px, 128, 64, 255));
        CHECK(errors.empty());
    }
    DeleteTexture(white);
}

// `live`'s render scale moves between a few sizes (--frame-budget, the resolution slider): with
// kept sizes a chain that returns to a size draws into the targets it had there.
TEST_CASE("isf host: a chain returning to a size it drew at takes that size's targets again when sizes are kept", "[isf][gl]") {
    const int keep = GENERATE(0, 2);
    INFO("kept sizes " << keep);
    Gl gl;
    const std::string path = TempDir() + "/host_sizes.fs";
    WriteText(path, Multiply("1.0, 0.5, 0.25"));
    const unsigned white = White();
    {
        IsfHost host(gl.Own(), IsfDrawIn::RenderThread);
        host.SetSpareTargets(false);
        host.SetKeptSizes(keep);
        Frames f{host, white, {}};
        auto outputs = [&](int w, int h) { return Outputs(host, white, w, h, f.in, 4); };
        host.Request({Parse(path)}, kW, kH);
        REQUIRE(f.UntilBuilt().adopted);
        const std::set<unsigned> full = outputs(kW, kH);
        const int made = host.TargetsMade();
        const std::set<unsigned> half = outputs(kW / 2, kH / 2);
        CHECK(host.TargetsMade() == made + 2);   // a size never drawn at: new targets
        const std::set<unsigned> back = outputs(kW, kH);
        const std::set<unsigned> halfAgain = outputs(kW / 2, kH / 2);
        // Kept: each size's own targets again, nothing new. Not kept: new ones at every change (their
        // names may be the deleted ones', so only the count tells).
        CHECK(host.TargetsMade() == (keep > 0 ? made + 2 : made + 6));
        if (keep > 0) {
            CHECK(back == full);
            CHECK(halfAgain == half);
            CHECK(std::none_of(half.begin(), half.end(), [&](unsigned t) { return full.count(t) > 0; }));
        }
        // A cycle through one size more than are kept finds each size still kept.
        outputs(kW / 4, kH / 4);
        const int cycled = host.TargetsMade();
        outputs(kW, kH), outputs(kW / 2, kH / 2), outputs(kW / 4, kH / 4);
        CHECK(host.TargetsMade() == (keep > 0 ? cycled : cycled + 6));
        outputs(kW, kH);
        Px px;
        f.Draw(&px);
        CHECK(Is(px, 255, 128, 64));   // the image at the size returned to, on targets cleared and drawn anew
    }
    DeleteTexture(white);
}
