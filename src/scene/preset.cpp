#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "scene/json_lines.h"
#include "scene/scene.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace sdfvj {

namespace {

constexpr double kParamLimit = 1e9;  // as for a scene's DEFAULT/MIN/MAX

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
    static const char* kKeys = "scene, params, effects, normals, mapping or take";
    for (auto it = j.begin(); it != j.end(); ++it) {
        const std::string& k = it.key();
        const json& v = it.value();
        if (k == "params") continue;
        std::string* field = k == "scene" ? &p.scene : k == "effects" ? &p.effects : k == "normals" ? &p.normals
                           : k == "mapping" ? &p.mapping : k == "take" ? &p.take : nullptr;
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
            if (!v.is_number())
                return fail(at, "parameter '" + it.key() + "' is " + v.type_name() +
                                    ", expected a number in its range");
            const double d = v.get<double>();
            if (!std::isfinite(d) || std::fabs(d) > kParamLimit) {
                std::ostringstream got;
                got << d;
                return fail(at, "parameter '" + it.key() + "' is " + got.str() + ", expected a number in [-1e+09, 1e+09]");
            }
            p.params[it.key()] = float(d);
        }
    }
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
