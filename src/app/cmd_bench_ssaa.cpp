// `sdfvj bench ssaa`: what the `ssaa` effect draws against the supersampled truth. For each scene,
// one sample a pixel, `ssaa` and `ssaa_exact` at the size, and the truth: the frame at twice the
// width and height averaged 2x2. PSNR and the share of pixels with a channel past 8/255
// (accuracy's CompareRgba8) for each pair: how much of the exact samples' anti-aliasing the
// shared shading keeps (docs/performance.md, "4x supersampling that shades each surface once").
// And `quad_reflections` in the frame twice the size (its bounce traced once per 2x2 pixels, once per
// shown pixel), averaged 2x2, against the truth: what issue 13's 7680x4320 show draws with it.
#include <cstdio>
#include <fstream>

#include "accuracy/accuracy.h"
#include "app/commands.h"

namespace sdfvj {

int RunSsaaBench(const SsaaBenchOptions& o) {
    std::string error;
    auto fail = [&](int code) {
        std::fprintf(stderr, "sdfvj bench ssaa: %s\n", error.c_str());
        return code;
    };
    int w = 0, h = 0;
    RenderPath path = RenderPath::Compute;
    if (!ParseSizeAndPath(o.size, o.path, &w, &h, &path, &error)) return fail(2);
    HeadlessContext gl;
    if (!gl.Create(&error)) return fail(2);
    FrameRenderer fr;
    std::string table = "| scene | one sample vs truth | `ssaa_exact` vs truth | `ssaa` vs truth | `ssaa` vs `ssaa_exact` | "
                        "one sample vs `ssaa_exact` | `quad_reflections` twice the size vs truth |\n|---|---|---|---|---|---|---|\n";
    std::printf("# sdfvj bench ssaa on %s, %dx%d, %s path, the scene's effects plus %s; the truth: %dx%d averaged 2x2\n%s",
                gl.Description().c_str(), w, h, RenderPathName(path), o.effects.c_str(), 2 * w, 2 * h, table.c_str());
    for (const std::string& name : o.scenes.empty() ? ListScenes() : o.scenes) {
        SceneInfo scene;
        if (!FindScene(name, &scene, &error)) return fail(2);
        FrameInputs in;
        for (const ParamDecl& d : scene.params) in.params.emplace_back(d.name, d.defaultValue);
        // The scene's own effects with --effects applied over them (as `render --effects`), supersampled as asked.
        EffectSet base = scene.effects;
        if (!ParseEffectList(o.effects, &base, &error)) return fail(2);
        auto draw = [&](int supersample, int dw, int dh, std::vector<uint8_t>* out, bool quadReflections = false) {
            EffectSet e = base;
            e.supersample = supersample;
            e.quadReflections = quadReflections;
            ShaderSource src;
            Program program;
            if (!AssembleProgram(scene, VariantKey{scene.path, e, path}, &src, &error) || !program.Build(src, path, &error) ||
                !fr.Resize(dw, dh, &error))
                return false;
            fr.Draw(program, scene, in);
            *out = fr.ReadPixels();
            return true;
        };
        std::vector<uint8_t> one, shared, exact, big, bigQuads;
        if (!draw(0, w, h, &one) || !draw(1, w, h, &shared) || !draw(2, w, h, &exact) || !draw(0, 2 * w, 2 * h, &big) ||
            !draw(0, 2 * w, 2 * h, &bigQuads, true))
            return fail(1);
        const std::vector<uint8_t> truth = accuracy::DownsampleRgba8x2(big, 2 * w, 2 * h);
        const std::vector<uint8_t> quads = accuracy::DownsampleRgba8x2(bigQuads, 2 * w, 2 * h);
        auto cell = [](const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
            const accuracy::ImageError e = accuracy::CompareRgba8(a, b);
            char s[64];
            std::snprintf(s, sizeof s, "%.1f dB, %.2f %%", e.psnr, e.pctOver8);
            return std::string(s);
        };
        const std::string row = "| " + scene.name + " | " + cell(one, truth) + " | " + cell(exact, truth) + " | " +
                                cell(shared, truth) + " | " + cell(shared, exact) + " | " + cell(one, exact) + " | " +
                                cell(quads, truth) + " |\n";
        std::printf("%s", row.c_str());
        std::fflush(stdout);
        table += row;
    }
    if (!o.markdown.empty()) std::ofstream(o.markdown) << table;
    return 0;
}

}  // namespace sdfvj
