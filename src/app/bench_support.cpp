// Warm-up, drift check and CSV shared by the benches (bench_support.h).
#include "app/bench_support.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
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

int RefreshesMissed(double frameMs, double fps) {
    if (fps <= 0 || !(frameMs > 0)) return 0;
    return std::max(0, (int)std::ceil(frameMs * fps / 1000.0 - 1e-9) - 1);
}

std::string SetDriverCaches(const std::string& mode, const std::filesystem::path& scratch, bool oneLaunch) {
    if (mode == "off") {
        setenv("MESA_SHADER_CACHE_DISABLE", "true", 1);
        setenv("__GL_SHADER_DISK_CACHE", "0", 1);
        return "off (MESA_SHADER_CACHE_DISABLE=true, __GL_SHADER_DISK_CACHE=0)";
    }
    if (mode == "fresh") {
        unsetenv("MESA_SHADER_CACHE_DISABLE");
        setenv("MESA_SHADER_CACHE_DIR", (scratch / "mesa").c_str(), 1);
        setenv("__GL_SHADER_DISK_CACHE", "1", 1);
        setenv("__GL_SHADER_DISK_CACHE_PATH", (scratch / "nv").c_str(), 1);
        std::filesystem::create_directories(scratch / "nv");
        return "on, in empty folders of this run (MESA_SHADER_CACHE_DIR, __GL_SHADER_DISK_CACHE_PATH): cold";
    }
    const char* mesa = std::getenv("MESA_SHADER_CACHE_DISABLE");
    const char* nv = std::getenv("__GL_SHADER_DISK_CACHE");
    return std::string("as the environment has them (MESA_SHADER_CACHE_DISABLE=") + (mesa ? mesa : "unset") +
           ", __GL_SHADER_DISK_CACHE=" + (nv ? nv : "unset") + ")" +
           (oneLaunch ? ", kept from earlier launches" : ", warmed by an untimed pass of the same saves");
}

std::string DriverCacheContents(const std::filesystem::path& scratch) {
    namespace fs = std::filesystem;
    std::string out;
    for (const char* d : {"nv", "mesa"}) {
        size_t files = 0, bytes = 0;
        std::error_code ec;
        for (auto it = fs::recursive_directory_iterator(scratch / d, ec); !ec && it != fs::recursive_directory_iterator(); it.increment(ec))
            if (it->is_regular_file(ec)) ++files, bytes += (size_t)it->file_size(ec);
        if (files)
            out += "\ndriver disk cache " + std::string(d) + " after the run: " + std::to_string(files) + " files, " + std::to_string(bytes) +
                   " bytes\n";
    }
    return out;
}

void SaveLikeAnEditor(const std::filesystem::path& file, const std::string& text) {
    const std::filesystem::path tmp = file.string() + ".sdfvj-save~";
    std::ofstream(tmp, std::ios::binary) << text;
    std::filesystem::rename(tmp, file);
}

}  // namespace sdfvj
