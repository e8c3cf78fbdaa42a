// `sdfvj bench accuracy`: the quality sweep of src/accuracy as a command. Prints one line per
// setting, writes accuracy.csv, accuracy_<scene>.png/.svg and accuracy.md into --out (and the
// report to --markdown too, with plot links pointing at accuracy/ next to it).
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "accuracy/accuracy.h"
#include "app/bench_support.h"
#include "app/commands.h"

namespace fs = std::filesystem;

namespace sdfvj {

int RunAccuracyBench(const AccuracyBenchOptions& o) {
    std::string error;
    accuracy::SweepOptions so;
    if (!ParseSize(o.size, &so.width, &so.height, &error)) { std::fprintf(stderr, "sdfvj bench accuracy: %s\n", error.c_str()); return 2; }
    if (!o.refSize.empty() && !ParseSize(o.refSize, &so.refWidth, &so.refHeight, &error)) {
        std::fprintf(stderr, "sdfvj bench accuracy: --ref-size: %s\n", error.c_str());
        return 2;
    }
    so.scenes.clear();
    for (const std::string& s : o.scenes) {
        if (s == "all") { for (const auto& n : accuracy::CpuSceneNames()) so.scenes.push_back(n); continue; }
        SceneInfo info;
        if (!FindScene(s, &info, &error)) { std::fprintf(stderr, "sdfvj bench accuracy: %s\n", error.c_str()); return 2; }
        if (!accuracy::HasCpuScene(info.name)) {
            std::string known;
            for (const auto& n : accuracy::CpuSceneNames()) known += (known.empty() ? "" : ", ") + n;
            std::fprintf(stderr, "sdfvj bench accuracy: no CPU reference build of scene '%s', expected one of %s "
                         "(a scene file added since the last cmake configure needs a rebuild)\n", s.c_str(), known.c_str());
            return 2;
        }
        so.scenes.push_back(info.name);
    }
    if (o.sweep != "full" && o.sweep != "tiny" && o.sweep != "scale" && o.sweep != "looks") { std::fprintf(stderr, "sdfvj bench accuracy: unknown sweep '%s', expected full, tiny, scale or looks\n", o.sweep.c_str()); return 2; }
    if (o.path != "auto" && o.path != "compute" && o.path != "fragment") { std::fprintf(stderr, "sdfvj bench accuracy: unknown path '%s', expected auto, compute or fragment\n", o.path.c_str()); return 2; }
    for (const std::string& kv : o.params) {
        auto eq = kv.find('=');
        char* end = nullptr;
        float v = eq == std::string::npos ? 0.0f : std::strtof(kv.c_str() + eq + 1, &end);
        if (eq == std::string::npos || end == kv.c_str() + eq + 1 || *end != '\0') {
            std::fprintf(stderr, "sdfvj bench accuracy: bad --param '%s', expected NAME=VALUE\n", kv.c_str());
            return 2;
        }
        so.params.emplace_back(kv.substr(0, eq), v);
    }
    so.sweep = o.sweep;
    so.path = o.path;
    so.frames = o.frames;
    so.warmup = o.warmup;
    so.time = o.time;
    so.threads = o.threads;
    so.log = [](const std::string& s) { std::printf("%s\n", s.c_str()); std::fflush(stdout); };

    HeadlessContext gl;
    if (!gl.Create(&error)) { std::fprintf(stderr, "sdfvj bench accuracy: %s\n", error.c_str()); return 2; }
    std::printf("# sdfvj bench accuracy on %s\n", gl.Description().c_str());
    std::vector<accuracy::Row> rows;
    accuracy::SweepInfo info;
    if (!accuracy::RunSweep(so, &rows, &info, &error)) { std::fprintf(stderr, "sdfvj bench accuracy: %s\n", error.c_str()); return 1; }
    info.device = gl.Description();

    std::error_code ec;
    fs::create_directories(o.out, ec);
    {
        std::ofstream csv(fs::path(o.out) / "accuracy.csv");
        csv << accuracy::CsvHeader() << "\n";
        for (const auto& r : rows) csv << accuracy::CsvLine(r) << "\n";
        if (!csv) { std::fprintf(stderr, "sdfvj bench accuracy: cannot write %s/accuracy.csv\n", o.out.c_str()); return 1; }
    }
    for (const std::string& sc : so.scenes) {
        if (!accuracy::WritePlotPng((fs::path(o.out) / ("accuracy_" + sc + ".png")).string(), rows, sc, &error)) {
            std::fprintf(stderr, "sdfvj bench accuracy: %s\n", error.c_str());
            return 1;
        }
        std::ofstream((fs::path(o.out) / ("accuracy_" + sc + ".svg"))) << accuracy::PlotSvg(rows, sc);
    }
    for (const auto& [scene, d] : info.drift) {
        Drift drift;
        drift.label = scene + " " + rows.front().s.label;
        drift.startMs = d.first;
        drift.endMs = d.second;
        std::printf("%s\n", drift.Line().c_str());
    }
    if (!o.csv.empty()) {
        // the shared bench columns first, then the sweep's own (accuracy.csv's, less its scene)
        std::string text = "scene,lighting,size,path,ms,gpu," + accuracy::CsvHeader().substr(accuracy::CsvHeader().find(',') + 1) + "\n";
        const std::string size = SizeName(so.width, so.height), gpu = CsvField(GlRendererName());
        for (const auto& r : rows) {
            SceneInfo scene;
            std::string lighting = FindScene(r.scene, &scene, &error) ? DescribeEffects(scene.effects) : "";
            std::string line = accuracy::CsvLine(r);
            text += CsvField(r.scene) + "," + CsvField(lighting) + "," + size + "," + info.path + "," +
                    accuracy::Format("%.4f", r.gpuMs) + "," + gpu + "," + line.substr(line.find(',') + 1) + "\n";
        }
        std::ofstream f(o.csv);
        f << text;
        if (!f) { std::fprintf(stderr, "sdfvj bench accuracy: cannot write %s, expected a writable path for --csv\n", o.csv.c_str()); return 1; }
    }
    std::string md = accuracy::MarkdownReport(rows, so, info, o.commandLine);
    std::ofstream(fs::path(o.out) / "accuracy.md") << md;
    if (!o.markdown.empty()) {
        // the report links its plots as accuracy/accuracy_<scene>.svg next to the markdown file
        fs::path dir = fs::path(o.markdown).parent_path() / "accuracy";
        fs::create_directories(dir, ec);
        for (const std::string& sc : so.scenes)
            for (const char* ext : {".png", ".svg"})
                fs::copy_file(fs::path(o.out) / ("accuracy_" + sc + ext), dir / ("accuracy_" + sc + ext),
                              fs::copy_options::overwrite_existing, ec);
        std::ofstream(o.markdown) << md;
    }
    std::printf("wrote %s/accuracy.csv, accuracy_<scene>.png/.svg, accuracy.md%s%s\n", o.out.c_str(),
                o.markdown.empty() ? "" : " and ", o.markdown.c_str());
    return 0;
}

}  // namespace sdfvj
