// Bad input: a parameter outside its declared range (preset, --param) is clamped and reported,
// and FrameRenderer never uploads an unclamped value.
#include <catch2/catch.hpp>

#include <epoxy/gl.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/show.h"
#include "gl_fixture.h"

using namespace sdfvj;

namespace {

// Runs f with stderr captured into the returned string.
template <class F>
std::string CaptureStderr(F f) {
    std::fflush(stderr);
    std::string path = (std::filesystem::temp_directory_path() / ("sdfvj_stability_stderr_" + std::to_string(getpid()))).string();
    int saved = dup(2);
    FILE* tmp = std::fopen(path.c_str(), "w");
    dup2(fileno(tmp), 2);
    f();
    std::fflush(stderr);
    dup2(saved, 2);
    close(saved);
    std::fclose(tmp);
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    std::filesystem::remove(path);
    return ss.str();
}

float ParamValue(const Show& s, const std::string& name) {
    for (const auto& [n, v] : s.params)
        if (n == name) return v;
    return NAN;
}

}  // namespace

TEST_CASE("stability: out-of-range --param and preset values are clamped and reported", "[stability][input]") {
    auto presetPath = std::filesystem::temp_directory_path() / ("sdfvj_stability_preset_" + std::to_string(getpid()) + ".json");
    std::ofstream(presetPath) << R"({"scene": "midi", "params": {"twist": -7.5, "displacement": 0.1}})";
    ShowOptions o;
    o.preset = presetPath.string();
    o.params = {"scale=100", "smoothness=-1"};
    Show show;
    std::string error;
    bool ok = false;
    std::string err = CaptureStderr([&] { ok = PrepareShow(o, &show, &error); });
    std::filesystem::remove(presetPath);
    INFO(error << "\nstderr: " << err);
    REQUIRE(ok);
    CHECK(ParamValue(show, "twist") == -3.0f);
    CHECK(ParamValue(show, "displacement") == 0.1f);
    CHECK(ParamValue(show, "scale") == 2.0f);
    CHECK(ParamValue(show, "smoothness") == 0.0f);
    CHECK(err.find("twist = -7.5 is outside [-3, 3], clamped to -3") != std::string::npos);
    CHECK(err.find("--param: scale = 100 is outside [0.25, 2], clamped to 2") != std::string::npos);
    CHECK(err.find("smoothness = -1 is outside [0, 1], clamped to 0") != std::string::npos);
    CHECK(err.find("displacement") == std::string::npos);   // in range: not reported
}

TEST_CASE("stability: FrameRenderer uploads parameters clamped to their range", "[stability][input][gpu]") {
    test::RequireGl();
    SceneInfo scene;
    std::string error;
    REQUIRE(FindScene("midi", &scene, &error));
    ShaderSource src;
    REQUIRE(AssembleProgram(scene, VariantKey{scene.path, scene.effects, RenderPath::Fragment}, &src, &error));
    Program p;
    REQUIRE(p.Build(src, RenderPath::Fragment, &error));
    FrameRenderer fr;
    REQUIRE(fr.Resize(8, 8, &error));
    FrameInputs in;
    // ClampParam: finite values are clamped into [MIN, MAX], non-finite ones become the default
    in.params = {{"twist", 1e9f}, {"displacement", -5.0f}, {"scale", std::numeric_limits<float>::infinity()}};
    fr.Draw(p, scene, in);
    auto value = [&](const char* name) {
        float v = NAN;
        glGetUniformfv(p.Id(), glGetUniformLocation(p.Id(), name), &v);
        return v;
    };
    CHECK(value("u_twist") == 3.0f);
    CHECK(value("u_displacement") == 0.0f);
    CHECK(value("u_scale") == 1.0f);   // not finite: the declared default
}
