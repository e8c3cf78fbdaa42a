// bench_reload_report.h - `sdfvj bench reload`'s figures (cmd_bench_reload.cpp times the rounds):
// one round as it was measured, a table row per round, the medians of a mode's rounds, and the
// modes side by side.
#pragma once
#include <string>
#include <vector>

namespace sdfvj {

struct Round {
    double beginCall = 0, finishCall = 0;   // the optimized program's Begin and Finish on the render thread
    double longestBefore = 0;   // longest frame before the first swap (the program built or loaded elsewhere)
    double longestAt = 0;       // when the longest frame began, ms after the save
    double firstMs = 0, optimizedMs = 0, longestFrame = 0, longestUpdate = 0, firstDraw = 0, compileMs = 0;
    int frames = 0;
    std::vector<double> quickFrames;   // frame times while the quick tier was on screen
    bool quickSeen = false, fromCache = false, ok = false;
    bool evaluatorSeen = false;   // the first tier was the evaluator program (a quick tier too)
    bool usedBefore = false;   // a program on screen this round was used on the loader before the hand-over
    double loadMs = 0;         // ... its load + first use there
    std::vector<double> around;   // the 3 frames before the swap to the optimized program, its own, the 3 after
    double longestAfter = 0;      // the longest frame in the 300 ms after that swap (what it replaced is retired then)
    int missed = 0;               // display refreshes missed from the save to 300 ms after the swap (paced frames)
};

// What the modes-side-by-side table shows of one mode (medians of its rounds).
struct ReloadSummary {
    std::string mode;
    double first = 0, optimized = 0, longest = 0, ratio = 0, steady = 0, after = 0, missed = 0;
};

// The round's row of the per-mode table (cmd_bench_reload.cpp prints its header).
void PrintReloadRound(int round, const Round& r);
// The medians of a mode's rounds (at least one), printed under its table; steadyMedian: the frame
// before any save; steadyMissed: refreshes missed in the last steady frames; fps: the pacing (0: none).
ReloadSummary ReportReloadRounds(const std::string& mode, const std::vector<Round>& rounds, double steadyMedian, int steadyMissed,
                                 double fps);
// The modes side by side (when there are two or more).
void PrintModesSideBySide(const std::vector<ReloadSummary>& summary, double fps);

}  // namespace sdfvj
