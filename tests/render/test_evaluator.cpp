// The scene evaluator (issue 12, src/shader/evaluator.h): GLSL -> SPIR-V (glslang) -> register
// machine code, run on the CPU machine, against the C++ float build of each scene
// (src/accuracy/cpu_scene.h) and against hand-computed values for single constructs. No GL.
#include <catch2/catch.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <cmath>
#include <random>

#include "accuracy/cpu_scene.h"
#include "shader/eval_program.h"
#include "shader/evaluator.h"

using namespace sdfvj;
using namespace sdfvj::eval;

namespace {

using V4 = std::array<float, 4>;

// A tiny unit: `body` defines hooks (map, sceneBound, ...); main() calls map so glslang keeps it.
std::string Unit(const std::string& body, const std::string& calls = "o = map(vec3(u_a));") {
    return "#version 450 core\nuniform float u_a;\nuniform vec3 u_v;\n" + body +
           "\nlayout(local_size_x = 1) in;\nlayout(std430, binding = 0) buffer O { vec4 o; };\nvoid main() { " + calls +
           " }\n";
}

Program MustTranslate(const std::string& unit, std::vector<std::string> slots = {"u_a", "u_v"}) {
    Program p;
    std::string error;
    INFO(unit);
    const bool ok = Translate(unit, slots, &p, &error);
    INFO(error);
    REQUIRE(ok);
    return p;
}

V4 Call(const Program& p, const std::string& name, std::vector<V4> args, Machine* m) {
    V4 r{};
    std::string error;
    INFO(error);
    REQUIRE(Run(p, name, args, m, &r, &error));
    return r;
}

V4 Map(const Program& p, V4 arg, std::vector<V4> uniforms = {{0, 0, 0, 0}, {0, 0, 0, 0}}) {
    Machine m;
    m.uniformValues = uniforms;
    return Call(p, "map", {arg}, &m);
}

void CheckNear(V4 got, V4 want, int lanes = 4) {
    for (int i = 0; i < lanes; ++i) {
        INFO("lane " << i << ": got " << got[i] << ", want " << want[i]);
        CHECK(std::fabs(got[i] - want[i]) <= 1e-5f * (1.0f + std::fabs(want[i])));
    }
}

}  // namespace

TEST_CASE("evaluator: a loop and an if/else", "[evaluator]") {
    const Program p = MustTranslate(Unit(R"(
vec4 map(vec3 p) {
    float s = 0.0;
    for (int i = 0; i < 5; i++) {
        if (float(i) < p.x) s += float(i);
        else s -= 1.0;
    }
    return vec4(s, p.y * 2.0, 0.0, 1.0);
})"));
    CheckNear(Map(p, {2.5f, 3, 0, 0}), {0 + 1 + 2 - 1 - 1, 6, 0, 1});
    CheckNear(Map(p, {10, -1, 0, 0}), {10, -2, 0, 1});
}

TEST_CASE("evaluator: structs and functions with out and inout params", "[evaluator]") {
    const Program p = MustTranslate(Unit(R"(
struct S { float a; vec3 b; };
S make(float x) { S s; s.a = x; s.b = vec3(x, 2.0 * x, 3.0 * x); return s; }
void split(in float x, out float whole, inout float acc) { whole = floor(x); acc += x - whole; }
vec4 map(vec3 p) {
    S s = make(p.x);
    s.b.y += 1.0;
    float w, acc = 10.0;
    split(p.y, w, acc);
    return vec4(s.a + s.b.y, s.b.z, w, acc);
})"));
    CheckNear(Map(p, {2, 3.25f, 0, 0}), {2 + 5, 6, 3, 10.25f});
}

TEST_CASE("evaluator: matrices and swizzles", "[evaluator]") {
    const Program p = MustTranslate(Unit(R"(
vec4 map(vec3 p) {
    mat2 r = mat2(0.0, 1.0, -1.0, 0.0);          // 90 degrees
    vec2 q = r * p.xy;                           // (-y, x)
    vec2 t = p.xy * r;                           // (y, -x)
    mat3 m = mat3(1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0);
    vec3 mv = transpose(m) * vec3(1.0, 0.0, 0.0); // the first row of m: (1, 4, 7)
    mat2 rr = r * r * 2.0;                       // -2 I
    vec4 v = vec4(0.0);
    v.zx = q;                                    // a swizzle store
    v.y = mv.y + rr[0][0] + t.x;
    v.w = mv.z;
    return v;
})"));
    // p = (2, 3): q = (-3, 2), t = (3, -2), v.z = -3, v.x = 2, v.y = 4 - 2 + 3, v.w = 7
    CheckNear(Map(p, {2, 3, 0, 0}), {2, 5, -3, 7});
}

TEST_CASE("evaluator: copies and one-lane swizzles fold into what reads them, a copy whose source is written again stays", "[evaluator]") {
    const Program p = MustTranslate(Unit(R"(
vec4 map(vec3 p) {
    vec3 q = p;                  // a copy
    float y = q.y;               // one lane of it
    vec3 s = vec3(y) * q;        // that lane in all four
    float z = s.z;
    vec3 r = q.zzz + p.xxx;
    p.x = 5.0;                   // p written again: q must keep p's old value
    return vec4(y, z, r.x, q.x + p.x);
})"));
    // p = (2, 3, 4): y = 3, s = (6, 9, 12), z = 12, r.x = 4 + 2, q.x + p.x = 2 + 5
    CheckNear(Map(p, {2, 3, 4, 0}), {3, 12, 6, 7});
    // Without the second write to p: every swizzle that only put one lane in all four was folded
    // into its readers (an operand's lane, evaluator.h), and so was every copy of a register but the
    // result's, into the entry's result register.
    const Program folded = MustTranslate(Unit(R"(
vec4 map(vec3 p) {
    vec3 q = p;
    float y = q.y;
    vec3 s = vec3(y) * q;
    return vec4(y, s.z, q.z + p.x, 1.0);
})"));
    CheckNear(Map(folded, {2, 3, 4, 0}), {3, 12, 6, 1});
    int broadcasts = 0, copies = 0;
    for (const Instr& in : folded.code) {
        if (in.op == kSwizzle && in.b == kNone && (in.imm == 0 || in.imm == 0x249 || in.imm == 0x492 || in.imm == 0x6db)) ++broadcasts;
        if (in.op == kMov && (in.a & kConstFlag) == 0) ++copies;
    }
    INFO(folded.code.size() << " instructions");
    CHECK(broadcasts == 0);
    CHECK(copies <= 1);
}

TEST_CASE("evaluator: an int loop with shifts and masks", "[evaluator]") {
    const Program p = MustTranslate(Unit(R"(
vec4 map(vec3 p) {
    int n = int(p.x);
    int bits = 0, sum = 0;
    for (int i = 0; i < 8; i++) {
        bits += (n >> i) & 1;
        sum = sum ^ (i << 2);
    }
    uint u = uint(n) % 5u;
    int q = -7 / 2, r = -7 % 3;
    return vec4(float(bits), float(sum), float(u), float(q * 10 + (n | 16)));
})"));
    int sum = 0;
    for (int i = 0; i < 8; i++) sum ^= i << 2;
    // 181 = 0b10110101: 5 bits set; -7 / 2 = -3 (truncation)
    CheckNear(Map(p, {181, 0, 0, 0}), {5, (float)sum, 181 % 5, -30 + (181 | 16)});
}

TEST_CASE("evaluator: built-in math, uniforms, globals and arrays", "[evaluator]") {
    const Program p = MustTranslate(Unit(R"(
float g_k;
float table[4];
void sceneSetup() { g_k = u_a * 2.0; }
vec4 map(vec3 p) {
    for (int i = 0; i < 4; i++) table[i] = float(i * i);
    int j = int(p.z);
    float l = length(p) + distance(p, vec3(0.0)) ;
    vec3 n = normalize(vec3(3.0, 0.0, 4.0));
    float s = smoothstep(0.0, 1.0, 0.5) + step(0.5, 0.25) + mix(1.0, 3.0, 0.25) + clamp(5.0, 0.0, 2.0);
    return vec4(l + table[j], n.z + g_k, s + u_v.y, mod(-1.0, 3.0) + fract(1.25) + atan(1.0, 1.0) * 4.0);
})",
                                         "sceneSetup(); o = map(vec3(u_a));"));
    Machine m;
    m.uniformValues = {{1.5f, 0, 0, 0}, {0, 10, 0, 0}};
    Call(p, "sceneSetup", {}, &m);
    const V4 r2 = Call(p, "map", {{0, 0, 3, 0}}, &m);   // |p| = 3, table[int(p.z)] = 9
    CheckNear(r2, {3 + 3 + 9, 0.8f + 3.0f, 0.5f + 0 + 1.5f + 2 + 10, 2 + 0.25f + 3.14159265f});
    CHECK(p.globals >= 1);
}

TEST_CASE("evaluator: a texture lookup fails with a message naming it", "[evaluator]") {
    Program p;
    std::string error;
    CHECK_FALSE(Translate(Unit("uniform sampler2D u_tex;\nvec4 map(vec3 p) { return texture(u_tex, p.xy); }"),
                          {"u_a", "u_v"}, &p, &error));
    INFO(error);
    CHECK(error.find("evaluator: ") == 0);
    CHECK(error.find("texture") != std::string::npos);
    CHECK(error.find("is not supported") != std::string::npos);
    CHECK_FALSE(Translate(Unit("vec4 map(vec3 p) { return vec4(u_b); }\nuniform float u_b;"), {"u_a", "u_v"}, &p, &error));
    CHECK(error.find("u_b") != std::string::npos);
    CHECK_FALSE(Translate(Unit("vec4 map(vec3 p) { return vec4(p, undefinedThing); }"), {"u_a", "u_v"}, &p, &error));
    CHECK(error.find("undefinedThing") != std::string::npos);
}

TEST_CASE("evaluator: PackCode puts one header per hook before the code", "[evaluator]") {
    const Program p = MustTranslate(Unit("vec4 map(vec3 p) { return vec4(p, 1.0); }\nfloat sceneLipschitz() { return 2.0; }",
                                         "o = map(vec3(u_a)) + vec4(sceneLipschitz());"));
    const auto packed = PackCode(p);
    REQUIRE(packed.size() == HookNames().size() + p.code.size());
    for (size_t k = 0; k < HookNames().size(); ++k) {
        const Entry* e = p.Find(HookNames()[k]);
        CHECK(packed[k][3] == (e ? 1u : 0u));
        if (e) CHECK(packed[k][0] == e->pc);
    }
    Machine m;
    CHECK(Call(p, "sceneLipschitz", {}, &m)[0] == 2.0f);
}

// ---- the shipped scenes against their C++ float builds ----

namespace {

// The uniform values of a slot table from the CPU build's uniforms (CAMERA_UNIFORMS and others the
// C++ build does not expose stay 0: no scene hook reads them).
std::vector<V4> UniformValues(const std::vector<std::string>& slots, const accuracy::CpuScene<float>& s) {
    std::vector<V4> v(slots.size(), V4{0, 0, 0, 0});
    for (size_t k = 0; k < slots.size(); ++k) {
        const std::string& n = slots[k];
        auto f = [&](float x) { v[k] = {x, 0, 0, 0}; };
        auto v3 = [&](const glm::vec3& x) { v[k] = {x.x, x.y, x.z, 0}; };
        if (n == "u_time") f(*s.time);
        else if (n == "u_frame") f((float)*s.frame);
        else if (n == "u_resolution") v[k] = {s.resolution->x, s.resolution->y, 0, 0};
        else if (n == "u_beat") f(*s.beat);
        else if (n == "u_camPos") v3(*s.camPos);
        else if (n == "u_camTarget") v3(*s.camTarget);
        else if (n == "u_fov") f(*s.fov);
        else if (n == "u_lightDir") v3(*s.lightDir);
        else if (n == "u_lightColor") v3(*s.lightColor);
        else if (n == "u_maxSteps") f((float)*s.maxSteps);
        else if (n == "u_hitEps") f(*s.hitEps);
        else if (n == "u_maxDist") f(*s.maxDist);
        else if (n == "u_stepFactor") f(*s.stepFactor);
        else if (n == "u_fixedStep") f(*s.fixedStep);
        else if (n == "u_shadowSteps") f((float)*s.shadowSteps);
        else if (n == "u_shadowK") f(*s.shadowK);
        else if (n == "u_aoSamples") f((float)*s.aoSamples);
        else if (n == "u_normalEps") f(*s.normalEps);
        else if (n == "u_roughness") f(*s.roughness);
        else if (n == "u_metalness") f(*s.metalness);
        else if (n == "u_effectsOff") f((float)*s.effectsOff);
        else if (n.rfind("u_", 0) == 0 && s.inputs.count(n.substr(2))) f(*s.inputs.at(n.substr(2)));
    }
    return v;
}

// Assembles and translates a scene; ms: the two together, assembleMs: the unit alone.
bool TranslateScene(const std::string& name, Program* p, std::string* error, double* ms, double* assembleMs = nullptr) {
    SceneInfo scene;
    if (!FindScene(name, &scene, error)) return false;
    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    std::string unit;
    std::vector<std::string> slots;
    VariantKey key{scene.path, scene.effects, RenderPath::Fragment};
    if (!AssembleEvaluatorUnit(scene, key, &unit, &slots, error)) return false;
    const auto t1 = Clock::now();
    const bool ok = Translate(unit, slots, p, error);
    *ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    if (assembleMs) *assembleMs = std::chrono::duration<double, std::milli>(t1 - t0).count();
    return ok;
}

}  // namespace

// The evaluator must take these scenes; the field scenes may be refused (their lib/field.glsl
// cells loop may not fit the registers), but then with a message and never a crash.
TEST_CASE("evaluator: every shipped scene translates or is refused with a message", "[evaluator]") {
    const std::vector<std::string> required = {"midi", "primitives", "character", "mandelbulb"};
    for (const auto& build : accuracy::CpuSceneBuilds()) {
        Program p;
        std::string error;
        double cold = 0, ms = 0, assembleMs = 0;
        if (&build == &accuracy::CpuSceneBuilds().front()) {   // glslang's set-up, once per process
            const auto t0 = std::chrono::steady_clock::now();
            PrepareTranslator();
            const double setupMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
            WARN("PrepareTranslator (glslang's set-up, once a process): " << setupMs << " ms");
        }
        TranslateScene(build.name, &p, &error, &cold);
        const bool ok = TranslateScene(build.name, &p, &error, &ms, &assembleMs);
        WARN(build.name << ": " << (ok ? "translated" : "refused: " + error) << " in " << ms << " ms (unit "
                        << assembleMs << " ms; " << cold << " ms the first time for this scene), "
                        << p.code.size() << " instructions, " << p.constants.size() << " constants, "
                        << p.registers << " registers (" << p.globals << " globals)");
        if (std::find(required.begin(), required.end(), build.name) != required.end()) {
            INFO(build.name << ": " << error);
            CHECK(ok);
        } else if (!ok) {
            CHECK(error.rfind("evaluator: ", 0) == 0);
        }
    }
}

// map() on the machine equals the C++ float build's map() at a few thousand points in and around
// the scene's bound, for the inputs' defaults, minima and maxima. Tolerance |dw| <= 1e-4 (1 + |w|)
// and colour within 1e-4: both run the same float32 ops in the same order (glslang only folds
// constants, which the C++ compiler folds too), so they differ only where a libm call or a folded
// constant rounds differently, by an ulp or so; 1e-4 leaves room for that ulp to grow through a
// few dozen ops (the Mandelbulb's iterations) and still catches any wrong op, which is off by far
// more.
TEST_CASE("evaluator: each accepted scene's map equals its C++ float build", "[evaluator]") {
    std::mt19937 rng(12);
    for (const auto& build : accuracy::CpuSceneBuilds()) {
        double worstOfScene = 0;
        Program p;
        std::string error;
        double ms = 0;
        if (!TranslateScene(build.name, &p, &error, &ms)) continue;
        SceneInfo scene;
        REQUIRE(FindScene(build.name, &scene, &error));
        accuracy::CpuScene<float> cpu = build.make32();
        const std::vector<std::string> slots = UniformSlots(scene);
        for (int setting = 0; setting < 4; ++setting) {
            for (const ParamDecl& d : scene.params) {
                float v = d.defaultValue;
                if (setting == 1) v = d.minValue;
                if (setting == 2) v = d.maxValue;
                if (setting == 3) v = std::uniform_real_distribution<float>(d.minValue, d.maxValue)(rng);
                *cpu.inputs.at(d.name) = ClampParam(d, v);
            }
            *cpu.time = setting * 1.7f;
            *cpu.beat = 0.25f * setting;
            Machine m;
            m.uniformValues = UniformValues(slots, cpu);
            if (p.Find("sceneSetup")) Call(p, "sceneSetup", {}, &m);
            glm::vec4 bound = cpu.hasBound ? cpu.sceneBound() : glm::vec4(0, 1, 0, 3);
            if (p.Find("sceneBound")) {
                const V4 b = Call(p, "sceneBound", {}, &m);
                CHECK(std::fabs(b[3] - bound.w) <= 1e-4f * (1 + std::fabs(bound.w)));
            }
            int bad = 0;
            double worst = 0;
            for (int k = 0; k < 1000; ++k) {
                std::uniform_real_distribution<float> u(-1.5f, 1.5f);
                const glm::vec3 q(bound.x + bound.w * u(rng), bound.y + bound.w * u(rng), bound.z + bound.w * u(rng));
                const glm::vec4 want = cpu.map(q);
                const V4 got = Call(p, "map", {{q.x, q.y, q.z, 0}}, &m);
                const double dw = std::fabs(got[3] - want.w) / (1 + std::fabs(want.w));
                double dc = 0;
                for (int i = 0; i < 3; ++i) dc = std::max(dc, (double)std::fabs(got[i] - want[i]));
                worst = std::max(worst, std::max(dw, dc));
                if (dw > 1e-4 || dc > 1e-4) {
                    if (bad++ < 3)
                        WARN(build.name << " setting " << setting << " at (" << q.x << ", " << q.y << ", " << q.z
                                        << "): machine (" << got[0] << ", " << got[1] << ", " << got[2] << ", " << got[3]
                                        << "), C++ (" << want.x << ", " << want.y << ", " << want.z << ", " << want.w << ")");
                }
            }
            INFO(build.name << " setting " << setting << ": worst relative difference " << worst);
            CHECK(bad == 0);
            worstOfScene = std::max(worstOfScene, worst);
        }
        WARN(build.name << ": map() within " << worstOfScene << " of the C++ float build (relative in w, absolute in colour)");
    }
}

// A scene file written into the tests' output folder, loaded.
static SceneInfo WrittenScene(const std::string& file, const std::string& text) {
    const std::string path = std::string(SDFVJ_TEST_OUTPUT_DIR) + "/" + file;
    std::filesystem::create_directories(SDFVJ_TEST_OUTPUT_DIR);
    std::ofstream(path) << text;
    SceneInfo scene;
    std::string error;
    REQUIRE(LoadScene(path, &scene, &error));
    return scene;
}

// A refused construct names the scene file and line the performer edited.
TEST_CASE("evaluator: a refused scene names its file and line", "[evaluator]") {
    const SceneInfo scene = WrittenScene("evaluator_refused.glsl",
                                         "/*{ \"NAME\": \"refused\", \"INPUTS\": [{\"NAME\": \"k\", \"TYPE\": \"float\", \"DEFAULT\": 1.0}] }*/\n"
                                         "#include \"lib/common.glsl\"\n"
                                         "float g_hash(vec3 p) { return intBitsToFloat(floatBitsToInt(p.x) & 0x7fffff); }\n"
                                         "vec4 map(vec3 p) { return vec4(1.0, 1.0, 1.0, length(p) - u_k + g_hash(p)); }\n"
                                         "float sceneLipschitz() { return 1.0; }\n");
    std::string error, unit;
    std::vector<std::string> slots;
    REQUIRE(AssembleEvaluatorUnit(scene, VariantKey{scene.path, scene.effects, RenderPath::Fragment}, &unit, &slots, &error));
    CHECK(slots.back() == "u_k");
    Program p;
    CHECK_FALSE(Translate(unit, slots, &p, &error));
    INFO(error);
    CHECK(error.find("evaluator_refused.glsl:3: ") != std::string::npos);
    CHECK(error.find("bit cast") != std::string::npos);
}

TEST_CASE("evaluator: a #line whose source number overflows an int is refused with a message and nothing thrown", "[evaluator]") {
    const SceneInfo scene = WrittenScene("evaluator_line_overflow.glsl",
                                         "/*{ \"NAME\": \"overflow\", \"INPUTS\": [] }*/\n"
                                         "#include \"lib/common.glsl\"\n"
                                         "#line 3 99999999999999999999\n"
                                         "vec4 map(vec3 p) { return vec4(1.0, 1.0, 1.0, length(p) - 1.0); }\n"
                                         "float sceneLipschitz() { return 1.0; }\n");
    std::string error;
    ShaderSource src;
    bool ok = true;
    REQUIRE_NOTHROW(ok = AssembleEvaluatorProgram(scene, VariantKey{scene.path, scene.effects, RenderPath::Fragment}, &src, &error));
    CHECK_FALSE(ok);
    INFO(error);
    CHECK(error.find("#line names source 99999999999999999999") != std::string::npos);
}
