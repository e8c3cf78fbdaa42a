#include "app/show.h"

#include <algorithm>

#include "isf/isf.h"

#include <cstdio>
#include <filesystem>

namespace fs = std::filesystem;

namespace sdfvj {

bool ParseSizeAndPath(const std::string& size, const std::string& path, int* w, int* h, RenderPath* rp, std::string* error) {
    if (!ParseSize(size, w, h, error)) return false;
    if (path != "compute" && path != "fragment") {
        *error = "unknown path '" + path + "', expected compute or fragment";
        return false;
    }
    *rp = path == "fragment" ? RenderPath::Fragment : RenderPath::Compute;
    return true;
}

bool ParseSize(const std::string& text, int* w, int* h, std::string* error) {
    int a = 0, b = 0;
    char x = 0, extra = 0;
    if (std::sscanf(text.c_str(), "%d%c%d%c", &a, &x, &b, &extra) != 3 || (x != 'x' && x != 'X') || a <= 0 || b <= 0 ||
        a > 16384 || b > 16384) {
        *error = "bad size '" + text + "', expected WIDTHxHEIGHT such as 1280x720 (1..16384 each)";
        return false;
    }
    *w = a;
    *h = b;
    return true;
}

std::vector<ParamDecl> ShowDecls(const Show& show) {
    std::vector<ParamDecl> decls = show.scene.params;
    for (const ParamDecl& d : show.postDecls)
        if (std::none_of(decls.begin(), decls.end(), [&](const ParamDecl& x) { return x.name == d.name; })) decls.push_back(d);
    return decls;
}

namespace {

bool SameFile(const fs::path& a, const fs::path& b) {
    std::error_code ea, eb;
    const fs::path ca = fs::weakly_canonical(a, ea), cb = fs::weakly_canonical(b, eb);
    return !ea && !eb && ca == cb;
}

}  // namespace

bool PrepareShow(const ShowOptions& opts, Show* show, std::string* error) {
    Show s;
    std::string sceneName = opts.scene;
    if (!opts.preset.empty()) {
        std::string p = opts.preset;
        if (!fs::is_regular_file(p)) {
            fs::path inPresets = fs::path(DataRoot()) / "presets" / p;
            if (fs::is_regular_file(inPresets)) p = inPresets.string();
            else if (fs::is_regular_file(inPresets.string() + ".json")) p = inPresets.string() + ".json";
            else {
                *error = "unknown preset '" + opts.preset + "', expected a file or one of presets/*.json";
                return false;
            }
        }
        if (!LoadPreset(p, &s.preset, error)) return false;
        if (sceneName.empty()) sceneName = s.preset.scene;
    }
    if (sceneName.empty()) {
        *error = "no scene given, expected --scene NAME or --preset FILE (see `sdfvj list`)";
        return false;
    }
    if (IsIsfPath(sceneName)) {
        // An ISF generator (or a Shadertoy mainImage): no raymarched program; it is the post
        // chain's first stage, and its inputs are the show's parameters.
        s.isfScene = true;
        s.scene.name = fs::path(sceneName).stem().string();
        s.scene.path = ResolveIsfPath(sceneName);
        s.scene.description = "ISF generator";
        if (!fs::is_regular_file(s.scene.path)) {
            *error = "cannot read ISF scene '" + sceneName + "', expected a .fs file";
            return false;
        }
    } else if (!FindScene(sceneName, &s.scene, error)) {
        const Show* stage = opts.onStage;
        if (!stage || stage->isfScene || stage->scene.path.empty() || !SameFile(SceneFile(sceneName), stage->scene.path))
            return false;
        s.notices.push_back(*error + " — the scene on stage keeps its last good header");
        error->clear();
        s.scene = stage->scene;
    }
    s.effects = s.scene.effects;
    if (!s.preset.effects.empty() && !ParseEffectList(s.preset.effects, &s.effects, error)) {
        *error = s.preset.path + ": " + *error;
        return false;
    }
    if (!opts.effects.empty() && !ParseEffectList(opts.effects, &s.effects, error)) return false;
    const std::string normals = !opts.normals.empty() ? opts.normals : s.preset.normals;
    if (!normals.empty() && !ParseNormalMethod(normals, &s.effects.normals, error)) return false;
    if (opts.path != "auto" && opts.path != "compute" && opts.path != "fragment") {
        *error = "unknown render path '" + opts.path + "', expected auto, compute or fragment";
        return false;
    }

    // The post chain's inputs are parameters like the scene's (parsed only: no GL here).
    s.post = !opts.post.empty() ? opts.post : s.preset.post;
    if (s.isfScene) s.post = s.scene.path + (s.post.empty() ? "" : "," + s.post);
    if (!s.post.empty() && !IsfListParams(SplitIsfList(s.post), &s.postDecls, error)) {
        if (!opts.onStage || opts.onStage->post != s.post) {
            if (opts.post.empty()) *error = s.preset.path + ": post: " + *error;
            return false;
        }
        // The chain on stage stays: its last good inputs (its program on screen is the last good too).
        s.notices.push_back(*error + " — the post chain on stage keeps its last good inputs");
        error->clear();
        s.postDecls = opts.onStage->postDecls;
    }
    const std::vector<ParamDecl> decls = ShowDecls(s);

    // Parameter values: scene defaults, then the preset, then --param; each clamped and reported.
    auto setParam = [&](const std::string& name, float value, const std::string& origin) {
        for (const ParamDecl& d : decls) {
            if (d.name != name) continue;
            float c = ClampParam(d, value);
            if (c != value)
                std::fprintf(stderr, "%s: %s = %g is outside [%g, %g], clamped to %g\n", origin.c_str(), name.c_str(),
                             value, d.minValue, d.maxValue, c);
            for (auto& [n, v] : s.params)
                if (n == name) { v = c; return true; }
            s.params.emplace_back(name, c);
            return true;
        }
        std::string known;
        for (const ParamDecl& d : decls) known += (known.empty() ? "" : ", ") + d.name;
        *error = origin + ": scene '" + s.scene.name + "' has no parameter '" + name + "', expected one of: " +
                 (known.empty() ? "(none)" : known);
        return false;
    };
    for (const ParamDecl& d : decls) s.params.emplace_back(d.name, d.defaultValue);
    for (const auto& [name, value] : s.preset.params)
        if (!setParam(name, value, s.preset.path)) return false;
    for (const std::string& kv : opts.params) {
        auto eq = kv.find('=');
        char* end = nullptr;
        float v = eq == std::string::npos ? 0.0f : std::strtof(kv.c_str() + eq + 1, &end);
        if (eq == std::string::npos || end == kv.c_str() + eq + 1 || *end != '\0') {
            *error = "bad --param '" + kv + "', expected NAME=VALUE such as twist=0.5";
            return false;
        }
        if (!setParam(kv.substr(0, eq), v, "--param")) return false;
    }
    s.quality = opts.quality;
    *show = std::move(s);
    return true;
}

void PickRenderPath(Show* show, const std::string& pathOption, bool verbose) {
    if (pathOption == "compute") show->path = RenderPath::Compute;
    else if (pathOption == "fragment") show->path = RenderPath::Fragment;
    else {
        std::string log;
        show->path = ProbeRenderPath(show->scene, &log);
        if (verbose) std::fprintf(stderr, "%s\n", log.c_str());
    }
}

bool BuildShow(Show* show, const std::string& pathOption, std::string* error, bool verbose) {
    PickRenderPath(show, pathOption, verbose);
    VariantKey key{show->scene.path, show->effects, show->path};
    ShaderSource src;
    if (!AssembleProgram(show->scene, key, &src, error)) return false;
    auto prog = std::make_unique<Program>();
    if (!prog->Build(src, show->path, error)) return false;
    show->program = std::move(prog);
    return true;
}

void PrintProgress(int done, int total, double elapsed) {
    static double lastPrinted = -1.0;   // a few updates a second are enough, also in CI logs
    if (done < total && done > 1 && elapsed - lastPrinted < 0.25) return;
    lastPrinted = elapsed;
    const int width = 30;
    const double frac = total > 0 ? (double)done / total : 1.0;
    const double fps = elapsed > 0 ? done / elapsed : 0.0;
    const double left = fps > 0 ? (total - done) / fps : 0.0;
    std::string bar(width, ' ');
    for (int i = 0; i < (int)(frac * width + 0.5); ++i) bar[i] = '#';
    std::fprintf(stderr, "\r[%s] %d/%d frames  %.1f fps  %.0fs left ", bar.c_str(), done, total, fps, left);
    if (done == total) std::fprintf(stderr, "\n");
    std::fflush(stderr);
}

}  // namespace sdfvj
