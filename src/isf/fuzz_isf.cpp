// libFuzzer entry for ISF files, which a VJ saves during a show (untrusted): any bytes must give a
// parsed file or one "path:LINE: ..." error, never a crash, a sanitizer report, an exception or a
// runaway allocation; and what a parsed file hands the renderer (parameters, pass sizes, the
// translated GLSL) must be usable as it is. Run with scripts/fuzz.sh --only isf.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <map>
#include <string>

#include "isf/isf.h"

namespace {

// "path:LINE: ..." with LINE a positive number.
bool NamesFileAndLine(const std::string& message, const std::string& path) {
    if (message.rfind(path + ":", 0) != 0) return false;
    size_t i = path.size() + 1, digits = 0;
    while (i < message.size() && message[i] >= '0' && message[i] <= '9') ++i, ++digits;
    return digits > 0 && i + 1 < message.size() && message[i] == ':' && message[i + 1] == ' ' && message[path.size() + 1] != '0';
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    const std::string path = "/nonexistent/fuzz/effect.fs";

    // The pass-size expression evaluator alone: a value is finite, an error is a sentence.
    {
        const std::map<std::string, double> vars{{"WIDTH", 640}, {"HEIGHT", 360}, {"amount", 0.5}};
        double v = 0;
        std::string why;
        if (sdfvj::EvalIsfExpression(text.substr(0, 256), vars, &v, &why)) {
            if (!std::isfinite(v)) std::abort();
        } else if (why.empty()) {
            std::abort();
        }
    }

    sdfvj::IsfFile f;
    std::string error;
    if (!sdfvj::ParseIsfText(text, path, &f, &error)) {
        if (!NamesFileAndLine(error, path)) std::abort();
        return 0;
    }
    if (f.passes.empty()) std::abort();
    for (const std::string& n : f.notices)
        if (!NamesFileAndLine(n, path)) std::abort();
    // Parameters: finite, the default inside its range (ClampParam and the overlay rely on it).
    const std::vector<sdfvj::ParamDecl> decls = sdfvj::IsfParams(f);
    std::map<std::string, double> vars{{"WIDTH", 1920}, {"HEIGHT", 1080}};
    for (const sdfvj::ParamDecl& d : decls) {
        if (!std::isfinite(d.minValue) || !std::isfinite(d.maxValue) || !std::isfinite(d.defaultValue)) std::abort();
        if (!(d.minValue <= d.defaultValue && d.defaultValue <= d.maxValue)) std::abort();
        if (d.name.empty()) std::abort();
    }
    for (const sdfvj::IsfInput& in : f.inputs) {
        if (in.name.empty()) std::abort();
        vars[in.name] = in.defaultValue[0];
    }
    // A pass's size as the renderer computes it: the expression evaluates (it was checked at load)
    // or the renderer falls back to the frame's size; either way a finite number.
    for (const sdfvj::IsfPass& p : f.passes)
        for (const std::string* e : {&p.widthExpr, &p.heightExpr}) {
            if (e->empty()) continue;
            double v = 0;
            std::string why;
            if (sdfvj::EvalIsfExpression(*e, vars, &v, &why) && !std::isfinite(v)) std::abort();
        }
    // --param overrides of every parameter, by name, with a value out of range: clamped, no error.
    std::vector<std::string> overrides;
    for (const sdfvj::ParamDecl& d : decls) overrides.push_back(d.name + "=1e30");
    std::vector<std::pair<std::string, float>> values;
    std::string why;
    if (!sdfvj::ApplyIsfParamOverrides(decls, overrides, &values, &why)) std::abort();
    for (const auto& [name, v] : values)
        if (!std::isfinite(v)) std::abort();
    // The GLSL the driver gets: starts with #version, or an error naming the file.
    sdfvj::IsfSources src;
    if (sdfvj::TranslateIsf(f, &src, &why)) {
        if (src.fragment.text.rfind("#version", 0) != 0 || src.vertex.text.rfind("#version", 0) != 0) std::abort();
    } else if (!NamesFileAndLine(why, path)) {
        std::abort();
    }
    return 0;
}
