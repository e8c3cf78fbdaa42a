// libFuzzer target for presets: ParsePresetText, the code LoadPreset runs. The first byte
// picks raw text (0) or a preset built by JsonGen from the fuzz bytes. Invariants: no crash,
// no exception; an error is "fuzz.json:LINE: ... expected ..."; a loaded preset names a scene
// and holds only finite parameter values. scripts/fuzz.sh builds and runs it.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "scene/fuzz_json_gen.h"
#include "scene/scene.h"

using namespace sdfvj;

namespace {

std::string BuildPreset(fuzz::JsonGen& g) {
    std::vector<std::string> top;
    g.Member(&top, "scene", g.Field("\"midi\""));
    std::vector<std::string> params;
    for (int i = 0, n = g.in().ConsumeIntegralInRange<int>(0, 5); i < n; ++i)
        g.Member(&params, "p" + std::to_string(i),
                 g.Field(i == 1 ? "\"0.4 + 0.3 * lfo_sine(beat / 4)\"" : g.in().ConsumeBool() ? "0.5" : "true"));
    g.Member(&top, "params", g.Field(fuzz::JsonGen::Object(params)));
    static const char* kEffects[] = {"\"\"", "\"soft_shadows,ao\"", "\"none,-ao,reflections=3\"", "\"reflections=99999999999\"",
                                     "\"sparkles\"", "\" , ,fog\""};
    g.Member(&top, "effects", g.Field(kEffects[g.in().ConsumeIntegralInRange<int>(0, 5)]));
    g.Member(&top, "normals", g.Field(g.in().ConsumeBool() ? "\"tetrahedron\"" : "\"sideways\""));
    g.Member(&top, "mapping", g.Field("\"mappings/akai_lpd8.toml\""));
    g.Member(&top, "take", g.Field("\"presets/demo_take.mid\""));
    // The scripted sections (bpm, morph, envelopes, cues, loop_bars).
    g.Member(&top, "bpm", g.Field("128"));
    g.Member(&top, "loop_bars", g.Field("16"));
    std::vector<std::string> morph;
    g.Member(&morph, "seconds", g.Field("1.5"));
    g.Member(&morph, "easing", g.Field("\"ease_out\""));
    g.Member(&top, "morph", g.Field(fuzz::JsonGen::Object(morph)));
    std::vector<std::string> env, envs;
    g.Member(&env, "note", g.Field("36"));
    g.Member(&env, "channel", g.Field("0"));
    g.Member(&env, "attack", g.Field("0.01"));
    g.Member(&env, "decay", g.Field("0.1"));
    g.Member(&env, "sustain", g.Field("0.5"));
    g.Member(&env, "release", g.Field("0.5"));
    g.Member(&envs, "flash", g.Field(fuzz::JsonGen::Object(env)));
    g.Member(&top, "envelopes", g.Field(fuzz::JsonGen::Object(envs)));
    std::string cues = "[";
    for (int i = 0, n = g.in().ConsumeIntegralInRange<int>(0, 3); i < n; ++i) {
        std::vector<std::string> cue, set;
        g.Member(&cue, "bar", g.Field("8"));
        g.Member(&cue, "preset", g.Field("\"walker\""));
        g.Member(&cue, "over", g.Field("2"));
        g.Member(&set, "twist", g.Field("1.0"));
        g.Member(&cue, "set", g.Field(fuzz::JsonGen::Object(set)));
        cues += (i ? ",\n  " : "") + fuzz::JsonGen::Object(cue);
    }
    g.Member(&top, "cues", g.Field(cues + "]"));
    return g.Damage(fuzz::JsonGen::Object(top) + "\n");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    std::string text;
    if (data[0] == 0) {
        text.assign(reinterpret_cast<const char*>(data + 1), size - 1);
    } else {
        FuzzedDataProvider in(data + 1, size - 1);
        fuzz::JsonGen g(in);
        text = BuildPreset(g);
    }
    Preset p;
    std::string error;
    bool ok = false;
    try {
        ok = ParsePresetText(text, "fuzz.json", &p, &error);
    } catch (...) {
        std::abort();  // the project's rule: no exception leaves a parser
    }
    if (ok) {
        if (p.scene.empty()) std::abort();
        for (const auto& [name, v] : p.params)
            if (!std::isfinite(v)) std::abort();
    } else {
        if (error.rfind("fuzz.json:", 0) != 0 || error.find("expected") == std::string::npos) std::abort();
        size_t i = 10;
        long line = 0, lines = 1;
        while (i < error.size() && i < 20 && error[i] >= '0' && error[i] <= '9') line = line * 10 + (error[i++] - '0');
        for (char c : text) lines += c == '\n';
        if (i == 10 || error.compare(i, 2, ": ") != 0 || line < 1 || line > lines) std::abort();
    }
    return 0;
}
