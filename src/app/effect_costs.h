// effect_costs: what each effect of the program on screen costs, measured on demand (the
// overlay's "measure costs" button). The program is drawn offscreen, at the size the show
// renders, with every effect on and with one effect switched off by u_effectsOff: the same
// program, so nothing recompiles. The draws go in rounds (all on, then each effect off), so
// clock drift hits every variant alike; an effect's cost is the median over the rounds of
// (all on - that one off). A GPU times each draw with a GpuTimerRing (no sync; results come a
// few frames late); llvmpipe, whose timer queries are meaningless, with glFinish and the wall
// clock. Costs are of the scene draw alone, the overlay and the present are not in them.
//
// Usage, render thread:
//   StartEffectCosts(costs, live.Key().effects, 9, IsSoftwareRenderer());     // the button
//   each frame: StepEffectCosts(costs, scratch, program, scene, inputs);      // one extra draw
//   for (const EffectCostRow& r : costs.rows) ... r.name, EffectCostText(r, costs) ...
// A frame runs one measuring draw, so the show keeps going (at a lower frame rate) meanwhile.
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "render/gpu_timer.h"
#include "render/render.h"

namespace sdfvj {

struct EffectCostRow {
    std::string name;            // the overlay's checkbox name: shadows, ao, specular, fog, pbr, reflections
    int offBit = 0;              // its u_effectsOff bit; 0: no run-time switch (pbr), not measured
    std::vector<double> diffs;   // per round, ms: all on - this one off
};

struct EffectCosts {
    EffectSet effects;                 // the variant measured (a different program makes the costs stale)
    std::vector<EffectCostRow> rows;   // one per effect the variant has
    int rounds = 0;
    bool wallClock = false;            // glFinish + wall clock, else GL_TIME_ELAPSED through the ring
    std::string timedBy;               // StepEffectCostsTimed: who timed the draws (for the note)
    int submitted = 0;                 // draws submitted: index = round * Variants() + variant
    std::vector<double> ms;            // per draw index, < 0 until known
    std::unique_ptr<GpuTimerRing> ring;
    int Variants() const { return 1 + (int)rows.size(); }    // all on, then each row off
    int Draws() const { return rounds * Variants(); }
    bool Started() const { return rounds > 0; }
    bool Done() const;
    int Known() const;                  // draws whose time is in
};

// One row per effect the variant has, in checkbox order (pbr has no run-time switch: offBit 0).
std::vector<EffectCostRow> EffectCostRows(const EffectSet& variant);
// Starts (or restarts) a measurement of `variant` over `rounds` rounds.
void StartEffectCosts(EffectCosts& c, const EffectSet& variant, int rounds, bool wallClock);
// One measuring draw of `program` into `scratch` (sized by the caller) and the results that came
// in; nothing once done. `in` is the frame's inputs (its effectsOff is replaced).
void StepEffectCosts(EffectCosts& c, FrameRenderer& scratch, const Program& program, const SceneInfo& scene,
                     FrameInputs in);
// The same where a draw is timed by someone else and waited for (`live --render-process`: the
// server on screen draws it offscreen and times it, RenderProcess::TimeDraw): timeDraw returns ms,
// or < 0 when it failed (that draw is asked for again next frame). Start it with wallClock = true
// (no timer ring here); `timedBy` says how, in the note.
void StepEffectCostsTimed(EffectCosts& c, FrameInputs in, const std::function<double(const FrameInputs&)>& timeDraw,
                          const std::string& timedBy);
// The median over the rounds of a row's difference, ms; NaN until done or for a row not measured.
double EffectCostMs(const EffectCostRow& row, const EffectCosts& c);
// "+3.21 ms", "-0.02 ms" (noise), "n/a" (no run-time switch), "..." while measuring.
std::string EffectCostText(const EffectCostRow& row, const EffectCosts& c);
// What the numbers are: "median of 9 frame pairs (all on - one off), glFinish + wall clock (software GL)",
// or "measuring 12/54 draws".
std::string EffectCostNote(const EffectCosts& c);

}  // namespace sdfvj
