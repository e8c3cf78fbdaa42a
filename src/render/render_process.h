// RenderProcess: a scene drawn by a child process, `sdfvj render-server`, its frames shown here
// (issue 12, session 16: `bench reload --modes render-process`, a lever measured before `live`
// uses it).
//
// Why another process: on NVIDIA a new program's first use stalls every thread of the process that
// makes it for 100-300 ms (docs/performance.md, session 14: stages), and a running process never
// gets another's program through the driver's disk cache. A compile process's builds (and its
// priming draws) did not stall the show's frames at all. So the process that finishes a program
// must be the one that draws it: each program gets a render server of its own, which compiles,
// uses and draws it while the server on screen goes on drawing; then the show switches servers.
//
// The server draws into its own target and hands each frame over by one of three transports:
//   vkmem   it copies the frame into an image both processes import (render/shared_image.h:
//           Vulkan-allocated, GL_EXT_memory_object_fd): the frame never leaves the GPU.
//   dmabuf  the same through a texture exported as a dma-buf (EGL_MESA_image_dma_buf_export) and
//           imported by the show (EGL_EXT_image_dma_buf_import); the NVIDIA H200's EGL lists it
//           but its export failed there (no DRM device in that container).
//   shm     it reads the pixels into shared memory (a memfd) and the show uploads them: a copy
//           each way, works on every driver.
// Asked for the GPU (any transport but shm), the server tries vkmem, then dmabuf, then shm, and
// says why each one it passed over failed.
// A frame is synchronous: the show sends the inputs, the server draws and finishes (glFinish,
// before it answers) and says done; the show then reads the frame. On the GPU (vkmem) the server
// hands frames over in two images by turns, so the show may ask for the next frame while its read
// of this one is still on the GPU: it waits (a fence, Read) only for the read of the image the
// server writes next, a frame older. One image (shm, dmabuf, or SDFVJ_SERVER_IMAGES=1 in the
// server's environment): the show waits for its read before it asks for the next frame.
//
// Wire format (a stream socket, the server's fd 3; native byte order; each message
// u32 type, u32 payload length, payload):
//   show -> server  1 load:  u32 path, i32 width, i32 height, u32 transport (0 shm, else the GPU), u32 quick
//                            tier (0/1), scene path,
//                            u32 own effects (0: the scene's own; 1: an EffectSet's bytes follow),
//                            u32 lifted (1: the scene's literals as uniforms, the literal tier),
//                            u32 len, a scene path (a field morph from that scene; 0: none),
//                            u32 n, n x (u32 len, path): the post chain's files (ServerLoad::post)
//                   2 frame: FrameInputs (f64 time, i32 frame, f32 beat, f32 bpm, Quality's bytes,
//                            i32 effectsOff, f32 yaw, f32 pitch, u32 n, n x (u32 len, name, f32))
//                   3 literals: u32 n, n x f32 (no answer)
//                   4 build ahead: a load's payload; the program is built into the program cache
//                            (program_cache.h), used and drawn once offscreen; only before a load, any
//                            number; the server keeps the last one's program, and a load of the same
//                            source (same quick tier, path) takes it instead of building
//                   5 time a draw: FrameInputs; drawn offscreen, timed, not handed over
//                   6 audio: u32 n, n x f32 waveform, u32 m, m x f32 spectrum, for the post chain's
//                            audio inputs from the next frame on (no answer); also before a load, whose
//                            first draws of the chain then have it
//                   7 prepare: i32 width, i32 height, u32 transport (0 shm, else the GPU): the hand-over's
//                            images made ahead for a load of that size (before a load, once; answered 7)
//                   8 inputs of now: u32 number, FrameInputs (no answer): a load's first frame is drawn
//                            with the last ones that came before it
//   server -> show  1 ready: u32 ok, u32 transport, f64 build ms, f64 first use ms, f64 first frame
//                            ms, u32 fourcc, u64 modifier, i32 stride, i32 offset, u64 memory size,
//                            u32 len, text (the error, or a note); one fd rides along when ok (memfd,
//                            Vulkan memory or dma-buf); then u32 from the program cache (0/1),
//                            u32 images (1, or 2: a second Vulkan image's fd rides along too),
//                            f64 the hand-over's set-up ms (images made and exported, the first frame in),
//                            u32 the program was the one a build ahead left in the server (0/1),
//                            u32 a quick load showing the optimized program from the cache (0/1),
//                            u32 the images were made ahead (wire type 7: none ride along now) (0/1),
//                            u32 the number of the streamed inputs (type 8) its first frame was drawn with (0: none)
//                   7 prepared: a ready's payload (nothing built; ok 0: none made), its fds as a ready's
//                   2 done:  f64 the server's draw + hand-over ms, u32 the image the frame is in
//                   4 built: u32 ok, u32 it was in the program cache already, f64 ms, u32 len, the error
//                   5 timed: f64 ms (a GL timer query; glFinish + wall clock on a software renderer; < 0 failed)
// Render thread only (the show's side), except RunRenderServer (the child's main).
#pragma once
#include <sys/types.h>

#include <cstdint>
#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "render/import_thread.h"
#include "render/render.h"

namespace sdfvj {

enum class FrameTransport { Shm = 0, DmaBuf = 1, VkMemory = 2 };

// What a server builds and draws.
struct ServerLoad {
    std::string scenePath;
    bool sceneEffects = true;   // the scene's own effects, or:
    EffectSet effects;
    RenderPath path = RenderPath::Fragment;
    int width = 0, height = 0;
    bool lifted = false;   // the scene's float literals as uniforms (the literal tier: RenderProcess::SetLiterals)
    // A field morph (render/field_morph.h) from this scene to scenePath: one program of both fields,
    // each frame's inputs MorphParamValues (its `morph` input, 0..1, mixes the headers too).
    std::string morphFrom;
    // The post chain (ISF files, resolved paths) each frame is drawn through before it is handed over,
    // so that a post effect's build, first draw and new targets land in the server, not in the show
    // (the show on NVIDIA held 28-41 ms at a bloom save in its own process: docs/performance.md,
    // "Session 32"). Empty: the frame as the scene draws it.
    std::vector<std::string> post;
    bool operator==(const ServerLoad&) const = default;
};

// What a server draws its frames through after the scene: the post chain of ServerLoad::post. The
// render library knows no ISF; sdfvj's main (and a test's) gives RunRenderServer the ISF chain's
// (isf/isf_server_post.h). The server's GL context is current in every call.
class ServerPost {
public:
    virtual ~ServerPost() = default;
    // Builds the chain of these files and draws it at w x h with this sound (its first draws, its
    // targets', and on llvmpipe the code for the audio textures' sizes); false with the file:line of
    // what failed.
    virtual bool Load(const std::vector<std::string>& paths, unsigned input, int w, int h, const std::vector<float>& wave,
                      const std::vector<float>& spectrum, std::string* error) = 0;
    // The frame `input` (w x h) through the chain; returns the texture holding the result.
    virtual unsigned Render(unsigned input, int w, int h, const FrameInputs& in, const std::vector<float>& wave,
                            const std::vector<float>& spectrum) = 0;
};
using ServerPostFactory = std::unique_ptr<ServerPost> (*)();
const char* FrameTransportName(FrameTransport t);

class RenderProcess {
public:
    struct Ready {
        bool ok = false;
        FrameTransport transport = FrameTransport::Shm;
        double buildMs = 0, useMs = 0, firstFrameMs = 0;   // in the server: compile + link, first use, first real frame
        std::string text;                                  // the error, or a note (a transport refused)
        bool fromCache = false;                            // the program came from the program cache: nothing compiled
        double shareMs = 0;                                // in the server: the hand-over set up (images made, the first frame in)
        bool fromStandby = false;                          // the program a build ahead left in that server: nothing built, nothing first used
        double importMs = 0;                               // here, the render thread: the answer read and its images imported (PollReady)
        double importThreadMs = -1;                        // on the import thread (SetImporter): its imports; -1: none there
        bool optimized = false;                            // a quick tier's load found the optimized program in the cache and shows it
        bool imagesAhead = false;                          // its hand-over's images were made before the load (PrepareImages): shareMs is the first frame's copy
        uint32_t firstSeq = 0;                             // its first frame (in the image shown) was drawn with the inputs SendInputsOfNow numbered so; 0: the scene's defaults
    };
    struct BuiltAhead {
        bool ok = false, fromCache = false;   // fromCache: it was there already
        double buildMs = 0;
        std::string text;   // the error
    };
    RenderProcess() = default;
    ~RenderProcess();   // Stop(), then waits for the server to end
    // Closes the socket and ends the server, frees what was imported (GL current); does not wait.
    void Stop();
    // After Stop(): true once the server has ended (never blocks).
    bool TryReap();
    RenderProcess(const RenderProcess&) = delete;
    RenderProcess& operator=(const RenderProcess&) = delete;

    // Spawns `exe render-server`; it opens its own GL context and waits for Load. Never blocks on it.
    // env: NAME=value entries over this process's environment, for the server.
    bool Start(std::string* error, const std::string& exe = "/proc/self/exe", const std::vector<std::string>& env = {});
    // Asks the server to build and draw a scene (from its file, as the show would). Never blocks.
    // quick: the quick first tier of the program (QuickTierText).
    bool Load(const ServerLoad& load, FrameTransport transport, bool quick = false);
    // The hand-over's images (and the frame's target) made now for a later Load of this size and
    // transport, while the server waits: that load then only hands its first frame over
    // (Ready::imagesAhead). Before Load, once; a load of another size makes its own. Never blocks.
    bool PrepareImages(int width, int height, FrameTransport transport);
    // The prepare's answer read and its images imported (on the import thread where there is one),
    // so that the load that follows brings none; never blocks with timeoutMs 0. True once read (or
    // none was asked for); false: not here yet (or the server is gone: Usable()).
    bool TakePrepared(int timeoutMs = 0);
    // The inputs of the show's frame now, sent to a server building a load (wire type 8): it draws its
    // first frame with the last ones it has (Ready::firstSeq says which), so that frame can go on screen
    // in the frame that reads its answer. Numbered from 1; skipped (false) while the socket holds more
    // than 16 KB the server has not read (some 20 frames: a longer build's first frame is asked for). Never blocks.
    bool SendInputsOfNow(const FrameInputs& in);
    uint32_t LastInputsSent() const { return inputsSeq_; }   // the number of the last SendInputsOfNow that went
    // The load's first frame (drawn with Ready::firstSeq's inputs) as Texture(), uncollected: shared
    // memory copied in, as Collect does. False when there are no images.
    bool ShowFirstFrame();
    // Builds a load's program into the program cache (program_cache.h) and draws nothing, so that a
    // later Load of it, in any server, is a cache load. Only before Load; one at a time: the next
    // after PollBuiltAhead said it is done. Never blocks.
    bool BuildAhead(const ServerLoad& load);
    // True once the server answered BuildAhead (or died: then built->ok is false). Never blocks
    // with timeoutMs 0.
    bool PollBuiltAhead(BuiltAhead* built, int timeoutMs = 0);
    // The values of the lifted program's u_lit[i] (a Load with lifted: the scene's float literals
    // read from uniforms) for the frames from now on. Never blocks; ignored when the count differs.
    bool SetLiterals(const std::vector<float>& values);
    // The sound the post chain's audio inputs read (wire type 6), from the next frame on. Never blocks.
    bool SetAudio(const std::vector<float>& wave, const std::vector<float>& spectrum);
    // True once the server answered Load (or died: then ready->ok is false). Never blocks; with
    // a timeout > 0 it waits up to that long. On success the frame is importable: Texture().
    // With an importer (SetImporter), the GPU transport's images are imported on its thread: the
    // answer is read in one call, and a later call (the next frame's) takes the textures.
    bool PollReady(Ready* ready, int timeoutMs = 0);
    // The thread that imports this server's images (vkmem); null: the render thread does. Before Load.
    void SetImporter(ImportThread* importer) { importer_ = importer; }
    bool Importing() const { return importing_ != nullptr && loadAnswered_; }   // its load answered, its images on the import thread
    // One frame: sends the inputs, waits for the server (up to timeoutMs), makes the frame this
    // process's Texture(). False when the server died or timed out: the caller keeps what it had.
    bool DrawFrame(const FrameInputs& in, int timeoutMs = 5000, int deadMs = -1) { return Request(in) && Collect(timeoutMs, deadMs); }
    // The same in two halves, for a frame loop that lets the server draw while it waits for the
    // display (the frame shown is then one behind the inputs): Request sends the inputs and returns;
    // Collect waits for that frame. Texture() must not be read by the GPU while the server may
    // write it: call Read() after the commands that read it; Request then waits for the read of the
    // image the server writes next (with two images, that of the frame before: long done).
    bool Request(const FrameInputs& in);
    // Request's first frame while this server's images are still on the import thread (Importing()):
    // the server draws it as the images are imported, so the frame is here when they are (a swap a
    // display refresh sooner). Nothing reads the images yet, so nothing is waited for. False when
    // not importing, a frame is already asked for, or the server is gone.
    bool RequestWhileImporting(const FrameInputs& in);
    void Read();
    // deadMs > timeoutMs: a frame not here after timeoutMs stays asked for (Outstanding(); Collect
    // again later) until deadMs have passed since its Request, when the server is taken for dead.
    bool Collect(int timeoutMs = 5000, int deadMs = -1);
    bool Outstanding() const { return outstanding_; }
    double OutstandingMs() const;   // how long the frame asked for has been awaited (0: none is)
    // Texture() stays whole while the server draws the next frame: two images by turns, or shared
    // memory copied in at Collect. One GPU image (a dma-buf, or SDFVJ_SERVER_IMAGES=1) is written in place.
    bool LastFrameStable() const { return images_ > 1 || transport_ == FrameTransport::Shm; }
    // The program drawn once more with `in`, offscreen in the server, timed there (the overlay's
    // "measure costs"); waits for the answer. -1 when it failed (or a frame is outstanding).
    double TimeDraw(const FrameInputs& in, int timeoutMs = 5000);
    // True when the frame asked for has arrived (Collect will not wait). Never blocks.
    bool Arrived();
    unsigned Texture() const { return texture_; }   // this context's texture holding the last frame
    // A framebuffer of this context that reads Texture(): one per image, attached at its first read
    // and kept, where attaching the image read each frame re-validated one every frame (the two
    // images alternate: 0.04-0.05 ms of the show's frame on the H200). Dropped with the images (Stop,
    // an import), as GL may give a freed texture's name to the next server's image. 0: no frame.
    unsigned ReadFramebuffer();
    double LastServerMs() const { return lastServerMs_; }
    bool Usable() const { return fd_ >= 0 && !dead_; }
    pid_t Pid() const { return pid_; }

private:
    bool Send(const std::string& message);
    bool SendRequest(const FrameInputs& in);   // a frame asked for (wire type 2): outstanding from now
    bool Receive(int timeoutMs);                 // reads what arrived (fds too) into inbox_/fds_
    bool TakeMessage(uint32_t* type, std::string* payload);
    bool Answer(uint32_t* type, std::string* payload, int timeoutMs);   // false: none yet, or the server is gone
    bool Import(const std::string& payload, Ready* ready, bool* pending);
    bool FinishImport(Ready* ready, int timeoutMs);
    void MarkDead();
    int fd_ = -1;
    pid_t pid_ = -1;
    bool dead_ = false, killed_ = false;
    std::string inbox_;
    std::vector<int> fds_;
    int width_ = 0, height_ = 0;
    FrameTransport transport_ = FrameTransport::Shm;
    unsigned texture_ = 0;    // the image holding the last frame: textures_[shown_]
    unsigned textures_[2] = {0, 0};
    unsigned memories_[2] = {0, 0};   // GL memory objects of the Vulkan images
    unsigned readFbos_[2] = {0, 0};       // ReadFramebuffer's, each with readTextures_[i] attached
    unsigned readTextures_[2] = {0, 0};
    void DropReadFramebuffers();
    void* reads_[2] = {nullptr, nullptr};   // GLsync: the show's last read of each image
    int images_ = 1, shown_ = 0;
    void* image_ = nullptr;   // EGLImage of the dma-buf
    void* shm_ = nullptr;
    size_t shmBytes_ = 0;
    double lastServerMs_ = 0;
    bool outstanding_ = false;
    std::chrono::steady_clock::time_point requestedAt_{};   // when the outstanding frame was asked for
    ImportThread* importer_ = nullptr;
    std::shared_ptr<ImportThread::Job> importing_;   // the images being imported there
    Ready importingReady_;                           // the answer they came with
    bool loadAnswered_ = false;                      // PollReady read the load's answer
    bool prepareAsked_ = false, prepareTaken_ = false, prepared_ = false;   // PrepareImages: asked, answered, imported (or importing)
    uint32_t inputsSeq_ = 0;                         // SendInputsOfNow's last number
    void FreeImages();                               // the images imported here (or being imported), and what reads them
    void UploadShm();                                // shared memory's frame into Texture()
};

// The child's main: a headless context of its own, then Load and frames from `fd` until it closes.
// `sdfvj render-server` calls this with fd 3. Returns the exit code. post: what makes a load's post
// chain (null: a load with one fails, saying so).
int RunRenderServer(int fd, ServerPostFactory post = nullptr);

}  // namespace sdfvj
