#include "app/bench_reload_report.h"

#include <algorithm>
#include <cstdio>

#include "app/bench_support.h"
#include "render/render.h"

namespace sdfvj {

void PrintReloadRound(int round, const Round& r) {
    char quick[32] = "-";
    if (!r.quickFrames.empty()) std::snprintf(quick, sizeof quick, "%.2f", MedianMs(r.quickFrames));
    char used[48] = "no";
    if (r.usedBefore) std::snprintf(used, sizeof used, "yes (%.1f)", r.loadMs);
    std::printf("| %d | %.1f%s | %.1f | %d | %.1f | %.1f (%.1f / %.1f) | %.1f | %s | %.1f | %s | %s |\n", round,
                r.firstMs, r.evaluatorSeen ? " (evaluator)" : r.quickSeen ? " (quick)" : "", r.optimizedMs, r.frames, r.longestFrame,
                r.longestUpdate, r.beginCall, r.finishCall, r.firstDraw, quick, r.compileMs, used,
                r.fromCache ? "yes" : "no");
}

ReloadSummary ReportReloadRounds(const std::string& mode, const std::vector<Round>& rounds, double steadyMedian, int steadyMissed,
                                 double fps) {
    std::vector<double> first, optimized, longest, compile, before, at, atShare, pastBuild;
    for (const Round& r : rounds) {
        first.push_back(r.firstMs);
        optimized.push_back(r.optimizedMs);
        longest.push_back(r.longestFrame);
        before.push_back(r.longestBefore);
        at.push_back(r.longestAt);
        atShare.push_back(r.firstMs > 0 ? r.longestAt / r.firstMs : 0.0);
        compile.push_back(r.compileMs);
        if (r.compileMs > 0) pastBuild.push_back(r.optimizedMs - r.compileMs);
    }
    const double worst = MedianMs(longest);
    const double ratio = steadyMedian > 0 ? worst / steadyMedian : 0.0;
    std::printf("median: save -> first tier %.1f ms, -> optimized %.1f ms; longest frame during a reload %.1f ms "
                "= %.1fx the steady median %.2f ms (target <= 2x); compile %.1f ms\n",
                MedianMs(first), MedianMs(optimized), worst, ratio, steadyMedian, MedianMs(compile));
    if (!pastBuild.empty())   // what a save waits for besides its build
        std::printf("past the build (save -> optimized less its compile: polls, hand-over, import, frames): median %.1f ms\n", MedianMs(pastBuild));
    std::vector<double> miss;   // what a display at --fps shows: a frame past its refresh shows the one before again
    for (const Round& r : rounds) miss.push_back(r.missed);
    if (fps > 0) {
        std::printf("display refreshes missed at %.0f Hz from a save to 300 ms after its swap: median %.0f, most %.0f "
                    "(%d in the last 20 steady frames)\n", fps, MedianMs(miss), *std::max_element(miss.begin(), miss.end()), steadyMissed);
    }
    std::printf("longest frame before the first swap (while it was built or loaded elsewhere): %.1f ms median of rounds; "
                "the longest frame began %.1f ms after the save (%.2f of the way to the first swap), medians of rounds\n",
                MedianMs(before), MedianMs(at), MedianMs(atShare));
    std::vector<double> after;
    std::vector<std::vector<double>> around(7);
    for (const Round& r : rounds) {
        after.push_back(std::max(r.longestFrame, r.longestAfter));
        for (size_t i = 0; i < r.around.size() && i < around.size(); ++i) around[i].push_back(r.around[i]);
    }
    std::printf("frames around the swap, medians of rounds (ms): -3 %.2f, -2 %.2f, -1 %.2f, the swap %.2f, +1 %.2f, +2 %.2f, +3 %.2f; "
                "longest frame with the 300 ms after the swap %.1f ms = %.1fx the steady median\n",
                MedianMs(around[0]), MedianMs(around[1]), MedianMs(around[2]), MedianMs(around[3]), MedianMs(around[4]),
                MedianMs(around[5]), MedianMs(around[6]), MedianMs(after),
                steadyMedian > 0 ? MedianMs(after) / steadyMedian : 0.0);
    return {mode, MedianMs(first), MedianMs(optimized), worst, ratio, steadyMedian, MedianMs(after), MedianMs(miss)};
}

void PrintModesSideBySide(const std::vector<ReloadSummary>& summary, double fps) {
if (summary.size() > 1) {
    std::printf("\n## modes side by side (rounds interleaved; medians)\n| mode | save -> first tier ms | save -> optimized ms | "
                "longest frame ms | x steady median | steady median ms | longest with the 300 ms after the swap ms | x steady | "
                "display refreshes missed a save |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for (const ReloadSummary& s : summary)
        std::printf("| %s | %.1f | %.1f | %.1f | %.1f | %.2f | %.1f | %.1f | %s |\n", s.mode.c_str(), s.first, s.optimized, s.longest, s.ratio,
                    s.steady, s.after, s.steady > 0 ? s.after / s.steady : 0.0, fps > 0 ? std::to_string((int)s.missed).c_str() : "-");
}
}

}  // namespace sdfvj
