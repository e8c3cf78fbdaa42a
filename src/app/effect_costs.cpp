// What each effect costs, measured on demand (see effect_costs.h).
#include "app/effect_costs.h"

#include <cmath>
#include <cstdio>
#include <limits>

namespace sdfvj {

namespace {

// The u_effectsOff bits of shaders/render/uniforms.glsl.
constexpr int kOffShadows = 1, kOffAo = 2, kOffSpecular = 4, kOffReflections = 8, kOffFog = 16;

// Once every draw's time is in: each row's differences, round by round.
void FinishEffectCosts(EffectCosts& c) {
    if (!c.Done()) return;
    const int variants = c.Variants();
    for (int r = 0; r < c.rounds; ++r)
        for (size_t i = 0; i < c.rows.size(); ++i)
            if (c.rows[i].offBit)
                c.rows[i].diffs.push_back(c.ms[(size_t)(r * variants)] - c.ms[(size_t)(r * variants + 1 + (int)i)]);
    c.ring.reset();
}

}  // namespace

std::vector<EffectCostRow> EffectCostRows(const EffectSet& e) {
    std::vector<EffectCostRow> rows;
    if (e.shadows) rows.push_back({"shadows", kOffShadows, {}});
    if (e.ao) rows.push_back({"ao", kOffAo, {}});
    if (e.specular && !e.pbr) rows.push_back({"specular", kOffSpecular, {}});   // PBR has its own highlight
    if (e.fog) rows.push_back({"fog", kOffFog, {}});
    if (e.pbr) rows.push_back({"pbr", 0, {}});
    if (e.reflections) rows.push_back({"reflections", kOffReflections, {}});
    return rows;
}

bool EffectCosts::Done() const { return Started() && Known() == Draws(); }

int EffectCosts::Known() const {
    int n = 0;
    for (double v : ms) n += v >= 0.0;
    return n;
}

void StartEffectCosts(EffectCosts& c, const EffectSet& variant, int rounds, bool wallClock) {
    c = EffectCosts{};
    c.effects = variant;
    c.rows = EffectCostRows(variant);
    c.rounds = rounds < 1 ? 1 : rounds;
    c.wallClock = wallClock;
    c.ms.assign((size_t)c.Draws(), -1.0);
    if (!wallClock) c.ring = std::make_unique<GpuTimerRing>(8);
}

void StepEffectCosts(EffectCosts& c, FrameRenderer& scratch, const Program& program, const SceneInfo& scene,
                     FrameInputs in) {
    if (!c.Started() || c.Done()) return;
    if (c.submitted < c.Draws()) {
        const int variant = c.submitted % c.Variants();
        in.effectsOff = variant == 0 ? 0 : c.rows[(size_t)variant - 1].offBit;
        if (c.wallClock) {
            scratch.Draw(program, scene, in, true);   // glFinish + wall clock (llvmpipe)
            c.ms[(size_t)c.submitted++] = scratch.LastGpuMs();
        } else if (c.ring->Begin(c.submitted)) {   // a full ring: this frame submits nothing
            scratch.Draw(program, scene, in);
            c.ring->End();
            ++c.submitted;
        }
    }
    if (c.ring)
        for (const GpuTimerRing::Sample& s : c.ring->Poll()) c.ms[(size_t)s.tag] = s.ms;
    FinishEffectCosts(c);
}

void StepEffectCostsTimed(EffectCosts& c, FrameInputs in, const std::function<double(const FrameInputs&)>& timeDraw,
                          const std::string& timedBy) {
    if (!c.Started() || c.Done()) return;
    c.timedBy = timedBy;
    const int variant = c.submitted % c.Variants();
    in.effectsOff = variant == 0 ? 0 : c.rows[(size_t)variant - 1].offBit;
    const double ms = timeDraw(in);
    if (ms >= 0) c.ms[(size_t)c.submitted++] = ms;
    FinishEffectCosts(c);
}

double EffectCostMs(const EffectCostRow& row, const EffectCosts& c) {
    if (!c.Done() || row.diffs.empty()) return std::numeric_limits<double>::quiet_NaN();
    return MedianMs(row.diffs);
}

std::string EffectCostText(const EffectCostRow& row, const EffectCosts& c) {
    if (!row.offBit) return "n/a";
    const double ms = EffectCostMs(row, c);
    if (std::isnan(ms)) return "...";
    char text[32];
    std::snprintf(text, sizeof text, "%+.2f ms", ms);
    return text;
}

std::string EffectCostNote(const EffectCosts& c) {
    if (!c.Started()) return "";
    char text[160];
    if (!c.Done()) std::snprintf(text, sizeof text, "measuring costs: %d/%d draws", c.Known(), c.Draws());
    else
        std::snprintf(text, sizeof text, "median of %d frame pairs (all on - one off), %s", c.rounds,
                      !c.timedBy.empty() ? c.timedBy.c_str() : c.wallClock ? "glFinish + wall clock (software GL)" : "GPU timer queries");
    return text;
}

}  // namespace sdfvj
