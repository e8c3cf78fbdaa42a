#include "scene/scene.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

namespace fs = std::filesystem;
using nlohmann::json;

namespace sdfvj {

std::string DataRoot() {
    if (const char* env = std::getenv("SDFVJ_ROOT"); env && *env) return env;
    // A binary carried to another machine runs next to a copy of the tree: prefer ./shaders.
    if (fs::exists("shaders/scenes")) return fs::current_path().string();
    return SDFVJ_SOURCE_ROOT;
}

namespace {

int LineOfOffset(const std::string& text, size_t offset) {
    offset = std::min(offset, text.size());
    return 1 + (int)std::count(text.begin(), text.begin() + (long)offset, '\n');
}

bool ReadFile(const std::string& path, std::string* text) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return false;
    std::stringstream ss;
    ss << in.rdbuf();
    *text = ss.str();
    return true;
}

// Reads an [x, y, z] array; false with a reason when it is anything else.
bool ReadVec3(const json& j, Vec3f* out) {
    if (!j.is_array() || j.size() != 3) return false;
    for (int i = 0; i < 3; ++i) {
        if (!j[i].is_number()) return false;
        (*out)[i] = j[i].get<float>();
    }
    return true;
}

int ShadowKind(const std::string& s) {
    if (s == "none" || s == "off") return 0;
    if (s == "hard") return 1;
    if (s == "soft") return 2;
    if (s == "improved" || s == "improved_soft") return 3;
    return -1;
}

}  // namespace

bool LoadScene(const std::string& path, SceneInfo* out, std::string* error) {
    std::string text;
    if (!ReadFile(path, &text)) {
        *error = path + ":1: cannot read the file, expected a readable scene .glsl";
        return false;
    }
    size_t open = text.find("/*{");
    if (open == std::string::npos) {
        *error = path + ":1: no scene header, expected the file to open with a /*{ ... }*/ JSON header";
        return false;
    }
    size_t close = text.find("}*/", open);
    if (close == std::string::npos) {
        *error = path + ":" + std::to_string(LineOfOffset(text, open)) +
                 ": scene header is never closed, expected }*/ after the JSON";
        return false;
    }
    const size_t jsonStart = open + 2;
    const std::string header = text.substr(jsonStart, close + 1 - jsonStart);
    json j;
    try {
        j = json::parse(header);
    } catch (const json::parse_error& e) {
        std::string what = e.what();
        if (auto p = what.find("parse error"); p != std::string::npos) what = what.substr(p);
        *error = path + ":" + std::to_string(LineOfOffset(text, jsonStart + (e.byte > 0 ? e.byte - 1 : 0))) +
                 ": bad JSON in scene header (" + what + "), expected ISF-style JSON";
        return false;
    }
    const int headerLine = LineOfOffset(text, open);
    // Line of the first occurrence of a key, so errors point near the culprit.
    auto lineOf = [&](const std::string& needle) {
        size_t p = text.find(needle, open);
        return std::to_string(p == std::string::npos || p > close ? headerLine : LineOfOffset(text, p));
    };
    auto fail = [&](const std::string& needle, const std::string& msg) {
        *error = path + ":" + lineOf(needle) + ": " + msg;
        return false;
    };
    if (!j.is_object()) return fail("{", "scene header is not a JSON object, expected {\"NAME\": ..., \"INPUTS\": [...]}");

    SceneInfo s;
    s.path = fs::absolute(path).lexically_normal().string();
    s.name = j.value("NAME", fs::path(path).stem().string());
    s.description = j.value("DESCRIPTION", "");

    if (j.contains("INPUTS")) {
        if (!j["INPUTS"].is_array()) return fail("\"INPUTS\"", "INPUTS is not an array, expected a list of parameters");
        for (const json& in : j["INPUTS"]) {
            ParamDecl d;
            if (!in.is_object() || !in.contains("NAME") || !in["NAME"].is_string())
                return fail("\"INPUTS\"", "an input has no NAME, expected {\"NAME\": \"twist\", \"TYPE\": \"float\", ...}");
            d.name = in["NAME"].get<std::string>();
            const std::string at = "\"" + d.name + "\"";
            bool identifier = !d.name.empty() && !std::isdigit((unsigned char)d.name[0]) &&
                              std::all_of(d.name.begin(), d.name.end(), [](char c) { return std::isalnum((unsigned char)c) || c == '_'; });
            if (!identifier) return fail(at, "input name '" + d.name + "' is not an identifier, expected letters, digits and _");
            std::string type = in.value("TYPE", "float");
            if (type == "float") d.type = ParamType::Float;
            else if (type == "int" || type == "long") d.type = ParamType::Int;
            else if (type == "bool") d.type = ParamType::Bool;
            else return fail(at, "input '" + d.name + "' has TYPE '" + type + "', expected float, int or bool");
            for (const char* key : {"DEFAULT", "MIN", "MAX"}) {
                if (in.contains(key) && !(in[key].is_number() || in[key].is_boolean()))
                    return fail(at, "input '" + d.name + "' has a non-numeric " + key + ", expected a number");
            }
            auto num = [&](const char* key, float fallback) {
                if (!in.contains(key)) return fallback;
                return in[key].is_boolean() ? (in[key].get<bool>() ? 1.0f : 0.0f) : in[key].get<float>();
            };
            d.minValue = num("MIN", d.type == ParamType::Bool ? 0.0f : 0.0f);
            d.maxValue = num("MAX", 1.0f);
            d.defaultValue = num("DEFAULT", d.minValue);
            if (d.minValue > d.maxValue) return fail(at, "input '" + d.name + "' has MIN > MAX, expected MIN <= MAX");
            if (d.defaultValue < d.minValue || d.defaultValue > d.maxValue)
                return fail(at, "input '" + d.name + "' has DEFAULT outside [MIN, MAX], expected a default inside its range");
            d.label = in.value("LABEL", d.name);
            for (const ParamDecl& other : s.params)
                if (other.name == d.name) return fail(at, "input '" + d.name + "' is declared twice, expected unique names");
            s.params.push_back(d);
        }
    }

    if (j.contains("EFFECTS")) {
        const json& e = j["EFFECTS"];
        if (!e.is_object()) return fail("\"EFFECTS\"", "EFFECTS is not an object, expected {\"SHADOWS\": \"soft\", \"AO\": true, ...}");
        for (auto it = e.begin(); it != e.end(); ++it) {
            const std::string& k = it.key();
            const json& v = it.value();
            const std::string at = "\"" + k + "\"";
            if (k == "SHADOWS") {
                int kind = v.is_string() ? ShadowKind(v.get<std::string>()) : (v.is_boolean() ? (v.get<bool>() ? 2 : 0) : -1);
                if (kind < 0) return fail(at, "SHADOWS must be none, hard, soft or improved");
                s.effects.shadows = kind;
            } else if (k == "AO" || k == "SPECULAR" || k == "PBR" || k == "FOG") {
                if (!v.is_boolean()) return fail(at, k + " must be true or false");
                bool b = v.get<bool>();
                if (k == "AO") s.effects.ao = b;
                if (k == "SPECULAR") s.effects.specular = b;
                if (k == "PBR") s.effects.pbr = b;
                if (k == "FOG") s.effects.fog = b;
            } else if (k == "REFLECTIONS") {
                if (!v.is_number_integer() || v.get<int>() < 0 || v.get<int>() > 8)
                    return fail(at, "REFLECTIONS must be a bounce count 0..8");
                s.effects.reflections = v.get<int>();
            } else {
                return fail(at, "unknown effect '" + k + "', expected SHADOWS, AO, SPECULAR, PBR, REFLECTIONS or FOG");
            }
        }
    }
    if (j.contains("CAMERA")) {
        const json& c = j["CAMERA"];
        if ((c.contains("POSITION") && !ReadVec3(c["POSITION"], &s.camPos)) ||
            (c.contains("TARGET") && !ReadVec3(c["TARGET"], &s.camTarget)))
            return fail("\"CAMERA\"", "CAMERA POSITION and TARGET must be [x, y, z]");
        if (c.contains("FOV")) {
            if (!c["FOV"].is_number()) return fail("\"FOV\"", "FOV must be a number of degrees");
            s.fov = c["FOV"].get<float>();
        }
    }
    if (j.contains("LIGHT")) {
        const json& l = j["LIGHT"];
        if ((l.contains("DIRECTION") && !ReadVec3(l["DIRECTION"], &s.lightDir)) ||
            (l.contains("COLOR") && !ReadVec3(l["COLOR"], &s.lightColor)))
            return fail("\"LIGHT\"", "LIGHT DIRECTION and COLOR must be [x, y, z]");
        float len = std::sqrt(s.lightDir[0] * s.lightDir[0] + s.lightDir[1] * s.lightDir[1] + s.lightDir[2] * s.lightDir[2]);
        if (len < 1e-6f) return fail("\"DIRECTION\"", "LIGHT DIRECTION is zero, expected a direction towards the light");
        for (float& c : s.lightDir) c /= len;
    }
    if (j.contains("MATERIAL")) {
        const json& m = j["MATERIAL"];
        s.roughness = m.value("ROUGHNESS", s.roughness);
        s.metalness = m.value("METALNESS", s.metalness);
    }
    *out = std::move(s);
    return true;
}

std::vector<std::string> ListScenes() {
    std::vector<std::string> names;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(fs::path(DataRoot()) / "shaders" / "scenes", ec))
        if (entry.path().extension() == ".glsl") names.push_back(entry.path().stem().string());
    std::sort(names.begin(), names.end());
    return names;
}

bool FindScene(const std::string& nameOrFile, SceneInfo* out, std::string* error) {
    fs::path asFile(nameOrFile);
    if (nameOrFile.find('/') != std::string::npos || asFile.extension() == ".glsl") {
        if (!fs::exists(asFile)) {
            *error = "scene file '" + nameOrFile + "' does not exist";
            return false;
        }
        return LoadScene(nameOrFile, out, error);
    }
    fs::path p = fs::path(DataRoot()) / "shaders" / "scenes" / (nameOrFile + ".glsl");
    if (!fs::exists(p)) {
        std::string known;
        for (const auto& n : ListScenes()) known += (known.empty() ? "" : ", ") + n;
        *error = "unknown scene '" + nameOrFile + "', expected one of: " + known;
        return false;
    }
    return LoadScene(p.string(), out, error);
}

bool ParseNormalMethod(const std::string& name, int* method, std::string* error) {
    if (name == "central") *method = 0;
    else if (name == "forward") *method = 1;
    else if (name == "tetrahedron" || name == "tetra") *method = 2;
    else {
        *error = "unknown normal method '" + name + "', expected central, forward or tetrahedron";
        return false;
    }
    return true;
}

bool ParseEffectList(const std::string& list, EffectSet* effects, std::string* error) {
    std::stringstream ss(list);
    std::string item;
    while (std::getline(ss, item, ',')) {
        item.erase(std::remove_if(item.begin(), item.end(), ::isspace), item.end());
        if (item.empty()) continue;
        bool on = true;
        if (item[0] == '-') { on = false; item.erase(0, 1); }
        EffectSet& e = *effects;
        if (item == "none") { int n = e.normals; e = EffectSet{}; e.normals = n; }
        else if (item == "hard_shadows") e.shadows = on ? 1 : 0;
        else if (item == "soft_shadows" || item == "shadows") e.shadows = on ? 2 : 0;
        else if (item == "improved_shadows") e.shadows = on ? 3 : 0;
        else if (item == "ao") e.ao = on;
        else if (item == "specular") e.specular = on;
        else if (item == "pbr") e.pbr = on;
        else if (item == "fog") e.fog = on;
        else if (item == "fixed_step") e.marchFixed = on;
        else if (item == "heatmap" || item == "steps") e.debugView = on ? 1 : 0;
        else if (item == "depth") e.debugView = on ? 2 : 0;
        else if (item == "normals") e.debugView = on ? 3 : 0;
        else if (item.rfind("reflections", 0) == 0) {
            int n = 1;
            if (item.size() > 11) {
                if (item[11] != '=' && item[11] != ':') { *error = "bad effect '" + item + "', expected reflections=N"; return false; }
                n = std::atoi(item.c_str() + 12);
                if (n < 0 || n > 8) { *error = "reflections bounce count must be 0..8"; return false; }
            }
            e.reflections = on ? n : 0;
        } else {
            *error = "unknown effect '" + item + "', expected hard_shadows, soft_shadows, improved_shadows, ao, specular, pbr, "
                     "reflections[=N], fog, fixed_step, heatmap, depth, normals or none (prefix - to remove)";
            return false;
        }
    }
    return true;
}

std::string DescribeEffects(const EffectSet& e) {
    std::string s;
    auto add = [&](const std::string& x) { s += (s.empty() ? "" : ",") + x; };
    static const char* kShadows[] = {"", "hard_shadows", "soft_shadows", "improved_shadows"};
    if (e.shadows) add(kShadows[e.shadows]);
    if (e.ao) add("ao");
    if (e.specular) add("specular");
    if (e.pbr) add("pbr");
    if (e.reflections) add("reflections=" + std::to_string(e.reflections));
    if (e.fog) add("fog");
    if (e.marchFixed) add("fixed_step");
    static const char* kDebug[] = {"", "heatmap", "depth", "normals"};
    if (e.debugView) add(kDebug[e.debugView]);
    return s.empty() ? "none" : s;
}

std::vector<LightingTest> SeedLightingTests() {
    EffectSet full, shadowsAo, shadows, none;
    full.shadows = shadowsAo.shadows = shadows.shadows = 2;
    full.ao = shadowsAo.ao = true;
    full.specular = true;
    return {{"full", full}, {"shadows_ao", shadowsAo}, {"shadows", shadows}, {"none", none}};
}

}  // namespace sdfvj
