// ISF inputs as scene parameters, --param overrides, and post-chain lists.
#include <cstdlib>
#include <filesystem>

#include "isf/isf.h"
#include "scene/scene.h"

namespace fs = std::filesystem;

namespace sdfvj {

std::vector<ParamDecl> IsfParams(const IsfFile& file) {
    std::vector<ParamDecl> out;
    auto add = [&](const IsfInput& in, const std::string& name, ParamType type, int c, const std::string& label) {
        ParamDecl d;
        d.name = name;
        d.type = type;
        d.defaultValue = in.defaultValue[c];
        d.minValue = in.minValue[c];
        d.maxValue = in.maxValue[c];
        d.label = label;
        out.push_back(d);
    };
    for (const IsfInput& in : file.inputs) {
        switch (in.type) {
            case IsfInputType::Float: add(in, in.name, ParamType::Float, 0, in.label); break;
            case IsfInputType::Bool: case IsfInputType::Event: add(in, in.name, ParamType::Bool, 0, in.label); break;
            case IsfInputType::Long: add(in, in.name, ParamType::Int, 0, in.label); break;
            case IsfInputType::Point2D:
                add(in, in.name + "_x", ParamType::Float, 0, in.label + " x");
                add(in, in.name + "_y", ParamType::Float, 1, in.label + " y");
                break;
            case IsfInputType::Color: {
                const char* ch[] = {"_r", "_g", "_b", "_a"};
                for (int c = 0; c < 4; ++c) add(in, in.name + ch[c], ParamType::Float, c, in.label + ch[c]);
                break;
            }
            default: break;   // images and audio are textures, not values
        }
    }
    return out;
}

bool ApplyIsfParamOverrides(const std::vector<ParamDecl>& decls, const std::vector<std::string>& overrides,
                            std::vector<std::pair<std::string, float>>* values, std::string* error) {
    for (const std::string& kv : overrides) {
        const size_t eq = kv.find('=');
        char* end = nullptr;
        const float v = eq == std::string::npos ? 0.0f : std::strtof(kv.c_str() + eq + 1, &end);
        if (eq == std::string::npos || end == kv.c_str() + eq + 1 || *end != '\0') {
            *error = "bad --param '" + kv + "', expected NAME=VALUE such as amount=0.5";
            return false;
        }
        const std::string name = kv.substr(0, eq);
        const ParamDecl* decl = nullptr;
        for (const ParamDecl& d : decls)
            if (d.name == name) decl = &d;
        if (!decl) {
            std::string known;
            for (const ParamDecl& d : decls) known += (known.empty() ? "" : ", ") + d.name;
            *error = "--param: no ISF input '" + name + "', expected one of: " + (known.empty() ? "(none)" : known);
            return false;
        }
        bool set = false;
        for (auto& [n, value] : *values)
            if (n == name) { value = ClampParam(*decl, v); set = true; }
        if (!set) values->emplace_back(name, ClampParam(*decl, v));
    }
    return true;
}

bool IsfListParams(const std::vector<std::string>& paths, std::vector<ParamDecl>* out, std::string* error) {
    for (const std::string& p : paths) {
        IsfFile f;
        std::error_code ec;
        if (!fs::is_regular_file(p, ec)) {
            std::string known;
            for (const auto& e : fs::directory_iterator(fs::path(DataRoot()) / "shaders" / "isf", ec))
                if (IsIsfPath(e.path().string())) known += (known.empty() ? "" : ", ") + e.path().stem().string();
            *error = "unknown ISF file '" + p + "', expected a .fs file or one of shaders/isf: " + (known.empty() ? "(none)" : known);
            return false;
        }
        if (!LoadIsfFile(p, &f, error)) return false;
        for (const ParamDecl& d : IsfParams(f)) {
            bool seen = false;
            for (const ParamDecl& o : *out) seen = seen || o.name == d.name;
            if (!seen) out->push_back(d);
        }
    }
    return true;
}

void SplitIsfOverrides(const std::vector<ParamDecl>& decls, std::vector<std::string>* params, std::vector<std::string>* isf) {
    std::vector<std::string> rest;
    for (const std::string& kv : *params) {
        const std::string name = kv.substr(0, kv.find('='));
        bool ours = false;
        for (const ParamDecl& d : decls) ours = ours || d.name == name;
        (ours ? *isf : rest).push_back(kv);
    }
    *params = std::move(rest);
}

std::vector<std::string> SplitIsfList(const std::string& list) {
    std::vector<std::string> out;
    size_t b = 0;
    while (b <= list.size()) {
        size_t e = list.find(',', b);
        if (e == std::string::npos) e = list.size();
        std::string item = list.substr(b, e - b);
        while (!item.empty() && item.front() == ' ') item.erase(item.begin());
        while (!item.empty() && item.back() == ' ') item.pop_back();
        if (!item.empty()) out.push_back(ResolveIsfPath(item));
        b = e + 1;
    }
    return out;
}

std::string ResolveIsfPath(const std::string& name) {
    std::error_code ec;
    if (fs::is_regular_file(name, ec)) return name;
    const fs::path shipped = fs::path(DataRoot()) / "shaders" / "isf" / name;
    if (fs::is_regular_file(shipped, ec)) return shipped.string();
    if (fs::is_regular_file(shipped.string() + ".fs", ec)) return shipped.string() + ".fs";
    return name;   // LoadIsfFile then says it cannot read it
}

}  // namespace sdfvj
