// libFuzzer target for scene headers: ParseSceneText, the code LoadScene and hot reload run.
// The first byte picks the input: 0 raw text after "/*{" (libFuzzer's own mutations), else a
// header built from the fuzz bytes by JsonGen (valid skeleton, hostile fields). Invariants:
// no crash, no sanitizer report, no exception; an error is "fuzz.glsl:LINE: ... expected ...";
// a header that loads holds only finite, in-range values. scripts/fuzz.sh builds and runs it.
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "scene/fuzz_json_gen.h"
#include "scene/scene.h"

using namespace sdfvj;

namespace {

std::string BuildHeader(fuzz::JsonGen& g) {
    std::vector<std::string> top;
    g.Member(&top, "NAME", g.Field("\"fuzz\""));
    g.Member(&top, "DESCRIPTION", g.Field("\"a fuzzed scene\""));
    std::string inputs = "[";
    for (int i = 0, n = g.in().ConsumeIntegralInRange<int>(0, 5); i < n; ++i) {
        std::vector<std::string> in;
        static const char* kTypes[] = {"\"float\"", "\"int\"", "\"long\"", "\"bool\"", "\"color\""};
        g.Member(&in, "NAME", g.Field("\"p" + std::to_string(g.in().ConsumeIntegralInRange<int>(0, 3)) + "\""));
        g.Member(&in, "TYPE", g.Field(kTypes[g.in().ConsumeIntegralInRange<int>(0, 4)]));
        g.Member(&in, "MIN", g.Field("0"));
        g.Member(&in, "MAX", g.Field("1"));
        g.Member(&in, "DEFAULT", g.Field(g.in().ConsumeBool() ? "0.5" : "true"));
        g.Member(&in, "LABEL", g.Field("\"P\""));
        inputs += (i ? ",\n  " : "") + (g.in().ConsumeIntegralInRange<int>(0, 15) != 15 ? fuzz::JsonGen::Object(in) : g.AnyValue(2));
    }
    g.Member(&top, "INPUTS", g.Field(inputs + "]"));
    std::vector<std::string> fx;
    g.Member(&fx, "SHADOWS", g.Field(g.in().ConsumeBool() ? "\"soft\"" : "\"improved\""));
    g.Member(&fx, "AO", g.Field("true"));
    g.Member(&fx, "SPECULAR", g.Field("false"));
    g.Member(&fx, "PBR", g.Field("true"));
    g.Member(&fx, "REFLECTIONS", g.Field("2"));
    g.Member(&fx, "FOG", g.Field("true"));
    g.Member(&top, "EFFECTS", g.Field(fuzz::JsonGen::Object(fx)));
    auto vec3 = [&](const char* valid) {
        if (g.in().ConsumeIntegralInRange<int>(0, 3)) return g.Field(valid);
        return "[" + g.Field("0") + ", " + g.Field("1") + ", " + g.Field("-5") + "]";
    };
    std::vector<std::string> cam;
    g.Member(&cam, "POSITION", vec3("[0, 2, -6]"));
    g.Member(&cam, "TARGET", vec3("[0, 1, 0]"));
    g.Member(&cam, "FOV", g.Field("45"));
    g.Member(&top, "CAMERA", g.Field(fuzz::JsonGen::Object(cam)));
    std::vector<std::string> light;
    g.Member(&light, "DIRECTION", vec3("[0.6, 0.8, -0.4]"));
    g.Member(&light, "COLOR", vec3("[1, 0.9, 0.8]"));
    g.Member(&top, "LIGHT", g.Field(fuzz::JsonGen::Object(light)));
    std::vector<std::string> mat;
    g.Member(&mat, "ROUGHNESS", g.Field("0.4"));
    g.Member(&mat, "METALNESS", g.Field("0"));
    g.Member(&top, "MATERIAL", g.Field(fuzz::JsonGen::Object(mat)));
    std::string header = fuzz::JsonGen::Object(top);
    return g.Damage("// fuzz\n/*" + header + "*/\nvec4 render(vec2 p) { return vec4(0); }\n");
}

bool InRange(float v, float lo, float hi) { return std::isfinite(v) && v >= lo && v <= hi; }

void CheckLoaded(const SceneInfo& s) {
    if (s.name.empty()) std::abort();
    for (const ParamDecl& d : s.params) {
        if (!InRange(d.minValue, -FLT_MAX, FLT_MAX) || !InRange(d.maxValue, d.minValue, FLT_MAX) ||
            !std::isfinite(d.maxValue - d.minValue) ||
            !InRange(d.defaultValue, d.minValue, d.maxValue) || d.name.empty())
            std::abort();
    }
    if (!(s.fov > 0.0f && s.fov < 180.0f)) std::abort();
    for (int i = 0; i < 3; ++i)
        if (!InRange(s.camPos[i], -1e6f, 1e6f) || !InRange(s.camTarget[i], -1e6f, 1e6f) ||
            !InRange(s.lightDir[i], -1.0001f, 1.0001f) || !InRange(s.lightColor[i], 0.0f, 1e3f))
            std::abort();
    if (!InRange(s.roughness, 0, 1) || !InRange(s.metalness, 0, 1)) std::abort();
    if (s.effects.reflections < 0 || s.effects.reflections > 8 || s.effects.shadows < 0 || s.effects.shadows > 3)
        std::abort();
}

void CheckError(const std::string& error, const std::string& text) {
    // "fuzz.glsl:LINE: ... expected ..." with LINE inside the file.
    if (error.rfind("fuzz.glsl:", 0) != 0) std::abort();
    size_t i = 10;
    long line = 0;
    while (i < error.size() && i < 20 && error[i] >= '0' && error[i] <= '9') line = line * 10 + (error[i++] - '0');
    if (i == 10 || error.compare(i, 2, ": ") != 0) std::abort();
    long lines = 1;
    for (char c : text) lines += c == '\n';
    if (line < 1 || line > lines) std::abort();
    if (error.find("expected") == std::string::npos) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    std::string text;
    if (data[0] == 0) {
        text = "/*{" + std::string(reinterpret_cast<const char*>(data + 1), size - 1);
    } else {
        FuzzedDataProvider in(data + 1, size - 1);
        fuzz::JsonGen g(in);
        text = BuildHeader(g);
    }
    SceneInfo s;
    std::string error;
    bool ok = false;
    try {
        ok = ParseSceneText(text, "fuzz.glsl", &s, &error);
    } catch (...) {
        std::abort();  // the project's rule: no exception leaves a parser
    }
    if (ok) CheckLoaded(s);
    else CheckError(error, text);
    return 0;
}
