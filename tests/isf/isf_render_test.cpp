// The ISF pass graph on llvmpipe: built-ins, every input type reaching its uniform, GLSL 1.x files
// with a .vs, compile errors naming the .fs line, pass sizes, persistent and float buffers,
// imported images, Shadertoy files, hot reload that keeps the last good program.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "isf_test_util.h"
#include "render/render.h"

using namespace sdfvj;
using namespace sdfvj::isftest;
namespace fs = std::filesystem;

namespace {

bool Near(int a, int b, int tol) { return std::abs(a - b) <= tol; }

void WriteText(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

}  // namespace

TEST_CASE("isf render: built-ins TIME, TIMEDELTA, FRAMEINDEX, RENDERSIZE, DATE, PASSINDEX, isf_FragNormCoord", "[isf][gl]") {
    RequireGl();
    IsfEffect e;
    LoadOrFail(e, TestFile("builtins.fs"));
    IsfFrameInputs in;
    in.time = 2.5;
    in.timeDelta = 1.0 / 30;
    in.frame = 17;
    const Img img = ReadBack(e.Render(0, 64, 32, in), 64, 32);
    Save("builtins", img);
    CHECK(Near(img.At(5, 5, 0), 64, 1));    // 2.5 / 10 * 255
    CHECK(Near(img.At(5, 5, 1), 17, 1));
    CHECK(Near(img.At(5, 5, 2), 85, 1));    // 1/30 * 10 * 255
    CHECK(img.At(40, 5, 1) == 255);         // RENDERSIZE and isf_FragNormCoord agree
    CHECK(img.At(40, 5, 2) == 255);         // DATE, PASSINDEX
    // isf_FragNormCoord.y is 0 at the bottom: the top row (y = 0 in the image) is near 1
    CHECK(Near(img.At(40, 0, 0), int(255 * 31.5 / 32), 1));
    CHECK(Near(img.At(40, 31, 0), int(255 * 0.5 / 32 + 0.5), 1));
}

TEST_CASE("isf render: the show's tempo reaches ISF and Shadertoy files as u_beat and u_bpm, as it reaches scenes", "[isf][gl]") {
    RequireGl();
    for (const char* file : {"tempo.fs", "tempo_shadertoy.fs"}) {
        INFO(file);
        IsfEffect e;
        LoadOrFail(e, TestFile(file));
        IsfFrameInputs in;
        in.beat = 0.25f;
        in.bpm = 120.0f;
        Img img = ReadBack(e.Render(0, 16, 8, in), 16, 8);
        CHECK(Near(img.At(8, 4, 0), 64, 1));    // 0.25 * 255
        CHECK(Near(img.At(8, 4, 1), 128, 1));   // 120 / 240 * 255
        in.beat = 0.75f;
        in.bpm = 180.0f;
        img = ReadBack(e.Render(0, 16, 8, in), 16, 8);
        CHECK(Near(img.At(8, 4, 0), 191, 1));
        CHECK(Near(img.At(8, 4, 1), 191, 1));
    }
}

TEST_CASE("isf render: every input type reaches its uniform, audio reads silence", "[isf][gl]") {
    RequireGl();
    IsfEffect e;
    LoadOrFail(e, TestFile("all_inputs.fs"));
    const unsigned input = MakeTexture(64, 8, [](int, int) { return std::array<uint8_t, 4>{200, 0, 0, 255}; });
    IsfFrameInputs in;
    in.params = {{"amount", 0.5f}, {"flag", 0.0f}, {"choice", 10.0f}, {"where_x", 50.0f}, {"where_y", 25.0f},
                 {"tint_r", 1.0f}, {"tint_g", 0.0f}, {"tint_b", 0.2f}, {"bang", 1.0f}};
    const Img img = ReadBack(e.Render(input, 64, 8, in), 64, 8);
    DeleteTexture(input);
    CHECK(Near(img.At(4, 4, 0), 128, 1));   // amount 0.5
    CHECK(img.At(4, 4, 1) == 0);            // flag false
    CHECK(img.At(4, 4, 2) == 255);          // choice 10 / 10
    CHECK(Near(img.At(20, 4, 0), 128, 1));  // where 50 / 100
    CHECK(Near(img.At(20, 4, 1), 64, 1));   // where 25 / 100
    CHECK(img.At(20, 4, 2) == 255);         // bang
    CHECK((img.At(40, 4, 0) == 255 && img.At(40, 4, 1) == 0 && Near(img.At(40, 4, 2), 51, 1)));   // tint
    CHECK(img.At(60, 4, 0) == 200);         // the input image
    CHECK(Near(img.At(60, 4, 1), 128, 1));  // audio: a wave at rest
    CHECK(img.At(60, 4, 2) == 0);           // audioFFT: no energy
    // Out-of-range values are clamped, never passed on: amount 9 -> MAX 2 -> 1.0 on screen
    in.params = {{"amount", 9.0f}};
    CHECK(ReadBack(e.Render(0, 64, 8, in), 64, 8).At(4, 4, 0) == 255);
}

TEST_CASE("isf render: a GLSL 1.x file with its .vs runs on the 4.5 core profile", "[isf][gl]") {
    RequireGl();
    IsfEffect e;
    LoadOrFail(e, TestFile("glsl1.fs"));
    CHECK(!e.File().vertexPath.empty());
    // a vertical ramp: x * 8
    const unsigned input = MakeTexture(32, 4, [](int x, int) { return std::array<uint8_t, 4>{uint8_t(x * 8), 0, 0, 255}; });
    const Img img = ReadBack(e.Render(input, 32, 4, {}), 32, 4);
    DeleteTexture(input);
    for (int x = 1; x < 32; ++x) {
        INFO("x = " << x);
        CHECK(Near(img.At(x, 2, 0), 255 - (x - 1) * 8, 1));   // inverted, one pixel to the left
        CHECK(img.At(x, 2, 1) == 255);
    }
}

TEST_CASE("isf render: a compile error names the .fs file and its line, the last good program stays", "[isf][gl]") {
    RequireGl();
    IsfEffect e;
    std::string error;
    CHECK_FALSE(e.Load(TestFile("syntax_error.fs"), &error));
    INFO(error);
    CHECK(error.find("syntax_error.fs:9: ") != std::string::npos);
    CHECK(error.find("undeclaredThing") != std::string::npos);
    CHECK_FALSE(e.IsValid());
    CHECK(e.Render(0, 8, 8, {}) == 0u);   // nothing drawn, nothing crashed

    // Hot reload: a good file, then a broken save, then the fix.
    const std::string path = TempDir() + "/reload.fs";
    WriteText(path, "/*{}*/\nvoid main() { gl_FragColor = vec4(1.0, 0.0, 0.0, 1.0); }\n");
    IsfEffect live;
    LoadOrFail(live, path);
    CHECK(live.ReloadIfChanged(&error) == 0);
    WriteText(path, "/*{}*/\nvoid main() {\n gl_FragColor = vec4(0.0, 1.0, 0.0, 1.0) }\n");
    CHECK(live.ReloadIfChanged(&error) == -1);
    CHECK(error.find("reload.fs:3: ") != std::string::npos);
    CHECK(live.ReloadIfChanged(&error) == 0);   // reported once per save
    Img img = ReadBack(live.Render(0, 4, 4, {}), 4, 4);
    CHECK((img.At(1, 1, 0) == 255 && img.At(1, 1, 1) == 0));   // still the last good (red)
    WriteText(path, "/*{}*/\nvoid main() { gl_FragColor = vec4(0.0, 1.0, 0.0, 1.0); }\n");
    CHECK(live.ReloadIfChanged(&error) == 1);
    img = ReadBack(live.Render(0, 4, 4, {}), 4, 4);
    CHECK((img.At(1, 1, 0) == 0 && img.At(1, 1, 1) == 255));
}

TEST_CASE("isf render: a save that puts back the program on screen compiles nothing, a header-only change keeps the program too", "[isf][gl]") {
    RequireGl();
    const std::string path = TempDir() + "/same.fs";
    const std::string good = "/*{ \"INPUTS\": [{\"NAME\": \"k\", \"TYPE\": \"float\", \"DEFAULT\": 0.5}] }*/\n"
                             "void main() { gl_FragColor = vec4(k, 0.0, 0.0, 1.0); }\n";
    WriteText(path, good);
    IsfEffect live;
    LoadOrFail(live, path);
    REQUIRE(live.ProgramsBuilt() == 1);
    std::string error;
    WriteText(path, good + "void broken( {\n");                     // a typo saved mid-edit
    CHECK(live.ReloadIfChanged(&error) == -1);
    WriteText(path, good);                                          // the fix: the file on screen again
    CHECK(live.ReloadIfChanged(&error) == 1);
    CHECK(live.ProgramsBuilt() == 1);                               // nothing compiled
    Img img = ReadBack(live.Render(0, 4, 4, {}), 4, 4);
    CHECK(Near(img.At(1, 1, 0), 128, 1));
    // The header's LABEL is not in the GLSL: the same program, the new header.
    std::string labelled = good;
    labelled.replace(labelled.find("\"DEFAULT\""), 0, "\"LABEL\": \"Red\", ");
    WriteText(path, labelled);
    CHECK(live.ReloadIfChanged(&error) == 1);
    CHECK(live.ProgramsBuilt() == 1);
    CHECK(live.Params().at(0).label == "Red");
    // A change the GLSL sees builds a new program.
    WriteText(path, good + "// a comment the driver reads\n");
    CHECK(live.ReloadIfChanged(&error) == 1);
    CHECK(live.ProgramsBuilt() == 2);
    img = ReadBack(live.Render(0, 4, 4, {}), 4, 4);
    CHECK(Near(img.At(1, 1, 0), 128, 1));
}

TEST_CASE("isf render: PASSES targets get their WIDTH/HEIGHT expression sizes", "[isf][gl]") {
    RequireGl();
    IsfEffect e;
    LoadOrFail(e, TestFile("multipass.fs"));
    Img img = ReadBack(e.Render(0, 64, 40, {}), 64, 40);
    CHECK(img.At(10, 10, 0) == 8);    // pass 0 RENDERSIZE.x = 64 / 8
    CHECK(img.At(10, 10, 1) == 5);    // floor(40 / 8)
    CHECK(img.At(10, 10, 2) == 8);    // IMG_SIZE(small).x
    CHECK(img.At(10, 10, 3) == 64);   // the last pass is full size
    IsfFrameInputs in;
    in.params = {{"divisor", 4.0f}};   // an input in the expression
    img = ReadBack(e.Render(0, 64, 40, in), 64, 40);
    CHECK((img.At(10, 10, 0) == 16 && img.At(10, 10, 1) == 10));
}

TEST_CASE("isf render: a PERSISTENT FLOAT buffer accumulates across frames, without FLOAT small steps are lost", "[isf][gl]") {
    RequireGl();
    IsfEffect e;
    LoadOrFail(e, TestFile("persistent.fs"));
    IsfFrameInputs in;
    unsigned out = 0;
    for (int i = 0; i < 10; ++i) {
        in.frame = i;
        out = e.Render(0, 16, 16, in);
    }
    CHECK(Near(ReadBack(out, 16, 16).At(3, 3, 0), 159, 1));   // 10 * 0.0625 * 255
    // A step below half an 8-bit level: the float buffer sums 100 of them, an 8-bit one stays 0.
    in.params = {{"step", 0.001f}};
    IsfEffect f;
    LoadOrFail(f, TestFile("persistent.fs"));
    for (int i = 0; i < 100; ++i) out = f.Render(0, 16, 16, in);
    CHECK(Near(ReadBack(out, 16, 16).At(3, 3, 0), 26, 1));   // 0.1 * 255
    std::ifstream src(TestFile("persistent.fs"));
    std::string text((std::istreambuf_iterator<char>(src)), {});
    text.replace(text.find("\"FLOAT\": true"), 13, "\"FLOAT\": false");
    const std::string path = TempDir() + "/persistent8.fs";
    WriteText(path, text);
    IsfEffect g;
    LoadOrFail(g, path);
    for (int i = 0; i < 100; ++i) out = g.Render(0, 16, 16, in);
    CHECK(ReadBack(out, 16, 16).At(3, 3, 0) == 0);
    // A non-persistent target starts each frame from what the pass writes: already covered by multipass.
}

// `live`'s render scale (--frame-budget, the resolution slider) moves the chain between sizes: a
// PERSISTENT target's feedback goes on at the new size, scaled, instead of starting from black.
TEST_CASE("isf render: a PERSISTENT buffer's content goes on through a size change, scaled, kept sizes or not", "[isf][gl]") {
    RequireGl();
    const int keep = GENERATE(0, 1);
    INFO("kept sizes " << keep);
    IsfEffect e;
    e.SetKeptSizes(keep);
    LoadOrFail(e, TestFile("persistent.fs"));
    IsfFrameInputs in;
    unsigned out = 0;
    for (int i = 0; i < 10; ++i) out = e.Render(0, 16, 16, in);
    CHECK(Near(ReadBack(out, 16, 16).At(3, 3, 0), 159, 1));   // 10 * 0.0625 * 255
    out = e.Render(0, 8, 8, in);                               // 11 steps, not 1 (16 from black)
    const Img small = ReadBack(out, 8, 8);
    CHECK(Near(small.At(0, 0, 0), 175, 1));
    CHECK(Near(small.At(7, 7, 0), 175, 1));
    out = e.Render(0, 16, 16, in);                             // back: 12 steps, a kept size's old content or not
    CHECK(Near(ReadBack(out, 16, 16).At(15, 0, 0), 191, 1));
    // The trails through a move: a lit input pixel's trail survives at the new size.
    IsfEffect trails;
    LoadOrFail(trails, ShippedEffect("feedback_trails"));
    const unsigned white = MakeTexture(32, 32, [](int, int) { return std::array<uint8_t, 4>{255, 255, 255, 255}; });
    const unsigned black = MakeTexture(16, 16, [](int, int) { return std::array<uint8_t, 4>{0, 0, 0, 255}; });
    IsfFrameInputs t;
    t.params = {{"decay", 0.9f}, {"zoom", 1.0f}};
    trails.Render(white, 32, 32, t);
    const Img faded = ReadBack(trails.Render(black, 16, 16, t), 16, 16);   // the scene went dark, at half the size
    CHECK(Near(faded.At(8, 8, 0), 230, 2));                                // 0.9 * 255: the trail, not black
    DeleteTexture(white);
    DeleteTexture(black);
}

TEST_CASE("isf render: IMPORTED images keep their orientation", "[isf][gl]") {
    RequireGl();
    const std::string dir = TempDir();
    fs::copy_file(TestFile("imported.fs"), dir + "/imported.fs", fs::copy_options::overwrite_existing);
    // 2x2: top-left red, top-right green, bottom-left blue, bottom-right white
    const std::vector<uint8_t> logo = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255};
    std::string error;
    REQUIRE(WritePng(dir + "/logo.png", 2, 2, logo, &error));
    IsfEffect e;
    LoadOrFail(e, dir + "/imported.fs");
    const Img img = ReadBack(e.Render(0, 16, 16, {}), 16, 16);
    Save("imported", img);
    CHECK((img.At(1, 1, 0) == 255 && img.At(1, 1, 1) == 0 && img.At(1, 1, 2) == 0));       // top-left red
    CHECK((img.At(14, 1, 1) == 255 && img.At(14, 1, 0) == 0));                             // top-right green
    CHECK((img.At(1, 14, 2) == 255 && img.At(1, 14, 0) == 0));                             // bottom-left blue
    CHECK((img.At(14, 14, 0) == 255 && img.At(14, 14, 1) == 255 && img.At(14, 14, 2) == 255));
    // A file that is not an image: file:line of the IMPORTED entry and why.
    WriteText(dir + "/logo.png", "not a png");
    IsfEffect bad;
    CHECK_FALSE(bad.Load(dir + "/imported.fs", &error));
    CHECK(error.find("imported.fs:4: IMPORTED 'logo': ") != std::string::npos);
}

TEST_CASE("isf render: a Shadertoy mainImage runs as a generator with iChannel0 = the previous stage", "[isf][gl]") {
    RequireGl();
    IsfEffect e;
    LoadOrFail(e, TestFile("shadertoy.fs"));
    CHECK(e.File().kind == IsfKind::Shadertoy);
    const unsigned input = MakeTexture(32, 8, [](int, int) { return std::array<uint8_t, 4>{0, 0, 77, 255}; });
    IsfFrameInputs in;
    in.time = 1.0;
    in.frame = 51;
    const Img img = ReadBack(e.Render(input, 32, 8, in), 32, 8);
    DeleteTexture(input);
    CHECK(Near(img.At(16, 4, 0), int(255 * 16.5 / 32), 1));   // uv.x from iResolution
    CHECK(Near(img.At(16, 4, 1), 25 + 51, 1));                // iTime / 10 + iFrame / 255
    CHECK(img.At(16, 4, 2) == 77);                            // iChannel0
    CHECK(img.At(16, 4, 3) == 255);                           // Shadertoy's alpha is ignored: opaque
}

TEST_CASE("isf render: unsupported features are one notice per feature and the file still renders", "[isf][gl]") {
    RequireGl();
    IsfChain chain;
    std::string error;
    REQUIRE(chain.Load({TestFile("unsupported.fs")}, &error));
    const auto notices = chain.Notices();
    for (const auto& n : notices) UNSCOPED_INFO(n);
    CHECK(notices.size() == 5);   // unknown key, second image, audio, audioFFT, pass key BLEND
    for (const auto& n : notices) CHECK(n.find("unsupported.fs:") != std::string::npos);
    const unsigned input = MakeTexture(8, 8, [](int, int) { return std::array<uint8_t, 4>{90, 90, 90, 255}; });
    const Img img = ReadBack(chain.Render(input, 8, 8, {}), 8, 8);
    DeleteTexture(input);
    CHECK((img.At(4, 4, 0) == 90 && img.At(4, 4, 1) == 90));   // not blank
}

TEST_CASE("isf chain: stages run in order, a chain that fails to load keeps the one it had", "[isf][gl]") {
    RequireGl();
    IsfChain chain;
    std::string error;
    REQUIRE(chain.Load(SplitIsfList("color_grade, mirror"), &error));
    CHECK(chain.Size() == 2);
    CHECK_FALSE(chain.Load({ShippedEffect("mirror"), TestFile("syntax_error.fs")}, &error));
    CHECK(error.find("syntax_error.fs:9:") != std::string::npos);
    CHECK(chain.Size() == 2);
    CHECK(chain.Params().size() == 1 + 3 + 3 * 4);   // mode; exposure, contrast, saturation; lift, gamma, gain x4
}

// A chain's first draw is the build's (IsfHost draws each new chain once before the show does):
// it must bind what every later frame binds. On llvmpipe a texture of another size (a power of
// two or not) is another compile of the pass, which the show's first frame then paid (400-470 ms
// in the soak). So every pass's target is made before the first pass draws.
TEST_CASE("isf render: on the first frame a pass that reads a later pass's target reads it at its size", "[isf][gl]") {
    RequireGl();
    IsfEffect e;
    LoadOrFail(e, TestFile("reads_later_pass.fs"));
    for (int frame = 0; frame < 2; ++frame) {
        INFO("frame " << frame);
        const Img img = ReadBack(e.Render(0, 64, 40, {}), 64, 40);
        CHECK(img.At(20, 20, 0) == 16);   // `second` is 64/4 x 40/4, not a 1x1 stand-in
        CHECK(img.At(20, 20, 1) == 10);
    }
}
