// bench_support.h - what every `sdfvj bench` table shares so its figures can be trusted:
//
//   WarmGpu(draw)        after every compile, keep the GPU busy >= 1 s before timing (its clocks
//                        drop while it waits on a compile: one run read 2.9 ms, the next 1.7 ms)
//   Drift                the first setting timed at the start and again at the end; a table whose
//                        figures moved more than 3 % in between says so
//   BenchCsv             the table as CSV: scene,lighting,size,path,ms,gpu plus the bench's own
//                        columns, so plots and checks read every bench the same way
//
// Benches also interleave the settings they compare (each round draws every setting once), so a
// clock change lands on all of them alike.
#pragma once
#include <chrono>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace sdfvj {

// The benches' clock: milliseconds since t.
using Clock = std::chrono::steady_clock;
inline double MsSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

// Draws (drawOnce must finish its frame, e.g. glFinish) until `seconds` have passed, at least once.
void WarmGpu(const std::function<void()>& drawOnce, double seconds = 1.0);

// The first setting's median at the start and the end of a run.
struct Drift {
    std::string label;     // what was timed twice ("character full 1920x1080 compute")
    double startMs = 0, endMs = 0;
    double Pct() const { return startMs > 0 ? 100.0 * (endMs - startMs) / startMs : 0.0; }
    bool Exceeds(double limitPct = 3.0) const;
    // "drift check: <label> 1.234 ms at the start, 1.250 ms at the end (+1.3 %): ok" or
    // "... (+7.5 %): DRIFT over 3 %, figures of this table are not comparable"
    std::string Line() const;
};
// Sleeps out the rest of a display frame at `fps` after a frame that took `frameMs` (fps <= 0: none).
void PaceFrame(double frameMs, double fps);
// Display refreshes at `fps` that showed the frame before again because this one took `frameMs`:
// ceil(frameMs * fps / 1000) - 1, at least 0 (0 when fps <= 0: not paced).
int RefreshesMissed(double frameMs, double fps);
// Median of `frames` timed draws (timeOnce returns one frame's ms).
double TimeMedian(const std::function<double()>& timeOnce, int frames);

// A bench table as CSV. The first six columns are the same in every bench; `extra` names the
// bench's own (values per row in the same order). Fields with commas or quotes are quoted.
struct BenchCsv {
    std::vector<std::string> extra;
    std::vector<std::string> rows;
    void Add(const std::string& scene, const std::string& lighting, const std::string& size, const std::string& path,
             double ms, const std::string& gpu, const std::vector<std::string>& extraValues = {});
    std::string Text() const;
    // False with "cannot write FILE" when the file cannot be written.
    bool Write(const std::string& file, std::string* error) const;
};
std::string CsvField(const std::string& s);

// The drivers' disk caches for the compile benches (bench reload): sets their variables (must run
// before the first context exists: drivers read them when they load) and returns a line saying how.
// off: both off. fresh: on, in empty folders under `scratch` (cold, but Mesa can hand a worker's JIT
// to the render context through it). warm: left as the user has them (warmed by the bench's untimed
// pass of the same saves, or for one launch by earlier launches).
std::string SetDriverCaches(const std::string& mode, const std::filesystem::path& scratch, bool oneLaunch);
// What the caches of SetDriverCaches("fresh", scratch) hold: a line per non-empty folder
// ("driver disk cache nv after the run: N files, B bytes"), or nothing.
std::string DriverCacheContents(const std::filesystem::path& scratch);
std::string SizeName(int w, int h);   // "1920x1080"
// Writes like an editor: a temp file renamed over the original.
void SaveLikeAnEditor(const std::filesystem::path& file, const std::string& text);

}  // namespace sdfvj
