// The evaluator's GPU side (issue 12): render/eval.glsl's register machine and the scene's stub
// (shader/eval_program.h) draw what the scene's own compiled program draws, with the code the
// translator (shader/evaluator.h) makes; the stub is the same text whatever a save does inside
// the functions' bodies, while the code changes with it.
#include <catch2/catch.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include <epoxy/gl.h>

#include "gl_fixture.h"
#include "shader/eval_program.h"
#include "shader/evaluator.h"

using namespace sdfvj;
using namespace sdfvj::test;
namespace fs = std::filesystem;

namespace {

const fs::path kOutDir = fs::path(SDFVJ_TEST_OUTPUT_DIR) / "evaluator";

std::string ReadText(const fs::path& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// The scene's code as a save's first tier makes it: the unit, glslang, the machine's code.
bool TranslateScene(const SceneInfo& scene, const VariantKey& key, eval::Program* code, std::string* error) {
    std::string unit;
    std::vector<std::string> slots;
    return eval::AssembleEvaluatorUnit(scene, key, &unit, &slots, error) && eval::Translate(unit, slots, code, error);
}

// The scene's evaluator program, built (FAILs the test otherwise).
void BuildEvaluator(const SceneInfo& scene, const EffectSet& effects, RenderPath path, Program* program) {
    RequireGl();
    ShaderSource src;
    std::string error;
    // llvmpipe stops a shader's loops after 65535 iterations in all: the machine's loop unrolled there.
    const int unroll = IsSoftwareRenderer() ? kEvaluatorUnrollSoftware : 1;
    REQUIRE(AssembleEvaluatorProgram(scene, VariantKey{scene.path, effects, path}, &src, &error, unroll));
    fs::create_directories(kOutDir);
    std::ofstream(kOutDir / (scene.name + "_" + RenderPathName(path) + ".glsl")) << src.text;   // to read
    if (!program->Build(src, path, &error)) FAIL(error);
}

// One frame of `program` (an evaluator program with its code uploaded, or any other) as
// RenderScene draws one: time 1, the scene's defaults.
Image Draw(const Program& program, const SceneInfo& scene, int w, int h, double* ms = nullptr) {
    FrameRenderer fr;
    std::string error;
    REQUIRE(fr.Resize(w, h, &error));
    FrameInputs in;
    in.time = 1.0;
    for (const ParamDecl& d : scene.params) in.params.emplace_back(d.name, d.defaultValue);
    fr.Draw(program, scene, in, ms != nullptr);
    if (ms) *ms = fr.LastGpuMs();
    return Image{w, h, fr.ReadPixels()};
}

// `scene`'s text with `from` replaced by `to` (each must be there), written to `file`.
void WriteEdited(const SceneInfo& scene, const std::vector<std::pair<std::string, std::string>>& edits, const fs::path& file) {
    std::string text = ReadText(scene.path);
    for (const auto& [from, to] : edits) {
        const size_t at = text.find(from);
        INFO("edit: " << from);
        REQUIRE(at != std::string::npos);
        text.replace(at, from.size(), to);
    }
    fs::create_directories(file.parent_path());
    std::ofstream(file) << text;
}

}  // namespace

// eval.glsl's switch and the C++ enum are one list: the constants it reads are generated from the
// enum (EvaluatorOpConstants), and every op has exactly one case there.
TEST_CASE("evaluator render: eval.glsl handles every op of evaluator.h once under the enum's value", "[render][evaluator]") {
    const auto& ops = EvaluatorOpConstants();
    REQUIRE(ops.size() == eval::kOpCount);
    std::set<uint32_t> values;
    std::map<std::string, uint32_t> byName;
    for (const auto& [name, value] : ops) {
        values.insert(value);
        byName[name] = value;
    }
    CHECK(values.size() == eval::kOpCount);   // a permutation of 0..kOpCount-1
    CHECK(*values.rbegin() == eval::kOpCount - 1);
    CHECK(byName.size() == eval::kOpCount);
    CHECK(byName["EV_ADD"] == eval::kAdd);
    CHECK(byName["EV_JUMP_IF_NOT_ZERO"] == eval::kJumpIfNotZero);

    const std::string glsl = ReadText(fs::path(DataRoot()) / "shaders" / "render" / "eval.glsl");
    std::map<std::string, int> cases;
    static const std::regex kCase(R"(case\s+(EV_\w+)\s*:)");
    for (auto it = std::sregex_iterator(glsl.begin(), glsl.end(), kCase); it != std::sregex_iterator(); ++it) ++cases[(*it)[1]];
    for (const auto& [name, value] : ops) {
        INFO(name);
        CHECK(cases[name] == 1);
    }
    CHECK(cases.size() == ops.size());   // no case for a name the enum lacks

    // The program declares them with the enum's values, and the hooks' header slots in HookNames() order.
    SceneInfo midi;
    std::string error;
    REQUIRE(FindScene("midi", &midi, &error));
    ShaderSource src;
    REQUIRE(AssembleEvaluatorProgram(midi, VariantKey{midi.path, midi.effects, RenderPath::Fragment}, &src, &error));
    for (const auto& [name, value] : ops) CHECK(src.text.find("const uint " + name + " = " + std::to_string(value) + "u;\n") != std::string::npos);
    CHECK(src.text.find("const uint EV_HOOK_MAP = 0u;\n") != std::string::npos);
    CHECK(src.text.find("const uint EV_HOOK_SCENE_SETUP = " + std::to_string(eval::HookNames().size() - 1) + "u;\n") != std::string::npos);
    CHECK(src.text.find("const uint EV_HOOKS = " + std::to_string(eval::HookNames().size()) + "u;\n") != std::string::npos);
}

TEST_CASE("evaluator render: a scene's stub keeps its top level and calls the machine from its hooks", "[render][evaluator]") {
    SceneInfo midi;
    std::string error;
    REQUIRE(FindScene("midi", &midi, &error));
    ShaderSource src;
    REQUIRE(AssembleEvaluatorProgram(midi, VariantKey{midi.path, midi.effects, RenderPath::Fragment}, &src, &error));
    const std::string& t = src.text;
    CHECK(t.rfind("#version 450 core\n#define SCENE_EVALUATOR 1\n#define SCENE_SETUP_FRAME 0\n#define SCENE_TABLES 0\n"
                  "#define ONE_SITE 1\n#define CONE_PREPASS 0\n", 0) == 0);
    for (const char* kept : {"vec4 map(vec3 p) { return evalMap(p); }", "vec4 mapGround(vec3 p) { return evalMapGround(p); }",
                             "vec4 sceneBound() { return evalSceneBound(); }", "float sceneLipschitz() { return evalSceneLipschitz(); }",
                             "#define SCENE_BOUND 1", "const float MIDI_RADIUS = 1.45f;", "#ifndef SCENE_GLOBAL_LIPSCHITZ",
                             "uniform float u_twist;", "vec4 evalUniform(uint slot)", "case 0u: return vec4(u_time, 0.0, 0.0, 0.0);"}) {
        INFO(kept);
        CHECK(t.find(kept) != std::string::npos);
    }
    for (const char* gone : {"midiBlob", "midiCentre", "fDisplacement(q", "NAME\": \"midi"}) {
        INFO(gone);
        CHECK(t.find(gone) == std::string::npos);
    }
    // The library's functions stay (the renderer calls fOpUnionSmoothColor itself: SCENE_MAP_OF).
    CHECK(t.find("vec4 fOpUnionSmoothColor(") != std::string::npos);

    // What the scanner cannot stub for certain is refused with a reason.
    const fs::path dir = kOutDir / "stub";
    const std::pair<const char*, std::pair<std::string, std::string>> refused[] = {
        {"inside its body", {"vec3 midiCentre() {", "vec3 midiCentre() {\n#define MIDI_X 1\n"}},
        {"is not the renderer's", {"vec4 map(vec3 p) {", "vec4 map(vec2 p2) { vec3 p = vec3(p2, 0.0f);"}},
        {"closes nothing", {"vec3 midiCentre() {", "}\nvec3 midiCentre() {"}},
    };
    for (const auto& [why, edit] : refused) {
        SECTION(why) {
            const fs::path file = dir / "refused.glsl";
            WriteEdited(midi, {edit}, file);
            SceneInfo copy;
            REQUIRE(FindScene(file.string(), &copy, &error));
            CHECK_FALSE(AssembleEvaluatorProgram(copy, VariantKey{copy.path, copy.effects, RenderPath::Fragment}, &src, &error));
            INFO(error);
            CHECK(error.find(why) != std::string::npos);
        }
    }
}

// A save that edits inside functions (a helper's and a hook's body, lines added, comments) assembles
// the same evaluator program; its code differs. A new top-level constant makes another program.
TEST_CASE("evaluator render: an edit inside midi's functions leaves its evaluator program as it was and changes its code", "[render][evaluator]") {
    SceneInfo midi;
    std::string error;
    REQUIRE(FindScene("midi", &midi, &error));
    const VariantKey key{midi.path, midi.effects, RenderPath::Fragment};
    ShaderSource original;
    REQUIRE(AssembleEvaluatorProgram(midi, key, &original, &error));
    eval::Program originalCode;
    REQUIRE(TranslateScene(midi, key, &originalCode, &error));

    const fs::path file = kOutDir / "edit" / "midi.glsl";
    WriteEdited(midi, {{"fRoundBox(pTranslate(q, vec3(0.75f, -0.1f, 0.0f)), vec3(0.4f), 0.05f)",
                        "fSphere(pTranslate(q, vec3(0.75f, 0.1f, 0.0f)),\n        0.5f /* a sphere now */)"},
                       {"    return fOpUnionColor(mapGround(p), blob);", "    blob.xyz = vec3(blob.z, blob.y, blob.x);\n\n    return fOpUnionColor(mapGround(p), blob);"},
                       {"// The checkered ground plane y = 0.", "// The ground: checkered.\n// (two lines now)"}},
                file);
    SceneInfo edited;
    REQUIRE(FindScene(file.string(), &edited, &error));
    ShaderSource stub;
    REQUIRE(AssembleEvaluatorProgram(edited, VariantKey{edited.path, edited.effects, RenderPath::Fragment}, &stub, &error));
    CHECK(stub.hash == original.hash);
    CHECK(stub.text == original.text);
    eval::Program editedCode;
    const bool translated = TranslateScene(edited, VariantKey{edited.path, edited.effects, RenderPath::Fragment}, &editedCode, &error);
    INFO(error);
    REQUIRE(translated);
    CHECK(eval::PackCode(editedCode) != eval::PackCode(originalCode));

    const fs::path other = kOutDir / "edit" / "midi_const.glsl";
    WriteEdited(midi, {{"const float MIDI_DISPLACE_FREQ", "const float MIDI_EXTRA = 2.0f;\nconst float MIDI_DISPLACE_FREQ"}}, other);
    SceneInfo top;
    REQUIRE(FindScene(other.string(), &top, &error));
    REQUIRE(AssembleEvaluatorProgram(top, VariantKey{top.path, top.effects, RenderPath::Fragment}, &stub, &error));
    CHECK(stub.hash != original.hash);
}

// The machine on the GPU draws what the scene's compiled program draws. On llvmpipe the fragment
// path's frames are the same bytes (the machine runs the same float operations with the same
// built-ins, and the one-site renderer draws the renderer's picture) and the compute path's differ
// in a pixel (0.02 %: the compiled program's cone pre-pass, which the evaluator program leaves out,
// CONE_PREPASS 0). Tolerance: at most 0.5 % of the pixels more than 8/255 apart, for a GPU compiler
// that fuses or reorders the compiled field's arithmetic, which moves a hit by a step at a
// silhouette. Each frame is saved under test-images/evaluator/ to be looked at.
// `name` on `path` at w x h, drawn by its compiled program and by its evaluator program.
static void CheckEvaluated(const char* name, RenderPath path, int w, int h) {
    fs::create_directories(kOutDir);
    SceneInfo scene;
    std::string error;
    REQUIRE(FindScene(name, &scene, &error));
    const Image compiled = RenderScene(name, scene.effects, path, w, h);
    Program program;
    BuildEvaluator(scene, scene.effects, path, &program);
    eval::Program code;
    const bool translated = TranslateScene(scene, VariantKey{scene.path, scene.effects, path}, &code, &error);
    INFO(error);
    REQUIRE(translated);
    program.SetEvaluatorCode(eval::PackCode(code), code.constants);
    const Image evaluated = Draw(program, scene, w, h);
    SavePng((kOutDir / (std::string(name) + "_" + RenderPathName(path) + ".png")).string(), evaluated);
    SavePng((kOutDir / (std::string(name) + "_" + RenderPathName(path) + "_compiled.png")).string(), compiled);
    const ImageDiff d = CompareImages(compiled, evaluated, 8);
    INFO(code.code.size() << " instructions, " << code.constants.size() << " constants, " << code.registers
                          << " registers; over 8/255: " << d.fractionOver * 100 << " %, mean " << d.meanAbs << ", max " << d.maxAbs);
    CHECK(d.fractionOver <= 0.005);
    CHECK(d.meanAbs <= 0.5);
    // Not the compiled field by another way: the machine's code draws it. Every constant moved
    // (lengths, colours, the scene's numbers) moves the picture.
    eval::Program moved = code;
    for (auto& k : moved.constants)
        for (float& v : k) v = v * 1.25f + 0.05f;
    program.SetEvaluatorCode(eval::PackCode(moved), moved.constants);
    CHECK(CompareImages(compiled, Draw(program, scene, w, h), 8).fractionOver > 0.05);
}

// Every scene on the fragment path, and midi's on the compute path, small: on llvmpipe each
// evaluator program's first draw JITs the machine for seconds, and CI has two cores.
TEST_CASE("evaluator render: every scene drawn by the machine is its compiled program's picture, both paths", "[render][evaluator]") {
    for (const char* name : {"midi", "primitives", "character", "mandelbulb"})
        for (RenderPath path : {RenderPath::Fragment, RenderPath::Compute})
            if (path == RenderPath::Fragment || std::string(name) == "midi")
                SECTION(std::string(name) + " " + RenderPathName(path)) { CheckEvaluated(name, path, 48, 27); }
}

// The field scenes keep their hooks in an included file (lib/field_scene.glsl), stubbed there, and
// compose the floor's union from their frame state (SCENE_MAP_OF with the blend's reciprocal), which
// the evaluator program leaves to the renderer's own form. Small: a pixel runs 80,000 instructions.
TEST_CASE("evaluator render: the field scenes drawn by the machine are their compiled pictures", "[render][evaluator]") {
    for (const char* name : {"field50"})   // field150 is the same code with more cells (CI's time)
        SECTION(name) { CheckEvaluated(name, RenderPath::Fragment, 32, 18); }
}

// The machine on the GPU (render/eval.glsl) and on the CPU (evaluator.h Run) compute the same
// hooks from the same code: every scene's at 512 points through its bound, each hook a scene has.
// Tolerance: 1e-4 of the value's size (llvmpipe's sin, pow, ... are not libm's), and on at most
// 1 % of the points more (mandelbulb's orbits amplify an ulp near its surface).
TEST_CASE("evaluator render: the GPU machine computes what the CPU machine computes", "[render][evaluator]") {
    RequireGl();
    for (const char* name : {"midi", "primitives", "character", "mandelbulb", "field50"}) {
        SECTION(name) {
            SceneInfo scene;
            std::string error;
            REQUIRE(FindScene(name, &scene, &error));
            eval::Program code;
            REQUIRE(TranslateScene(scene, VariantKey{scene.path, scene.effects, RenderPath::Compute}, &code, &error));
            ShaderSource src;
            REQUIRE(AssembleEvaluatorProbe(scene, &src, &error));
            Program probe;
            if (!probe.Build(src, RenderPath::Compute, &error)) FAIL(error);
            probe.SetEvaluatorCode(eval::PackCode(code), code.constants);
            // Each uniform slot's value, the same on both machines (ints integral: the GPU's are ints).
            const std::map<std::string, std::array<float, 4>> builtins = {
                {"u_time", {1.0f, 0, 0, 0}}, {"u_frame", {3, 0, 0, 0}}, {"u_resolution", {96, 54, 0, 0}},
                {"u_beat", {0.25f, 0, 0, 0}}, {"u_bpm", {120, 0, 0, 0}}, {"u_maxSteps", {128, 0, 0, 0}},
                {"u_shadowSteps", {48, 0, 0, 0}}, {"u_aoSamples", {5, 0, 0, 0}}, {"u_effectsOff", {0, 0, 0, 0}}};
            eval::Machine cpu;
            for (const std::string& slot : code.uniforms) {
                std::array<float, 4> v{0.5f, 0.25f, 0.125f, 0.0f};
                if (builtins.count(slot)) v = builtins.at(slot);
                for (const ParamDecl& d : scene.params)
                    if (slot == "u_" + d.name) v = {d.defaultValue, 0, 0, 0};
                probe.Set(slot, v[0]);
                probe.Set(slot, v[0], v[1]);
                probe.Set(slot, v[0], v[1], v[2]);
                cpu.uniformValues.push_back(v);
            }
            std::vector<std::array<float, 4>> points;
            for (int i = 0; i < 8; ++i)
                for (int j = 0; j < 8; ++j)
                    for (int k = 0; k < 8; ++k) points.push_back({-1.5f + 3.0f * i / 7, -0.6f + 3.0f * j / 7, -1.5f + 3.0f * k / 7, 0});
            GLuint buffers[2];
            glCreateBuffers(2, buffers);
            glNamedBufferData(buffers[0], (GLsizeiptr)(points.size() * 16), points.data(), GL_STATIC_DRAW);
            glNamedBufferData(buffers[1], (GLsizeiptr)(points.size() * 8 * 16), nullptr, GL_STATIC_READ);
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buffers[0]);
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, buffers[1]);
            probe.BindEvaluator();
            glUseProgram(probe.Id());
            glDispatchCompute((GLuint)points.size() / 64, 1, 1);
            glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
            std::vector<std::array<float, 4>> gpu(points.size() * 8);
            glGetNamedBufferSubData(buffers[1], 0, (GLsizeiptr)(gpu.size() * 16), gpu.data());
            glDeleteBuffers(2, buffers);

            const char* hooks[] = {"map", "mapGround", "mapObjects", "sceneBound", "sceneLipschitz", "sceneGroundBlend", "sceneBoxMin", "sceneBoxMax"};
            const int lanes[] = {4, 4, 4, 4, 1, 1, 3, 3};
            if (code.Find("sceneSetup")) REQUIRE(eval::Run(code, "sceneSetup", {}, &cpu, nullptr, &error));
            for (int h = 0; h < 8; ++h) {
                if (!code.Find(hooks[h])) continue;
                int off = 0;
                double worst = 0;
                for (size_t n = 0; n < points.size(); ++n) {
                    std::array<float, 4> want{};
                    const bool field = h < 3;
                    if (!eval::Run(code, hooks[h], field ? std::vector<std::array<float, 4>>{points[n]} : std::vector<std::array<float, 4>>{}, &cpu, &want, &error)) FAIL(error);
                    const std::array<float, 4>& got = gpu[8 * n + h];
                    double err = 0;
                    for (int c = 0; c < lanes[h]; ++c) err = std::max(err, std::abs((double)got[c] - want[c]) / std::max(1.0, std::abs((double)want[c])));
                    worst = std::max(worst, err);
                    if (err > 1e-4) ++off;
                    if (err > 1e-4 && off <= 3)
                        WARN(name << " " << hooks[h] << " at (" << points[n][0] << ", " << points[n][1] << ", " << points[n][2] << "): gpu " << got[0] << " " << got[1] << " " << got[2] << " " << got[3] << ", cpu " << want[0] << " " << want[1] << " " << want[2] << " " << want[3]);
                }
                INFO(name << " " << hooks[h] << ": " << off << " of " << points.size() << " points past 1e-4, worst " << worst);
                CHECK(off <= (int)points.size() / 100);
            }
        }
    }
}

// The save's case: the program built for midi as it was draws an edited midi from the edit's
// code alone, the picture the edit's own compiled program draws.
TEST_CASE("evaluator render: midi's evaluator program draws an edit of midi from the edit's code", "[render][evaluator]") {
    SceneInfo midi;
    std::string error;
    REQUIRE(FindScene("midi", &midi, &error));
    Program program;
    BuildEvaluator(midi, midi.effects, RenderPath::Fragment, &program);
    const fs::path file = kOutDir / "save" / "midi.glsl";
    WriteEdited(midi, {{"fRoundBox(pTranslate(q, vec3(0.75f, -0.1f, 0.0f)), vec3(0.4f), 0.05f)", "fSphere(pTranslate(q, vec3(0.75f, 0.1f, 0.0f)), 0.5f)"},
                       {"res = fOpUnionSmoothColor(res, vec4(0.95f, 0.80f, 0.15f,", "if (u_time < -1.0f) res = fOpUnionSmoothColor(res, vec4(0.95f, 0.80f, 0.15f,"}},
                file);
    SceneInfo edited;
    REQUIRE(FindScene(file.string(), &edited, &error));
    eval::Program code;
    const bool translated = TranslateScene(edited, VariantKey{edited.path, edited.effects, RenderPath::Fragment}, &code, &error);
    INFO(error);
    REQUIRE(translated);
    program.SetEvaluatorCode(eval::PackCode(code), code.constants);
    const Image evaluated = Draw(program, edited, 96, 54);
    SavePng((kOutDir / "midi_edit.png").string(), evaluated);
    const ImageDiff same = CompareImages(RenderScene(file.string(), edited.effects, RenderPath::Fragment, 96, 54), evaluated, 8);
    INFO("against the edit's compiled program: over 8/255 " << same.fractionOver * 100 << " %, max " << same.maxAbs);
    CHECK(same.fractionOver <= 0.005);
    CHECK(CompareImages(RenderScene("midi", midi.effects, RenderPath::Fragment, 96, 54), evaluated, 8).fractionOver > 0.01);
}

// Code that never returns (a bad buffer, a translator's bug) ends: the machine stops an invocation
// after EV_MAX_STEPS instructions in all. A small frame: llvmpipe runs every one of them.
TEST_CASE("evaluator render: code that loops for ever still ends the frame", "[render][evaluator]") {
    SceneInfo midi;
    std::string error;
    REQUIRE(FindScene("midi", &midi, &error));
    Program program;
    BuildEvaluator(midi, midi.effects, RenderPath::Fragment, &program);
    std::vector<std::array<uint32_t, 4>> code(eval::HookNames().size(), std::array<uint32_t, 4>{0, eval::kNone, eval::kNone, 1});
    eval::Instr loop;
    loop.op = eval::kJump;   // instruction 0: jump to 0
    code.push_back(loop.Packed());
    program.SetEvaluatorCode(code, {});
    const auto t0 = std::chrono::steady_clock::now();
    Draw(program, midi, 4, 4);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    INFO(s << " s");
    CHECK(s < 60.0);
}

// Not a check, a measurement (hidden: `test_render "[.timing]"`): a frame of the evaluator program
// against the scene's compiled program, the median of 3 after one unmeasured, at 160x90.
TEST_CASE("evaluator render: frame time of the machine against the compiled program", "[.timing]") {
    RequireGl();
    const char* only = std::getenv("SDFVJ_EVAL_TIMING_SCENE");
    for (const char* name : {"midi", "primitives", "character", "mandelbulb"}) {
        if (only && std::string(only) != name) continue;
        for (RenderPath path : {RenderPath::Fragment, RenderPath::Compute}) {
            SceneInfo scene;
            std::string error;
            REQUIRE(FindScene(name, &scene, &error));
            ShaderSource src;
            REQUIRE(AssembleProgram(scene, VariantKey{scene.path, scene.effects, path}, &src, &error));
            Program compiled, evaluated;
            if (!compiled.Build(src, path, &error)) FAIL(error);
            BuildEvaluator(scene, scene.effects, path, &evaluated);
            eval::Program code;
            REQUIRE(TranslateScene(scene, VariantKey{scene.path, scene.effects, path}, &code, &error));
            evaluated.SetEvaluatorCode(eval::PackCode(code), code.constants);
            auto median = [&](const Program& p) {
                std::vector<double> ms;
                for (int i = 0; i < 4; ++i) {
                    double t = 0;
                    Draw(p, scene, 160, 90, &t);
                    if (i > 0) ms.push_back(t);
                }
                return MedianMs(ms);
            };
            const double c = median(compiled), e = median(evaluated);
            WARN(name << " " << RenderPathName(path) << " 160x90: compiled " << c << " ms, evaluator " << e << " ms (" << e / c << "x)");
        }
    }
}
