// ISF JSON header: every field type- and range-checked, each error with the line it is on.
#include <algorithm>
#include <limits>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "isf/isf.h"
#include "scene/json_lines.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace sdfvj {

const char* IsfInputTypeName(IsfInputType t) {
    switch (t) {
        case IsfInputType::Event: return "event";
        case IsfInputType::Bool: return "bool";
        case IsfInputType::Long: return "long";
        case IsfInputType::Float: return "float";
        case IsfInputType::Point2D: return "point2D";
        case IsfInputType::Color: return "color";
        case IsfInputType::Image: return "image";
        case IsfInputType::Audio: return "audio";
        case IsfInputType::AudioFFT: return "audioFFT";
    }
    return "?";
}

namespace {
std::string LowerTail3(const std::string& path) {   // ".fs" of "a/B.FS"
    std::string ext = path.size() < 3 ? std::string() : path.substr(path.size() - 3);
    for (char& c : ext) c = char(std::tolower((unsigned char)c));
    return ext;
}
}  // namespace

bool IsIsfPath(const std::string& path) { return LowerTail3(path) == ".fs"; }

bool IsfHasFeedback(const IsfFile& file) {
    return std::any_of(file.passes.begin(), file.passes.end(), [](const IsfPass& p) { return p.persistent; });
}

bool IsIsfSource(const std::string& path) {
    const std::string ext = LowerTail3(path);
    return ext == ".fs" || ext == ".vs";
}

namespace {

constexpr double kValueLimit = 1e9;      // DEFAULT/MIN/MAX: beyond this is a typo, not a look
constexpr size_t kMaxName = 64;
constexpr size_t kMaxText = 4096;

// Names the preamble declares: an input of the same name would not compile.
const char* const kReserved[] = {"PASSINDEX", "RENDERSIZE", "TIME", "TIMEDELTA", "DATE", "FRAMEINDEX",
                                 "u_beat", "u_bpm", "isf_FragNormCoord", "isf_FragColor", "main"};

bool IsIdentifier(const std::string& s) {
    return !s.empty() && s.size() <= kMaxName && !std::isdigit((unsigned char)s[0]) &&
           std::all_of(s.begin(), s.end(), [](char c) { return std::isalnum((unsigned char)c) || c == '_'; }) &&
           s.find("__") == std::string::npos && s.rfind("gl_", 0) != 0;
}

std::string Num(double v) {
    std::ostringstream o;
    o << v;
    return o.str();
}

struct Checker {
    const std::string& path;
    const std::string& text;
    const JsonLayout& layout;
    int headerLine;
    std::string* error;
    IsfFile* file;

    int Line(const std::string& pointer) const { return LineOfPointer(text, layout, pointer, headerLine); }
    bool Fail(const std::string& pointer, const std::string& msg) const {
        *error = path + ":" + std::to_string(Line(pointer)) + ": " + msg;
        return false;
    }
    void Notice(const std::string& pointer, const std::string& msg) const {
        file->notices.push_back(path + ":" + std::to_string(Line(pointer)) + ": " + msg);
    }
    bool String(const json& v, const std::string& at, const std::string& what, std::string* out) const {
        if (!v.is_string()) return Fail(at, what + " is " + v.type_name() + ", expected a string");
        if (v.get_ref<const std::string&>().size() > kMaxText) return Fail(at, what + " is longer than 4096 bytes, expected a short text");
        *out = v.get<std::string>();
        return true;
    }
    // A number (or a bool as 0/1) in +-kValueLimit.
    bool Number(const json& v, const std::string& at, const std::string& what, float* out) const {
        if (v.is_boolean()) { *out = v.get<bool>() ? 1.0f : 0.0f; return true; }
        if (!v.is_number()) return Fail(at, what + " is " + v.type_name() + ", expected a number");
        const double d = v.get<double>();
        if (!std::isfinite(d) || std::fabs(d) > kValueLimit)
            return Fail(at, what + " is " + Num(d) + ", expected a number in [-1e9, 1e9]");
        *out = float(d);
        return true;
    }
    // PERSISTENT, FLOAT: true/false, a number (positive = on) or "true"/"false".
    bool Flag(const json& v, const std::string& at, const std::string& what, bool* out) const {
        if (v.is_boolean()) *out = v.get<bool>();
        else if (v.is_number()) *out = v.get<double>() > 0;
        else if (v.is_string() && (v == "true" || v == "false" || v == "1" || v == "0")) *out = v == "true" || v == "1";
        else return Fail(at, what + " is " + v.type_name() + ", expected true or false");
        return true;
    }
    // `n` numbers in an array (a color may give 3: alpha is 1).
    bool Vector(const json& v, const std::string& at, const std::string& what, size_t n, std::array<float, 4>* out) const {
        const bool colorRgb = n == 4 && v.is_array() && v.size() == 3;
        if (!v.is_array() || (v.size() != n && !colorRgb))
            return Fail(at, what + " is " + (v.is_array() ? "an array of " + std::to_string(v.size()) : std::string(v.type_name())) +
                                ", expected an array of " + std::to_string(n) + " numbers");
        std::array<float, 4> r{0, 0, 0, 1};
        for (size_t i = 0; i < v.size(); ++i)
            if (!Number(v[i], at + "/" + std::to_string(i), what + "[" + std::to_string(i) + "]", &r[i])) return false;
        *out = r;
        return true;
    }

    bool Input(const json& in, const std::string& at, IsfInput* out) const {
        const std::string example = "{\"NAME\": \"amount\", \"TYPE\": \"float\", ...}";
        if (!in.is_object()) return Fail(at, std::string("an input is ") + in.type_name() + ", expected " + example);
        if (!in.contains("NAME")) return Fail(at, "an input has no NAME, expected " + example);
        IsfInput d;
        d.line = Line(at);
        if (!String(in["NAME"], at + "/NAME", "input NAME", &d.name)) return false;
        if (!IsIdentifier(d.name))
            return Fail(at + "/NAME", "input name '" + d.name.substr(0, kMaxName) +
                                          "' is not a GLSL identifier, expected letters, digits and _ (at most 64, no gl_ or __)");
        for (const char* r : kReserved)
            if (d.name == r) return Fail(at + "/NAME", "input name '" + d.name + "' is an ISF built-in, expected another name");
        for (const IsfInput& other : file->inputs)
            if (other.name == d.name) return Fail(at + "/NAME", "input '" + d.name + "' is declared twice, expected unique names");
        const std::string who = "input '" + d.name + "'";
        if (!in.contains("TYPE")) return Fail(at, who + " has no TYPE, expected one of event, bool, long, float, point2D, color, image, audio, audioFFT");
        std::string type;
        if (!String(in["TYPE"], at + "/TYPE", who + " TYPE", &type)) return false;
        static const std::pair<const char*, IsfInputType> kTypes[] = {
            {"event", IsfInputType::Event}, {"bool", IsfInputType::Bool}, {"long", IsfInputType::Long},
            {"float", IsfInputType::Float}, {"point2D", IsfInputType::Point2D}, {"color", IsfInputType::Color},
            {"image", IsfInputType::Image}, {"audio", IsfInputType::Audio}, {"audioFFT", IsfInputType::AudioFFT}};
        bool known = false;
        for (const auto& [n, t] : kTypes)
            if (type == n) { d.type = t; known = true; }
        if (!known)
            return Fail(at + "/TYPE", who + " has TYPE '" + type.substr(0, kMaxName) +
                                          "', expected one of event, bool, long, float, point2D, color, image, audio, audioFFT");
        d.label = d.name;
        if (in.contains("LABEL") && !String(in["LABEL"], at + "/LABEL", who + " LABEL", &d.label)) return false;

        // Defaults per type, then DEFAULT/MIN/MAX/IDENTITY where the type has values.
        size_t n = 1;
        switch (d.type) {
            case IsfInputType::Float: d.maxValue = {1, 0, 0, 0}; break;
            case IsfInputType::Bool: case IsfInputType::Event: d.maxValue = {1, 0, 0, 0}; break;
            case IsfInputType::Long: d.maxValue = {1, 0, 0, 0}; break;
            case IsfInputType::Point2D: n = 2; d.minValue = {-16384, -16384}; d.maxValue = {16384, 16384}; break;
            case IsfInputType::Color: n = 4; d.maxValue = {1, 1, 1, 1}; d.defaultValue = {0, 0, 0, 1}; break;
            default: n = 0; break;
        }
        auto value = [&](const char* key, std::array<float, 4>* v) {
            if (!in.contains(key)) return true;
            if (n == 0) {
                if ((d.type == IsfInputType::Audio || d.type == IsfInputType::AudioFFT) && std::string(key) == "MAX") {
                    float m = 0;
                    if (!Number(in[key], at + "/" + key, who + " MAX", &m)) return false;
                    if (m < 1 || m > 16384 || m != std::floor(m)) return Fail(at + "/MAX", who + " MAX is " + Num(m) + ", expected a sample count in 1..16384");
                    d.maxSamples = int(m);
                    return true;
                }
                Notice(at + "/" + key, who + " is an " + type + ": its " + key + " is ignored");
                return true;
            }
            if (n == 1) return Number(in[key], at + "/" + key, who + " " + key, &(*v)[0]);
            return Vector(in[key], at + "/" + key, who + " " + key, n, v);
        };
        const bool hadMin = in.contains("MIN"), hadMax = in.contains("MAX"), hadDefault = in.contains("DEFAULT");
        if (!value("MIN", &d.minValue) || !value("MAX", &d.maxValue) || !value("DEFAULT", &d.defaultValue)) return false;
        std::array<float, 4> identity{};
        if (!value("IDENTITY", &identity)) return false;
        if (d.type == IsfInputType::Long) {
            if (in.contains("VALUES")) {
                const json& v = in["VALUES"];
                if (!v.is_array() || v.empty()) return Fail(at + "/VALUES", who + " VALUES is not a non-empty array, expected [0, 1, 2]");
                for (size_t i = 0; i < v.size(); ++i) {
                    float x = 0;
                    const std::string p = at + "/VALUES/" + std::to_string(i);
                    if (!Number(v[i], p, who + " VALUES[" + std::to_string(i) + "]", &x)) return false;
                    if (x != std::floor(x)) return Fail(p, who + " VALUES[" + std::to_string(i) + "] is " + Num(x) + ", expected an integer");
                    d.values.push_back(int(x));
                }
                if (!hadMin) d.minValue[0] = float(*std::min_element(d.values.begin(), d.values.end()));
                if (!hadMax) d.maxValue[0] = float(*std::max_element(d.values.begin(), d.values.end()));
                if (!hadDefault) d.defaultValue[0] = float(d.values[0]);
            }
            if (in.contains("LABELS")) {
                const json& l = in["LABELS"];
                if (!l.is_array()) return Fail(at + "/LABELS", who + " LABELS is " + l.type_name() + ", expected an array of strings");
                for (size_t i = 0; i < l.size(); ++i) {
                    std::string s;
                    if (!String(l[i], at + "/LABELS/" + std::to_string(i), who + " LABELS[" + std::to_string(i) + "]", &s)) return false;
                    d.labels.push_back(s);
                }
                if (d.labels.size() != d.values.size())
                    return Fail(at + "/LABELS", who + " has " + std::to_string(d.labels.size()) + " LABELS and " +
                                                    std::to_string(d.values.size()) + " VALUES, expected one label per value");
            }
        }
        if (d.type == IsfInputType::Float && (!hadMin || !hadMax)) {
            // A bound not given is 0 (MIN) or 1 (MAX), widened so the other bound and the default
            // fit: {"MAX": 10} is 0..10, {"MIN": 2} is 2..3 (DEFAULT 2), {"DEFAULT": 5} is 0..5,
            // {"MAX": -1} is -2..-1. A bound the file gives is kept as written: values are
            // clamped to it on every path (--param, presets, OSC, mappings, the shader's uniform).
            const float inf = std::numeric_limits<float>::infinity();
            if (!hadDefault) d.defaultValue[0] = std::clamp(0.0f, hadMin ? d.minValue[0] : -inf, hadMax ? d.maxValue[0] : inf);
            if (!hadMin) d.minValue[0] = std::min({0.0f, d.defaultValue[0], d.maxValue[0]});
            if (!hadMin && d.minValue[0] >= d.maxValue[0]) d.minValue[0] = d.maxValue[0] - 1.0f;
            if (!hadMax) d.maxValue[0] = std::max({1.0f, d.defaultValue[0], d.minValue[0]});
            if (!hadMax && d.maxValue[0] <= d.minValue[0]) d.maxValue[0] = d.minValue[0] + 1.0f;
        }
        for (size_t i = 0; i < n; ++i) {
            if (d.minValue[i] > d.maxValue[i]) return Fail(at + "/MIN", who + " has MIN > MAX, expected MIN <= MAX");
            if (d.defaultValue[i] < d.minValue[i] || d.defaultValue[i] > d.maxValue[i])
                return Fail(at + "/DEFAULT", who + " has DEFAULT outside [MIN, MAX], expected a default inside its range");
        }
        if (d.type == IsfInputType::Audio || d.type == IsfInputType::AudioFFT)
            Notice(at + "/TYPE", who + " is " + type + ": 512 values a frame (MAX: at most that many) from --audio or the take's WAV; silent without one");
        *out = std::move(d);
        return true;
    }

    bool Pass(const json& p, const std::string& at, IsfPass* out) const {
        if (!p.is_object()) return Fail(at, std::string("a pass is ") + p.type_name() + ", expected {\"TARGET\": \"bufferA\", ...}");
        IsfPass d;
        d.line = Line(at);
        for (auto it = p.begin(); it != p.end(); ++it) {
            const std::string& k = it.key();
            const std::string kat = at + "/" + k;
            const json& v = it.value();
            if (k == "TARGET") {
                if (!String(v, kat, "pass TARGET", &d.target)) return false;
                if (!IsIdentifier(d.target)) return Fail(kat, "pass TARGET '" + d.target.substr(0, kMaxName) + "' is not a GLSL identifier, expected letters, digits and _");
            } else if (k == "PERSISTENT") {
                if (!Flag(v, kat, "pass PERSISTENT", &d.persistent)) return false;
            } else if (k == "FLOAT") {
                if (!Flag(v, kat, "pass FLOAT", &d.floatTarget)) return false;
            } else if (k == "WIDTH" || k == "HEIGHT") {
                std::string e;
                if (v.is_number()) e = Num(v.get<double>());
                else if (!String(v, kat, "pass " + k, &e)) return false;
                std::map<std::string, double> vars{{"WIDTH", 640}, {"HEIGHT", 360}};
                for (const IsfInput& in : file->inputs) vars[in.name] = in.defaultValue[0];
                double r = 0;
                std::string why;
                if (!EvalIsfExpression(e, vars, &r, &why)) return Fail(kat, "pass " + k + " '" + e.substr(0, 64) + "': " + why);
                (k == "WIDTH" ? d.widthExpr : d.heightExpr) = e;
            } else if (k == "DESCRIPTION") {
            } else {
                Notice(kat, "pass key '" + k.substr(0, kMaxName) + "' is not ISF 2.0, ignored");
            }
        }
        if (!d.target.empty()) {
            for (const IsfInput& in : file->inputs)
                if (in.name == d.target) return Fail(at + "/TARGET", "pass TARGET '" + d.target + "' is also an input's name, expected a new name");
        }
        *out = std::move(d);
        return true;
    }

    bool Import(const std::string& name, const json& v, const std::string& at, IsfImport* out) const {
        if (!IsIdentifier(name)) return Fail(at, "IMPORTED name '" + name.substr(0, kMaxName) + "' is not a GLSL identifier, expected letters, digits and _");
        if (!v.is_object() || !v.contains("PATH"))
            return Fail(at, "IMPORTED '" + name + "' is not {\"PATH\": \"image.png\"}, expected an object with a PATH");
        std::string rel;
        if (!String(v["PATH"], at + "/PATH", "IMPORTED '" + name + "' PATH", &rel)) return false;
        IsfImport d{name, (fs::path(path).parent_path() / rel).lexically_normal().string(), Line(at)};
        std::error_code ec;
        if (!fs::is_regular_file(d.path, ec))
            return Fail(at + "/PATH", "IMPORTED '" + name + "' PATH '" + rel.substr(0, 256) + "' is not a file, expected an image beside the .fs");
        *out = std::move(d);
        return true;
    }

    bool Header(const json& h) const {
        if (!h.is_object()) return Fail("", std::string("the ISF header is ") + h.type_name() + ", expected a JSON object {...}");
        std::vector<std::string> v1Persistent;   // ISF 1.0 PERSISTENT_BUFFERS
        for (auto it = h.begin(); it != h.end(); ++it) {
            const std::string& k = it.key();
            const json& v = it.value();
            const std::string at = "/" + k;
            if (k == "ISFVSN") { if (!String(v, at, "ISFVSN", &file->isfVersion)) return false; }
            else if (k == "DESCRIPTION") { if (!String(v, at, "DESCRIPTION", &file->description)) return false; }
            else if (k == "CREDIT") { if (!String(v, at, "CREDIT", &file->credit)) return false; }
            else if (k == "VSN") { std::string s; if (!String(v, at, "VSN", &s)) return false; }
            else if (k == "CATEGORIES") {
                if (!v.is_array()) return Fail(at, std::string("CATEGORIES is ") + v.type_name() + ", expected an array of strings");
                for (size_t i = 0; i < v.size(); ++i) {
                    std::string s;
                    if (!String(v[i], at + "/" + std::to_string(i), "CATEGORIES[" + std::to_string(i) + "]", &s)) return false;
                    file->categories.push_back(s);
                }
            } else if (k == "INPUTS") {
                if (!v.is_array()) return Fail(at, std::string("INPUTS is ") + v.type_name() + ", expected an array of inputs");
                for (size_t i = 0; i < v.size(); ++i) {
                    IsfInput in;
                    if (!Input(v[i], at + "/" + std::to_string(i), &in)) return false;
                    file->inputs.push_back(std::move(in));
                }
            } else if (k == "PASSES" || k == "IMPORTED" || k == "PERSISTENT_BUFFERS") {
                // after INPUTS: WIDTH/HEIGHT may name inputs
            } else {
                Notice(at, "key '" + k.substr(0, kMaxName) + "' is not ISF 2.0, ignored");
            }
        }
        if (h.contains("PERSISTENT_BUFFERS")) {
            const json& v = h["PERSISTENT_BUFFERS"];
            if (v.is_array()) {
                for (size_t i = 0; i < v.size(); ++i) {
                    std::string s;
                    if (!String(v[i], "/PERSISTENT_BUFFERS/" + std::to_string(i), "PERSISTENT_BUFFERS entry", &s)) return false;
                    v1Persistent.push_back(s);
                }
            } else if (v.is_object()) {
                for (auto it = v.begin(); it != v.end(); ++it) v1Persistent.push_back(it.key());
            } else {
                return Fail("/PERSISTENT_BUFFERS", std::string("PERSISTENT_BUFFERS is ") + v.type_name() + ", expected an array of names");
            }
        }
        if (h.contains("PASSES")) {
            const json& v = h["PASSES"];
            if (!v.is_array()) return Fail("/PASSES", std::string("PASSES is ") + v.type_name() + ", expected an array of passes");
            if (v.size() > 64) return Fail("/PASSES", "PASSES has " + std::to_string(v.size()) + " passes, expected at most 64");
            for (size_t i = 0; i < v.size(); ++i) {
                IsfPass p;
                if (!Pass(v[i], "/PASSES/" + std::to_string(i), &p)) return false;
                if (std::find(v1Persistent.begin(), v1Persistent.end(), p.target) != v1Persistent.end()) p.persistent = true;
                file->passes.push_back(std::move(p));
            }
        }
        if (h.contains("IMPORTED")) {
            const json& v = h["IMPORTED"];
            if (v.is_object()) {
                for (auto it = v.begin(); it != v.end(); ++it) {
                    IsfImport im;
                    if (!Import(it.key(), it.value(), "/IMPORTED/" + it.key(), &im)) return false;
                    file->imports.push_back(std::move(im));
                }
            } else if (v.is_array()) {   // ISF 1.0: [{"NAME": ..., "PATH": ...}]
                for (size_t i = 0; i < v.size(); ++i) {
                    const std::string at = "/IMPORTED/" + std::to_string(i);
                    std::string name;
                    if (!v[i].is_object() || !v[i].contains("NAME")) return Fail(at, "an IMPORTED entry has no NAME, expected {\"NAME\": \"img\", \"PATH\": \"img.png\"}");
                    if (!String(v[i]["NAME"], at + "/NAME", "IMPORTED NAME", &name)) return false;
                    IsfImport im;
                    if (!Import(name, v[i], at, &im)) return false;
                    file->imports.push_back(std::move(im));
                }
            } else {
                return Fail("/IMPORTED", std::string("IMPORTED is ") + v.type_name() + ", expected {\"name\": {\"PATH\": \"image.png\"}}");
            }
        }
        return true;
    }
};

}  // namespace

bool ParseIsfText(const std::string& text, const std::string& path, IsfFile* out, std::string* error) {
    IsfFile f;
    f.path = path;
    size_t i = 0;
    if (text.compare(0, 3, "\xEF\xBB\xBF") == 0) i = 3;   // UTF-8 byte order mark
    while (i < text.size() && std::isspace((unsigned char)text[i])) ++i;
    size_t open = std::string::npos, close = std::string::npos;
    if (text.compare(i, 2, "/*") == 0) {
        close = text.find("*/", i + 2);
        size_t j = i + 2;
        while (j < text.size() && std::isspace((unsigned char)text[j])) ++j;
        if (j < text.size() && text[j] == '{') open = j;
    }
    if (open == std::string::npos) {
        if (text.find("mainImage") != std::string::npos) {
            f.kind = IsfKind::Shadertoy;
            f.body = text;
            f.bodyLine = 1;
            f.passes.push_back(IsfPass{});
            for (const char* ch : {"iChannel1", "iChannel2", "iChannel3"})
                if (text.find(ch) != std::string::npos)
                    f.notices.push_back(path + ":1: Shadertoy " + std::string(ch) + " is not supported, it reads black (iChannel0 is the previous stage)");
            *out = std::move(f);
            return true;
        }
        *error = path + ":" + std::to_string(LineOfOffset(text, i)) +
                 ": no ISF header, expected the file to open with a JSON comment /*{ \"INPUTS\": [...] }*/ "
                 "(or a Shadertoy mainImage)";
        return false;
    }
    if (close == std::string::npos) {
        *error = path + ":" + std::to_string(LineOfOffset(text, i)) + ": the ISF header comment is not closed, expected */ after the JSON";
        return false;
    }
    const int headerLine = LineOfOffset(text, open);
    if (close - open > kMaxJsonBytes) {
        *error = path + ":" + std::to_string(headerLine) + ": the ISF header is larger than 1 MiB, expected a short JSON header";
        return false;
    }
    JsonLayout layout;
    if (!ScanJsonLayout(text, open, close, kMaxJsonDepth, &layout)) {
        *error = path + ":" + std::to_string(LineOfOffset(text, layout.tooDeepAt)) + ": the ISF header nests deeper than " +
                 std::to_string(kMaxJsonDepth) + " levels, expected a flat header";
        return false;
    }
    json h;
    try {
        h = json::parse(text.begin() + (long)open, text.begin() + (long)close);
    } catch (const json::parse_error& e) {
        const size_t at = std::min(close, open + (e.byte > 0 ? e.byte - 1 : 0));
        *error = path + ":" + std::to_string(LineOfOffset(text, at)) + ": the ISF header is not valid JSON (" +
                 JsonErrorReason(e.what()) + "), expected a JSON object";
        return false;
    } catch (const std::exception& e) {
        *error = path + ":" + std::to_string(headerLine) + ": the ISF header is not valid JSON (" + e.what() + ")";
        return false;
    }
    try {
        Checker c{path, text, layout, headerLine, error, &f};
        if (!c.Header(h)) return false;
    } catch (const std::exception& e) {   // a checker bug must not reach the frame loop either
        *error = path + ":" + std::to_string(headerLine) + ": the ISF header could not be read (" + e.what() + ")";
        return false;
    }
    f.body = text.substr(close + 2);
    f.bodyLine = LineOfOffset(text, close + 2);
    if (f.passes.empty()) {   // single pass to the output
        IsfPass p;
        p.line = headerLine;
        f.passes.push_back(p);
    }
    f.kind = IsfKind::Generator;
    int images = 0;
    for (const IsfInput& in : f.inputs)
        if (in.type == IsfInputType::Image) {
            f.kind = IsfKind::Filter;
            if (++images == 2)
                f.notices.push_back(path + ":" + std::to_string(in.line) + ": image input '" + in.name +
                                    "' also reads the previous stage's frame (sdfvj has one image source per stage)");
        }
    *out = std::move(f);
    return true;
}

bool LoadIsfFile(const std::string& path, IsfFile* out, std::string* error) {
    auto read = [](const std::string& p, std::string* text) {
        std::ifstream in(p, std::ios::binary);
        if (!in) return false;
        std::stringstream ss;
        ss << in.rdbuf();
        *text = ss.str();
        return true;
    };
    std::string text;
    if (!read(path, &text)) {
        *error = path + ":1: cannot read the file, expected an ISF .fs file";
        return false;
    }
    IsfFile f;
    if (!ParseIsfText(text, path, &f, error)) return false;
    const std::string vs = fs::path(path).replace_extension(".vs").string();
    std::error_code ec;
    if (fs::is_regular_file(vs, ec)) {
        if (!read(vs, &f.vertexBody)) {
            *error = vs + ":1: cannot read the file, expected the ISF vertex shader";
            return false;
        }
        f.vertexPath = vs;
    }
    *out = std::move(f);
    return true;
}

}  // namespace sdfvj
