// The frame budget's pure logic (frame_budget.h): candidates from the accuracy CSV, the
// Pareto front, and the once-a-period pick with hysteresis.
#include "app/frame_budget.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>

namespace sdfvj {

namespace {

// One CSV line into fields ("a,\"b, c\",d"); quotes doubled inside quoted fields.
std::vector<std::string> SplitCsv(const std::string& line) {
    std::vector<std::string> out(1);
    bool quoted = false;
    for (size_t i = 0; i < line.size(); ++i) {
        char c = line[i];
        if (quoted) {
            if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') { out.back() += '"'; ++i; }
            else if (c == '"') quoted = false;
            else out.back() += c;
        } else if (c == '"') quoted = true;
        else if (c == ',') out.emplace_back();
        else if (c != '\r') out.back() += c;
    }
    return out;
}

bool ParseNumber(const std::string& s, double* v) {
    char* end = nullptr;
    *v = std::strtod(s.c_str(), &end);
    return !s.empty() && end == s.c_str() + s.size() && std::isfinite(*v);
}

// The render scales a budget may use where the CSV measured none (with the stated model):
// supersampling (above 1) down to a quarter of the width.
const float kScales[] = {1.5f, 1.25f, 1.0f, 0.85f, 0.7f, 0.6f, 0.5f, 0.4f, 0.33f, 0.25f};

}  // namespace

double ResolutionErrorPct(float scale) {
    // Share of output pixels interpolated rather than rendered, scaled so that halving the
    // resolution (75 % interpolated) weighs like a clearly visible quality loss (30 %).
    return scale >= 1.0f ? 0.0 : 40.0 * (1.0 - (double)scale * scale);
}

bool ParseBudgetFloor(const std::string& text, BudgetFloor* out, std::string* error) {
    BudgetFloor f = *out;
    size_t at = 0;
    while (at < text.size()) {
        size_t comma = text.find(',', at);
        std::string item = text.substr(at, comma == std::string::npos ? std::string::npos : comma - at);
        at = comma == std::string::npos ? text.size() : comma + 1;
        size_t eq = item.find('=');
        double v = 0;
        if (eq == std::string::npos || !ParseNumber(item.substr(eq + 1), &v)) {
            *error = "--budget-floor: '" + item + "' is not NAME=NUMBER, expected e.g. scale=0.5,steps=64,shadow_steps=16,ao=2";
            return false;
        }
        std::string name = item.substr(0, eq);
        if (name == "scale" && v > 0.0 && v <= 2.0) f.scale = (float)v;
        else if (name == "steps" && v >= 1 && v <= 100000) f.steps = (int)v;
        else if (name == "shadow_steps" && v >= 0 && v <= 100000) f.shadowSteps = (int)v;
        else if (name == "ao" && v >= 0 && v <= 1000) f.aoSamples = (int)v;
        else {
            *error = "--budget-floor: '" + item + "' unknown or out of range, expected scale (0..2], steps >= 1, "
                     "shadow_steps >= 0 or ao >= 0";
            return false;
        }
    }
    *out = f;
    return true;
}

bool AboveFloor(const BudgetSetting& s, const BudgetFloor& f) {
    return s.scale >= f.scale - 1e-6f && s.quality.maxSteps >= f.steps && s.quality.shadowSteps >= f.shadowSteps &&
           s.quality.aoSamples >= f.aoSamples;
}

bool LoadBudgetCandidates(const std::string& csvPath, const std::string& scene, float maxScale,
                          std::vector<BudgetSetting>* out, std::string* error) {
    std::ifstream in(csvPath);
    std::string line;
    if (!in || !std::getline(in, line)) {
        *error = csvPath + ":1: cannot read the accuracy CSV, expected `sdfvj bench accuracy`'s accuracy.csv";
        return false;
    }
    std::vector<std::string> header = SplitCsv(line);
    auto col = [&](const char* name) {
        auto it = std::find(header.begin(), header.end(), name);
        return it == header.end() ? -1 : (int)(it - header.begin());
    };
    const char* needed[] = {"scene", "knob", "setting", "max_steps", "hit_eps", "eps_mode", "step_factor", "naive_step",
                            "normals", "normal_eps", "march_fixed", "shadow_steps", "shadow_k", "ao_samples", "gpu_ms",
                            "pct_over_8"};
    std::map<std::string, int> c;
    for (const char* n : needed) {
        if (col(n) < 0) {
            *error = csvPath + ":1: no column '" + n + "', expected the header of `sdfvj bench accuracy`'s accuracy.csv";
            return false;
        }
        c[n] = col(n);
    }
    // Rows Quality can express at the renderer's defaults otherwise, per scene and setting.
    struct Q { Quality q; double ms = 0, pct = 0; };
    std::map<std::string, std::map<std::string, Q>> rows;   // scene -> label -> row
    // Render-scale rows (`bench accuracy` knob "scale", column render_scale): the default drawn at
    // a scale, its ms and its % off the supersampled truth. scene -> scale x 1000 -> (ms, pct).
    const int scaleCol = col("render_scale");
    // The error against the scene's own look (a look row's own % off leaves out what the look
    // changed); without the column, rows with other AO samples than the default are left out.
    const int lookCol = col("pct_over_8_scene_look");
    std::map<std::string, std::map<int, std::pair<double, double>>> scaleRows;
    int lineNo = 1;
    while (std::getline(in, line)) {
        ++lineNo;
        if (line.empty()) continue;
        std::vector<std::string> f = SplitCsv(line);
        if (f.size() < header.size()) {
            *error = csvPath + ":" + std::to_string(lineNo) + ": " + std::to_string(f.size()) + " fields, expected " +
                     std::to_string(header.size());
            return false;
        }
        double v[16];
        bool ok = true;
        for (int i = 3; i < 16; ++i) ok = ok && ParseNumber(f[c[needed[i]]], &v[i]);
        if (!ok) {
            *error = csvPath + ":" + std::to_string(lineNo) + ": a number column is not a number, expected numbers from "
                     "max_steps to pct_over_8";
            return false;
        }
        // counts become ints: keep them where the cast is defined (a huge number is not a count)
        for (int i : {3, 11, 13})
            if (v[i] < 0 || v[i] > 1e6) {
                *error = csvPath + ":" + std::to_string(lineNo) + ": " + needed[i] + " " + f[c[needed[i]]] +
                         " is out of range, expected a count from 0 to 1000000";
                return false;
            }
        const std::string knob = f[c["knob"]];
        if (knob == "scale") {
            double s = 0;
            if (scaleCol < 0 || !ParseNumber(f[scaleCol], &s) || s <= 0 || s > 4) {
                *error = csvPath + ":" + std::to_string(lineNo) + ": a scale row without a render_scale in (0, 4], "
                         "expected the column `sdfvj bench accuracy` writes";
                return false;
            }
            scaleRows[f[c["scene"]]][(int)std::lround(s * 1000.0)] = {v[14], v[15]};
            continue;
        }
        const bool qualityKnob = knob == "default" || knob == "steps" || knob == "shadow_steps" || knob == "ao_samples" ||
                                 knob == "combo" || knob == "eps_relative" || knob == "step_factor";
        const Quality d;
        // (The normals column is the scene's own method on these rows: a scene header may choose it.)
        if (!qualityKnob || v[5] != 0 || v[7] != 0 || v[10] != 0 || std::fabs(v[9] - d.normalEps) > 1e-9 ||
            std::fabs(v[12] - d.shadowK) > 1e-6 || v[6] > 1.0 + 1e-6)
            continue;   // other epsilon modes, normal offsets, fixed steps, penumbrae, over-relaxation
        double lookPct = v[15];
        if (lookCol >= 0 && !ParseNumber(f[lookCol], &lookPct)) {
            *error = csvPath + ":" + std::to_string(lineNo) + ": pct_over_8_scene_look is not a number, expected a percentage";
            return false;
        }
        if (lookCol < 0 && (int)v[13] != d.aoSamples) continue;   // its error against the scene's look is unknown
        Q r;
        r.q.maxSteps = (int)v[3];
        r.q.hitEps = (float)v[4];
        r.q.stepFactor = (float)v[6];
        r.q.shadowSteps = (int)v[11];
        r.q.aoSamples = (int)v[13];
        r.ms = v[14];
        r.pct = lookPct;
        rows[f[c["scene"]]][f[c["setting"]]] = r;
    }
    // Costs relative to each scene's default row; the scene's own rows, else the mean over scenes.
    std::map<std::string, Q> chosen;
    std::map<std::string, int> count;
    for (const auto& [name, byLabel] : rows) {
        if (rows.count(scene) && name != scene) continue;
        auto def = byLabel.find("sdfvj default");
        if (def == byLabel.end() || def->second.ms <= 0) continue;
        for (const auto& [label, r] : byLabel) {
            Q& m = chosen[label];
            m.q = r.q;
            m.ms += r.ms / def->second.ms;
            m.pct += r.pct;
            ++count[label];
        }
    }
    if (chosen.empty()) {
        *error = csvPath + ":1: no quality rows with a 'sdfvj default' row, expected a sweep of steps, shadow steps or AO samples";
        return false;
    }
    // The resolution term: measured where the CSV has scale rows (the scene's own, else the mean
    // over the scenes that have them): cost relative to the scale-1 row, error = that row's % off
    // the supersampled truth, added to the quality row's. Without scale rows, the stated model
    // (cost scale^2, ResolutionErrorPct).
    struct S { double cost = 0, pct = 0; int n = 0; };
    std::map<int, S> measured;
    for (const auto& [name, byScale] : scaleRows) {
        if (scaleRows.count(scene) && name != scene) continue;
        auto one = byScale.find(1000);
        if (one == byScale.end() || one->second.first <= 0) continue;
        for (const auto& [s, r] : byScale) {
            S& m = measured[s];
            m.cost += r.first / one->second.first;
            m.pct += r.second;
            ++m.n;
        }
    }
    std::vector<std::pair<float, S>> scales;
    if (!measured.empty()) {
        for (auto& [s, m] : measured) scales.push_back({s / 1000.0f, S{m.cost / m.n, m.pct / m.n, 1}});
        // Fewer pixels never count as more accurate: a linear upscale of 0.85 can read closer to the
        // supersampled truth than the aliased scale 1 (its blur smooths the stairs; character and
        // primitives at 1080p), which would take scale 1 off the front. Each scale's term is at
        // least the next larger one's, plus a thousandth of a point, so the larger wins a tie.
        std::sort(scales.begin(), scales.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
        for (size_t i = 1; i < scales.size(); ++i)
            scales[i].second.pct = std::max(scales[i].second.pct, scales[i - 1].second.pct + 1e-3);
    } else {
        for (float s : kScales) scales.push_back({s, S{(double)s * s, ResolutionErrorPct(s), 1}});
    }
    out->clear();
    for (auto& [label, m] : chosen)
        for (const auto& [s, r] : scales) {
            if (s > maxScale + 1e-6f) continue;
            BudgetSetting b;
            char at[32];
            std::snprintf(at, sizeof at, " @ %.2f", s);
            b.label = label + at;
            b.scale = s;
            b.quality = m.q;
            b.cost = m.ms / count[label] * r.cost;
            b.error = m.pct / count[label] + r.pct;
            out->push_back(b);
        }
    return true;
}

std::vector<BudgetSetting> BudgetFront(std::vector<BudgetSetting> c) {
    std::sort(c.begin(), c.end(), [](const BudgetSetting& a, const BudgetSetting& b) {
        return a.cost != b.cost ? a.cost < b.cost : a.error < b.error;
    });
    std::vector<BudgetSetting> front;
    for (const BudgetSetting& s : c)   // cheapest first: keep each that lowers the error further
        if (front.empty() || s.error < front.back().error) front.push_back(s);
    return front;
}

bool BeginFrameBudget(FrameBudget* b, const FrameBudgetDesc& desc, const std::vector<BudgetSetting>& candidates,
                      std::string* error) {
    std::vector<BudgetSetting> allowed;
    for (const BudgetSetting& s : candidates)
        if (AboveFloor(s, desc.floor)) allowed.push_back(s);
    *b = FrameBudget{};
    b->desc = desc;
    b->front = BudgetFront(allowed);
    if (b->front.empty()) {
        *error = "--budget-floor: no setting of the accuracy sweep is at or above the floor, expected a lower floor";
        return false;
    }
    b->current = b->front.size() - 1;   // the best the front has
    return true;
}

size_t PickBudgetSetting(const std::vector<BudgetSetting>& front, size_t current, double measuredMs, double budgetMs,
                         double upMargin, bool allowUp) {
    if (front.empty() || current >= front.size() || measuredMs <= 0 || budgetMs <= 0) return current;
    const double perCost = measuredMs / std::max(front[current].cost, 1e-12);
    // the best (costliest) setting predicted to fit; costlier than now only with the margin
    for (size_t i = front.size(); i-- > 0;) {
        const double predicted = front[i].cost * perCost;
        if (i > current) {
            if (allowUp && predicted <= upMargin * budgetMs) return i;
        } else if (i == current) {
            if (measuredMs <= budgetMs) return current;
        } else if (predicted <= budgetMs) {
            return i;
        }
    }
    return 0;   // nothing fits: the cheapest above the floor
}

bool StepFrameBudget(FrameBudget& b, double now, double frameMs) {
    if (b.desc.budgetMs <= 0 || b.front.empty()) return false;
    if (b.periodStart < 0) b.periodStart = now;
    if (frameMs > 0 && std::isfinite(frameMs)) b.samples.push_back(frameMs);
    if (now - b.periodStart < b.desc.periodS || b.samples.empty()) return false;
    std::vector<double> s = b.samples;
    std::nth_element(s.begin(), s.begin() + s.size() / 2, s.end());
    b.lastMedianMs = s[s.size() / 2];
    b.samples.clear();
    b.periodStart = now;
    if (b.hold <= 0) b.hold = b.desc.holdAfterDownS;
    const bool allowUp = now - b.lastDown >= b.hold;
    size_t next = PickBudgetSetting(b.front, b.current, b.lastMedianMs, b.desc.budgetMs, b.desc.upMargin, allowUp);
    if (next == b.current) return false;
    if (next < b.current) {
        // a move up that did not fit (undone within two periods): wait twice as long next time
        b.hold = now - b.lastUp <= 2.0 * b.desc.periodS + 1e-9 ? std::min(2.0 * b.hold, 60.0) : b.desc.holdAfterDownS;
        b.lastDown = now;
    } else {
        b.lastUp = now;
    }
    b.current = next;
    ++b.moves;
    return true;
}

void ApplyBudgetSetting(const BudgetSetting& s, Quality* q, float* scale) {
    q->maxSteps = s.quality.maxSteps;
    q->hitEps = s.quality.hitEps;
    q->stepFactor = s.quality.stepFactor;
    q->shadowSteps = s.quality.shadowSteps;
    q->aoSamples = s.quality.aoSamples;
    *scale = s.scale;
}

std::vector<float> BudgetScalesAhead(const FrameBudget& b, float current, int n) {
    std::vector<float> scales;
    for (const BudgetSetting& s : b.front)
        if (s.scale > 0.0f && std::fabs(s.scale - current) > 1e-4f &&
            std::none_of(scales.begin(), scales.end(), [&](float x) { return std::fabs(x - s.scale) <= 1e-4f; }))
            scales.push_back(s.scale);
    const double c = std::max(current, 1e-3f);
    std::stable_sort(scales.begin(), scales.end(),
                     [&](float a, float x) { return std::fabs(std::log(a / c)) < std::fabs(std::log(x / c)); });
    if ((int)scales.size() > std::max(n, 0)) scales.resize((size_t)std::max(n, 0));
    return scales;
}

bool StartLiveFrameBudget(FrameBudget* b, double budgetMs, const std::string& floorText, const std::string& scene,
                          Quality* q, float* scale, std::string* error) {
    FrameBudgetDesc d;
    d.budgetMs = budgetMs;
    std::vector<BudgetSetting> c;
    if (!ParseBudgetFloor(floorText, &d.floor, error) ||
        !LoadBudgetCandidates(DataRoot() + "/docs/accuracy/accuracy.csv", scene, kLiveMaxScale, &c, error) ||
        !BeginFrameBudget(b, d, c, error))
        return false;
    ApplyBudgetSetting(b->front[b->current], q, scale);
    return true;
}

std::string FrameBudgetStatus(const FrameBudget& b) {
    if (b.desc.budgetMs <= 0 || b.front.empty() || b.current >= b.front.size()) return "";
    char line[256];
    char median[48] = "measuring";
    if (b.lastMedianMs > 0) std::snprintf(median, sizeof median, "median %.1f ms", b.lastMedianMs);
    std::snprintf(line, sizeof line, "frame budget %.3g ms: %s (%zu of %zu on the front), %s", b.desc.budgetMs,
                  b.front[b.current].label.c_str(), b.current + 1, b.front.size(), median);
    return line;
}

bool LiveFrameBudgetStep(FrameBudget& b, double now, double frameMs, Quality* q, float* scale, std::string* say) {
    if (!StepFrameBudget(b, now, frameMs)) return false;
    ApplyBudgetSetting(b.front[b.current], q, scale);
    char line[256];
    std::snprintf(line, sizeof line, "frame budget %.3g ms: median %.1f ms -> %s", b.desc.budgetMs, b.lastMedianMs,
                  b.front[b.current].label.c_str());
    *say = line;
    return true;
}

}  // namespace sdfvj
