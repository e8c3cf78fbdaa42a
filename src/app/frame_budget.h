// frame_budget.h - `live --frame-budget MS`: keep the frame under a budget by moving along the
// accuracy sweep's Pareto front of (cost, error), never below a floor the performer sets.
//
//   std::vector<BudgetSetting> c;
//   LoadBudgetCandidates("docs/accuracy/accuracy.csv", "character", 1.0f, &c, &error);
//   FrameBudget b;
//   BeginFrameBudget(&b, FrameBudgetDesc{.budgetMs = 8.0}, c);      // starts at the best setting
//   each frame: if (StepFrameBudget(b, now, frameMs)) ApplyBudgetSetting(b.front[b.current], &quality, &scale);
//
// A setting is a quality (steps, shadow steps, AO samples, hit epsilon, step factor: the sweep's
// rows that Quality can express) at a resolution scale (< 1 renders fewer pixels and upscales,
// > 1 supersamples). Its cost is the sweep's ms relative to the default times the scale's cost
// relative to scale 1; its error is the sweep's "% pixels more than 8/255 off" plus a resolution
// term. Both scale figures are measured by the sweep's render-scale rows (knob "scale": the
// default at that scale, resampled as live shows it, against the supersampled truth), so scale 1
// carries its aliasing and 2x2 supersampling lowers it. The sum is the model: a quality's and a
// scale's errors add. A CSV without scale rows falls back to cost scale^2 and ResolutionErrorPct,
// a stated model, not a measurement.
//
// About once a period (1 s) the median frame time of the period is compared with the budget;
// the time any other setting would take is predicted by scaling it with the front's cost
// ratio. Hysteresis, so it does not oscillate: it moves to a costlier setting only when the
// prediction fits under upMargin x budget and not within the hold after a move down
// (holdAfterDownS, doubled up to a minute each time a move up had to be undone at once).
// Pure logic: no GL, no clock of its own (tests/stability/test_frame_budget.cpp).
#pragma once
#include <string>
#include <vector>

#include "render/render.h"
#include "scene/scene.h"

namespace sdfvj {

struct BudgetSetting {
    std::string label;         // "steps=96 @ 0.70"
    float scale = 1.0f;        // fraction of the output's width and height that is rendered
    Quality quality;           // steps, shadow steps, AO samples, epsilon, step factor
    double cost = 1.0;         // relative: the quality's ms over the default's, times the scale's over scale 1's
    double error = 0.0;        // % pixels more than 8/255 off (the quality's row) + the scale's row (or model)
};

// What the performer will not go below: "scale=0.5,steps=64,shadow_steps=16,ao=2" (any subset).
struct BudgetFloor {
    float scale = 0.25f;
    int steps = 16;
    int shadowSteps = 8;
    int aoSamples = 1;
};
// False with "--budget-floor: ..., expected ..." on bad text.
bool ParseBudgetFloor(const std::string& text, BudgetFloor* out, std::string* error);
bool AboveFloor(const BudgetSetting& s, const BudgetFloor& f);

// The resolution term of the fallback model (a CSV without scale rows): % of pixels that are
// interpolated, not rendered (0 at scale >= 1).
double ResolutionErrorPct(float scale);

// Candidates from an accuracy CSV (sdfvj bench accuracy): the scene's rows that Quality can
// express, or the mean over all scenes in the file per setting when the scene has none, crossed
// with the render scales up to maxScale (the CSV's scale rows, the scene's or the mean, else
// kScales with the model). False with "file:line: ..." on a file it cannot read.
bool LoadBudgetCandidates(const std::string& csvPath, const std::string& scene, float maxScale,
                          std::vector<BudgetSetting>* out, std::string* error);

// The Pareto front of (cost, error), cheapest (and worst) first.
std::vector<BudgetSetting> BudgetFront(std::vector<BudgetSetting> candidates);

// The largest render scale `live` draws (2: each pixel the mean of 2x2 samples).
constexpr float kLiveMaxScale = 2.0f;

struct FrameBudgetDesc {
    double budgetMs = 0.0;        // <= 0: off
    double periodS = 1.0;         // how often it decides
    double upMargin = 0.8;        // a costlier setting must be predicted under this x budget
    double holdAfterDownS = 3.0;  // no move up this soon after a move down
    BudgetFloor floor;
};

struct FrameBudget {
    FrameBudgetDesc desc;
    std::vector<BudgetSetting> front;   // above the floor, cheapest first
    size_t current = 0;
    double periodStart = -1.0;
    std::vector<double> samples;        // frame ms of this period
    double lastDown = -1e30;
    double lastUp = -1e30;
    double hold = 0.0;                  // current hold after a move down (doubles when a move up failed)
    double lastMedianMs = 0.0;
    int moves = 0;
};

// Filters the candidates by the floor, builds the front and starts at its best (costliest)
// setting. False when nothing is above the floor.
bool BeginFrameBudget(FrameBudget* b, const FrameBudgetDesc& desc, const std::vector<BudgetSetting>& candidates,
                      std::string* error);

// The setting of `front` the budget picks when `current` took measuredMs. allowUp = false
// keeps it from moving to a costlier setting.
size_t PickBudgetSetting(const std::vector<BudgetSetting>& front, size_t current, double measuredMs, double budgetMs,
                         double upMargin, bool allowUp);

// Feeds one frame's time (ms) at time `now` (s). True when it moved to another setting
// (b.current); apply it with ApplyBudgetSetting.
bool StepFrameBudget(FrameBudget& b, double now, double frameMs);

void ApplyBudgetSetting(const BudgetSetting& s, Quality* q, float* scale);

// The render scales of the front other than `current`, nearest to it first (by ratio), at most n:
// the sizes `live` draws once ahead, so that the budget's first move to each takes targets kept
// from that draw (FrameRenderer::SetKeptSizes) and allocates none in a frame that is already late
// (on NVIDIA a new target's first draw held a 4K frame with bloom 36-48 ms, at scale 2 332 ms).
std::vector<float> BudgetScalesAhead(const FrameBudget& b, float current, int n);

// ---- live's glue (cmd_live.cpp calls these two) ------------------------------------------
// Starts a budget of budgetMs for `scene` from DataRoot()/docs/accuracy/accuracy.csv with the
// floor text of --budget-floor (scales up to kLiveMaxScale: 2, live's 2x2 supersampling);
// applies the best setting. False with a line to show when it cannot (the show then runs without a budget).
bool StartLiveFrameBudget(FrameBudget* b, double budgetMs, const std::string& floorText, const std::string& scene,
                          Quality* q, float* scale, std::string* error);
// The overlay's status line for a running budget: "frame budget 8 ms: steps=96 @ 0.85 (4 of 15
// on the front), median 7.2 ms" ("measuring" before its first period); "" when it is off.
std::string FrameBudgetStatus(const FrameBudget& b);
// One frame's time: when the budget moved, applies the new setting and sets `say` to
// "frame budget 8 ms: median 9.1 ms -> steps=96 @ 0.85".
bool LiveFrameBudgetStep(FrameBudget& b, double now, double frameMs, Quality* q, float* scale, std::string* say);

}  // namespace sdfvj
