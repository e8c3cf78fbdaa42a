// `sdfvj render-server`: the render process's side (render_process.h): its own context, a
// scene built, used and drawn on request, each frame handed over to the show.
#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <poll.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cstdlib>
#include <deque>
#include <cstring>

#include "render/compile_worker.h"
#include "render/field_morph.h"
#include "render/live_program.h"
#include "render/render_process.h"
#include "render/render_wire.h"
#include "render/server_target.h"
#include "render/shared_image.h"
#include "scene/scene.h"
#include "shader/shader.h"

namespace sdfvj {

using namespace render_wire;

namespace {

// A load or a build ahead (wire types 1 and 4: the same payload).
struct LoadMessage {
    RenderPath path = RenderPath::Fragment;
    int32_t width = 0, height = 0;
    uint32_t transport = 0, quick = 0, hasEffects = 0, lifted = 0;
    EffectSet effects;
    std::string scenePath;
    std::string morphFrom;   // a field morph from this scene to scenePath ("": none)
    std::vector<std::string> post;   // the post chain's files (ServerLoad::post)
};

bool ParseLoad(const std::string& payload, LoadMessage* m) {
    size_t at = 0;
    uint32_t path = 0;
    if (!Take(payload, &at, &path) || !Take(payload, &at, &m->width) || !Take(payload, &at, &m->height) ||
        !Take(payload, &at, &m->transport) || !Take(payload, &at, &m->quick) || !TakeText(payload, &at, &m->scenePath) ||
        !Take(payload, &at, &m->hasEffects) || (m->hasEffects && !Take(payload, &at, &m->effects)) || !Take(payload, &at, &m->lifted) ||
        !TakeText(payload, &at, &m->morphFrom))
        return false;
    uint32_t files = 0;
    if (!Take(payload, &at, &files) || files > kMaxPostFiles) return false;
    m->post.resize(files);
    for (std::string& f : m->post)
        if (!TakeText(payload, &at, &f)) return false;
    m->path = path == (uint32_t)RenderPath::Compute ? RenderPath::Compute : RenderPath::Fragment;
    return true;
}

// The scene read from its file, as the show would, and its program's source (no GL). A field morph
// reads both scenes (*from too).
// A quick tier's load also gives the optimized text (*optimized, when asked for).
bool AssembleLoad(const LoadMessage& m, SceneInfo* scene, SceneInfo* from, ShaderSource* src, std::string* error,
                  std::string* optimized = nullptr) {
    if (!LoadScene(m.scenePath, scene, error)) return false;
    const VariantKey key{m.scenePath, m.hasEffects ? m.effects : scene->effects, m.path};
    if (!m.morphFrom.empty()) return LoadScene(m.morphFrom, from, error) && AssembleMorphProgram(*from, *scene, key, src, error);
    if (!AssembleProgram(*scene, key, src, error, m.lifted != 0)) return false;
    if (m.quick && optimized) *optimized = src->text;
    if (m.quick) src->text = QuickTierText(src->text);
    return true;
}

// A quick tier's load whose optimized program the program cache holds (a scene or preset shown
// before): that one instead, no quick build and no optimized build to follow (ServerShow::Poll).
// In `sdfvj live`'s process the same holds (LiveProgram); here it halves the processes a preset
// change among scenes already seen starts. False: not cached (nothing done).
bool BuildOptimizedFromCache(const ShaderSource& quick, const std::string& optimizedText, RenderPath path, Program* program,
                             bool* ok, std::string* error) {
    if (optimizedText.empty()) return false;
    ShaderSource full = quick;
    full.text = optimizedText;
    PendingProgram pending;
    if (!pending.BeginFromCache(full, path)) return false;
    *ok = pending.Finish(program, error);
    return true;
}

// A program a build ahead (wire type 4) left built, used and drawn in this server's context: a
// load of the same source (the scene's file unchanged since) takes it instead of building it (the
// show's standby server: ServerShow::SetStandby).
struct KeptProgram {
    std::unique_ptr<Program> program;
    uint64_t hash = 0;
    RenderPath path = RenderPath::Fragment;
    uint32_t quick = 0;
    bool Matches(const ShaderSource& src, const LoadMessage& m) const {
        return program && src.hash == hash && m.path == path && m.quick == quick;
    }
};

// SDFVJ_SERVER_STRIPS=N (1-64): a server's first frame of a program (and a draw ahead) in N strips
// with a wait after each, so the show's frames, drawn meanwhile on the same GPU, are not queued
// behind one whole frame's dispatch (bench reload --modes render-process+SDFVJ_SERVER_STRIPS=8).
int FirstFrameStrips() {
    static const int strips = EnvInt("SDFVJ_SERVER_STRIPS", 1, 1, 64);
    return strips;
}

// Wire type 6: the post chain's sound, each row at most kMaxAudioValues.
bool ParseAudio(const std::string& payload, std::vector<float>* wave, std::vector<float>* spectrum) {
    size_t at = 0;
    for (std::vector<float>* v : {wave, spectrum}) {
        uint32_t n = 0;
        if (!Take(payload, &at, &n) || n > kMaxAudioValues || payload.size() - at < (size_t)n * sizeof(float)) return false;
        v->resize(n);
        std::memcpy(v->data(), payload.data() + at, (size_t)n * sizeof(float));
        at += (size_t)n * sizeof(float);
    }
    return at == payload.size();
}

}  // namespace

int RunRenderServer(int fd, ServerPostFactory makePost) {
    ::signal(SIGPIPE, SIG_IGN);
    HeadlessContext gl;
    std::string glError;
    const bool glOk = gl.Create(&glError);
    if (glOk && std::getenv("SDFVJ_CONTEXT_PRIORITY"))   // what the driver gave (headless.cpp)
        std::fprintf(stderr, "sdfvj render-server: %s\n", gl.Description().c_str());
    if (glOk) {   // a spare does these while it waits, off the save's path
        WarmCompiler();
        std::string ignored;   // a load that asks for the GPU says why there is none
        const char* prepare = std::getenv("SDFVJ_SERVER_PREPARE");   // 0: not (measured: bench reload --modes render-process+SDFVJ_SERVER_PREPARE=0)
        if (!prepare || std::string(prepare) != "0") SharedImage::Prepare(&ignored);   // the Vulkan device the images come from
        // SDFVJ_SERVER_NICE=N (1-19): this thread's builds (the compile, and a software renderer's
        // JIT at the first use) yield the CPU to the frames of the show and of the server on screen.
        // Only this thread: the renderer's own worker threads (llvmpipe's rasterizer and compute
        // pools), made with the context above, keep their priority, so the frames this server draws
        // once on screen do too. Off by default: on llvmpipe (2 cores, 320x180) it cut the longest
        // frame of a character reload by 16-20 % but made the build 26-44 % slower, and did nothing
        // for midi's (docs/performance.md, "Session 20").
        const int nice = EnvInt("SDFVJ_SERVER_NICE", 0, 0, 19);
        if (nice > 0) setpriority(PRIO_PROCESS, (id_t)syscall(SYS_gettid), nice);
    }
    SceneInfo scene;
    auto program = std::make_unique<Program>();
    KeptProgram kept;   // the last build ahead's program
    SceneInfo from;      // a field morph's first scene
    bool morph = false;  // the program is a field morph: each frame's header is the two scenes' mixed by its `morph` input
    SceneInfo mixed;     // its header this frame
    auto frameScene = [&](const FrameInputs& in) -> const SceneInfo& {
        if (!morph) return scene;
        float t = 0;
        for (const auto& [name, value] : in.params)
            if (name == "morph") t = value;
        mixed = MixSceneInfo(from, scene, t);
        return mixed;
    };
    FrameRenderer fr, scratch;   // scratch: draws timed for the show (wire type 5)
    std::unique_ptr<ServerPost> post;   // the load's post chain (ServerLoad::post); null: none
    std::vector<float> wave, spectrum;   // its sound (wire type 6)
    GLuint postRead = 0;                 // a framebuffer reading its output, attached each frame
    auto drawPost = [&](const FrameInputs& in) -> GLuint {   // the frame through the chain: postRead reads it; 0 without one
        if (!post) return 0;
        const unsigned out = post->Render(fr.Texture(), fr.Width(), fr.Height(), in, wave, spectrum);
        if (!postRead) glGenFramebuffers(1, &postRead);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, postRead);
        glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, out, 0);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
        return postRead;
    };
    // Two images on the GPU (vkmem): frame N into one while the show may still read frame N - 1 from
    // the other, so the show never waits for its own read before it asks for the next frame.
    // SDFVJ_SERVER_IMAGES=1: one image (every request then waits for the show's read: measured).
    std::unique_ptr<ServerTarget> targets[2] = {std::make_unique<ServerTarget>(), std::make_unique<ServerTarget>()};
    int images = 1, current = 0;
    const char* imagesEnv = std::getenv("SDFVJ_SERVER_IMAGES");
    const bool oneImage = imagesEnv && std::string(imagesEnv) == "1";
    // The frame's target and the hand-over's images for w x h (transport 0: shared memory; else the
    // GPU's, falling back as it must). False only when not even shared memory could be had.
    auto makeTargets = [&](int w, int h, uint32_t transport, std::string* error) {
        ServerTarget& target = *targets[0];
        std::string why, why2, whySecond;
        if (transport != 0 && !target.ShareVulkan(w, h, &why) && !target.ExportDmaBuf(w, h, &why2))
            target.note = "GPU hand-over refused (Vulkan image: " + why + "; dma-buf: " + why2 + "): shared memory instead";
        else if (transport != 0 && target.transport == FrameTransport::DmaBuf)
            target.note = "Vulkan image refused (" + why + "): dma-buf";
        if (target.transport == FrameTransport::Shm && !target.MakeShm(w, h, error)) return false;
        if (target.transport == FrameTransport::VkMemory && !oneImage) {
            if (targets[1]->ShareVulkan(w, h, &whySecond)) images = 2;
            else target.note = "one shared image (a second one failed: " + whySecond + "): each frame waits for the show's read";
        }
        return fr.Resize(w, h, error);
    };
    // The answer to a load (wire type 1), or to a prepare (7: the images alone, nothing built).
    auto readyPayload = [&](bool ok, const std::string& text, double buildMs, double useMs, double frameMs, bool cached, double shareMs,
                            bool standby, bool optimized, bool ahead, uint32_t seq) {
        const ServerTarget& target = *targets[0];
        std::string p;
        Put<uint32_t>(&p, ok ? 1 : 0);
        Put<uint32_t>(&p, (uint32_t)target.transport);
        Put(&p, buildMs);
        Put(&p, useMs);
        Put(&p, frameMs);
        Put<uint32_t>(&p, target.fourcc);
        Put<uint64_t>(&p, target.modifier);
        Put<int32_t>(&p, target.stride);
        Put<int32_t>(&p, target.offset);
        Put<uint64_t>(&p, target.memorySize);
        PutText(&p, ok ? target.note : text);
        Put<uint32_t>(&p, cached ? 1 : 0);
        Put<uint32_t>(&p, (uint32_t)images);
        Put(&p, shareMs);
        Put<uint32_t>(&p, standby ? 1 : 0);
        Put<uint32_t>(&p, optimized ? 1 : 0);
        Put<uint32_t>(&p, ahead ? 1 : 0);
        Put<uint32_t>(&p, seq);
        return p;
    };
    // An answer, with the images' fds when withImages: the show holds them from then on, so the GPU
    // images' are closed here (shared memory's stays: this side writes through it). False: the show is gone.
    auto answer = [&](uint32_t type, const std::string& p, bool withImages) {
        if (!SendAll(fd, Message(type, p), withImages ? targets[0]->fd : -1, withImages && images == 2 ? targets[1]->fd : -1)) return false;
        for (auto& t : targets)
            if (withImages && t->transport != FrameTransport::Shm && t->fd >= 0) ::close(t->fd), t->fd = -1;
        return true;
    };
    // Made ahead (wire type 7: a spare told the show's size while it waits), so that a load of that
    // size and transport only hands its first frame over. SDFVJ_SERVER_PREPARE_IMAGES=0: not (measured).
    struct { int w = 0, h = 0; uint32_t transport = 0; bool made = false; } prepared;
    const char* prepareImages = std::getenv("SDFVJ_SERVER_PREPARE_IMAGES");
    const bool prepareOn = !prepareImages || std::string(prepareImages) != "0";
    bool loaded = false;
    // The show's inputs of now (wire type 8), streamed while a load builds: its first frame is drawn
    // with the last ones, so the show can put it on screen in the frame that reads the answer.
    FrameInputs latest;
    uint32_t latestSeq = 0;   // 0: none came
    std::deque<std::pair<uint32_t, std::string>> queued;   // read while a load drained type 8s; answered after it
    auto readMessage = [&](uint32_t* type, std::string* payload) {
        uint32_t header[2];
        if (!ReadAll(fd, header, sizeof header) || header[1] > kMaxPayload) return false;
        *type = header[0];
        payload->assign(header[1], '\0');
        return ReadAll(fd, payload->data(), payload->size());
    };
    auto takeLatest = [&](const std::string& payload) {
        size_t at = 0;
        uint32_t seq = 0;
        FrameInputs in;
        if (!Take(payload, &at, &seq) || !DecodeInputs(payload.substr(at), &in)) return false;
        latest = std::move(in), latestSeq = seq;
        return true;
    };
    auto drainWaiting = [&]() {   // what the show sent meanwhile, without waiting; false: it is gone, or not ours
        for (;;) {
            pollfd pf{fd, POLLIN, 0};
            if (::poll(&pf, 1, 0) <= 0 || !(pf.revents & POLLIN)) return true;
            uint32_t type = 0;
            std::string payload;
            if (!readMessage(&type, &payload)) return false;
            if (type != 8) queued.emplace_back(type, std::move(payload));
            else if (!takeLatest(payload)) return false;
        }
    };
    for (;;) {
        uint32_t header[2];
        std::string payload;
        if (!queued.empty()) {
            header[0] = queued.front().first;
            payload = std::move(queued.front().second);
            queued.pop_front();
        } else if (!readMessage(&header[0], &payload)) {
            return 0;
        }
        if (header[0] == 8) {   // inputs of now: kept for a load's first frame
            if (!takeLatest(payload)) return 3;
            continue;
        }
        if (header[0] == 2 && loaded) {
            FrameInputs in;
            if (!DecodeInputs(payload, &in)) return 3;
            const auto t0 = Clock::now();
            fr.Draw(*program, frameScene(in), in);
            const GLuint read = drawPost(in);
            current = (current + 1) % images;
            targets[current]->HandOver(fr, read);
            std::string p;
            Put(&p, MsSince(t0));
            Put<uint32_t>(&p, (uint32_t)current);
            if (!SendAll(fd, Message(2, p))) return 0;
            continue;
        }
        if (header[0] == 5 && loaded) {   // a draw timed offscreen ("measure costs"): nothing handed over
            FrameInputs in;
            if (!DecodeInputs(payload, &in)) return 3;
            std::string ignored;
            double ms = -1;
            if (scratch.Resize(fr.Width(), fr.Height(), &ignored)) {
                scratch.Draw(*program, frameScene(in), in, true);   // a GL timer query, or glFinish + wall clock on llvmpipe
                ms = scratch.LastGpuMs();
            }
            std::string p;
            Put(&p, ms);
            if (!SendAll(fd, Message(5, p))) return 0;
            continue;
        }
        if (header[0] == 7) {   // the hand-over made ahead: i32 width, i32 height, u32 transport (before a load; no answer)
            size_t at = 0;
            int32_t w = 0, h = 0;
            uint32_t transport = 0;
            if (!Take(payload, &at, &w) || !Take(payload, &at, &h) || !Take(payload, &at, &transport) || loaded || prepared.made) return 3;
            std::string ignored;   // the load makes them again, and says what failed
            const auto t0 = Clock::now();
            if (glOk && prepareOn && w > 0 && h > 0 && w <= 16384 && h <= 16384 && makeTargets(w, h, transport, &ignored))
                prepared = {w, h, transport, true};
            else {
                for (auto& t : targets) t = std::make_unique<ServerTarget>();
                images = 1;
            }
            // Answered with them (the show imports them while this server waits), or ok 0: none made.
            if (!answer(7, readyPayload(prepared.made, "", 0, 0, 0, false, MsSince(t0), false, false, false, 0), prepared.made)) return 0;
            continue;
        }
        if (header[0] == 6) {   // the post chain's sound (before a load too: its first draws have it)
            if (!ParseAudio(payload, &wave, &spectrum)) return 3;
            continue;
        }
        if (header[0] == 3 && loaded) {   // the literal tier's numbers
            size_t at = 0;
            uint32_t n = 0;
            std::vector<float> values;
            if (!Take(payload, &at, &n) || n > kMaxPayload / 4) return 3;
            values.resize(n);
            for (float& v : values)
                if (!Take(payload, &at, &v)) return 3;
            if (values.size() == program->Literals().size()) program->SetLiterals(values);
            continue;
        }
        if ((header[0] != 1 && header[0] != 4) || loaded) return 3;   // out of turn: the show is not ours
        LoadMessage m;
        if (!ParseLoad(payload, &m)) return 3;
        const RenderPath rp = m.path;
        const uint32_t transport = m.transport;
        const int32_t w = m.width, h = m.height;
        double buildMs = 0, useMs = 0, frameMs = 0, shareMs = 0;
        std::string error;
        bool ok = glOk;
        if (!glOk) error = glError;
        if (header[0] == 4) {   // built ahead into the program cache, nothing drawn; the next message may be anything
            KeptProgram ahead;   // kept for a load of the same program
            ahead.program = std::make_unique<Program>();
            const auto t0 = Clock::now();
            ShaderSource src;
            SceneInfo aheadScene, aheadFrom;
            if (ok) ok = AssembleLoad(m, &aheadScene, &aheadFrom, &src, &error) && ahead.program->Build(src, m.path, &error);
            if (ok) {   // used and drawn once, as a load is: what the driver finishes there lands in its own disk cache
                PrimeProgram(ahead.program->Id(), rp, false);
                FrameRenderer target;
                FrameInputs in;
                for (const ParamDecl& d : aheadScene.params) in.params.emplace_back(d.name, d.defaultValue);
                target.SetStrips(FirstFrameStrips());
                if (target.Resize(w, h, &error)) target.Draw(*ahead.program, aheadScene, in);
                error.clear();
                glFinish();
                ahead.hash = src.hash, ahead.path = m.path, ahead.quick = m.quick;
            }
            std::string p;
            Put<uint32_t>(&p, ok ? 1 : 0);
            Put<uint32_t>(&p, ok && ahead.program->FromCache() ? 1 : 0);
            kept = ok && m.morphFrom.empty() ? std::move(ahead) : KeptProgram{};
            Put(&p, MsSince(t0));
            PutText(&p, error);
            if (!SendAll(fd, Message(4, p))) return 0;
            continue;
        }
        auto t0 = Clock::now();
        ShaderSource src;
        std::string optimizedText;
        if (ok) ok = AssembleLoad(m, &scene, &from, &src, &error, &optimizedText);
        const bool standby = ok && kept.Matches(src, m);   // built, used and drawn here already
        bool optimized = false;   // a quick load that shows the optimized program, from the cache
        if (standby) program = std::move(kept.program);
        else if (ok && BuildOptimizedFromCache(src, optimizedText, m.path, program.get(), &ok, &error)) optimized = ok;
        else if (ok) ok = program->Build(src, m.path, &error);
        kept = KeptProgram{};   // a server loads once
        morph = ok && !m.morphFrom.empty();
        buildMs = MsSince(t0);
        FrameInputs in;
        for (const ParamDecl& d : frameScene(in).params) in.params.emplace_back(d.name, d.defaultValue);
        uint32_t firstSeq = 0;   // the streamed inputs the first frame was drawn with (0: the defaults)
        if (ok) ok = fr.Resize(w, h, &error);
        if (ok) {
            t0 = Clock::now();
            if (!standby) PrimeProgram(program->Id(), rp, false);   // the driver's first use, here
            glFinish();
            useMs = MsSince(t0);
            t0 = Clock::now();
            if (!drainWaiting()) return 0;
            if (latestSeq != 0) in = latest, firstSeq = latestSeq;   // the show's last inputs: its frame of now
            fr.SetStrips(FirstFrameStrips());
            fr.Draw(*program, frameScene(in), in);
            fr.SetStrips(1);
            glFinish();
            frameMs = MsSince(t0);
        }
        if (ok && !m.post.empty()) {   // the post chain: built and drawn once here, part of the load's build
            t0 = Clock::now();
            post = makePost ? makePost() : nullptr;
            if (!post) error = "this render server has no post chain (ServerPostFactory)";
            ok = post && post->Load(m.post, fr.Texture(), w, h, wave, spectrum, &error);
            buildMs += MsSince(t0);
        }
        const bool madeAhead = ok && prepared.made && prepared.w == w && prepared.h == h && (prepared.transport != 0) == (transport != 0);
        if (ok) {
            t0 = Clock::now();
            if (!madeAhead) {   // none made ahead, or for another size: made now
                for (auto& t : targets) t = std::make_unique<ServerTarget>();
                images = 1;
                ok = makeTargets(w, h, transport, &error);
            }
            if (ok) targets[0]->HandOver(fr, drawPost(in));
            shareMs = MsSince(t0);
        }
        const std::string p = readyPayload(ok, error, buildMs, useMs, frameMs, ok && program->FromCache(), shareMs, standby, optimized,
                                           madeAhead, firstSeq);
        // Images made ahead went with the prepare's answer: none ride along now.
        if (!answer(1, p, ok && !madeAhead)) return 0;
        if (!ok) return 1;
        loaded = true;
    }
}


}  // namespace sdfvj
