// The shader module: include expansion, errors mapped back to the file the performer edited,
// and variants that leave out what a scene does not call for.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "gl_fixture.h"
#include "render/live_program.h"
#include "shader/literals.h"

using namespace sdfvj;
using namespace sdfvj::test;
namespace fs = std::filesystem;

namespace {

fs::path TempDir(const std::string& name) {
    fs::path d = fs::temp_directory_path() / ("sdfvj-test-" + name + "-" + std::to_string(::getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

void Write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

const char* kHeader = "/*{ \"NAME\": \"t\", \"INPUTS\": [{\"NAME\": \"r\", \"DEFAULT\": 0.5, \"MIN\": 0, \"MAX\": 1}] }*/\n";

bool Has(const std::vector<std::string>& v, const std::string& s) { return std::find(v.begin(), v.end(), s) != v.end(); }

}  // namespace

TEST_CASE("shader: compile errors name the edited file and line, also inside an include", "[shader]") {
    RequireGl();
    fs::path dir = TempDir("errors");
    Write(dir / "helper.glsl", "// helper\nfloat helper(float x) {\n    return x * undefinedThing;\n}\n");
    Write(dir / "scene.glsl", std::string(kHeader) + "#include \"helper.glsl\"\nvec4 map(vec3 p) { return vec4(1.0f, 1.0f, 1.0f, length(p) - u_r); }\nfloat sceneLipschitz() { return 1.0f; }\n");
    SceneInfo scene;
    std::string error;
    REQUIRE(LoadScene((dir / "scene.glsl").string(), &scene, &error));
    ShaderSource src;
    REQUIRE(AssembleProgram(scene, VariantKey{scene.path, {}, RenderPath::Fragment}, &src, &error));
    Program prog;
    REQUIRE_FALSE(prog.Build(src, RenderPath::Fragment, &error));
    INFO(error);
    CHECK(error.find("helper.glsl:3:") != std::string::npos);
    CHECK(error.find("undefinedThing") != std::string::npos);
    CHECK_FALSE(prog.IsValid());

    // An error in the scene itself, below the include, keeps its own line numbers.
    Write(dir / "helper.glsl", "float helper(float x) { return x; }\n");
    Write(dir / "scene.glsl", std::string(kHeader) + "#include \"helper.glsl\"\nvec4 map(vec3 p) {\n  return vec4(1.0f, 1.0f, 1.0f, fNoSuchThing(p));\n}\nfloat sceneLipschitz() { return 1.0f; }\n");
    REQUIRE(AssembleProgram(scene, VariantKey{scene.path, {}, RenderPath::Fragment}, &src, &error));
    REQUIRE_FALSE(prog.Build(src, RenderPath::Fragment, &error));
    INFO(error);
    CHECK(error.find("scene.glsl:4:") != std::string::npos);
}

TEST_CASE("shader: a missing include and a broken header are one readable line", "[shader]") {
    fs::path dir = TempDir("missing");
    Write(dir / "scene.glsl", std::string(kHeader) + "#include \"nope.glsl\"\n");
    SceneInfo scene;
    std::string error;
    REQUIRE(LoadScene((dir / "scene.glsl").string(), &scene, &error));
    ShaderSource src;
    REQUIRE_FALSE(AssembleProgram(scene, VariantKey{scene.path, {}, RenderPath::Fragment}, &src, &error));
    CHECK(error.find("scene.glsl:2: cannot open include") != std::string::npos);

    Write(dir / "bad.glsl", "// a scene\n/*{ \"NAME\": \"bad\",\n  \"INPUTS\": [ {\"NAME\": \"x\", \"TYPE\": \"vec9\"} ] }*/\n");
    REQUIRE_FALSE(LoadScene((dir / "bad.glsl").string(), &scene, &error));
    CHECK(error.find("bad.glsl:3: input 'x' has TYPE 'vec9', expected float, int or bool") != std::string::npos);

    Write(dir / "json.glsl", "/*{ \"NAME\": \"bad\",\n  \"INPUTS\": [ {\"NAME\": \"x\",, } ] }*/\n");
    REQUIRE_FALSE(LoadScene((dir / "json.glsl").string(), &scene, &error));
    CHECK(error.find("json.glsl:2: bad JSON") != std::string::npos);
}

TEST_CASE("variant: an effect the scene does not call for is not in its program", "[variant]") {
    RequireGl();
    SceneInfo scene;
    std::string error;
    REQUIRE(FindScene("midi", &scene, &error));
    auto build = [&](const EffectSet& e, Program* prog) {
        ShaderSource src;
        REQUIRE(AssembleProgram(scene, VariantKey{scene.path, e, RenderPath::Fragment}, &src, &error));
        INFO(error);
        REQUIRE(prog->Build(src, RenderPath::Fragment, &error));
    };
    EffectSet none, soft;
    soft.shadows = 2;
    soft.ao = true;
    Program plain, shadowed;
    build(none, &plain);
    build(soft, &shadowed);
    // The compiler keeps only uniforms the code uses: the shadow and AO uniforms exist only
    // where those effects were compiled in.
    auto a = plain.ActiveUniforms(), b = shadowed.ActiveUniforms();
    CHECK_FALSE(Has(a, "u_shadowK"));
    CHECK_FALSE(Has(a, "u_shadowSteps"));
    CHECK_FALSE(Has(a, "u_aoSamples"));
    CHECK(Has(b, "u_shadowSteps"));
    CHECK(Has(b, "u_aoSamples"));
    // And the switches are preprocessor defines, not uniforms.
    CHECK(plain.Source().text.find("#define SHADOWS 0") != std::string::npos);
    CHECK(shadowed.Source().text.find("#define SHADOWS 2") != std::string::npos);
    CHECK_FALSE(Has(b, "SHADOWS"));
}

TEST_CASE("shader: parameters are clamped before they reach the shader", "[shader]") {
    EffectSet none;
    Image atMax = RenderScene("midi", none, RenderPath::Fragment, 64, 48, 1.0, {{"twist", 1e9f}});
    SceneInfo midi;
    std::string error;
    REQUIRE(FindScene("midi", &midi, &error));
    float maxTwist = 0;
    for (const auto& d : midi.params)
        if (d.name == "twist") maxTwist = d.maxValue;
    Image clamped = RenderScene("midi", none, RenderPath::Fragment, 64, 48, 1.0, {{"twist", maxTwist}});
    CHECK(CompareImages(atMax, clamped, 0).maxAbs == 0);
}

TEST_CASE("literals: a scene's float constants in function bodies become u_lit, the rest stays", "[shader][literals]") {
    const std::string scene =
        "/*{ \"NAME\": \"x\", \"DEFAULT\": 1.5 }*/\n"
        "#define K 0.5f\n"
        "const float R = 2.0f;\n"
        "vec4 map(vec3 p) {\n"
        "    // 9.0 in a comment\n"
        "    const float c = 3.0;\n"
        "    float v = p.x * 0.25f + .5 - 1e-3 + 2.5e+1f;\n"
        "    for (int i = 0; i < 4; i++) v += float(i);\n"
        "    return vec4(v.xxx, 1.0lf + 7.);\n"
        "}\n";
    const LiftedText lifted = LiftLiterals(scene);
    REQUIRE(lifted.values.size() == 5);
    CHECK(lifted.values == std::vector<float>{0.25f, 0.5f, 1e-3f, 25.0f, 7.0f});
    CHECK(lifted.text.find("p.x * u_lit[0] + u_lit[1] - u_lit[2] + u_lit[3];") != std::string::npos);
    CHECK(lifted.text.find("1.0lf + u_lit[4])") != std::string::npos);   // doubles stay
    for (const char* kept : {"\"DEFAULT\": 1.5", "#define K 0.5f", "const float R = 2.0f;", "9.0 in a comment",
                             "const float c = 3.0;", "i < 4; i++"})
        CHECK(lifted.text.find(kept) != std::string::npos);
    // Lines are kept: driver messages still name the line the performer edited.
    CHECK(std::count(lifted.text.begin(), lifted.text.end(), '\n') == std::count(scene.begin(), scene.end(), '\n'));

    // A retune keeps the skeleton; a structural edit does not.
    bool found = false;
    const std::string retuned = RetuneFirstConstant(scene, 0.75, &found);
    REQUIRE(found);
    CHECK(retuned.find("p.x * 0.75f +") != std::string::npos);
    CHECK(LiftLiterals(retuned).text == lifted.text);
    CHECK(LiftLiterals(retuned).values[0] == 0.75f);
    CHECK(LiftLiterals(NudgeFirstConstant(scene, 1e-4, &found)).text != lifted.text);
}

TEST_CASE("literals: every shipped scene's lifted program compiles and draws the image its own program draws", "[shader][literals]") {
    RequireGl();
    FrameRenderer fr;
    std::string error;
    REQUIRE(fr.Resize(64, 48, &error));
    for (const char* name : {"midi", "primitives", "character", "mandelbulb", "field50", "field150"}) {
        INFO(name);
        SceneInfo scene;
        REQUIRE(FindScene(name, &scene, &error));
        const VariantKey key{scene.path, scene.effects, RenderPath::Fragment};
        ShaderSource plain, lifted;
        REQUIRE(AssembleProgram(scene, key, &plain, &error));
        REQUIRE(AssembleProgram(scene, key, &lifted, &error, true));
        // field50/field150 keep their code in lib/field_scene.glsl (not lifted) and only global consts here.
        const bool ownCode = std::string(name).rfind("field", 0) != 0;
        if (ownCode) CHECK(lifted.literals.size() >= 5);
        CHECK(lifted.text != plain.text);
        Program a, b;
        REQUIRE(a.Build(plain, key.path, &error));
        INFO(error);
        REQUIRE(b.Build(lifted, key.path, &error));
        FrameInputs in;
        in.time = 1.0;
        fr.Draw(a, scene, in);
        const Image ia{fr.Width(), fr.Height(), fr.ReadPixels()};
        fr.Draw(b, scene, in);
        const Image ib{fr.Width(), fr.Height(), fr.ReadPixels()};
        const ImageDiff d = CompareImages(ia, ib, 8);
        CHECK(d.fractionOver < 0.002);
        if (!ownCode) continue;
        // And the values are what it draws with: the same program with every literal zeroed differs.
        Program& z = b;
        z.SetLiterals(std::vector<float>(lifted.literals.size(), 0.0f));
        fr.Draw(z, scene, in);
        CHECK(CompareImages(ia, Image{fr.Width(), fr.Height(), fr.ReadPixels()}, 8).fractionOver > 0.01);
    }
}


TEST_CASE("headless context: SDFVJ_CONTEXT_PRIORITY asks the driver for a priority, says what it got, and the context still renders") {
    // A word that is not a level is named and ignored (this context is gone before the test's own).
    setenv("SDFVJ_CONTEXT_PRIORITY", "urgent", 1);
    {
        HeadlessContext bogus;
        std::string error;
        REQUIRE(bogus.Create(&error));
        INFO(bogus.Description());
        CHECK(bogus.Description().find("context priority 'urgent' ignored, expected low, medium or high") != std::string::npos);
    }
    setenv("SDFVJ_CONTEXT_PRIORITY", "low", 1);
    RequireGl();
    const std::string d = TestContext()->Description();
    unsetenv("SDFVJ_CONTEXT_PRIORITY");
    INFO(d);
    // A driver with EGL_IMG_context_priority (NVIDIA's) says the level it gave; one without
    // (llvmpipe) says so, and the context is made without asking.
    if (TestContext()->HasEglExtension("EGL_IMG_context_priority")) CHECK(d.find("(asked low)") != std::string::npos);
    else CHECK(d.find("context priority low asked, the driver offers none") != std::string::npos);
    const Image img = RenderScene("midi", EffectSet{}, RenderPath::Fragment, 64, 36);
    CHECK(MeanLuma(img, 0.0, 0.0, 1.0, 1.0) > 5.0);
}

// The compute path's frame state (src/shader/shader.cpp SceneStateBlocks): every SCENE_STATE name
// becomes a member of the blocks, names in a list too; a declaration it cannot read for certain
// (inside an #if, with an initialiser) leaves the program with its setup per invocation rather than
// a frame that reads a member never stored. Each program builds and draws the same frame as the
// fragment path, which always sets up per invocation.
TEST_CASE("shader: a scene's SCENE_STATE lines become the frame state (lists too) and what it cannot read keeps the setup per pixel", "[shader]") {
    RequireGl();
    const fs::path dir = TempDir("scene-state");
    const std::string body =
        "void sceneSetup() { g_a = vec3(0.0f, 0.5f + 0.2f * sin(u_time), 0.0f); g_b = vec3(0.3f, 0.0f, 0.0f);"
        " g_c[0] = 0.35f; g_c[1] = u_r; }\n"
        "#define SCENE_SETUP 1\n"
        "vec4 map(vec3 p) { return vec4(0.8f, 0.5f, 0.3f, min(fSphere(p - g_a - g_b, g_c[0]), p.y + 1.0f + g_c[1])); }\n"
        "float sceneLipschitz() { return 1.0f; }\n";
    struct Case { const char* name; const char* decls; bool frameState; };
    const Case cases[] = {
        {"list", "SCENE_STATE vec3 g_a, g_b;   // two names\nSCENE_STATE float g_c[2];\n", true},
        {"conditional", "SCENE_STATE vec3 g_a, g_b;\n#if 1\nSCENE_STATE float g_c[2];\n#endif\n", false},
        {"initialiser", "SCENE_STATE vec3 g_a = vec3(0.0f), g_b;\nSCENE_STATE float g_c[2];\n", false},
    };
    for (const Case& c : cases) {
        INFO(c.name);
        const fs::path file = dir / (std::string(c.name) + ".glsl");
        Write(file, std::string(kHeader) + "#include \"lib/primitives.glsl\"\n" + c.decls + body);
        SceneInfo scene;
        std::string error;
        REQUIRE(LoadScene(file.string(), &scene, &error));
        Image frames[2];
        for (RenderPath path : {RenderPath::Compute, RenderPath::Fragment}) {
            ShaderSource src;
            REQUIRE(AssembleProgram(scene, VariantKey{scene.path, {}, path}, &src, &error));
            const bool compute = path == RenderPath::Compute;
            CHECK((src.text.find("sceneIn_g_b;") != std::string::npos) == (compute && c.frameState));
            CHECK((src.text.find("sceneIn_g_c[2];") != std::string::npos) == (compute && c.frameState));
            Program prog;
            if (!prog.Build(src, path, &error)) FAIL(error);
            CHECK(prog.FrameState() == (compute && c.frameState));
            FrameRenderer fr;
            REQUIRE(fr.Resize(64, 36, &error));
            FrameInputs in;
            in.time = 0.8;
            in.params = {{"r", 0.25f}};
            fr.Draw(prog, scene, in);
            frames[compute ? 0 : 1] = Image{64, 36, fr.ReadPixels()};
        }
        const ImageDiff d = CompareImages(frames[0], frames[1], 8);
        INFO("compute against fragment: " << d.fractionOver * 100 << " % of pixels past 8/255");
        CHECK(d.fractionOver < 0.01);
        CHECK(MeanLuma(frames[0], 0.4, 0.3, 0.6, 0.7) > 20.0);   // the sphere is there
    }
}
