// `sdfvj render`: headless frames on the fixed clock (time = frame / fps), to PNGs or ffmpeg.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "app/commands.h"
#include "app/replay_driver.h"

namespace fs = std::filesystem;

namespace sdfvj {

namespace {

struct PipeCloser { void operator()(FILE* f) const { if (f) pclose(f); } };

}  // namespace

int RunRender(const RenderOptions& o) {
    HeadlessContext gl;   // declared first: destroyed after every GL object below
    std::string error;
    int w = 0, h = 0;
    if (!ParseSize(o.size, &w, &h, &error)) { std::fprintf(stderr, "sdfvj render: %s\n", error.c_str()); return 2; }
    if (o.fps <= 0 || o.fps > 1000) { std::fprintf(stderr, "sdfvj render: --fps must be in (0, 1000]\n"); return 2; }
    Show show;
    if (!PrepareShow(o.show, &show, &error)) { std::fprintf(stderr, "sdfvj render: %s\n", error.c_str()); return 2; }

    // Replay: a take drives the parameters through the mapping, exactly as live input does.
    std::unique_ptr<ReplayDriver> replay;
    std::string takePath = !o.replay.empty() ? o.replay : "";
    int frames = o.frames;
    if (!takePath.empty()) {
        replay = MakeReplayDriver(show, takePath, o.mapping, &error);
        if (!replay) { std::fprintf(stderr, "sdfvj render: %s\n", error.c_str()); return 2; }
        if (!o.framesGiven) frames = (int)std::ceil(replay->Duration() * o.fps) + 1;
    }
    if (frames <= 0) { std::fprintf(stderr, "sdfvj render: --frames must be at least 1\n"); return 2; }

    if (!gl.Create(&error)) { std::fprintf(stderr, "sdfvj render: %s\n", error.c_str()); return 2; }
    if (!o.quiet) std::fprintf(stderr, "GL: %s\n", gl.Description().c_str());
    if (!BuildShow(&show, o.show.path, &error, !o.quiet)) { std::fprintf(stderr, "%s\n", error.c_str()); return 1; }
    FrameRenderer fr;
    if (!fr.Resize(w, h, &error)) { std::fprintf(stderr, "sdfvj render: %s\n", error.c_str()); return 2; }

    std::unique_ptr<FILE, PipeCloser> video;
    if (!o.video.empty()) {
        if (std::system("command -v ffmpeg >/dev/null 2>&1") != 0) {
            std::fprintf(stderr, "sdfvj render: --video needs ffmpeg, which is not installed (apt-get install ffmpeg); "
                                 "use --out DIR for PNG frames\n");
            return 2;
        }
        char cmd[1024];
        std::snprintf(cmd, sizeof cmd,
                      "ffmpeg -loglevel error -y -f rawvideo -pix_fmt rgba -s %dx%d -r %g -i - -c:v libx264 "
                      "-pix_fmt yuv420p '%s'", w, h, o.fps, o.video.c_str());
        video.reset(popen(cmd, "w"));
        if (!video) { std::fprintf(stderr, "sdfvj render: cannot start ffmpeg\n"); return 1; }
    } else {
        std::error_code ec;
        fs::create_directories(o.out, ec);
        if (ec) { std::fprintf(stderr, "sdfvj render: cannot create %s: %s\n", o.out.c_str(), ec.message().c_str()); return 2; }
    }
    if (!o.quiet)
        std::fprintf(stderr, "rendering %s [%s, %s path] %dx%d, %d frames at %g fps -> %s\n", show.scene.name.c_str(),
                     DescribeEffects(show.effects).c_str(), RenderPathName(show.path), w, h, frames, o.fps,
                     o.video.empty() ? o.out.c_str() : o.video.c_str());

    FrameInputs in;
    in.quality = show.quality;
    in.params = show.params;
    const double dt = 1.0 / o.fps;
    auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < frames; ++i) {
        in.frame = i;
        in.time = i * dt;
        if (replay) replay->Advance(in.time, dt, &in.params);
        fr.Draw(*show.program, show.scene, in);
        std::vector<uint8_t> rgba = fr.ReadPixels();
        if (video) {
            if (std::fwrite(rgba.data(), 1, rgba.size(), video.get()) != rgba.size()) {
                std::fprintf(stderr, "\nsdfvj render: ffmpeg stopped reading frames\n");
                return 1;
            }
        } else {
            char name[64];
            std::snprintf(name, sizeof name, "frame_%05d.png", i);
            if (!WritePng((fs::path(o.out) / name).string(), w, h, rgba, &error)) {
                std::fprintf(stderr, "\nsdfvj render: %s\n", error.c_str());
                return 1;
            }
        }
        if (!o.quiet)
            PrintProgress(i + 1, frames, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    return 0;
}

}  // namespace sdfvj
