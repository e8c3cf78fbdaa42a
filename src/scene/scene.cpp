#include "scene/scene.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "scene/json_lines.h"

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

bool ReadFile(const std::string& path, std::string* text) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return false;
    std::stringstream ss;
    ss << in.rdbuf();
    *text = ss.str();
    return true;
}

int ShadowKind(const std::string& s) {
    if (s == "none" || s == "off") return 0;
    if (s == "hard") return 1;
    if (s == "soft") return 2;
    if (s == "improved" || s == "improved_soft") return 3;
    return -1;
}

std::string Format(double v) {
    std::ostringstream out;
    out << v;
    return out.str();
}

// A value for a message: strings quoted and cut, others by type.
std::string Brief(const json& v) {
    if (v.is_string()) return "'" + v.get_ref<const std::string&>().substr(0, 32) + "'";
    return v.type_name();
}

std::string Upper(std::string s) {
    for (char& c : s) c = char(std::toupper((unsigned char)c));
    return s;
}

// Ranges a header may declare. Wider values are typos or attacks, never a look anyone wants,
// and they overflow float arithmetic in the shader (a range of 3e38 - -3e38 is inf).
// DEFAULT/MIN/MAX: anything a float holds (the stability scenes declare MAX 1e30 on purpose),
// with MAX - MIN finite too, so normalising by the range never gives inf.
constexpr double kParamLimit = std::numeric_limits<float>::max();
constexpr double kCoordLimit = 1e6;     // CAMERA POSITION/TARGET, LIGHT DIRECTION
constexpr double kColorLimit = 1e3;     // LIGHT COLOR, 0..kColorLimit (HDR allowed)
constexpr size_t kMaxNameLength = 64;   // input NAME: a GLSL identifier, u_ prefixed
constexpr size_t kMaxTextLength = 4096; // NAME, DESCRIPTION, LABEL

// Every check of one header, with the text and layout it needs to put a line on its errors.
struct HeaderChecker {
    const std::string& path;
    const std::string& text;
    const JsonLayout& layout;
    int headerLine;
    std::string* error;

    bool Fail(const std::string& pointer, const std::string& msg) const {
        *error = path + ":" + std::to_string(LineOfPointer(text, layout, pointer, headerLine)) + ": " + msg;
        return false;
    }

    // A string of at most kMaxTextLength bytes.
    bool String(const json& v, const std::string& pointer, const std::string& what, std::string* out) const {
        if (!v.is_string()) return Fail(pointer, what + " is " + std::string(v.type_name()) + ", expected a string");
        const std::string& s = v.get_ref<const std::string&>();
        if (s.size() > kMaxTextLength) return Fail(pointer, what + " is longer than 4096 bytes, expected a short text");
        *out = s;
        return true;
    }

    // A finite JSON number in [lo, hi] (so it also fits a float: 1e300 is an error, not inf).
    bool Number(const json& v, const std::string& pointer, const std::string& what, double lo, double hi,
                float* out) const {
        auto range = [&] { return "expected a number in [" + Format(lo) + ", " + Format(hi) + "]"; };
        if (!v.is_number()) return Fail(pointer, what + " is " + std::string(v.type_name()) + ", " + range());
        const double d = v.get<double>();
        if (!std::isfinite(d) || d < lo || d > hi) return Fail(pointer, what + " is " + Format(d) + ", " + range());
        *out = float(d);
        return true;
    }

    // [x, y, z], each a finite number in [lo, hi].
    bool Vec3(const json& v, const std::string& pointer, const std::string& what, double lo, double hi,
              Vec3f* out) const {
        if (!v.is_array() || v.size() != 3)
            return Fail(pointer, what + " is " + (v.is_array() ? "an array of " + std::to_string(v.size())
                                                                 : std::string(v.type_name())) +
                                     ", expected [x, y, z]");
        Vec3f r{};
        for (size_t i = 0; i < 3; ++i)
            if (!Number(v[i], pointer + "/" + std::to_string(i), what + "[" + std::to_string(i) + "]", lo, hi, &r[i]))
                return false;
        *out = r;
        return true;
    }

    bool Object(const json& v, const std::string& pointer, const std::string& what, const std::string& example) const {
        if (!v.is_object()) return Fail(pointer, what + " is " + std::string(v.type_name()) + ", expected an object " + example);
        return true;
    }

    // Keys of an sdfvj section must be known: a typo ("POSITON") would otherwise be ignored.
    bool OnlyKeys(const json& obj, const std::string& pointer, const std::string& section,
                  std::initializer_list<const char*> known) const {
        for (auto it = obj.begin(); it != obj.end(); ++it) {
            if (std::find_if(known.begin(), known.end(), [&](const char* k) { return it.key() == k; }) != known.end())
                continue;
            std::string list;
            for (const char* k : known) list += (list.empty() ? "" : ", ") + std::string(k);
            return Fail(pointer + "/" + it.key(), "unknown key '" + it.key() + "' in " + section + ", expected " + list);
        }
        return true;
    }

    bool Input(const json& in, const std::string& at, const std::vector<ParamDecl>& earlier, ParamDecl* out) const {
        if (!in.is_object())
            return Fail(at, "an input is " + std::string(in.type_name()) +
                                ", expected {\"NAME\": \"twist\", \"TYPE\": \"float\", ...}");
        if (!in.contains("NAME"))
            return Fail(at, "an input has no NAME, expected {\"NAME\": \"twist\", \"TYPE\": \"float\", ...}");
        ParamDecl d;
        if (!in["NAME"].is_string())
            return Fail(at + "/NAME", "input NAME is " + std::string(in["NAME"].type_name()) + ", expected a string");
        d.name = in["NAME"].get_ref<const std::string&>();
        bool identifier = !d.name.empty() && d.name.size() <= kMaxNameLength && !std::isdigit((unsigned char)d.name[0]) &&
                          std::all_of(d.name.begin(), d.name.end(), [](char c) { return std::isalnum((unsigned char)c) || c == '_'; });
        if (!identifier)
            return Fail(at + "/NAME", "input name '" + d.name.substr(0, kMaxNameLength) +
                                          "' is not an identifier, expected letters, digits and _ (at most 64)");
        const std::string who = "input '" + d.name + "'";
        std::string type = "float";
        if (in.contains("TYPE") && !String(in["TYPE"], at + "/TYPE", who + " TYPE", &type)) return false;
        if (type == "float") d.type = ParamType::Float;
        else if (type == "int" || type == "long") d.type = ParamType::Int;
        else if (type == "bool") d.type = ParamType::Bool;
        else return Fail(at + "/TYPE", who + " has TYPE '" + type + "', expected float, int or bool");
        auto value = [&](const char* key, float fallback, float* v) {
            *v = fallback;
            if (!in.contains(key)) return true;
            const json& x = in[key];
            if (x.is_boolean()) {
                *v = x.get<bool>() ? 1.0f : 0.0f;
                return true;
            }
            if (!x.is_number())
                return Fail(at + "/" + key, who + " has a non-numeric " + key + " (" + x.type_name() +
                                                "), expected a number that fits a float");
            return Number(x, at + "/" + key, who + " " + key, -kParamLimit, kParamLimit, v);
        };
        if (!value("MIN", 0.0f, &d.minValue) || !value("MAX", 1.0f, &d.maxValue)) return false;
        if (!value("DEFAULT", d.minValue, &d.defaultValue)) return false;
        if (d.minValue > d.maxValue) return Fail(at + "/MIN", who + " has MIN > MAX, expected MIN <= MAX");
        if (double(d.maxValue) - double(d.minValue) > kParamLimit)
            return Fail(at + "/MIN", who + " has a range MAX - MIN that overflows a float, expected a narrower range");
        if (d.defaultValue < d.minValue || d.defaultValue > d.maxValue)
            return Fail(at + "/DEFAULT", who + " has DEFAULT outside [MIN, MAX], expected a default inside its range");
        d.label = d.name;
        if (in.contains("LABEL") && !String(in["LABEL"], at + "/LABEL", who + " LABEL", &d.label)) return false;
        for (const ParamDecl& other : earlier)
            if (other.name == d.name) return Fail(at + "/NAME", who + " is declared twice, expected unique names");
        *out = std::move(d);
        return true;
    }

    bool Effects(const json& e, EffectSet* out) const {
        if (!Object(e, "/EFFECTS", "EFFECTS", "{\"SHADOWS\": \"soft\", \"AO\": true, ...}")) return false;
        for (auto it = e.begin(); it != e.end(); ++it) {
            const std::string& k = it.key();
            const json& v = it.value();
            const std::string at = "/EFFECTS/" + k;
            if (k == "SHADOWS") {
                int kind = v.is_string() ? ShadowKind(v.get_ref<const std::string&>())
                                         : (v.is_boolean() ? (v.get<bool>() ? 2 : 0) : -1);
                if (kind < 0) return Fail(at, "SHADOWS is " + Brief(v) + ", expected none, hard, soft or improved");
                out->shadows = kind;
            } else if (k == "AO" || k == "SPECULAR" || k == "PBR" || k == "FOG") {
                if (!v.is_boolean()) return Fail(at, k + " is " + v.type_name() + ", expected true or false");
                bool b = v.get<bool>();
                if (k == "AO") out->ao = b;
                if (k == "SPECULAR") out->specular = b;
                if (k == "PBR") out->pbr = b;
                if (k == "FOG") out->fog = b;
            } else if (k == "REFLECTIONS") {
                float n = 0;
                if (!v.is_number_integer() || !Number(v, at, "REFLECTIONS", 0, 8, &n))
                    return Fail(at, "REFLECTIONS must be a bounce count 0..8, expected an integer");
                out->reflections = int(n);
            } else if (k == "NORMALS") {
                std::string why;
                if (!v.is_string() || !ParseNormalMethod(v.get_ref<const std::string&>(), &out->normals, &why))
                    return Fail(at, "NORMALS is " + Brief(v) + ", expected central, forward or tetrahedron");
            } else {
                return Fail(at, "unknown effect '" + k + "', expected SHADOWS, AO, SPECULAR, PBR, REFLECTIONS, FOG or NORMALS");
            }
        }
        return true;
    }

    bool Scene(const json& j, SceneInfo* s) const {
        if (!j.is_object()) return Fail("", "scene header is not a JSON object, expected {\"NAME\": ..., \"INPUTS\": [...]}");
        // Top-level keys sdfvj does not read are accepted: ISF headers carry others (ISFVSN,
        // CREDIT, CATEGORIES, PASSES...). A known key in the wrong case is a typo, not ISF.
        static const char* kKnown[] = {"NAME", "DESCRIPTION", "INPUTS", "EFFECTS", "CAMERA", "LIGHT", "MATERIAL"};
        for (auto it = j.begin(); it != j.end(); ++it)
            for (const char* k : kKnown)
                if (it.key() != k && Upper(it.key()) == k)
                    return Fail("/" + it.key(), "unknown key '" + it.key() + "', expected " + k + " (upper case)");
        if (j.contains("NAME") && !String(j["NAME"], "/NAME", "NAME", &s->name)) return false;
        if (s->name.empty()) return Fail("/NAME", "NAME is empty, expected the scene's name");
        if (j.contains("DESCRIPTION") && !String(j["DESCRIPTION"], "/DESCRIPTION", "DESCRIPTION", &s->description))
            return false;
        if (j.contains("INPUTS")) {
            const json& inputs = j["INPUTS"];
            if (!inputs.is_array())
                return Fail("/INPUTS", "INPUTS is " + std::string(inputs.type_name()) + ", expected a list of parameters");
            for (size_t i = 0; i < inputs.size(); ++i) {
                ParamDecl d;
                if (!Input(inputs[i], "/INPUTS/" + std::to_string(i), s->params, &d)) return false;
                s->params.push_back(std::move(d));
            }
        }
        if (j.contains("EFFECTS") && !Effects(j["EFFECTS"], &s->effects)) return false;
        if (j.contains("CAMERA")) {
            const json& c = j["CAMERA"];
            if (!Object(c, "/CAMERA", "CAMERA", "{\"POSITION\": [x, y, z], \"TARGET\": [x, y, z], \"FOV\": 45}") ||
                !OnlyKeys(c, "/CAMERA", "CAMERA", {"POSITION", "TARGET", "FOV"}))
                return false;
            if (c.contains("POSITION") && !Vec3(c["POSITION"], "/CAMERA/POSITION", "CAMERA POSITION", -kCoordLimit, kCoordLimit, &s->camPos))
                return false;
            if (c.contains("TARGET") && !Vec3(c["TARGET"], "/CAMERA/TARGET", "CAMERA TARGET", -kCoordLimit, kCoordLimit, &s->camTarget))
                return false;
            if (c.contains("FOV")) {
                if (!Number(c["FOV"], "/CAMERA/FOV", "CAMERA FOV", 0, 180, &s->fov)) return false;
                if (s->fov <= 0.0f || s->fov >= 180.0f)
                    return Fail("/CAMERA/FOV", "CAMERA FOV is " + Format(s->fov) + ", expected degrees in (0, 180)");
            }
            if (s->camPos == s->camTarget)
                return Fail("/CAMERA", "CAMERA POSITION equals TARGET, expected a camera that looks somewhere");
        }
        if (j.contains("LIGHT")) {
            const json& l = j["LIGHT"];
            if (!Object(l, "/LIGHT", "LIGHT", "{\"DIRECTION\": [x, y, z], \"COLOR\": [r, g, b]}") ||
                !OnlyKeys(l, "/LIGHT", "LIGHT", {"DIRECTION", "COLOR"}))
                return false;
            if (l.contains("DIRECTION") && !Vec3(l["DIRECTION"], "/LIGHT/DIRECTION", "LIGHT DIRECTION", -kCoordLimit, kCoordLimit, &s->lightDir))
                return false;
            if (l.contains("COLOR") && !Vec3(l["COLOR"], "/LIGHT/COLOR", "LIGHT COLOR", 0, kColorLimit, &s->lightColor))
                return false;
            const double x = s->lightDir[0], y = s->lightDir[1], z = s->lightDir[2];
            const double len = std::sqrt(x * x + y * y + z * z);
            if (len < 1e-6) return Fail("/LIGHT/DIRECTION", "LIGHT DIRECTION is zero, expected a direction towards the light");
            for (float& c : s->lightDir) c = float(c / len);
        }
        if (j.contains("MATERIAL")) {
            const json& m = j["MATERIAL"];
            if (!Object(m, "/MATERIAL", "MATERIAL", "{\"ROUGHNESS\": 0.5, \"METALNESS\": 0.0}") ||
                !OnlyKeys(m, "/MATERIAL", "MATERIAL", {"ROUGHNESS", "METALNESS"}))
                return false;
            if (m.contains("ROUGHNESS") && !Number(m["ROUGHNESS"], "/MATERIAL/ROUGHNESS", "MATERIAL ROUGHNESS", 0, 1, &s->roughness))
                return false;
            if (m.contains("METALNESS") && !Number(m["METALNESS"], "/MATERIAL/METALNESS", "MATERIAL METALNESS", 0, 1, &s->metalness))
                return false;
        }
        return true;
    }
};

// ParseSceneText without the last-resort catch.
bool ParseSceneHeader(const std::string& text, const std::string& path, SceneInfo* out, std::string* error) {
    size_t open = text.find("/*{");
    if (open == std::string::npos) {
        *error = path + ":1: no scene header, expected the file to open with a /*{ ... }*/ JSON header";
        return false;
    }
    const int headerLine = LineOfOffset(text, open);
    size_t close = text.find("}*/", open);
    if (close == std::string::npos) {
        *error = path + ":" + std::to_string(headerLine) + ": scene header is never closed, expected }*/ after the JSON";
        return false;
    }
    const size_t jsonStart = open + 2;
    if (close + 1 - jsonStart > kMaxJsonBytes) {
        *error = path + ":" + std::to_string(headerLine) + ": scene header is larger than 1 MiB, expected a short JSON header";
        return false;
    }
    JsonLayout layout;
    if (!ScanJsonLayout(text, jsonStart, close + 1, kMaxJsonDepth, &layout)) {
        *error = path + ":" + std::to_string(LineOfOffset(text, layout.tooDeepAt)) +
                 ": scene header nests deeper than 64 levels, expected at most 64 levels of [ and {";
        return false;
    }
    const std::string header = text.substr(jsonStart, close + 1 - jsonStart);
    json j;
    try {
        j = json::parse(header);
    } catch (const json::parse_error& e) {
        *error = path + ":" + std::to_string(LineOfOffset(text, jsonStart + (e.byte > 0 ? e.byte - 1 : 0))) +
                 ": bad JSON in scene header (" + JsonErrorReason(e.what()) + "), expected ISF-style JSON";
        return false;
    } catch (const json::exception& e) {
        // out_of_range.406 "number overflow parsing '1e400'": find the number for its line.
        std::string what = JsonErrorReason(e.what());
        size_t at = open;
        if (size_t q = what.find('\''); q != std::string::npos) {
            size_t q2 = what.find('\'', q + 1);
            if (q2 != std::string::npos && q2 > q + 1)
                if (size_t p = header.find(what.substr(q + 1, q2 - q - 1)); p != std::string::npos) at = jsonStart + p;
        }
        *error = path + ":" + std::to_string(LineOfOffset(text, at)) + ": bad JSON in scene header (" + what +
                 "), expected numbers that fit a float";
        return false;
    }
    HeaderChecker check{path, text, layout, headerLine, error};
    SceneInfo s;
    s.path = fs::absolute(path).lexically_normal().string();
    s.name = fs::path(path).stem().string();
    if (!check.Scene(j, &s)) return false;
    *out = std::move(s);
    return true;
}

}  // namespace

bool ParseSceneText(const std::string& text, const std::string& path, SceneInfo* out, std::string* error) {
    // Last resort: every check above returns errors as values; anything that still throws
    // (a bug, bad_alloc) becomes one line instead of ending the show.
    try {
        return ParseSceneHeader(text, path, out, error);
    } catch (const std::exception& e) {
        *error = path + ":1: cannot read the scene header (" + std::string(e.what()) + "), expected ISF-style JSON";
    } catch (...) {
        *error = path + ":1: cannot read the scene header (unknown error), expected ISF-style JSON";
    }
    return false;
}

bool LoadScene(const std::string& path, SceneInfo* out, std::string* error) {
    std::string text;
    if (!ReadFile(path, &text)) {
        *error = path + ":1: cannot read the file, expected a readable scene .glsl";
        return false;
    }
    return ParseSceneText(text, path, out, error);
}

std::vector<std::string> ListScenes() {
    std::vector<std::string> names;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(fs::path(DataRoot()) / "shaders" / "scenes", ec))
        if (entry.path().extension() == ".glsl") names.push_back(entry.path().stem().string());
    std::sort(names.begin(), names.end());
    return names;
}

std::string SceneFile(const std::string& nameOrFile) {
    if (nameOrFile.find('/') != std::string::npos || fs::path(nameOrFile).extension() == ".glsl") return nameOrFile;
    return (fs::path(DataRoot()) / "shaders" / "scenes" / (nameOrFile + ".glsl")).string();
}

bool FindScene(const std::string& nameOrFile, SceneInfo* out, std::string* error) {
    const std::string p = SceneFile(nameOrFile);
    if (p == nameOrFile) {
        if (!fs::exists(p)) {
            *error = "scene file '" + nameOrFile + "' does not exist";
            return false;
        }
        return LoadScene(nameOrFile, out, error);
    }
    if (!fs::exists(p)) {
        std::string known;
        for (const auto& n : ListScenes()) known += (known.empty() ? "" : ", ") + n;
        *error = "unknown scene '" + nameOrFile + "', expected one of: " + known;
        return false;
    }
    return LoadScene(p, out, error);
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
        item.erase(std::remove_if(item.begin(), item.end(), [](char c) { return std::isspace((unsigned char)c) != 0; }),
                   item.end());
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
        else if (item == "direct_reflections") e.directReflections = on;
        else if (item == "quad_reflections") e.quadReflections = on;
        else if (item == "ssaa") e.supersample = on ? 1 : 0;
        else if (item == "ssaa_exact") e.supersample = on ? 2 : 0;
        else if (item == "heatmap" || item == "steps") e.debugView = on ? 1 : 0;
        else if (item == "depth") e.debugView = on ? 2 : 0;
        else if (item == "normals") e.debugView = on ? 3 : 0;
        else if (item == "work") e.debugView = on ? 8 : 0;
        else if (item.rfind("reflections", 0) == 0) {
            int n = 1;
            if (item.size() > 11) {
                if (item[11] != '=' && item[11] != ':') { *error = "bad effect '" + item + "', expected reflections=N"; return false; }
                const std::string digits = item.substr(12);
                if (digits.empty() || digits.size() > 1 || !std::isdigit((unsigned char)digits[0]) || digits[0] > '8') {
                    *error = "reflections count '" + digits.substr(0, 16) + "' is not 0..8, expected reflections=N with N 0..8";
                    return false;
                }
                n = digits[0] - '0';
            }
            e.reflections = on ? n : 0;
        } else {
            *error = "unknown effect '" + item + "', expected hard_shadows, soft_shadows, improved_shadows, ao, specular, pbr, "
                     "reflections[=N], direct_reflections, quad_reflections, fog, fixed_step, ssaa, ssaa_exact, heatmap, depth, normals, work or none (prefix - to "
                     "remove)";
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
    if (e.directReflections) add("direct_reflections");
    if (e.quadReflections) add("quad_reflections");
    if (e.fog) add("fog");
    if (e.marchFixed) add("fixed_step");
    if (e.supersample) add(e.supersample == 2 ? "ssaa_exact" : "ssaa");
    static const char* kDebug[] = {"", "heatmap", "depth", "normals", "geometry", "radiance", "work_primary", "work_reflection", "work"};
    if (e.debugView > 0 && e.debugView < int(sizeof kDebug / sizeof kDebug[0])) add(kDebug[e.debugView]);
    else if (e.debugView) add("debug_view=" + std::to_string(e.debugView));
    return s.empty() ? "none" : s;
}

}  // namespace sdfvj
