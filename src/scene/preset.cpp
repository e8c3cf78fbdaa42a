#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "scene/scene.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace sdfvj {

// Presets are JSON (presets/*.json):
//   {"scene": "midi", "params": {"twist": 0.5}, "effects": "soft_shadows,ao",
//    "normals": "tetrahedron", "mapping": "mappings/akai_lpd8.toml", "take": "presets/demo_take.mid"}
bool LoadPreset(const std::string& path, Preset* out, std::string* error) {
    std::ifstream in(path);
    if (!in) {
        *error = path + ":1: cannot read the preset, expected a readable .json file";
        return false;
    }
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string text = ss.str();
    json j;
    try {
        j = json::parse(text);
    } catch (const json::parse_error& e) {
        size_t at = std::min<size_t>(e.byte > 0 ? e.byte - 1 : 0, text.size());
        int line = 1 + (int)std::count(text.begin(), text.begin() + (long)at, '\n');
        *error = path + ":" + std::to_string(line) + ": bad JSON (" + e.what() + "), expected a preset object";
        return false;
    }
    auto lineOf = [&](const std::string& key) {
        size_t p = text.find("\"" + key + "\"");
        return std::to_string(p == std::string::npos ? 1 : 1 + std::count(text.begin(), text.begin() + (long)p, '\n'));
    };
    auto fail = [&](const std::string& key, const std::string& msg) {
        *error = path + ":" + lineOf(key) + ": " + msg;
        return false;
    };
    Preset p;
    p.path = path;
    if (!j.is_object()) return fail("", "preset is not a JSON object, expected {\"scene\": ..., \"params\": {...}}");
    for (const char* key : {"scene", "effects", "normals", "mapping", "take"})
        if (j.contains(key) && !j[key].is_string()) return fail(key, std::string(key) + " must be a string");
    if (!j.contains("scene")) return fail("", "preset names no scene, expected \"scene\": \"NAME\"");
    p.scene = j["scene"].get<std::string>();
    p.effects = j.value("effects", "");
    p.normals = j.value("normals", "");
    p.mapping = j.value("mapping", "");
    p.take = j.value("take", "");
    if (j.contains("params")) {
        if (!j["params"].is_object()) return fail("params", "params must be an object of name: number");
        for (auto it = j["params"].begin(); it != j["params"].end(); ++it) {
            if (!it.value().is_number() && !it.value().is_boolean())
                return fail(it.key(), "parameter '" + it.key() + "' is not a number, expected a number in its range");
            p.params[it.key()] = it.value().is_boolean() ? (float)it.value().get<bool>() : it.value().get<float>();
        }
    }
    *out = std::move(p);
    return true;
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
