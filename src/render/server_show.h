// ServerShow: the render servers behind a show (issue 12; render_process.h says why a program is
// drawn by a process of its own). `bench reload --modes render-process*` and `live
// --render-process` both run on it.
//
// It holds the server on screen; the ones building a save (the optimized program, and with
// tiering a quick first tier beside it); spares started ahead, whose GL contexts and compilers are
// warm before a save needs them; and ended servers not yet reaped (never waited for on a frame).
// A save goes to a spare while the server on screen goes on drawing; a build that finishes goes on
// screen, one that fails says why and the one on screen stays. A server on screen that dies or
// stops answering is replaced by a spare building the same program, while the last frame it
// delivered stays on screen: a crash in a shader ends a server, never the show.
// Render thread only (the show's GL context current in every call and in the destructor); the
// spares are spawned on a helper thread, which touches no GL.
#pragma once
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <thread>
#include <string>
#include <vector>

#include "render/render_process.h"

namespace sdfvj {

class ServerShow {
public:
    // transport: how frames come over (FrameTransport::Shm, or the GPU where both sides can: the
    // server says which it could, and an import this side refuses falls back to Shm).
    // pipelined: the server draws the next frame while the show presents this one (Request after
    // the frame was read, AfterRead). tiered: every load also builds the quick tier (QuickTierText).
    ServerShow(FrameTransport transport, bool pipelined, bool tiered)
        : transport_(transport), pipelined_(pipelined), tiered_(tiered) {}
    ~ServerShow();
    ServerShow(const ServerShow&) = delete;
    ServerShow& operator=(const ServerShow&) = delete;

    // The first program, waited for (up to timeoutMs), and the spares opened for the next load.
    // False with *error when it did not build (the show may go on: a later Load that builds goes on
    // screen) or no server could start.
    bool Start(const ServerLoad& load, std::string* error, int timeoutMs = 120000);
    // NAME=value entries over this process's environment for every server started from now on (a
    // bench's program cache folder, say). Before Start.
    void SetServerEnv(std::vector<std::string> env) { env_ = std::move(env); }
    // The thread that imports each new server's images (render/import_thread.h), so that the frame
    // that takes a server's answer does not import them. Before Start; it must outlive this show's
    // frames (a job it has not done when a server is stopped is abandoned, not waited for).
    void SetImporter(ImportThread* importer) { importer_ = importer; }
    // Tiered: the optimized build starts once the quick tier is on screen (or failed), not beside it,
    // so the quick build has the driver and the CPU to itself (bench reload --modes render-process-in-turn).
    void SetTiersInTurn(bool inTurn) { inTurn_ = inTurn; }
    // A new program: a spare builds it while the one on screen goes on; a build still running for an
    // earlier Load is ended. Never blocks. False when no server could start.
    // quickTier false: no quick tier for this load even when tiered (a post chain's save, say, whose
    // scene program the program cache holds).
    bool Load(const ServerLoad& load, std::string* error, bool quickTier = true);
    // Reaps ended servers; puts a finished build on screen; replaces a dead server on screen.
    // True when the server on screen changed. *error: why a build failed or a server was replaced
    // ("" when nothing went wrong); the one on screen stays.
    bool Poll(std::string* error);
    // This frame's image into Texture(): drawn now (synchronous) or the one asked for a frame
    // before (pipelined). False when there is none to show this frame (no server on screen, or it
    // failed: Texture() still holds the last frame delivered, if any).
    // With deadMs > timeoutMs (pipelined or not): a frame still not here after timeoutMs is late, not
    // lost: Texture() keeps the last frame, the request stays, the next Frame collects it (LateFrames());
    // only deadMs after its request is the server taken for dead (and replaced by Poll).
    bool Frame(const FrameInputs& in, int timeoutMs = 1000, int deadMs = -1);
    // Frames shown again because the server on screen had not delivered the next in time (Frame's
    // timeoutMs), and the longest such wait so far, ms since the request; read and reset by the caller.
    int LateFrames() const { return lateFrames_; }
    double LongestLateMs() const { return longestLateMs_; }
    void ResetLate() { lateFrames_ = 0, longestLateMs_ = 0; }
    bool StillLate() const { return lateNow_; }   // the last Frame was late and nothing has come since
    // The sound the post chain of the server on screen reads (ServerLoad::post: its audio inputs),
    // sent with each frame asked for from now on; empty rows: silence.
    void SetAudio(std::vector<float> wave, std::vector<float> spectrum) {
        wave_ = std::move(wave);
        spectrum_ = std::move(spectrum);
    }
    // Pipelined: the show has issued what reads Texture() (fenced: RenderProcess::Read); the server
    // may draw the next frame.
    void AfterRead(const FrameInputs& in);
    // The frame is on screen and its GPU work done (after the swap, or a bench's glFinish): the servers
    // retired during it end now, and the import thread takes the images of a server that answered
    // during it (ImportOptions::afterFrame), so that the driver's teardown and imports fall in the
    // gap before the next frame rather than beside this one. A show that never calls this ends
    // retired servers in its next Poll and imports at once.
    void FrameDone();
    // A standby (issue 12): once a program is on screen and nothing builds, a spare builds the same
    // program ahead (RenderProcess::BuildAhead: built, used and drawn once in that process) and waits.
    // A load of that program (the same scene, variant and path: another size, another post chain, a
    // replacement for a server that died) goes to it and builds nothing; its build time is then the
    // post chain's and the first frame's. A scene save whose source changed goes to it as to any
    // spare. Off by default (it holds a second copy of the program and, on llvmpipe, compiles it again).
    void SetStandby(bool on) { standbyOn_ = on; }
    bool StandbyReady() const { return standbyReady_; }
    int StandbyUsed() const { return standbyUsed_; }
    // The way before (bench reload --modes render-process-retire-now): servers retired end at once,
    // in the frame that retired them.
    void SetRetireAtOnce(bool on) { retireAfterFrame_ = !on; }
    // The way before (bench reload --modes render-process-first-after-import): a new server's first
    // frame is asked for once its images are imported (the frame after its answer), not while they
    // are, so it goes on screen a display refresh later.
    void SetFirstFrameAfterImport(bool on) { firstAfterImport_ = on; }
    // Polls from the one that read the last server put on screen's answer to the one that put it
    // there (1: the next Poll; -1: none yet).
    long LastSwapPolls() const { return lastSwapPolls_; }

    unsigned Texture() const;                  // the show context's texture of the frame on screen; 0: none
    unsigned ReadFramebuffer();                // a framebuffer reading Texture() (RenderProcess::ReadFramebuffer); 0: none
    // Spares started and waiting (the spawner's; never blocks beyond its lock).
    int SparesReady() {
        std::lock_guard<std::mutex> lock(spareMutex_);
        return (int)spares_.size();
    }
    // Programs held ready off screen, each by a server of its own that a spare becomes, in slots:
    //   Literal  the literal tier (`lifted`: its numbers from uniforms); Poll never puts it on
    //            screen, PromotePrepared does, with new numbers, as a quick tier (an optimized build
    //            follows it)
    //   Morph    a field morph (ServerLoad::morphFrom) drawn beside the show while a scene change
    //            morphs (HeldFrame), never on screen as a program of its own
    enum class Held { Literal = 0, Morph = 1 };
    bool Prepare(const ServerLoad& load, std::string* error, Held slot = Held::Literal);
    bool HasPrepared(Held slot = Held::Literal) const { return held_[(int)slot].c.process != nullptr; }
    const ServerLoad& PreparedLoad(Held slot = Held::Literal) const { return held_[(int)slot].load; }
    bool PreparedReady(Held slot = Held::Literal);   // never blocks; one that failed or died is dropped (*PreparedError says why)
    const std::string& PreparedError(Held slot = Held::Literal) const { return held_[(int)slot].error; }
    bool PromotePrepared(const std::vector<float>& literals);
    // A ready held server's frame for `in` into HeldTexture(slot), as SideFrame; false when it failed.
    bool HeldFrame(Held slot, const FrameInputs& in, int timeoutMs = 1000, int deadMs = -1);
    unsigned HeldTexture(Held slot) const { return HasPrepared(slot) ? held_[(int)slot].c.process->Texture() : 0; }
    void DropHeld(Held slot);
    // Variants built ahead (issue 12: what an effect pad or a preset reaches next): a server of their
    // own builds each into the program cache, one at a time and only while no save builds, so that a
    // later Load of one is a cache load in its spare. Replaces the list not yet built; its server
    // ends when the list is done.
    struct BuiltAheadLoad {
        ServerLoad load;
        RenderProcess::BuiltAhead built;
    };
    void BuildAhead(std::vector<ServerLoad> loads);
    const std::vector<BuiltAheadLoad>& BuiltAheadLoads() const { return builtAhead_; }
    size_t BuildAheadLeft() const { return aheadQueue_.size() + (aheadAsked_ ? 1 : 0); }
    // Keep the server a build replaced (for a crossfade from its frames) until DropPrevious or the
    // next build on screen; off by default (it is ended at once). A quick tier is never kept: the
    // optimized program that replaces it leaves the previous one as it was.
    void SetKeepPrevious(bool on) { keepPrevious_ = on; }
    bool HasPrevious() const { return previous_ && previous_->Usable(); }
    const ServerLoad& PreviousLoad() const { return previousLoad_; }
    // The previous server's frame for `in` into PreviousTexture(), as SideFrame; false when it failed.
    bool PreviousFrame(const FrameInputs& in, int timeoutMs = 1000, int deadMs = -1) { return HasPrevious() && SideFrame(*previous_, in, timeoutMs, deadMs); }
    // A frame of a server beside the one on screen (the scene before in a crossfade, a held morph),
    // waited for as Frame waits for the one on screen's: one later than timeoutMs is not waited for
    // (its last image is used again, and the frame collected by a later call) until deadMs after it was
    // asked for, when the server is taken for dead (timeoutMs 0: not waited for at all, each frame
    // asked for one call and shown from the next). false when it failed; true when late.
    static bool SideFrame(RenderProcess& p, const FrameInputs& in, int timeoutMs, int deadMs);
    // p's frame for `in` (or the one asked for already), waited for up to timeoutMs (deadMs if its one
    // image is being written); false when late or failed. Frame and SideFrame.
    static bool WaitFrame(RenderProcess& p, const FrameInputs& in, int timeoutMs, int deadMs);
    double PreviousServerMs() const { return previous_ ? previous_->LastServerMs() : 0.0; }
    double HeldServerMs(Held slot) const { return HasPrepared(slot) ? held_[(int)slot].c.process->LastServerMs() : 0.0; }
    unsigned PreviousTexture() const { return previous_ ? previous_->Texture() : 0; }
    void DropPrevious() { Retire(std::move(previous_)); }
    // The program on screen drawn once more offscreen by its server, timed there (RenderProcess::TimeDraw).
    double TimeDraw(const FrameInputs& in) { return onScreen_ && onScreen_->Usable() ? onScreen_->TimeDraw(in) : -1; }
    bool OnScreen() const { return onScreen_ != nullptr; }
    const ServerLoad& OnScreenLoad() const { return onScreenLoad_; }
    bool OnScreenQuick() const { return onScreenQuick_; }
    bool Building() const { return next_.process != nullptr || quick_.process != nullptr || deferred_; }
    bool BuildingQuick() const { return quick_.process != nullptr; }   // a quick tier builds (or waits to be shown)
    const ServerLoad& BuildingLoad() const { return building_; }
    FrameTransport Transport() const { return transport_; }
    // Every server that went on screen, its figures in its process: build, first use, first frame.
    const std::vector<RenderProcess::Ready>& Shown() const { return shown_; }
    const std::vector<bool>& ShownQuick() const { return shownQuick_; }
    const std::string& Note() const { return note_; }   // a transport refused, and why
    int FailedFrames() const { return failedFrames_; }
    double LastServerMs() const { return onScreen_ ? onScreen_->LastServerMs() : 0.0; }   // its last draw + hand-over
    int Replaced() const { return replaced_; }
    pid_t OnScreenPid() const { return onScreen_ ? onScreen_->Pid() : -1; }          // servers on screen that died and were replaced

private:
    struct Candidate {
        std::unique_ptr<RenderProcess> process;
        bool quick = false;
        bool asked = false;   // pipelined: its first frame was asked for; it goes on screen when that arrives
        bool ready = false;   // its answer taken (and its images imported): it goes on screen with its first frame
        long answeredAt = -1;   // the Poll (polls_) that read its answer
        bool optimized = false;   // quick, but it loaded the optimized program from the cache (Ready::optimized)
        void Clear() { asked = ready = optimized = false, answeredAt = -1; }   // before a load, or once retired
    };
    void Drop(Candidate& c) { Retire(std::move(c.process)), c.Clear(); }   // retired: its flags go with it
    std::unique_ptr<RenderProcess> Spawn(std::string* error);
    std::unique_ptr<RenderProcess> TakeSpare(std::string* error, bool spawn = true);   // spawn: one now when none is ready
    void FillSpares();
    bool Promote(Candidate& c, std::string* error);   // true when c went on screen
    void PutOnScreen(std::unique_ptr<RenderProcess> p, const ServerLoad& load, bool quick);
    void Retire(std::unique_ptr<RenderProcess> p);
    void EndRetired();   // Stop() the ones retired since the last call
    bool Send(Candidate& c, const ServerLoad& load, std::string* error);
    void StepBuildAhead();
    void StepStandby();
    std::unique_ptr<RenderProcess> TakeFor(const Candidate& c, const ServerLoad& load, std::string* error);
    bool standbyOn_ = false, standbyAsked_ = false, standbyReady_ = false;
    int standbyUsed_ = 0;
    std::unique_ptr<RenderProcess> standby_;
    ServerLoad standbyLoad_;

    FrameTransport transport_;
    bool pipelined_, tiered_;
    bool inTurn_ = false, deferred_ = false;   // deferred_: the optimized build waits for the quick tier
    std::vector<std::string> env_;
    ImportThread* importer_ = nullptr;
    std::unique_ptr<RenderProcess> onScreen_;
    ServerLoad onScreenLoad_, building_;
    Candidate next_, quick_{nullptr, true, false};
    // Spares are spawned on a thread of their own (posix_spawn blocks its caller 1-10 ms while the
    // child execs: not in a frame); TakeSpare spawns on the render thread only when none is ready.
    void SpawnLoop();
    std::mutex spareMutex_;
    std::condition_variable spareWake_;
    std::thread spawner_;
    bool stopSpawner_ = false;
    int spawnWanted_ = 0, spawning_ = 0;                    // spares asked of the spawner; being spawned
    int prepareW_ = 0, prepareH_ = 0;                       // the last load's size and transport: a spare's images are made for them
    FrameTransport prepareTransport_ = FrameTransport::Shm;
    std::vector<std::unique_ptr<RenderProcess>> spares_;    // guarded by spareMutex_
    std::vector<std::unique_ptr<RenderProcess>> retired_;   // ended, not yet reaped
    std::vector<std::unique_ptr<RenderProcess>> ending_;    // retired during this frame: ended at FrameDone
    bool retireAfterFrame_ = true;
    bool firstAfterImport_ = false;
    long polls_ = 0, lastSwapPolls_ = -1;
    double previousTime_ = 0.0;   // the time of the inputs before lastInputs_
    FrameInputs FirstFrameInputs() const;   // a new server's first frame: lastInputs_ one frame on
    std::unique_ptr<RenderProcess> lastFrame_;              // a dead server on screen: its texture until the replacement draws
    std::unique_ptr<RenderProcess> previous_;               // SetKeepPrevious: the one a build replaced
    ServerLoad previousLoad_;
    std::unique_ptr<RenderProcess> ahead_;   // BuildAhead's server
    std::vector<ServerLoad> aheadQueue_;
    ServerLoad aheadLoad_;
    bool aheadAsked_ = false;
    std::vector<BuiltAheadLoad> builtAhead_;
    struct HeldServer {
        Candidate c;
        ServerLoad load;
        RenderProcess::Ready ready;
        bool isReady = false;
        std::string error;
    };
    HeldServer held_[2];
    bool keepPrevious_ = false;
    bool onScreenQuick_ = false;
    bool fresh_ = false;   // the frame in onScreen_'s texture is collected and not yet shown
    FrameInputs lastInputs_;
    std::vector<float> wave_, spectrum_;   // SetAudio
    void SendAudio(RenderProcess& p) const;
    std::vector<RenderProcess::Ready> shown_;
    std::vector<bool> shownQuick_;
    std::string note_;
    int failedFrames_ = 0, replaced_ = 0;
    int lateFrames_ = 0;
    double longestLateMs_ = 0;
    bool lateNow_ = false;
    std::chrono::steady_clock::time_point retryAt_{};   // a server on screen that died: replaced no sooner
    int retryS_ = 1;
};

}  // namespace sdfvj
