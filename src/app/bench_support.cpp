// Warm-up, drift check and CSV shared by the benches (bench_support.h).
#include "app/bench_support.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <thread>

#include "render/render.h"

namespace sdfvj {

void WarmGpu(const std::function<void()>& drawOnce, double seconds) {
    const auto t0 = std::chrono::steady_clock::now();
    do drawOnce();
    while (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < seconds);
}

bool Drift::Exceeds(double limitPct) const { return std::fabs(Pct()) > limitPct; }

std::string Drift::Line() const {
    char b[512];
    std::snprintf(b, sizeof b, "drift check: %s %.3f ms at the start, %.3f ms at the end (%+.1f %%): %s", label.c_str(),
                  startMs, endMs, Pct(),
                  Exceeds() ? "DRIFT over 3 %, the figures of this table are not comparable" : "ok (within 3 %)");
    return b;
}

double TimeMedian(const std::function<double()>& timeOnce, int frames) {
    std::vector<double> ms;
    for (int i = 0; i < std::max(frames, 1); ++i) ms.push_back(timeOnce());
    return MedianMs(ms);
}

std::string CsvField(const std::string& s) {
    if (s.find_first_of(",\"\n") == std::string::npos) return s;
    std::string q = "\"";
    for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
}

std::string SizeName(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

void BenchCsv::Add(const std::string& scene, const std::string& lighting, const std::string& size, const std::string& path,
                   double ms, const std::string& gpu, const std::vector<std::string>& extraValues) {
    char m[32];
    std::snprintf(m, sizeof m, "%.4f", ms);
    std::string row = CsvField(scene) + "," + CsvField(lighting) + "," + CsvField(size) + "," + CsvField(path) + "," + m +
                      "," + CsvField(gpu);
    for (size_t i = 0; i < extra.size(); ++i) row += "," + CsvField(i < extraValues.size() ? extraValues[i] : "");
    rows.push_back(row);
}

std::string BenchCsv::Text() const {
    std::string t = "scene,lighting,size,path,ms,gpu";
    for (const auto& e : extra) t += "," + CsvField(e);
    t += "\n";
    for (const auto& r : rows) t += r + "\n";
    return t;
}

bool BenchCsv::Write(const std::string& file, std::string* error) const {
    std::ofstream f(file);
    f << Text();
    if (!f) {
        *error = "cannot write " + file + ", expected a writable path for --csv";
        return false;
    }
    return true;
}

void PaceFrame(double frameMs, double fps) {
    if (fps > 0 && frameMs < 1000.0 / fps)
        std::this_thread::sleep_for(std::chrono::microseconds((int64_t)((1000.0 / fps - frameMs) * 1000)));
}

}  // namespace sdfvj
