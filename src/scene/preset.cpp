#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "scene/json_lines.h"
#include "scene/scene.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace sdfvj {

namespace {

constexpr double kParamLimit = std::numeric_limits<float>::max();  // as for a scene's DEFAULT/MIN/MAX

// A finite number in [lo, hi] at `pointer`; false with a line otherwise.
bool ReadNumber(const json& v, double lo, double hi, double* out) {
    if (!v.is_number()) return false;
    const double d = v.get<double>();
    if (!std::isfinite(d) || d < lo || d > hi) return false;
    *out = d;
    return true;
}

// The scripted parts of a preset: bpm, morph, envelopes, cues, loop_bars (see
// core/automation_desc.h). Types and ranges checked here; expressions compile in `automation`.
bool ParseAutomationSections(const json& j, const std::string& text, const JsonLayout& layout, const std::string& path,
                             AutomationDesc* a, std::string* error) {
    auto lineOf = [&](const std::string& pointer) { return LineOfPointer(text, layout, pointer, 1); };
    auto fail = [&](const std::string& pointer, const std::string& msg) {
        *error = path + ":" + std::to_string(lineOf(pointer)) + ": " + msg;
        return false;
    };
    if (j.contains("bpm") && !ReadNumber(j["bpm"], 20.0, 400.0, &a->bpm))
        return fail("/bpm", "bpm is not a tempo, expected a number of beats per minute in [20, 400]");
    if (j.contains("loop_bars") && !ReadNumber(j["loop_bars"], 0.0, 1e5, &a->loopBars))
        return fail("/loop_bars", "loop_bars is not a bar count, expected a number in [0, 100000]");
    if (j.contains("morph")) {
        const json& m = j["morph"];
        if (m.is_number()) {
            if (!ReadNumber(m, 0.0, 600.0, &a->morph.seconds))
                return fail("/morph", "morph is not a duration, expected seconds in [0, 600]");
        } else if (m.is_object()) {
            for (auto it = m.begin(); it != m.end(); ++it) {
                const std::string at = "/morph/" + it.key();
                if (it.key() == "seconds") {
                    if (!ReadNumber(it.value(), 0.0, 600.0, &a->morph.seconds))
                        return fail(at, "morph seconds is not a duration, expected a number in [0, 600]");
                } else if (it.key() == "easing") {
                    if (!it.value().is_string() || !ParseEasing(it.value().get_ref<const std::string&>(), &a->morph.easing))
                        return fail(at, "morph easing is not known, expected linear, smooth, ease_in, ease_out or cut");
                } else if (it.key() == "scenes") {
                    const bool ok = it.value().is_string() && (it.value().get_ref<const std::string&>() == "field" ||
                                                               it.value().get_ref<const std::string&>() == "crossfade");
                    if (!ok) return fail(at, "morph scenes is not known, expected \"field\" or \"crossfade\"");
                    a->morph.fieldMorph = it.value().get_ref<const std::string&>() == "field";
                } else {
                    return fail(at, "unknown key '" + it.key() + "' in morph, expected seconds, easing or scenes");
                }
            }
        } else {
            return fail("/morph", "morph is " + std::string(m.type_name()) + ", expected seconds or {\"seconds\": 2, \"easing\": \"smooth\"}");
        }
    }
    if (j.contains("envelopes")) {
        const json& envs = j["envelopes"];
        if (!envs.is_object())
            return fail("/envelopes", "envelopes is " + std::string(envs.type_name()) + ", expected {\"NAME\": {\"note\": 36, \"attack\": 0.01, ...}}");
        if (envs.size() > 64) return fail("/envelopes", "more than 64 envelopes, expected a few");
        for (auto it = envs.begin(); it != envs.end(); ++it) {
            const std::string at = "/envelopes/" + it.key();
            if (!it.value().is_object()) return fail(at, "envelope '" + it.key() + "' is not an object, expected {\"note\": 36, \"attack\": 0.01, ...}");
            EnvelopeDesc e;
            e.name = it.key();
            e.line = lineOf(at);
            for (auto f = it.value().begin(); f != it.value().end(); ++f) {
                const std::string fat = at + "/" + f.key();
                double v = 0;
                if (f.key() == "note" || f.key() == "channel") {
                    const double hi = f.key() == "note" ? 127 : 16;
                    if (!ReadNumber(f.value(), 0, hi, &v) || v != std::floor(v))
                        return fail(fat, "envelope " + f.key() + " is not a whole number in [0, " + std::to_string((int)hi) +
                                        "], expected a MIDI " + (f.key() == "note" ? "note number" : "channel (0 = any)"));
                    (f.key() == "note" ? e.note : e.channel) = (int)v;
                } else if (f.key() == "attack" || f.key() == "decay" || f.key() == "release") {
                    if (!ReadNumber(f.value(), 0, 3600, &v)) return fail(fat, "envelope " + f.key() + " is not a time, expected seconds in [0, 3600]");
                    (f.key() == "attack" ? e.attack : f.key() == "decay" ? e.decay : e.release) = v;
                } else if (f.key() == "sustain") {
                    if (!ReadNumber(f.value(), 0, 1, &v)) return fail(fat, "envelope sustain is not a level, expected a number in [0, 1]");
                    e.sustain = v;
                } else {
                    return fail(fat, "unknown key '" + f.key() + "' in envelope, expected note, channel, attack, decay, sustain or release");
                }
            }
            a->envelopes.push_back(e);
        }
    }
    if (j.contains("cues")) {
        const json& cues = j["cues"];
        if (!cues.is_array()) return fail("/cues", "cues is " + std::string(cues.type_name()) + ", expected a list of {\"bar\": 8, \"preset\": \"walker\", \"over\": 2}");
        if (cues.size() > 1024) return fail("/cues", "more than 1024 cues, expected a shorter list");
        for (size_t i = 0; i < cues.size(); ++i) {
            const std::string at = "/cues/" + std::to_string(i);
            const json& c = cues[i];
            if (!c.is_object()) return fail(at, "cue " + std::to_string(i) + " is not an object, expected {\"bar\": 8, \"preset\": \"walker\"}");
            CueDesc cue;
            cue.line = lineOf(at);
            bool hasBar = false;
            for (auto f = c.begin(); f != c.end(); ++f) {
                const std::string fat = at + "/" + f.key();
                if (f.key() == "bar") {
                    if (!ReadNumber(f.value(), 0, 1e5, &cue.bar)) return fail(fat, "cue bar is not a bar number, expected a number in [0, 100000]");
                    hasBar = true;
                } else if (f.key() == "over") {
                    if (!ReadNumber(f.value(), 0, 1e4, &cue.overBeats)) return fail(fat, "cue over is not a duration, expected beats in [0, 10000]");
                } else if (f.key() == "preset") {
                    if (!f.value().is_string() || f.value().get_ref<const std::string&>().empty() || f.value().get_ref<const std::string&>().size() > 256)
                        return fail(fat, "cue preset is not a name, expected a preset name such as \"walker\"");
                    cue.preset = f.value().get<std::string>();
                } else if (f.key() == "set") {
                    if (!f.value().is_object()) return fail(fat, "cue set is not an object, expected {\"twist\": 1.0}");
                    for (auto s = f.value().begin(); s != f.value().end(); ++s) {
                        double v = 0;
                        if (!ReadNumber(s.value(), -1e9, 1e9, &v))
                            return fail(fat + "/" + s.key(), "cue value for '" + s.key() + "' is not a number, expected a number in its range");
                        cue.values[s.key()] = (float)v;
                    }
                } else {
                    return fail(fat, "unknown key '" + f.key() + "' in cue, expected bar, preset, set or over");
                }
            }
            if (!hasBar) return fail(at, "cue " + std::to_string(i) + " has no bar, expected \"bar\": N");
            if (cue.preset.empty() && cue.values.empty()) return fail(at, "cue " + std::to_string(i) + " does nothing, expected a preset or set");
            a->cues.push_back(cue);
        }
    }
    return true;
}

// ParsePresetText without the last-resort catch.
bool ParsePresetJson(const std::string& text, const std::string& path, Preset* out, std::string* error) {
    if (text.size() > kMaxJsonBytes) {
        *error = path + ":1: preset is larger than 1 MiB, expected a short JSON object";
        return false;
    }
    JsonLayout layout;
    if (!ScanJsonLayout(text, 0, text.size(), kMaxJsonDepth, &layout)) {
        *error = path + ":" + std::to_string(LineOfOffset(text, layout.tooDeepAt)) +
                 ": preset nests deeper than 64 levels, expected at most 64 levels of [ and {";
        return false;
    }
    json j;
    try {
        j = json::parse(text);
    } catch (const json::parse_error& e) {
        *error = path + ":" + std::to_string(LineOfOffset(text, e.byte > 0 ? e.byte - 1 : 0)) + ": bad JSON (" +
                 JsonErrorReason(e.what()) + "), expected a preset object";
        return false;
    } catch (const json::exception& e) {
        // out_of_range.406 "number overflow parsing '1e400'": find the number for its line.
        std::string what = JsonErrorReason(e.what());
        size_t at = 0;
        if (size_t q = what.find('\''); q != std::string::npos) {
            size_t q2 = what.find('\'', q + 1);
            if (q2 != std::string::npos && q2 > q + 1)
                if (size_t p = text.find(what.substr(q + 1, q2 - q - 1)); p != std::string::npos) at = p;
        }
        *error = path + ":" + std::to_string(LineOfOffset(text, at)) + ": bad JSON (" + what +
                 "), expected numbers that fit a float";
        return false;
    }
    auto fail = [&](const std::string& pointer, const std::string& msg) {
        *error = path + ":" + std::to_string(LineOfPointer(text, layout, pointer, 1)) + ": " + msg;
        return false;
    };
    if (!j.is_object()) return fail("", "preset is not a JSON object, expected {\"scene\": ..., \"params\": {...}}");
    Preset p;
    p.path = path;
    static const char* kKeys = "scene, params, effects, normals, mapping, take, post, bpm, morph, envelopes, cues or loop_bars";
    for (auto it = j.begin(); it != j.end(); ++it) {
        const std::string& k = it.key();
        const json& v = it.value();
        if (k == "params" || k == "bpm" || k == "morph" || k == "envelopes" || k == "cues" || k == "loop_bars") continue;
        std::string* field = k == "scene" ? &p.scene : k == "effects" ? &p.effects : k == "normals" ? &p.normals
                           : k == "mapping" ? &p.mapping : k == "take" ? &p.take : k == "post" ? &p.post : nullptr;
        if (!field) return fail("/" + k, "unknown key '" + k + "', expected " + kKeys);
        if (!v.is_string()) return fail("/" + k, k + " is " + v.type_name() + ", expected a string");
        *field = v.get_ref<const std::string&>();
        if (field->size() > 4096) return fail("/" + k, k + " is longer than 4096 bytes, expected a short text");
    }
    if (!j.contains("scene")) return fail("", "preset names no scene, expected \"scene\": \"NAME\"");
    if (p.scene.empty()) return fail("/scene", "scene is empty, expected a scene name such as \"midi\"");
    std::string why;
    EffectSet effects;
    if (!ParseEffectList(p.effects, &effects, &why)) return fail("/effects", why);
    int normals = 0;
    if (!p.normals.empty() && !ParseNormalMethod(p.normals, &normals, &why)) return fail("/normals", why);
    if (j.contains("params")) {
        const json& params = j["params"];
        if (!params.is_object())
            return fail("/params", "params is " + std::string(params.type_name()) + ", expected an object of name: number");
        for (auto it = params.begin(); it != params.end(); ++it) {
            const std::string at = "/params/" + it.key();
            const json& v = it.value();
            if (v.is_boolean()) {
                p.params[it.key()] = v.get<bool>() ? 1.0f : 0.0f;
                continue;
            }
            if (v.is_string()) {   // a scripted parameter: an expression evaluated every frame
                const std::string& formula = v.get_ref<const std::string&>();
                if (formula.empty() || formula.size() > 4096)
                    return fail(at, "expression for '" + it.key() + "' is empty or longer than 4096 bytes, expected a short formula");
                p.automation.expressions.push_back({it.key(), formula, LineOfPointer(text, layout, at, 1)});
                continue;
            }
            if (!v.is_number())
                return fail(at, "parameter '" + it.key() + "' is " + v.type_name() +
                                    ", expected a number in its range or an expression string");
            const double d = v.get<double>();
            if (!std::isfinite(d) || std::fabs(d) > kParamLimit) {
                std::ostringstream got;
                got << d;
                return fail(at, "parameter '" + it.key() + "' is " + got.str() + ", expected a number that fits a float");
            }
            p.params[it.key()] = float(d);
        }
    }
    if (!ParseAutomationSections(j, text, layout, path, &p.automation, error)) return false;
    p.automation.file = path;
    *out = std::move(p);
    return true;
}

}  // namespace

// Presets are JSON (presets/*.json):
//   {"scene": "midi", "params": {"twist": 0.5}, "effects": "soft_shadows,ao",
//    "normals": "tetrahedron", "mapping": "mappings/akai_lpd8.toml", "take": "presets/demo_take.mid"}
bool ParsePresetText(const std::string& text, const std::string& path, Preset* out, std::string* error) {
    // Last resort: the checks return errors as values; anything that still throws (a bug,
    // bad_alloc) becomes one line instead of ending the show.
    try {
        return ParsePresetJson(text, path, out, error);
    } catch (const std::exception& e) {
        *error = path + ":1: cannot read the preset (" + std::string(e.what()) + "), expected a preset object";
    } catch (...) {
        *error = path + ":1: cannot read the preset (unknown error), expected a preset object";
    }
    return false;
}

bool LoadPreset(const std::string& path, Preset* out, std::string* error) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        *error = path + ":1: cannot read the preset, expected a readable .json file";
        return false;
    }
    std::stringstream ss;
    ss << in.rdbuf();
    return ParsePresetText(ss.str(), path, out, error);
}

std::vector<std::string> ListPresets() {
    std::vector<std::string> names;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(fs::path(DataRoot()) / "presets", ec))
        if (e.path().extension() == ".json") names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

}  // namespace sdfvj
