#include "render/server_show.h"

#include <epoxy/gl.h>
#include <poll.h>

#include <algorithm>
#include <cmath>

#include "render/render_wire.h"

namespace sdfvj {

ServerShow::~ServerShow() {
    // The show's context is current: textures and imported images are freed here.
    onScreen_.reset();
    lastFrame_.reset();
    previous_.reset();
    for (HeldServer& h : held_) h.c.process.reset();
    ahead_.reset();
    standby_.reset();
    next_.process.reset();
    quick_.process.reset();
    {
        std::lock_guard<std::mutex> lock(spareMutex_);
        stopSpawner_ = true;
    }
    spareWake_.notify_all();
    if (spawner_.joinable()) spawner_.join();
    spares_.clear();
    ending_.clear();
    retired_.clear();
}

std::unique_ptr<RenderProcess> ServerShow::Spawn(std::string* error) {
    auto p = std::make_unique<RenderProcess>();
    p->SetImporter(importer_);
    if (!p->Start(error, "/proc/self/exe", env_)) return nullptr;
    return p;
}

std::unique_ptr<RenderProcess> ServerShow::TakeSpare(std::string* error, bool spawn) {
    for (;;) {
        std::unique_ptr<RenderProcess> p;
        {
            std::lock_guard<std::mutex> lock(spareMutex_);
            if (spares_.empty()) break;
            p = std::move(spares_.back());
            spares_.pop_back();
        }
        if (p->Usable()) return p;
        Retire(std::move(p));   // a spare that died while it waited
    }
    return spawn ? Spawn(error) : nullptr;
}

// Spares open their contexts and warm their compilers now, off the next load's path; the spawner
// thread starts them.
void ServerShow::FillSpares() {
    {
        std::lock_guard<std::mutex> lock(spareMutex_);
        spawnWanted_ = std::max(0, (tiered_ ? 2 : 1) - (int)spares_.size() - spawning_);
        if (!spawner_.joinable()) spawner_ = std::thread([this] { SpawnLoop(); });
    }
    spareWake_.notify_all();
}

void ServerShow::SpawnLoop() {
    std::unique_lock<std::mutex> lock(spareMutex_);
    for (;;) {
        spareWake_.wait(lock, [this] { return stopSpawner_ || spawnWanted_ > 0; });
        if (stopSpawner_) return;
        --spawnWanted_;
        ++spawning_;
        lock.unlock();
        std::string ignored;
        auto p = Spawn(&ignored);
        lock.lock();
        // Its images for the show's size made while it waits (RenderProcess::PrepareImages); the
        // socket is this thread's alone until the spare is in spares_.
        if (p && prepareW_ > 0) p->PrepareImages(prepareW_, prepareH_, prepareTransport_);
        --spawning_;
        if (p) spares_.push_back(std::move(p));   // ended by the destructor when the show is over
    }
}

void ServerShow::Retire(std::unique_ptr<RenderProcess> p) {
    if (!p) return;
    if (retireAfterFrame_) {   // ended at FrameDone, after the frame that retired it
        ending_.push_back(std::move(p));
        return;
    }
    p->Stop();
    retired_.push_back(std::move(p));
}

void ServerShow::EndRetired() {
    for (std::unique_ptr<RenderProcess>& p : ending_) {
        p->Stop();
        retired_.push_back(std::move(p));
    }
    ending_.clear();
}

void ServerShow::FrameDone() {
    EndRetired();
    if (importer_) importer_->FrameDone();   // a new server's images imported in the gap too
}

bool ServerShow::Send(Candidate& c, const ServerLoad& load, std::string* error) {
    c.Clear();
    for (int attempt = 0; attempt < 2; ++attempt) {   // a spare may have died while it waited: then a new one
        c.process = attempt == 0 ? TakeFor(c, load, error) : Spawn(error);
        if (c.process) c.process->TakePrepared();   // a spare's images made ahead: imported while it builds
        if (c.process && !load.post.empty() && (!wave_.empty() || !spectrum_.empty())) c.process->SetAudio(wave_, spectrum_);   // its chain's first draws with it
        if (c.process && c.process->Load(load, transport_, c.quick)) return true;
        Retire(std::move(c.process));
    }
    if (error->empty()) *error = "the render process did not start";
    return false;
}

bool ServerShow::Start(const ServerLoad& load, std::string* error, int timeoutMs) {
    if (!Load(load, error)) return false;
    const auto t0 = render_wire::Clock::now();
    while (!onScreen_) {
        if (Poll(error)) break;
        if (!error->empty() && !Building()) return false;   // it did not build: *error says why
        if (render_wire::MsSince(t0) >= timeoutMs) {
            *error = "the render process did not answer in " + std::to_string(timeoutMs / 1000) + " s";
            return false;
        }
        ::poll(nullptr, 0, 2);
    }
    return true;
}

bool ServerShow::Load(const ServerLoad& load, std::string* error, bool quickTier) {
    error->clear();
    for (Candidate* c : {&next_, &quick_}) Drop(*c);   // superseded before they were shown
    building_ = load;
    deferred_ = false;
    {
        std::lock_guard<std::mutex> lock(spareMutex_);
        prepareW_ = load.width, prepareH_ = load.height;   // the size the next spares make their images for
        prepareTransport_ = transport_;
    }
    if (tiered_ && quickTier && inTurn_) {   // the quick tier alone first; the optimized build once it is on screen (Poll)
        if (!Send(quick_, load, error)) return false;
        deferred_ = true;
        FillSpares();
        return true;
    }
    if (!Send(next_, load, error)) return false;
    if (tiered_ && quickTier && !Send(quick_, load, error)) return false;
    FillSpares();
    return true;
}

bool ServerShow::Promote(Candidate& c, std::string* error) {
    if (!c.process) return false;
    if (!c.ready) {
        RenderProcess::Ready r;
        const bool taken = c.process->PollReady(&r, 0);
        if (c.answeredAt < 0 && (taken || c.process->Importing())) c.answeredAt = polls_;
        if (!taken) {
            // Answered, its images on the import thread: its first frame is drawn meanwhile, with the
            // inputs of now (as a pipelined frame is), and collected once they are imported.
            if (pipelined_ && !firstAfterImport_ && !c.asked && c.process->Importing())
                c.asked = c.process->RequestWhileImporting(FirstFrameInputs());
            return false;
        }
        if (!r.ok) {
            Drop(c);
            if (r.transport != FrameTransport::Shm && transport_ != FrameTransport::Shm) {
                // The server shared an image this context could not import: shared memory from now on.
                note_ = std::string(FrameTransportName(r.transport)) + " import refused here (" + r.text + "): shared memory instead";
                transport_ = FrameTransport::Shm;
                Send(c, building_, error);
                return false;
            }
            *error = r.text;
            return false;
        }
        if (!r.text.empty() && note_.empty()) note_ = r.text;
        transport_ = r.transport;
        c.ready = true;
        c.optimized = c.quick && r.optimized;
        shown_.push_back(r);
        shownQuick_.push_back(c.quick && !c.optimized);
        if (pipelined_ && !c.asked && !firstAfterImport_ && r.firstSeq != 0 && r.firstSeq == c.process->LastInputsSent() &&
            c.process->ShowFirstFrame()) {
            // Its first frame is in the image shown, drawn with the last frame's inputs (streamed while it
            // built), as a pipelined frame is: on screen in this frame, the one that read the answer.
            fresh_ = true;
        } else if (pipelined_ && !c.asked) {   // its first frame with the inputs of now, drawn while the one on screen goes on
            c.asked = c.process->Request(FirstFrameInputs());
            if (c.asked) return false;
        }
    }
    if (c.asked) {
        if (!c.process->Arrived() && c.process->Usable()) return false;
        c.asked = false;
        fresh_ = c.process->Collect(0);
    }
    lastSwapPolls_ = polls_ - c.answeredAt;
    const bool quick = c.quick && !c.optimized;
    c.Clear();
    PutOnScreen(std::move(c.process), building_, quick);
    return true;
}

void ServerShow::PutOnScreen(std::unique_ptr<RenderProcess> p, const ServerLoad& load, bool quick) {
    if (keepPrevious_ && onScreen_ && onScreen_->Usable() && !onScreenQuick_) {   // a quick tier is never kept
        Retire(std::move(previous_));
        previous_ = std::move(onScreen_);
        previousLoad_ = onScreenLoad_;
    }
    Retire(std::move(onScreen_));
    Retire(std::move(lastFrame_));
    retryS_ = 1;
    onScreen_ = std::move(p);
    onScreenLoad_ = load;
    onScreenQuick_ = quick;
    lateNow_ = false;
}

bool ServerShow::Prepare(const ServerLoad& load, std::string* error, Held slot) {
    error->clear();
    HeldServer& h = held_[(int)slot];
    Retire(std::move(h.c.process));
    h.load = load;
    h.isReady = false;
    h.error.clear();
    const bool ok = Send(h.c, load, error);
    FillSpares();
    return ok;
}

bool ServerShow::PreparedReady(Held slot) {
    HeldServer& h = held_[(int)slot];
    if (!h.c.process) return false;
    if (!h.isReady) {
        if (!h.c.process->PollReady(&h.ready, 0)) return false;
        h.isReady = h.ready.ok;
        if (!h.ready.ok) h.error = h.ready.text;
    }
    if (h.isReady && h.c.process->Usable()) return true;
    if (h.error.empty()) h.error = "its render process ended";
    Retire(std::move(h.c.process));
    h.isReady = false;
    return false;
}

bool ServerShow::PromotePrepared(const std::vector<float>& literals) {
    HeldServer& h = held_[(int)Held::Literal];
    if (!PreparedReady(Held::Literal) || !h.c.process->SetLiterals(literals)) return false;
    shown_.push_back(h.ready);
    shownQuick_.push_back(true);
    fresh_ = false;
    PutOnScreen(std::move(h.c.process), h.load, true);
    h.isReady = false;
    return true;
}

bool ServerShow::HeldFrame(Held slot, const FrameInputs& in, int timeoutMs, int deadMs) {
    return PreparedReady(slot) && SideFrame(*held_[(int)slot].c.process, in, timeoutMs, deadMs);
}

bool ServerShow::WaitFrame(RenderProcess& p, const FrameInputs& in, int timeoutMs, int deadMs) {
    if (!p.LastFrameStable()) timeoutMs = std::max(timeoutMs, deadMs);   // its one image is being written: not shown again
    if (timeoutMs <= 0) p.Arrived();   // not waited for at all: what has come is read
    return p.Outstanding() ? p.Collect(timeoutMs, deadMs) : p.DrawFrame(in, timeoutMs, deadMs);
}

bool ServerShow::SideFrame(RenderProcess& p, const FrameInputs& in, int timeoutMs, int deadMs) {
    return WaitFrame(p, in, timeoutMs, deadMs) || (p.Outstanding() && p.Texture() != 0);
}

void ServerShow::DropHeld(Held slot) {
    HeldServer& h = held_[(int)slot];
    Retire(std::move(h.c.process));
    h.isReady = false;
    h.error.clear();
}

void ServerShow::BuildAhead(std::vector<ServerLoad> loads) {
    aheadQueue_ = std::move(loads);
    std::reverse(aheadQueue_.begin(), aheadQueue_.end());   // taken from the back
}

void ServerShow::StepBuildAhead() {
    if (aheadAsked_) {
        RenderProcess::BuiltAhead built;
        if (!ahead_->PollBuiltAhead(&built, 0)) return;
        aheadAsked_ = false;
        builtAhead_.push_back({aheadLoad_, built});
        if (!ahead_->Usable()) Retire(std::move(ahead_));   // a build that killed it: the next one gets another
    }
    if (aheadQueue_.empty()) {
        Retire(std::move(ahead_));
        return;
    }
    if (Building()) return;   // a save's build first: the driver and the CPU are its
    if (!ahead_) {
        std::string error;
        ahead_ = TakeSpare(&error);
        FillSpares();
        if (!ahead_) {
            aheadQueue_.clear();
            return;
        }
    }
    aheadLoad_ = aheadQueue_.back();
    aheadQueue_.pop_back();
    aheadAsked_ = ahead_->BuildAhead(aheadLoad_);
    if (!aheadAsked_) Retire(std::move(ahead_));
}

namespace {
// The same program, whatever the size and the post chain.
bool SameProgram(const ServerLoad& a, const ServerLoad& b) {
    return a.scenePath == b.scenePath && a.sceneEffects == b.sceneEffects && (a.sceneEffects || a.effects == b.effects) && a.path == b.path &&
           a.lifted == b.lifted && a.morphFrom == b.morphFrom;
}
}  // namespace

std::unique_ptr<RenderProcess> ServerShow::TakeFor(const Candidate& c, const ServerLoad& load, std::string* error) {
    if (!c.quick && standbyReady_ && standby_ && standby_->Usable() && SameProgram(standbyLoad_, load)) {
        standbyReady_ = false;
        ++standbyUsed_;
        return std::move(standby_);
    }
    return TakeSpare(error);
}

void ServerShow::StepStandby() {
    if (!standbyOn_) return;
    if (standby_ && standbyAsked_) {
        RenderProcess::BuiltAhead built;
        if (!standby_->PollBuiltAhead(&built, 0)) return;
        standbyAsked_ = false;
        standbyReady_ = built.ok;
    }
    if (standby_ && (!standby_->Usable() || !standbyReady_)) {   // died, or its build failed
        standbyReady_ = false;
        Retire(std::move(standby_));
    }
    if (!onScreen_ || onScreenQuick_ || Building() || aheadAsked_) return;   // a save's build first
    if (standby_ && SameProgram(standbyLoad_, onScreenLoad_)) return;
    Retire(std::move(standby_));
    standbyReady_ = false;
    std::string ignored;
    standby_ = TakeSpare(&ignored, false);   // a spare the spawner made, or none yet: never a spawn in a frame
    FillSpares();
    if (!standby_) return;
    standbyLoad_ = onScreenLoad_;
    standbyAsked_ = standby_->BuildAhead(standbyLoad_);
    if (!standbyAsked_) Retire(std::move(standby_));
}

bool ServerShow::Poll(std::string* error) {
    error->clear();
    ++polls_;
    EndRetired();   // a show that does not call FrameDone: those the last frame retired end now
    for (size_t i = 0; i < retired_.size();)
        if (retired_[i]->TryReap()) retired_.erase(retired_.begin() + (long)i);
        else ++i;
    StepBuildAhead();
    StepStandby();
    const bool died = onScreen_ && !onScreen_->Usable();
    if ((died || (!onScreen_ && lastFrame_)) && !Building() && render_wire::Clock::now() >= retryAt_) {
        // Died or stopped answering (or its replacement did): its last frame stays on screen while
        // a spare builds its program; tried again after 1 s, 2 s, 4 s ... 32 s while it fails.
        if (died) {
            ++replaced_;
            *error = "the render server on screen ended; a new one builds the same program";
            Retire(std::move(lastFrame_));
            lastFrame_ = std::move(onScreen_);
        } else {
            *error = "the render server that was to replace the one on screen failed; another one builds it";
        }
        retryAt_ = render_wire::Clock::now() + std::chrono::seconds(retryS_);
        retryS_ = std::min(retryS_ * 2, 32);
        std::string why;
        if (!Load(onScreenLoad_, &why)) *error += " (" + why + ")";
        return false;
    }
    if (Promote(next_, error)) {
        Drop(quick_);   // the optimized program came first or follows: the quick one is done
        return true;
    }
    std::string quickError;
    const bool quick = Promote(quick_, &quickError);
    if (quick && !onScreenQuick_) {   // the quick load showed the optimized program (from the cache): nothing follows
        deferred_ = false;
        Drop(next_);
    }
    if (deferred_ && !quick_.process) {   // the quick tier is on screen (or failed): the optimized build now
        deferred_ = false;
        std::string why;
        if (!Send(next_, building_, &why) && error->empty()) *error = why;
        FillSpares();
    }
    if (error->empty() && !next_.process) *error = quickError;
    return quick;
}

unsigned ServerShow::Texture() const {
    if (onScreen_ && onScreen_->Texture()) return onScreen_->Texture();
    return lastFrame_ ? lastFrame_->Texture() : 0;
}

unsigned ServerShow::ReadFramebuffer() {
    if (onScreen_ && onScreen_->Texture()) return onScreen_->ReadFramebuffer();
    return lastFrame_ ? lastFrame_->ReadFramebuffer() : 0;
}

void ServerShow::SendAudio(RenderProcess& p) const {
    if (!onScreenLoad_.post.empty() && (!wave_.empty() || !spectrum_.empty())) p.SetAudio(wave_, spectrum_);
}

FrameInputs ServerShow::FirstFrameInputs() const {
    // A Poll comes before its frame's inputs: the last ones are a frame old, and pipelined the frame
    // asked for now is shown a frame later, in place of one the server on screen would have drawn
    // with this frame's inputs. Asked for with the last inputs, the new server's first frame showed
    // the time of the frame before again (a one-frame stall at every swap): one frame on, as far as
    // the last two frames went (not across a seek, a pause or a stall of more than 0.5 s).
    FrameInputs next = lastInputs_;
    const double dt = lastInputs_.time - previousTime_;
    if (dt > 0.0 && dt <= 0.5) {
        next.time += dt;
        next.frame += 1;
        const double beat = next.beat + dt * next.bpm / 60.0;
        next.beat = (float)(beat - std::floor(beat));
    }
    return next;
}

bool ServerShow::Frame(const FrameInputs& in, int timeoutMs, int deadMs) {
    previousTime_ = lastInputs_.time;
    lastInputs_ = in;
    if (pipelined_ && !firstAfterImport_)   // a build's first frame drawn with these if they are the last it has
        for (Candidate* c : {&next_, &quick_})
            if (c->process && !c->ready && !c->asked && c->answeredAt < 0) c->process->SendInputsOfNow(in);
    if (!onScreen_) return false;
    RenderProcess& p = *onScreen_;
    if (!fresh_ && !p.Outstanding()) SendAudio(p);
    // A server just put on screen: its first frame is here already (pipelined), or drawn now.
    const bool ok = fresh_ || WaitFrame(p, in, timeoutMs, deadMs);
    fresh_ = false;
    lateNow_ = !ok && p.Outstanding();
    if (lateNow_) {   // late, still asked for: the last frame is shown again
        ++lateFrames_;
        longestLateMs_ = std::max(longestLateMs_, p.OutstandingMs());
    } else if (!ok) {
        ++failedFrames_;   // the last frame stays on screen
    }
    return ok;
}

void ServerShow::AfterRead(const FrameInputs& in) {
    if (!pipelined_ || !onScreen_) return;
    // What read the frame is fenced; the request waits for the read of the image it will be drawn
    // into (with two images, the frame before's: done by now).
    onScreen_->Read();
    if (onScreen_->Outstanding()) return;   // a late frame is still coming: asked for once
    SendAudio(*onScreen_);
    if (!onScreen_->Request(in)) ++failedFrames_;
}

}  // namespace sdfvj
