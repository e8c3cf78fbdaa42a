// `sdfvj render`: headless frames on the fixed clock (time = frame / fps), to PNGs or ffmpeg.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>

#include "app/commands.h"
#include "app/replay_driver.h"
#include "isf/isf.h"
#include "render/field_morph.h"
#include "shader/eval_program.h"
#include "shader/evaluator.h"

extern char** environ;

namespace fs = std::filesystem;

namespace sdfvj {

namespace {

// ffmpeg as a child process reading raw RGBA frames on its stdin. Started from an argv (no
// shell: quotes, spaces and `$` in the output path are just characters), waited for, and its
// exit status is the verdict: a failed encode is a failed render. Owns the pipe and the child;
// the destructor closes the pipe and reaps the child on every early return.
class FfmpegEncoder {
public:
    FfmpegEncoder() = default;
    ~FfmpegEncoder() { Finish(); }
    FfmpegEncoder(const FfmpegEncoder&) = delete;
    FfmpegEncoder& operator=(const FfmpegEncoder&) = delete;

    // Returns 0, or ENOENT when there is no ffmpeg on PATH, or another errno with *error set.
    int Start(const std::vector<std::string>& argv, std::string* error) {
        int fds[2];
        if (pipe2(fds, O_CLOEXEC) != 0) { *error = std::string("cannot make a pipe for ffmpeg: ") + std::strerror(errno); return errno; }
        posix_spawn_file_actions_t actions;
        posix_spawn_file_actions_init(&actions);
        posix_spawn_file_actions_adddup2(&actions, fds[0], 0);   // dup2 clears O_CLOEXEC on fd 0
        std::vector<char*> args;
        for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
        args.push_back(nullptr);
        int rc = posix_spawnp(&pid_, args[0], &actions, nullptr, args.data(), environ);
        posix_spawn_file_actions_destroy(&actions);
        close(fds[0]);
        if (rc != 0) {
            close(fds[1]);
            pid_ = -1;
            *error = std::string("cannot start ffmpeg: ") + std::strerror(rc);
            return rc;
        }
        fd_ = fds[1];
        return 0;
    }

    // Writes all of `bytes`; false when ffmpeg closed its end (it exited or failed: EPIPE).
    bool Write(const std::vector<uint8_t>& bytes) {
        size_t done = 0;
        while (done < bytes.size()) {
            ssize_t n = write(fd_, bytes.data() + done, bytes.size() - done);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) return false;
            done += size_t(n);
        }
        return true;
    }

    // Closes the pipe (end of input) and waits for ffmpeg. Returns "" when it exited with 0,
    // else how it ended ("exit status 1", "killed by signal 9"). Idempotent.
    std::string Finish() {
        if (fd_ >= 0) { close(fd_); fd_ = -1; }
        if (pid_ <= 0) return result_;
        int status = 0;
        pid_t r;
        do r = waitpid(pid_, &status, 0); while (r < 0 && errno == EINTR);
        pid_ = -1;
        if (r < 0) result_ = std::string("lost track of it: ") + std::strerror(errno);
        else if (WIFEXITED(status) && WEXITSTATUS(status) == 0) result_ = "";
        else if (WIFEXITED(status)) result_ = "exit status " + std::to_string(WEXITSTATUS(status));
        else if (WIFSIGNALED(status)) result_ = "killed by signal " + std::to_string(WTERMSIG(status));
        else result_ = "ended with wait status " + std::to_string(status);
        return result_;
    }

private:
    pid_t pid_ = -1;
    int fd_ = -1;
    std::string result_;
};

// The ffmpeg command line for raw RGBA frames of w x h on stdin. libx264's yuv420p needs even
// sizes: an odd width or height gets one black column/row of padding (right/bottom).
std::vector<std::string> FfmpegArgs(int w, int h, double fps, const std::string& outPath) {
    char size[32], rate[32];
    std::snprintf(size, sizeof size, "%dx%d", w, h);
    std::snprintf(rate, sizeof rate, "%g", fps);
    std::vector<std::string> a = {"ffmpeg", "-hide_banner", "-loglevel", "error", "-y",
                                  "-f", "rawvideo", "-pix_fmt", "rgba", "-s", size, "-r", rate, "-i", "pipe:0"};
    if (w % 2 || h % 2) a.insert(a.end(), {"-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2"});
    // "file:" keeps a path that starts with '-' or holds ':' from being read as an option or
    // a protocol; the container is still chosen from the extension.
    a.insert(a.end(), {"-c:v", "libx264", "-pix_fmt", "yuv420p", "file:" + outPath});
    return a;
}

// Cues that switch presets (ReplayDriver::TakeShowSwitch): the new show's program is built at
// the cue's frame, on this thread (never in the background: the same bytes every run), and a
// scene change with a morph time crossfades from the old scene's frame, its values frozen, as
// `live` does.
class CueSwitcher {
public:
    // Puts `next` on stage in `show`; false with *error when its program does not build.
    bool Apply(ReplayDriver::ShowSwitch next, Show& show, const std::vector<std::pair<std::string, float>>& oldParams,
               double time, std::string* error) {
        next.show->path = show.path;
        if (!BuildShow(next.show.get(), RenderPathName(show.path), error, false)) return false;
        fade_.reset();
        field_.Reset();
        std::string why;
        if (next.fadeSeconds > 0 && next.show->preset.automation.morph.fieldMorph) {
            // As in `live`: the two fields morph in one program where both scenes allow it.
            field_.Prepare(show.scene, next.show->scene, UnionEffects(show.effects, next.show->effects), show.path);
            if (field_.Wait() != FieldMorph::State::Ready) {
                const std::string& e = field_.Error();
                std::fprintf(stderr, "sdfvj render: %s and %s cannot morph as one field (%s) — crossfading their frames\n",
                             show.scene.name.c_str(), next.show->scene.name.c_str(), e.substr(0, e.find('\n')).c_str());
                field_.Reset();
            }
        }
        if (next.fadeSeconds > 0 && !crossfade_.Init(&why))
            std::fprintf(stderr, "sdfvj render: %s — the scene change cuts\n", why.c_str());
        else if (next.fadeSeconds > 0)
            fade_ = std::make_unique<Fade>(Fade{std::move(show), oldParams, time, next.fadeSeconds, next.weight});
        show = std::move(*next.show);
        return true;
    }
    // The frame to show: `scene` itself, or while a fade runs the mix of the old scene's frame
    // (drawn here with `in` and the frozen values) and `scene`.
    const FrameRenderer& Frame(const FrameRenderer& scene, const FrameInputs& in, int w, int h) {
        std::string error;
        if (!fade_ || in.time - fade_->start >= fade_->seconds || !old_.Resize(w, h, &error) || !mixed_.Resize(w, h, &error)) {
            fade_.reset();   // done: the old program may go
            field_.Reset();
            return scene;
        }
        if (field_.Current()) {
            field_.Draw(mixed_, in, fade_->params, fade_->weight(in.time - fade_->start));
            return mixed_;
        }
        FrameInputs old = in;
        old.params = fade_->params;
        old_.Draw(*fade_->show.program, fade_->show.scene, old);
        crossfade_.Draw(old_.Texture(), scene.Texture(), fade_->weight(in.time - fade_->start), mixed_.Framebuffer(), w, h);
        return mixed_;
    }

private:
    struct Fade {
        Show show;
        std::vector<std::pair<std::string, float>> params;
        double start = 0.0, seconds = 0.0;
        std::function<float(double)> weight;
    };
    std::unique_ptr<Fade> fade_;
    FieldMorph field_;   // the fields' morph, when both scenes compile into one program
    FrameRenderer old_, mixed_;
    Crossfade crossfade_;
};

// `--frame-range A:B` (both inclusive) or `A:` (to the last frame) against a whole render of
// `frames` frames; `frames` < 0 means "not known" (no take, no --frames): B then sets the length.
// B past the last frame is clamped, so a farm's last slice may say more than it needs.
bool ParseFrameRange(const std::string& text, int frames, int* first, int* last, std::string* error) {
    const size_t colon = text.find(':');
    auto number = [](const std::string& t, int* v) {
        if (t.empty() || t.size() > 9 || t.find_first_not_of("0123456789") != std::string::npos) return false;
        *v = std::stoi(t);
        return true;
    };
    const std::string a = colon == std::string::npos ? "" : text.substr(0, colon), b = colon == std::string::npos ? "" : text.substr(colon + 1);
    if (!number(a, first) || (!b.empty() && !number(b, last))) {
        *error = "--frame-range '" + text + "': expected A:B or A: with frame indices (0-based, B included), e.g. 0:99";
        return false;
    }
    if (b.empty()) {
        if (frames < 0) { *error = "--frame-range " + text + " runs to the end: give --frames (or a take) to say where that is"; return false; }
        *last = frames - 1;
    }
    if (frames >= 0) *last = std::min(*last, frames - 1);
    if (*first > *last) {
        *error = "--frame-range " + text + ": no frames in it (the whole render has " + std::to_string(frames < 0 ? *last + 1 : frames) +
                 "), expected A <= B";
        return false;
    }
    return true;
}

// True when a post/generator pass keeps its image across frames (feedback): a frame range must
// then draw the frames before it too, not only step the parameters.
bool HasFeedback(IsfChain& chain) {
    for (size_t i = 0; i < chain.Size(); ++i)
        if (IsfHasFeedback(chain.Stage(i).File())) return true;
    return false;
}

// --evaluator: the scene's evaluator program (shader/eval_program.h) drawing the scene's code
// (shader/evaluator.h), as a save's first tier draws it, in place of the compiled program. 0, or
// the exit code with its message printed: 2 when the scene cannot be evaluated.
int BuildEvaluatorShow(Show* show, const std::string& pathOption, bool verbose) {
    PickRenderPath(show, pathOption, verbose);
    const VariantKey key{show->scene.path, show->effects, show->path};
    const auto t0 = std::chrono::steady_clock::now();
    ShaderSource src;
    std::string unit, error;
    std::vector<std::string> slots;
    eval::Program code;
    // llvmpipe stops a shader's loops after 65535 iterations in all: the machine's loop unrolled there.
    if (!AssembleEvaluatorProgram(show->scene, key, &src, &error, IsSoftwareRenderer() ? kEvaluatorUnrollSoftware : 1) ||
        !eval::AssembleEvaluatorUnit(show->scene, key, &unit, &slots, &error) || !eval::Translate(unit, slots, &code, &error)) {
        std::fprintf(stderr, "sdfvj render: --evaluator: %s cannot be evaluated: %s\n", DisplayPath(show->scene.path).c_str(),
                     error.substr(0, error.find('\n')).c_str());
        return 2;
    }
    const double translateMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    auto program = std::make_unique<Program>();
    if (!program->Build(src, show->path, &error)) {
        std::fprintf(stderr, "%s\n", error.c_str());
        return 1;
    }
    program->SetEvaluatorCode(eval::PackCode(code), code.constants);
    program->MarkEvaluatorTier();
    if (verbose)
        std::fprintf(stderr, "evaluator: %zu instructions, %zu constants, %u registers, translated in %.1f ms; its program %s in %.0f ms\n",
                     code.code.size(), code.constants.size(), code.registers, translateMs,
                     program->FromCache() ? "loaded from the program cache" : "built", program->Origin().buildMs);
    show->program = std::move(program);
    return 0;
}

}  // namespace

int RunRender(const RenderOptions& o) {
    HeadlessContext gl;   // declared first: destroyed after every GL object below
    std::string error;
    int w = 0, h = 0;
    if (!ParseSize(o.size, &w, &h, &error)) { std::fprintf(stderr, "sdfvj render: %s\n", error.c_str()); return 2; }
    if (o.fps <= 0 || o.fps > 1000) { std::fprintf(stderr, "sdfvj render: --fps must be in (0, 1000]\n"); return 2; }
    // The show: a raymarched scene, or an ISF/Shadertoy generator (--scene x.fs, or a preset whose
    // scene is one: PrepareShow makes it the post chain's first stage). --post, else the preset's
    // "post", filters the frame; every ISF input is a show parameter like a scene input (defaults,
    // preset, --param, then the take, mapping and automation each frame).
    Show show;
    if (!PrepareShow(o.show, &show, &error)) { std::fprintf(stderr, "sdfvj render: %s\n", error.c_str()); return 2; }
    const bool isfScene = show.isfScene;
    if (o.evaluator && isfScene) {
        std::fprintf(stderr, "sdfvj render: --evaluator draws a raymarched scene's hooks, not an ISF generator\n");
        return 2;
    }
    const std::vector<std::string> isfPaths = SplitIsfList(show.post);   // the generator first

    // Replay: a take drives the parameters through the mapping, exactly as live input does.
    std::unique_ptr<ReplayDriver> replay;
    std::string takePath = !o.replay.empty() ? o.replay : "";
    int frames = o.frames;
    if (!takePath.empty() || !show.preset.automation.Empty()) {   // a take, or a scripted preset
        replay = MakeReplayDriver(show, takePath, o.mapping, &error, &o.show);
        if (!replay) { std::fprintf(stderr, "sdfvj render: %s\n", error.c_str()); return 2; }
        if (!o.framesGiven && !takePath.empty()) frames = (int)std::ceil(replay->Duration() * o.fps) + 1;
    }
    if (frames <= 0) { std::fprintf(stderr, "sdfvj render: --frames must be at least 1\n"); return 2; }
    // --frame-range: the frames before A only step the state (take, mapping, smoothing, automation,
    // cues, whose programs are built at their frames as in the whole run); nothing is drawn.
    int first = 0, last = frames - 1;
    const bool lengthKnown = o.framesGiven || !takePath.empty();
    if (!o.frameRange.empty()) {
        if (!ParseFrameRange(o.frameRange, lengthKnown ? frames : -1, &first, &last, &error)) {
            std::fprintf(stderr, "sdfvj render: %s\n", error.c_str());
            return 2;
        }
        if (!lengthKnown) frames = last + 1;
    }
    if (o.countFrames) {
        std::printf("%d\n", frames);
        return 0;
    }

    if (!gl.Create(&error)) { std::fprintf(stderr, "sdfvj render: %s\n", error.c_str()); return 2; }
    if (!o.quiet) std::fprintf(stderr, "GL: %s\n", gl.Description().c_str());
    if (o.evaluator) {
        if (const int rc = BuildEvaluatorShow(&show, o.show.path, !o.quiet)) return rc;
    } else if (!isfScene && !BuildShow(&show, o.show.path, &error, !o.quiet)) {
        std::fprintf(stderr, "%s\n", error.c_str());
        return 1;
    }
    FrameRenderer fr;
    if (!isfScene && !fr.Resize(w, h, &error)) { std::fprintf(stderr, "sdfvj render: %s\n", error.c_str()); return 2; }
    IsfChain isf;   // the generator (if any), then the post effects
    if (!isfPaths.empty() && !isf.Load(isfPaths, &error)) { std::fprintf(stderr, "%s\n", error.c_str()); return 1; }
    for (const std::string& line : isf.Notices()) std::fprintf(stderr, "%s\n", line.c_str());
    if (isfScene) show.scene.name = isf.Stage(0).File().path;

    std::unique_ptr<FfmpegEncoder> video;
    if (!o.video.empty()) {
        // A dead ffmpeg must not kill us silently: write() then fails with EPIPE instead.
        signal(SIGPIPE, SIG_IGN);
        video = std::make_unique<FfmpegEncoder>();
        int rc = video->Start(FfmpegArgs(w, h, o.fps, o.video), &error);
        if (rc == ENOENT) {
            std::fprintf(stderr, "sdfvj render: --video needs ffmpeg, which is not installed (apt-get install ffmpeg); "
                                 "use --out DIR for PNG frames\n");
            return 2;
        }
        if (rc != 0) { std::fprintf(stderr, "sdfvj render: %s\n", error.c_str()); return 1; }
        if ((w % 2 || h % 2) && !o.quiet)
            std::fprintf(stderr, "sdfvj render: %dx%d is odd, the video is padded to %dx%d (libx264 needs even sizes)\n",
                         w, h, w + w % 2, h + h % 2);
    } else {
        std::error_code ec;
        fs::create_directories(o.out, ec);
        if (ec) { std::fprintf(stderr, "sdfvj render: cannot create %s: %s\n", o.out.c_str(), ec.message().c_str()); return 2; }
    }
    const bool feedback = HasFeedback(isf);
    if (!o.quiet)
        std::fprintf(stderr, "rendering %s [%s, %s path] %dx%d, frames %d..%d of %d at %g fps -> %s\n", show.scene.name.c_str(),
                     isfScene ? "ISF" : DescribeEffects(show.effects).c_str(), isfScene ? "fragment" : RenderPathName(show.path), w, h,
                     first, last, frames, o.fps, o.video.empty() ? o.out.c_str() : o.video.c_str());
    if (first > 0 && feedback && !o.quiet)
        std::fprintf(stderr, "sdfvj render: an ISF pass is PERSISTENT (feedback): frames 0..%d are drawn too, not written\n", first - 1);

    FrameInputs in;
    in.quality = show.quality;
    in.params = show.params;
    const double dt = 1.0 / o.fps;
    CueSwitcher cues;
    auto start = std::chrono::steady_clock::now();
    for (int i = 0; i <= last; ++i) {
        in.frame = i;
        in.time = i * dt;
        if (replay) {
            const std::vector<std::pair<std::string, float>> before = in.params;
            replay->Advance(in.time, dt, &in.params);
            in.beat = replay->BeatPhase(in.time);
            in.bpm = replay->Bpm();
            ReplayDriver::ShowSwitch next = replay->TakeShowSwitch();
            if (next.show && !cues.Apply(std::move(next), show, before, in.time, &error)) {
                std::fprintf(stderr, "\nsdfvj render: %s — at frame %d a cue switches to a preset whose program does not build\n",
                             error.c_str(), i);
                return 1;
            }
        }
        if (i < first && !feedback) continue;   // fast-forward: state only
        std::vector<uint8_t> rgba;
        if (isf.Empty()) {
            fr.Draw(*show.program, show.scene, in);
            rgba = cues.Frame(fr, in, w, h).ReadPixels();
        } else {
            IsfFrameInputs isfIn;
            isfIn.time = in.time;
            isfIn.timeDelta = i > 0 ? dt : 0.0;   // DATE stays fixed: replays render the same bytes
            isfIn.frame = i;
            isfIn.params = in.params;   // the ISF host takes its own inputs' names (clamped there)
            isfIn.beat = in.beat;       // the take's / preset's tempo, as the scene gets it
            isfIn.bpm = in.bpm;
            // ISF audio/audioFFT inputs: the WAV recorded beside the take, at this frame's time.
            if (replay) replay->AudioAt(in.time, &isfIn.audioWaveform, &isfIn.audioSpectrum);
            if (!isfScene) fr.Draw(*show.program, show.scene, in);
            const unsigned sceneTexture = isfScene ? 0u : cues.Frame(fr, in, w, h).Texture();
            const unsigned out = isf.Render(sceneTexture, w, h, isfIn);
            if (i < first) continue;   // drawn for the feedback only
            rgba = ReadTextureRgba(out, w, h);
        }
        if (video) {
            if (!video->Write(rgba)) {
                std::string how = video->Finish();
                std::fprintf(stderr, "\nsdfvj render: ffmpeg stopped reading frames at frame %d (%s), %s is not complete\n",
                             i, how.empty() ? "it exited with status 0" : how.c_str(), o.video.c_str());
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
            PrintProgress(i - first + 1, last - first + 1, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    if (video) {
        std::string how = video->Finish();
        if (!how.empty()) {
            std::fprintf(stderr, "\nsdfvj render: ffmpeg failed to encode %s (%s), expected exit status 0; its message is above\n",
                         o.video.c_str(), how.c_str());
            return 1;
        }
    }
    return 0;
}

}  // namespace sdfvj
