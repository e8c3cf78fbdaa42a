// Every scene x the seed's four lighting tests, rendered headless on llvmpipe and compared with
// committed reference images. Tolerance: at most 0.2% of pixels may have a channel more than 8/255
// off, and the mean channel difference must stay under 0.5/255 — loose enough for another Mesa
// build's float rounding, tight enough that any visible change to a scene or the lighting fails.
// Regenerate on purpose with SDFVJ_UPDATE_REFERENCES=1 (a section: -c NAME.png), then look at the PNGs.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <tuple>

#include <epoxy/gl.h>

#include "gl_fixture.h"
#include "render/gl_stages.h"

using namespace sdfvj;
using namespace sdfvj::test;
namespace fs = std::filesystem;

namespace {
constexpr int kW = 160, kH = 120;
const fs::path kReferenceDir = SDFVJ_TEST_REFERENCE_DIR;
const fs::path kActualDir = SDFVJ_TEST_OUTPUT_DIR;

}  // namespace

TEST_CASE("render: every scene x lighting test matches its reference image", "[render]") {
    const bool update = std::getenv("SDFVJ_UPDATE_REFERENCES") != nullptr;
    const auto scenes = ListScenes();
    REQUIRE(scenes.size() >= 4);
    fs::create_directories(kActualDir);
    for (const std::string& scene : scenes) {
        SceneInfo info;
        std::string error;
        REQUIRE(FindScene(scene, &info, &error));
        for (const LightingTest& t : SeedLightingTests()) {
            const std::string name = scene + "_" + t.name + ".png";
            SECTION(name) {
                EffectSet effects = t.effects;
                effects.normals = info.effects.normals;   // the scene's normal estimator (its header's NORMALS)
                Image actual = RenderScene(scene, effects, RenderPath::Fragment, kW, kH);
                SavePng((kActualDir / name).string(), actual);
                if (update) {
                    SavePng((kReferenceDir / name).string(), actual);
                    WARN("updated reference " << name);
                    continue;
                }
                Image ref;
                INFO("reference " << (kReferenceDir / name) << ", actual " << (kActualDir / name));
                REQUIRE(LoadPng((kReferenceDir / name).string(), &ref));
                ImageDiff d = CompareImages(actual, ref, 8);
                INFO("mean " << d.meanAbs << ", max " << d.maxAbs << ", over 8/255: " << d.fractionOver * 100 << "%");
                CHECK(d.fractionOver <= 0.002);
                CHECK(d.meanAbs <= 0.5);
            }
        }
    }
}

TEST_CASE("render: fragment and compute paths give the same image", "[render]") {
    // Same shader body, two wrappers. Tolerance: no channel more than 2/255 off on more than
    // 0.1% of pixels (llvmpipe vectorises the two differently). Small size: compute is ~100x
    // slower than fragment on llvmpipe. The compute path's cone pre-pass starts rays elsewhere
    // (the same surfaces, stopped a step apart at silhouettes: 1 % of pixels at this size, where a
    // tile is a sixth of the frame; tests/stability/test_cone.cpp holds it to its own claims).
    // Over-relaxed sphere tracing (on by default) spreads the two step sequences further: midi
    // 1.8 % past 2/255 (0.6 % stepping plainly), most of it 3-6/255 of shading on grazing surfaces.
    for (const std::string& scene : ListScenes()) {
        SECTION(scene) {
            EffectSet full = SeedLightingTests()[0].effects;
            Quality fromEye;
            fromEye.conePrepass = false;
            Image frag = RenderScene(scene, full, RenderPath::Fragment, 64, 48);
            Image comp = RenderScene(scene, full, RenderPath::Compute, 64, 48, 1.0, {}, fromEye);
            ImageDiff d = CompareImages(frag, comp, 2);
            INFO("mean " << d.meanAbs << ", max " << d.maxAbs << ", over 2/255: " << d.fractionOver * 100 << "%");
            CHECK(d.fractionOver <= 0.001);
            Image cone = RenderScene(scene, full, RenderPath::Compute, 64, 48);
            ImageDiff c = CompareImages(frag, cone, 2);
            INFO("with the cone pre-pass: mean " << c.meanAbs << ", max " << c.maxAbs << ", over 2/255: " << c.fractionOver * 100 << "%");
            CHECK(c.fractionOver <= 0.025);
        }
    }
}

// A scene that declares first-order normals ("NORMALS": "forward", 3 map() calls from the march's
// value at the hit, or "tetrahedron", 4; both at a tenth of central's offset, render.glsl
// surfaceNormal) draws what central differences draw: the accuracy report measures it against the
// CPU double reference (docs/accuracy.md); here the two images, full lighting: up to 0.07 % of
// pixels past 8/255. It fails with the tetrahedron at central's own offset (0.14-0.22 % on the
// three scenes: its first-order error).
TEST_CASE("render: a scene's first-order normals (forward or tetrahedron) draw the image central differences draw", "[render]") {
    int declared = 0;
    for (const std::string& scene : ListScenes()) {
        SceneInfo info;
        std::string error;
        REQUIRE(FindScene(scene, &info, &error));
        if (info.effects.normals == 0) continue;
        ++declared;
        SECTION(scene) {
            EffectSet own = SeedLightingTests()[0].effects;
            own.normals = info.effects.normals;
            EffectSet central = own;
            central.normals = 0;
            Image a = RenderScene(scene, own, RenderPath::Fragment, 320, 180);
            Image b = RenderScene(scene, central, RenderPath::Fragment, 320, 180);
            ImageDiff d = CompareImages(a, b, 8);
            INFO("mean " << d.meanAbs << ", max " << d.maxAbs << ", over 8/255: " << d.fractionOver * 100 << "%");
            CHECK(d.fractionOver <= 0.001);
            CHECK(d.meanAbs <= 0.3);
        }
    }
    CHECK(declared >= 5);   // every shipped scene but mandelbulb
}

TEST_CASE("render: what a person would see", "[render]") {
    for (const std::string& scene : ListScenes()) {
        SECTION(scene) {
            const auto tests = SeedLightingTests();
            Image full = RenderScene(scene, tests[0].effects, RenderPath::Fragment, kW, kH);
            Image none = RenderScene(scene, tests[3].effects, RenderPath::Fragment, kW, kH);
            // Something is in the middle of the frame: its centre differs from the top corners (sky).
            double centre = MeanLuma(full, 0.4, 0.4, 0.6, 0.6);
            double corner = MeanLuma(full, 0.0, 0.0, 0.1, 0.1);
            INFO("centre luma " << centre << ", corner luma " << corner);
            CHECK(std::abs(centre - corner) > 8.0);
            // Not a blank or saturated frame.
            double mean = MeanLuma(full, 0, 0, 1, 1);
            CHECK(mean > 15.0);
            CHECK(mean < 240.0);
            // Shadows, AO and specular change the picture: full lighting is not the unlit image.
            ImageDiff d = CompareImages(full, none, 8);
            INFO("full vs none: " << d.fractionOver * 100 << "% of pixels differ by more than 8/255");
            CHECK(d.fractionOver > 0.02);
            // The scene moves with time (character walks; others animate or stay still).
            if (scene == "character") {
                Image later = RenderScene(scene, tests[0].effects, RenderPath::Fragment, kW, kH, 1.5);
                CHECK(CompareImages(full, later, 8).fractionOver > 0.005);
            }
        }
    }
}

TEST_CASE("render: a scene parameter changes the image", "[render]") {
    SceneInfo midi;
    std::string error;
    REQUIRE(FindScene("midi", &midi, &error));
    EffectSet none;
    for (const ParamDecl& d : midi.params) {
        SECTION(d.name) {
            Image lo = RenderScene("midi", none, RenderPath::Fragment, 96, 72, 1.0, {{d.name, d.minValue}});
            Image hi = RenderScene("midi", none, RenderPath::Fragment, 96, 72, 1.0, {{d.name, d.maxValue}});
            CHECK(CompareImages(lo, hi, 8).fractionOver > 0.01);
        }
    }
}

// The compute path's work-group size is the program's (main_comp.glsl WORKGROUP_X/Y, read back
// with GL_COMPUTE_WORK_GROUP_SIZE): a scene that defines another shape covers every pixel of a
// frame whose size no shape divides, with and without the cone pre-pass, and draws the same
// bytes as 8x8 (each pixel runs the same code). With the dispatch still sized for 8x8 groups, a
// 16x4 group leaves a band of rows unwritten, a 4x16 one columns.
TEST_CASE("render: the compute path dispatches by the program's work-group size", "[render]") {
    const fs::path dir = fs::path(SDFVJ_TEST_OUTPUT_DIR) / "workgroup";
    fs::create_directories(dir);
    SceneInfo info;
    std::string error;
    REQUIRE(FindScene("midi", &info, &error));
    EffectSet own = info.effects;
    for (const char* shape : {"16x4", "4x16", "32x2"}) {
        SECTION(shape) {
            const std::string s = shape;
            const std::string x = s.substr(0, s.find('x')), y = s.substr(s.find('x') + 1);
            const fs::path file = dir / ("midi_wg" + s + ".glsl");
            REQUIRE(WriteSceneCopy("midi", "#define WORKGROUP_X " + x + "\n#define WORKGROUP_Y " + y, file));
            for (bool cone : {true, false}) {
                Quality q;
                q.conePrepass = cone;
                Image a = RenderScene("midi", own, RenderPath::Compute, 45, 27, 1.0, {}, q);
                Image b = RenderScene(file.string(), own, RenderPath::Compute, 45, 27, 1.0, {}, q);
                REQUIRE(a.rgba.size() == b.rgba.size());
                ImageDiff d = CompareImages(a, b, 0);
                INFO("cone pre-pass " << cone << ": " << d.fractionOver * 100 << " % of pixels differ, by up to " << d.maxAbs);
                CHECK(a.rgba == b.rgba);
            }
        }
    }
}

// Over-relaxed sphere tracing (render.glsl OVERRELAX, on by default for distance bounds;
// docs/performance.md; field150 declares it off): the scenes as shipped find the surfaces plain
// sphere tracing (a copy with OVERRELAX 0) finds. Its gap test steps back wherever the over-long
// step could have jumped a surface, so the frames differ only where a ray stops at another point
// within the hit epsilon: at most 0.5 % of pixels past 8/255. With the step back left out (a bare
// 1.2x step) rays tunnel through thin parts and the test fails.
TEST_CASE("render: over-relaxed sphere tracing finds the surfaces plain sphere tracing finds", "[render]") {
    const fs::path dir = fs::path(SDFVJ_TEST_OUTPUT_DIR) / "overrelax";
    fs::create_directories(dir);
    for (const char* name : {"midi", "character", "field50"}) {
        SECTION(name) {
            SceneInfo info;
            std::string error;
            REQUIRE(FindScene(name, &info, &error));
            const fs::path file = dir / (std::string(name) + "_plain.glsl");
            REQUIRE(WriteSceneCopy(name, "#define OVERRELAX 0", file));
            EffectSet own = info.effects;
            Image plain = RenderScene(file.string(), own, RenderPath::Fragment, 320, 180);
            Image relaxed = RenderScene(name, own, RenderPath::Fragment, 320, 180);
            SavePng((dir / (std::string(name) + "_plain.png")).string(), plain);
            ImageDiff d = CompareImages(plain, relaxed, 8);
            INFO(d.fractionOver * 100 << " % of pixels past 8/255, mean " << d.meanAbs << ", max " << d.maxAbs);
            CHECK(d.fractionOver <= 0.005);
            CHECK(d.meanAbs <= 0.3);
        }
    }
    // A distance estimate (the Mandelbulb's sceneLipschitz() > 1) steps plainly: over-relaxed it
    // moved 4 % of its pixels on the H200. The frame as shipped is the plain copy's, byte for byte.
    SECTION("mandelbulb") {
        const fs::path file = dir / "mandelbulb_plain.glsl";
        REQUIRE(WriteSceneCopy("mandelbulb", "#define OVERRELAX 0", file));
        SceneInfo info;
        std::string error;
        REQUIRE(FindScene("mandelbulb", &info, &error));
        Image plain = RenderScene(file.string(), info.effects, RenderPath::Fragment, 160, 90);
        Image shipped = RenderScene("mandelbulb", info.effects, RenderPath::Fragment, 160, 90);
        CHECK(plain.rgba == shipped.rgba);
    }
}

// A scene's setup once per frame on the compute path (lib/common.glsl SCENE_SETUP_FRAME): the cone
// pre-pass's first invocation (or a group of its own without the pre-pass) stores what sceneSetup()
// computes, and every pixel loads it as a uniform block. The frames are what a per-pixel setup (a
// copy with SCENE_SETUP_FRAME 0) draws, within rounding: llvmpipe may contract sceneSetup's
// arithmetic differently in the two programs (4 of 129,600 pixels of character by 1/255 at
// 480x270). Without the store, the frame reads an empty skeleton; without the load, the program
// is the per-pixel one.
TEST_CASE("render: a scene's setup runs once per frame on the compute path and draws what the per-pixel setup draws", "[render]") {
    RequireGl();
    const fs::path dir = fs::path(SDFVJ_TEST_OUTPUT_DIR) / "setup_frame";
    fs::create_directories(dir);
    for (const char* scene : {"character", "mandelbulb"}) {
        SceneInfo info;
        std::string error;
        REQUIRE(FindScene(scene, &info, &error));
        const fs::path copy = dir / (std::string(scene) + "_pixel.glsl");
        REQUIRE(WriteSceneCopy(scene, "#define SCENE_SETUP_FRAME 0", copy));
        SceneInfo pixelInfo;
        REQUIRE(LoadScene(copy.string(), &pixelInfo, &error));
        // The shipped scene's compute program has the frame state; the copy's and the fragment path's do not.
        for (const auto& [sceneInfo, path, want] : {std::tuple{info, RenderPath::Compute, true},
                                                    std::tuple{pixelInfo, RenderPath::Compute, false},
                                                    std::tuple{info, RenderPath::Fragment, false}}) {
            ShaderSource src;
            REQUIRE(AssembleProgram(sceneInfo, VariantKey{sceneInfo.path, sceneInfo.effects, path}, &src, &error));
            Program prog;
            INFO(scene << " " << (path == RenderPath::Compute ? "compute" : "fragment") << ": " << error);
            REQUIRE(prog.Build(src, path, &error));
            CHECK(prog.FrameState() == want);
        }
        for (bool cone : {true, false})
            for (int strips : {1, 3}) {
                Quality q;
                q.conePrepass = cone;
                const Image a = RenderScene(scene, info.effects, RenderPath::Compute, 96, 54, 1.7, {}, q, strips);
                const Image b = RenderScene(copy.string(), info.effects, RenderPath::Compute, 96, 54, 1.7, {}, q, strips);
                REQUIRE(a.rgba.size() == b.rgba.size());
                const ImageDiff d = CompareImages(a, b, 2);
                INFO(scene << ", cone pre-pass " << cone << ", " << strips << " strips: " << d.fractionOver * 100
                           << " % of pixels past 2/255, by up to " << d.maxAbs);
                CHECK(d.fractionOver < 0.001);
                CHECK(d.maxAbs <= 4);
            }
    }
}

// The camera's basis set once per frame (uniforms.glsl, FrameRenderer's MakeCameraBasis) draws what
// render.glsl's cameraRay() computed in every pixel (a copy with CAMERA_UNIFORMS 0), on both paths,
// from the scene's camera and from a mouse orbit (live), in a frame wider than tall and one taller
// than wide. The rays differ in their last bits only. A basis with right and up swapped, or
// scaled by the width, moves most of the frame.
TEST_CASE("render: the camera's basis set once per frame draws what the per-pixel camera ray draws", "[render]") {
    RequireGl();
    const fs::path dir = fs::path(SDFVJ_TEST_OUTPUT_DIR) / "camera_uniforms";
    fs::create_directories(dir);
    const fs::path copy = dir / "midi_pixel_camera.glsl";
    REQUIRE(WriteSceneCopy("midi", "#define CAMERA_UNIFORMS 0", copy));
    SceneInfo shipped, perPixel;
    std::string error;
    REQUIRE(FindScene("midi", &shipped, &error));
    REQUIRE(LoadScene(copy.string(), &perPixel, &error));
    for (RenderPath path : {RenderPath::Compute, RenderPath::Fragment}) {
        Program a, b;
        for (auto [info, prog] : {std::pair{&shipped, &a}, std::pair{&perPixel, &b}}) {
            ShaderSource src;
            REQUIRE(AssembleProgram(*info, VariantKey{info->path, info->effects, path}, &src, &error));
            INFO(error);
            REQUIRE(prog->Build(src, path, &error));
        }
        for (const auto& [w, h] : {std::pair{96, 54}, std::pair{48, 80}})
            for (float yaw : {0.0f, 0.7f}) {
                FrameInputs in;
                in.time = 1.3;
                in.orbitYaw = yaw;
                in.orbitPitch = yaw * 0.5f;
                for (const ParamDecl& d : shipped.params) in.params.emplace_back(d.name, d.defaultValue);
                FrameRenderer fa, fb;
                REQUIRE(fa.Resize(w, h, &error));
                REQUIRE(fb.Resize(w, h, &error));
                fa.Draw(a, shipped, in);
                fb.Draw(b, perPixel, in);
                const Image ia{w, h, fa.ReadPixels()}, ib{w, h, fb.ReadPixels()};
                const ImageDiff d = CompareImages(ia, ib, 8);
                INFO((path == RenderPath::Compute ? "compute " : "fragment ") << w << "x" << h << ", orbit " << yaw << ": "
                     << d.fractionOver * 100 << " % of pixels past 8/255, by up to " << d.maxAbs);
                CHECK(d.fractionOver < 0.005);
                CHECK(d.meanAbs < 0.2);
            }
    }
}

// `live`'s render scale moves between a few sizes (--frame-budget, the resolution slider). On
// NVIDIA a new texture's first draw holds every context's frames (about 1 ms per MB), so with kept
// sizes a return to a size takes the target it had there: the same texture, the same image a
// renderer new at that size draws (the cone pre-pass's texture, kept with it, is rewritten each
// frame), and no target made. Without kept sizes every change makes one.
TEST_CASE("render: a return to a size drawn at before takes its target again when sizes are kept", "[render]") {
    const int keep = GENERATE(0, 2);
    INFO("kept sizes " << keep);
    RequireGl();
    SceneInfo scene;
    std::string error;
    REQUIRE(FindScene("midi", &scene, &error));
    ShaderSource src;
    REQUIRE(AssembleProgram(scene, VariantKey{scene.path, scene.effects, RenderPath::Compute}, &src, &error));
    Program prog;
    if (!prog.Build(src, RenderPath::Compute, &error)) FAIL(error);
    FrameInputs in;
    in.time = 1.0;
    for (const ParamDecl& d : scene.params) in.params.emplace_back(d.name, d.defaultValue);
    FrameRenderer fr;
    fr.SetKeptSizes(keep);
    auto draw = [&](int w, int h) {
        REQUIRE(fr.Resize(w, h, &error));
        fr.Draw(prog, scene, in);
        return fr.Texture();
    };
    const unsigned full = draw(64, 36);
    const unsigned half = draw(32, 18);
    CHECK(fr.TargetsMade() == 2);
    const unsigned back = draw(64, 36);
    const Image image{64, 36, fr.ReadPixels()};
    const unsigned halfAgain = draw(32, 18);
    CHECK(fr.TargetsMade() == (keep > 0 ? 2 : 4));
    if (keep > 0) {   // without, a new texture may get a deleted one's name: only the count tells
        CHECK(back == full);
        CHECK(halfAgain == half);
        CHECK(half != full);
    }
    const Image fresh = RenderScene("midi", scene.effects, RenderPath::Compute, 64, 36, 1.0);
    CHECK(image.rgba == fresh.rgba);
    // Sizes past the count are let go, the least recently left first.
    fr.SetKeptSizes(1);
    draw(48, 27);   // leaves 32x18 kept; 64x36 goes
    draw(64, 36);
    CHECK(fr.TargetsMade() == (keep > 0 ? 4 : 6));
    // A cycle through one size more than are kept (the one drawn at and `keep` others) finds each
    // size still kept: the size asked for is taken before the size left can push it out.
    fr.SetKeptSizes(keep);
    for (int round = 0; round < 2; ++round) {
        const int made = fr.TargetsMade();
        draw(32, 18), draw(48, 27), draw(64, 36);
        if (round == 1) CHECK(fr.TargetsMade() == (keep > 0 ? made : made + 3));
    }
}

TEST_CASE("render: the identity blend a full-screen pass draws with on llvmpipe gives the image blending off gives", "[render]") {
    RequireGl();
    // On llvmpipe blending is on as the identity (ONE, ZERO, ADD), so that llvmpipe builds each
    // fragment program once, not also a whole-tile copy; elsewhere off (gl_stages.h).
    CHECK(OverwriteBlendOn() == (IsSoftwareRenderer() && std::getenv("SDFVJ_IDENTITY_BLEND") == nullptr));
    struct Reset {
        ~Reset() { SetOverwriteBlendOverride(-1); }
    } reset;
    EffectSet effects;
    effects.shadows = 2;
    effects.ao = true;
    effects.specular = true;
    Image drawn[2];
    for (int on : {1, 0}) {
        SetOverwriteBlendOverride(on);
        drawn[on] = RenderScene("midi", effects, RenderPath::Fragment, 96, 54);
        GLint src = 0, dst = 0, eq = 0;
        glGetIntegerv(GL_BLEND_SRC_RGB, &src);
        glGetIntegerv(GL_BLEND_DST_RGB, &dst);
        glGetIntegerv(GL_BLEND_EQUATION_RGB, &eq);
        INFO("identity blend " << on);
        CHECK((bool)glIsEnabled(GL_BLEND) == (on == 1));
        if (on) CHECK((src == GL_ONE && dst == GL_ZERO && eq == GL_FUNC_ADD));
    }
    const ImageDiff d = CompareImages(drawn[1], drawn[0], 0);
    CHECK(d.maxAbs == 0);   // the same pixels, exactly
    CHECK(MeanLuma(drawn[1], 0, 0, 1, 1) > 10.0);   // and a scene was drawn, not a blank
}

TEST_CASE("render: the identity blend writes the shader's value over a float target holding NaN or infinity", "[render]") {
    RequireGl();
    // A feedback pass (ISF PERSISTENT FLOAT buffers) draws over what it drew last frame. With the
    // identity blend the pixel must still be the shader's alone: a NaN or an infinity under it
    // (times the factor zero) must not come through, as it would not with blending off.
    struct Reset {
        ~Reset() { SetOverwriteBlendOverride(-1); }
    } reset;
    std::string log;
    const unsigned vs = CompileStage(GL_VERTEX_SHADER, FullscreenVertexShader(), &log);
    const unsigned fs = CompileStage(GL_FRAGMENT_SHADER, "#version 450\nout vec4 color; void main() { color = vec4(0.25, -2.0, 3.5, 0.75); }\n", &log);
    INFO(log);
    REQUIRE(vs);
    REQUIRE(fs);
    const unsigned prog = LinkStages({vs, fs}, &log);
    REQUIRE(prog);
    GLuint tex = 0, fbo = 0, vao = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &tex);
    glTextureStorage2D(tex, 1, GL_RGBA32F, 8, 8);
    glCreateFramebuffers(1, &fbo);
    glNamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, tex, 0);
    glCreateVertexArrays(1, &vao);
    const float nan = std::nanf(""), inf = INFINITY;
    for (int on : {1, 0}) {
        SetOverwriteBlendOverride(on);
        for (const float under : {nan, inf, -inf}) {
            const float clear[4] = {under, under, under, under};
            glClearNamedFramebufferfv(fbo, GL_COLOR, 0, clear);
            glBindFramebuffer(GL_FRAMEBUFFER, fbo);
            glViewport(0, 0, 8, 8);
            glUseProgram(prog);
            glBindVertexArray(vao);
            SetOverwriteBlend();
            glDrawArrays(GL_TRIANGLES, 0, 3);
            std::vector<float> px(8 * 8 * 4);
            glReadPixels(0, 0, 8, 8, GL_RGBA, GL_FLOAT, px.data());
            INFO("identity blend " << on << ", under it " << under);
            int wrong = 0;
            for (size_t i = 0; i < px.size(); i += 4)
                wrong += !(px[i] == 0.25f && px[i + 1] == -2.0f && px[i + 2] == 3.5f && px[i + 3] == 0.75f);
            CHECK(wrong == 0);
        }
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glUseProgram(0);
    glBindVertexArray(0);
    glDisable(GL_BLEND);
    glDeleteVertexArrays(1, &vao);
    glDeleteFramebuffers(1, &fbo);
    glDeleteTextures(1, &tex);
    glDeleteProgram(prog);
}

// The one-site renderer (render/one_site.glsl, ONE_SITE 1): the march, the normal's samples, the
// shadow ray, the AO probes and the mirror bounce as phases of one loop with one call site of the
// scene's field, the same arithmetic in the same order as traceRay's functions. It draws the same
// picture: on llvmpipe byte for byte (measured on all six scenes); the tolerance here allows 2/255
// on 0.1 % of the pixels for another build's rounding. Every scene with its own effects, with the
// show's (PBR, a mirror bounce: the phases run again for the reflected ray), with hard shadows and
// tetrahedron normals (the other loops), with none; the compute path with its cone pre-pass (the
// primary ray starts at the tile's distance, the bounce at mirrorStart's).
TEST_CASE("render: the one-site renderer draws the picture the renderer's own functions draw", "[render]") {
    const fs::path dir = fs::path(SDFVJ_TEST_OUTPUT_DIR) / "one_site";
    fs::create_directories(dir);
    for (const std::string& scene : ListScenes()) {
        SECTION(scene) {
            SceneInfo info;
            std::string error;
            REQUIRE(FindScene(scene, &info, &error));
            const fs::path file = dir / (scene + "_one_site.glsl");
            REQUIRE(WriteSceneCopy(scene, "#define ONE_SITE 1", file));
            EffectSet show = info.effects, other = info.effects, none;
            REQUIRE(ParseEffectList("pbr,reflections=1", &show, &error));
            REQUIRE(ParseEffectList("hard_shadows,ao", &other, &error));
            other.normals = 2;
            none.normals = info.effects.normals;
            const std::pair<const char*, EffectSet> sets[] = {{"own", info.effects}, {"show", show}, {"hard+tetra", other}, {"none", none}};
            for (const auto& [label, effects] : sets) {
                Image shipped = RenderScene(scene, effects, RenderPath::Fragment, 96, 54);
                Image oneSite = RenderScene(file.string(), effects, RenderPath::Fragment, 96, 54);
                ImageDiff d = CompareImages(shipped, oneSite, 2);
                INFO(label << ": " << d.fractionOver * 100 << " % of pixels past 2/255, mean " << d.meanAbs << ", max " << d.maxAbs);
                CHECK(d.fractionOver <= 0.001);
                CHECK(d.meanAbs <= 0.05);
                if (d.maxAbs > 0) SavePng((dir / (scene + "_" + label + ".png")).string(), oneSite);
            }
            Image shipped = RenderScene(scene, show, RenderPath::Compute, 48, 32);
            Image oneSite = RenderScene(file.string(), show, RenderPath::Compute, 48, 32);
            ImageDiff d = CompareImages(shipped, oneSite, 2);
            INFO("compute, the show: " << d.fractionOver * 100 << " % of pixels past 2/255, max " << d.maxAbs);
            CHECK(d.fractionOver <= 0.001);
            // A save's quick tier also defines QUICK_TIER, for which a scene may pick code that builds
            // sooner (character.glsl): the same picture.
            const fs::path quick = dir / (scene + "_quick_tier.glsl");
            REQUIRE(WriteSceneCopy(scene, "#define ONE_SITE 1\n#define QUICK_TIER 1", quick));
            ImageDiff q = CompareImages(RenderScene(scene, info.effects, RenderPath::Fragment, 96, 54),
                                        RenderScene(quick.string(), info.effects, RenderPath::Fragment, 96, 54), 2);
            INFO("the quick tier's scene, own effects: " << q.fractionOver * 100 << " % of pixels past 2/255, max " << q.maxAbs);
            CHECK(q.fractionOver <= 0.001);
            CHECK(q.meanAbs <= 0.05);
        }
    }
}
