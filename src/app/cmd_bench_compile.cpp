// `sdfvj bench compile`: which part of a scene's program a driver's build time goes to (issue 12).
// A save reaches the screen no sooner than its quick tier builds (NVIDIA: `#pragma optionNV(inline
// none)`, 290-470 ms on an H100 or H200 against the issue's 150 ms for midi), so the question is what
// that time is spent on: the scene's map(), or the renderer around it (the march, the normal, the
// shadow and AO loops, the lighting), which every scene's program carries and no edit of a scene
// changes. Each *cut* builds the scene's compute program another way, every step to its first use
// timed (bench_build.h); cuts are interleaved round by round (the order rotated), each build a text
// no cache has seen (its first constant nudged), the drivers' disk caches off.
//
// A cut: TIER[/EFFECTS][@sphere][+NAME=VALUE]...[!HINT]...
//   TIER       optimized (as `live` builds it) or quick (QuickTierText: the first tier of a tiered build)
//   /EFFECTS   applied to the scene's own effects, as --effects reads them ("-ao,-soft_shadows", "none")
//   @sphere    the scene's map() replaced by a sphere on a plane (its header, uniforms and effects kept):
//              what the renderer alone costs
//   +NAME=VALUE  a #define before everything else (the renderer's #ifndef knobs: CONE_PREPASS=0, ...)
//   !HINT      an NVIDIA compiler hint, `#pragma optionNV(HINT)` with the dashes as spaces (!unroll-none)
#include <epoxy/gl.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <unistd.h>

#include "app/bench_build.h"
#include "app/bench_support.h"
#include "app/commands.h"
#include "render/live_program.h"
#include "render/render.h"
#include "scene/scene.h"
#include "shader/shader.h"

namespace sdfvj {

namespace fs = std::filesystem;

namespace {

struct Cut {
    std::string label;
    bool quick = false;
    bool sphere = false;
    EffectSet effects;
    std::vector<std::string> defines;   // "NAME VALUE"
    std::vector<std::string> hints;     // NVIDIA's optionNV hints ("unroll none")
    std::string text;                   // the program's source, built once
};

bool Identifier(const std::string& s) {
    if (s.empty() || std::isdigit((unsigned char)s[0])) return false;
    return std::all_of(s.begin(), s.end(), [](char c) { return std::isalnum((unsigned char)c) || c == '_'; });
}

bool DefineValue(const std::string& s) {
    return !s.empty() && s.size() <= 32 &&
           std::all_of(s.begin(), s.end(), [](char c) { return std::isalnum((unsigned char)c) || c == '_' || c == '.' || c == '-'; });
}

bool ParseCut(const std::string& text, const EffectSet& own, Cut* out, std::string* error) {
    Cut c;
    c.label = text;
    c.effects = own;
    std::string head = text;
    // !HINT..: `#pragma optionNV(HINT)` each (words joined by '-'), after the tier's own
    for (size_t bang = head.rfind('!'); bang != std::string::npos; bang = head.rfind('!')) {
        std::string hint = head.substr(bang + 1);
        head.erase(bang);
        if (hint.empty() || hint.size() > 40 || hint.find_first_not_of("abcdefghijklmnopqrstuvwxyz-") != std::string::npos) {
            *error = "cut '" + text + "': bad hint '!" + hint + "', expected !WORDS-JOINED-BY-DASHES (an optionNV hint: !unroll-none)";
            return false;
        }
        std::replace(hint.begin(), hint.end(), '-', ' ');
        c.hints.insert(c.hints.begin(), hint);
    }
    size_t plus = head.find('+');
    std::string defines = plus == std::string::npos ? "" : head.substr(plus + 1);
    if (plus != std::string::npos) head.erase(plus);
    while (!defines.empty()) {
        const size_t next = defines.find('+');
        const std::string one = defines.substr(0, next);
        defines = next == std::string::npos ? "" : defines.substr(next + 1);
        const size_t eq = one.find('=');
        const std::string name = one.substr(0, eq), value = eq == std::string::npos ? "1" : one.substr(eq + 1);
        if (!Identifier(name) || !DefineValue(value)) {
            *error = "cut '" + text + "': bad define '" + one + "', expected +NAME=VALUE (a macro name, a number or a name)";
            return false;
        }
        c.defines.push_back(name + " " + value);
    }
    if (const size_t at = head.find('@'); at != std::string::npos) {
        if (head.substr(at + 1) != "sphere") {
            *error = "cut '" + text + "': unknown '@" + head.substr(at + 1) + "', expected @sphere";
            return false;
        }
        c.sphere = true;
        head.erase(at);
    }
    std::string effects;
    if (const size_t slash = head.find('/'); slash != std::string::npos) {
        effects = head.substr(slash + 1);
        head.erase(slash);
    }
    if (head != "optimized" && head != "quick") {
        *error = "cut '" + text + "': unknown tier '" + head + "', expected optimized or quick";
        return false;
    }
    c.quick = head == "quick";
    if (!effects.empty() && !ParseEffectList(effects, &c.effects, error)) {
        *error = "cut '" + text + "': " + *error;
        return false;
    }
    *out = std::move(c);
    return true;
}

// The scene's header (its /*{ ... }*/ block) over a map() of a sphere on a plane.
bool WriteSphereScene(const SceneInfo& scene, const fs::path& file, std::string* error) {
    std::ifstream in(scene.path, std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const size_t end = text.find("}*/");
    if (end == std::string::npos) {
        *error = scene.path + ": no /*{ ... }*/ header to keep for @sphere";
        return false;
    }
    std::ofstream out(file, std::ios::binary);
    out << text.substr(0, end + 3) << "\n#include \"lib/common.glsl\"\n"
        << "vec4 map(vec3 p) { return vec4(vec3(0.8f), min(length(p - vec3(0.0f, 1.0f, 0.0f)) - 1.0f, p.y)); }\n"
        << "float sceneLipschitz() { return 1.0f; }\n";
    if (!out) {
        *error = "cannot write " + file.string();
        return false;
    }
    return true;
}

bool CutText(const SceneInfo& scene, const SceneInfo& sphere, RenderPath path, Cut* c, std::string* error) {
    ShaderSource src;
    const SceneInfo& from = c->sphere ? sphere : scene;
    if (!AssembleProgram(from, VariantKey{from.path, c->effects, path}, &src, error)) return false;
    std::string text = c->quick ? QuickTierText(src.text) : src.text;
    std::string defines;
    for (const std::string& h : c->hints) defines += "#pragma optionNV(" + h + ")\n";
    for (const std::string& d : c->defines) defines += "#define " + d + "\n";
    const size_t eol = text.find('\n');
    c->text = text.substr(0, eol + 1) + defines + text.substr(eol + 1);
    return true;
}

}  // namespace

int RunCompileBench(const CompileBenchOptions& o) {
    const fs::path work = fs::temp_directory_path() / ("sdfvj-compile-" + std::to_string(::getpid()));
    fs::create_directories(work);
    struct Cleanup {
        fs::path dir;
        ~Cleanup() {
            std::error_code ec;
            fs::remove_all(dir, ec);
        }
    } cleanup{work};
    const std::string caches = SetDriverCaches("off", work, false);
    SceneInfo scene, sphere;
    std::string error;
    if (!FindScene(o.scene, &scene, &error) || !WriteSphereScene(scene, work / "sphere.glsl", &error) ||
        !LoadScene((work / "sphere.glsl").string(), &sphere, &error)) {
        std::fprintf(stderr, "sdfvj bench compile: %s\n", error.c_str());
        return 2;
    }
    RenderPath path = RenderPath::Compute;
    if (o.path == "fragment") path = RenderPath::Fragment;
    else if (o.path != "compute") {
        std::fprintf(stderr, "sdfvj bench compile: path '%s', expected compute or fragment\n", o.path.c_str());
        return 2;
    }
    std::vector<Cut> cuts;
    for (const std::string& text : o.cuts) {
        Cut c;
        if (!ParseCut(text, scene.effects, &c, &error) || !CutText(scene, sphere, path, &c, &error)) {
            std::fprintf(stderr, "sdfvj bench compile: %s\n", error.c_str());
            return 2;
        }
        cuts.push_back(std::move(c));
    }
    HeadlessContext gl;
    if (!gl.Create(&error)) {
        std::fprintf(stderr, "sdfvj bench compile: %s\n", error.c_str());
        return 2;
    }
    const std::string gpu = (const char*)glGetString(GL_RENDERER);
    std::printf("# sdfvj bench compile: %s (its own effects: %s) on %s, %s\n%s\n", scene.name.c_str(), DescribeEffects(scene.effects).c_str(),
                gpu.c_str(), (const char*)glGetString(GL_VERSION), caches.c_str());
    std::printf("each round builds every cut once (the order rotated), the scene's first constant nudged each time; %s "
                "path (first use: a 1x1 %s); ms\n\n| round | cut | compile | link | first use | total |\n|---:|---|---:|---:|---:|---:|\n",
                RenderPathName(path), path == RenderPath::Compute ? "dispatch" : "draw");
    const size_t n = cuts.size();
    std::vector<std::vector<double>> compile(n), link(n), use(n), total(n);
    std::vector<std::string> failed(n);
    for (int round = 1; round <= o.rounds; ++round) {
        for (size_t k = 0; k < n; ++k) {
            const size_t i = (k + (size_t)round) % n;
            bool nudged = false;
            const std::string text = NudgeFirstConstant(cuts[i].text, 1e-4 * (double)(round * (int)n + (int)i + 1), &nudged);
            const BuildSteps s = TimedGlslBuild(text, path);
            if (!s.ok) {
                failed[i] = s.error;
                std::replace(failed[i].begin(), failed[i].end(), '\n', ' ');
                std::printf("| %d | %s | failed: %s |\n", round, cuts[i].label.c_str(), failed[i].c_str());
                continue;
            }
            std::printf("| %d | %s | %.1f | %.1f | %.1f | %.1f |\n", round, cuts[i].label.c_str(), s.compile, s.link, s.use, s.Total());
            compile[i].push_back(s.compile);
            link[i].push_back(s.link);
            use[i].push_back(s.use);
            total[i].push_back(s.Total());
        }
        std::fflush(stdout);
    }
    const double base = total[0].empty() ? 0.0 : MedianMs(total[0]);
    std::printf("\n## medians (%d rounds)\n| cut | effects | source chars | compile | link | first use | total | x %s |\n"
                "|---|---|---:|---:|---:|---:|---:|---:|\n", o.rounds, cuts[0].label.c_str());
    BenchCsv csv{{"cut", "compile_ms", "link_ms", "use_ms", "source_chars"}, {}};
    for (size_t i = 0; i < n; ++i) {
        const Cut& c = cuts[i];
        if (total[i].empty()) {
            std::printf("| %s | %s | %zu | failed: %s |\n", c.label.c_str(), DescribeEffects(c.effects).c_str(), c.text.size(), failed[i].c_str());
            continue;
        }
        const double t = MedianMs(total[i]);
        std::printf("| %s | %s | %zu | %.1f | %.1f | %.1f | **%.1f** | %.2f |\n", c.label.c_str(), DescribeEffects(c.effects).c_str(),
                    c.text.size(), MedianMs(compile[i]), MedianMs(link[i]), MedianMs(use[i]), t, base > 0 ? t / base : 0.0);
        char cm[32], lm[32], um[32];
        std::snprintf(cm, sizeof cm, "%.2f", MedianMs(compile[i]));
        std::snprintf(lm, sizeof lm, "%.2f", MedianMs(link[i]));
        std::snprintf(um, sizeof um, "%.2f", MedianMs(use[i]));
        csv.Add(scene.name, DescribeEffects(c.effects), "-", RenderPathName(path), t, gpu, {c.label, cm, lm, um, std::to_string(c.text.size())});
    }
    if (!o.csv.empty() && !csv.Write(o.csv, &error)) {
        std::fprintf(stderr, "sdfvj bench compile: %s\n", error.c_str());
        return 2;
    }
    for (const std::string& f : failed)
        if (!f.empty()) return 1;
    return 0;
}

}  // namespace sdfvj
