// `live --post a,b` or a preset's "post": an ISF filter chain (src/isf) over the raymarched frame.
// Its inputs join the scene's parameters, so OSC (/sdfvj/param/NAME), mappings, presets and the
// overlay's sliders reach them; a saved .fs reloads, and a broken one keeps its last good program.
#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "app/live_app.h"

namespace fs = std::filesystem;

namespace sdfvj {

// The chain the show asks for (state_.show.post) is requested from the host, which builds it
// where no frame waits; until it is built the chain on screen keeps drawing. A chain whose files
// do not parse, or whose build fails, keeps the one on screen and says why.
void LiveSession::UpdatePost() {
    if (post_) {
        IsfHost::Done done;
        if (post_->Poll(&done)) {
            const char* keep = done.adopted ? "" : " — keeping the post chain on screen";
            for (const std::string& e : done.errors) state_.report.Say(e + keep);
            if (postHere_) postDecls_ = post_->Chain().Params();   // else the servers' chain's: the one here was let go
            if (done.adopted) {
                for (const std::string& line : post_->Chain().Notices()) state_.report.Say(line);
                if (!postSay_.empty()) {
                    char ms[64];
                    std::snprintf(ms, sizeof ms, " (built in %.0f ms)", done.buildMs);
                    state_.report.Say(postSay_ + ms);
                }
                postSay_.clear();
            }
        }
    }
    if (postInServers_ && servers_) {
        if (audio_) servers_->SetAudio(audio_->Textures().waveform, audio_->Textures().spectrum);
        const bool serversShowIt = servers_->Servers().OnScreenLoad().post == servers_->Post();
        if (!postHere_ && !postSay_.empty() && serversShowIt && !servers_->Post().empty()) {
            state_.report.Say(postSay_ + ", drawn by the render process");
            postSay_.clear();
        }
        // A chain with feedback built here goes on screen with the first server frame without one; the servers' chain is on screen until then. The other way, this process's
        // chain draws until a server with the servers' chain is on screen, then goes.
        if (postHere_ && HasPost() && !post_->Busy() && !servers_->Post().empty()) servers_->SetPost({});
        if (!postHere_ && serversShowIt && post_ && !post_->Wanted().empty()) post_->Request({}, Scaled(fbw_), Scaled(fbh_));
    }
    if (state_.show.post == postShown_) return;
    postShown_ = state_.show.post;
    std::vector<IsfFile> files;
    std::string error;
    if (!LoadPostFiles(postShown_, &files, &error)) {
        state_.report.Say(error + " — keeping the post chain on screen");
        return;
    }
    for (const IsfFile& f : files) Watch(fs::path(f.path).parent_path().string());
    postHere_ = !PostInServers(files);
    if (!postHere_) {   // the servers build it: a spare with the chain goes on screen when it is ready
        SetServersPost(files);
        SetPostDecls(files);
        postSay_ = postShown_.empty() ? "" : "post: " + postShown_;
        return;
    }
    if (!post_) {
        std::array<IsfHostContext, 2> own;
        // SDFVJ_POST_CONTEXTS=0: in the window's context, as before session 31 (scripts/live_gaps.sh --post compares).
        const char* env = std::getenv("SDFVJ_POST_CONTEXTS");
        if (postContexts_ && !files.empty() && !(env && std::string(env) == "0")) own = postContexts_();
        post_ = own[0].makeCurrent ? std::make_unique<IsfHost>(own) : std::make_unique<IsfHost>();
        post_->SetKeptSizes(keepSizes_);
        // The scene's frame (FrameRenderer: RGBA8; an ISF generator has none) and the audio
        // input's textures, from the first build on.
        post_->SetFrameHint(state_.show.isfScene ? 0 : GL_RGBA8, audio_ ? (int)audio_->Textures().waveform.size() : 0,
                            audio_ ? (int)audio_->Textures().spectrum.size() : 0);
        if (!files.empty() && !post_->OwnContexts())
            state_.report.Say("sdfvj live: no context of its own for the post chain; its builds hold a frame");
    }
    SetPostDecls(files);   // the new chain's inputs join the show's parameters now (a preset's values for them apply)
    postSay_ = postShown_.empty() ? "" : "post: " + postShown_;
    if (postInServers_ && servers_ && !files.empty())
        state_.report.Say("post: " + postShown_ + " has feedback (a PERSISTENT target): drawn in this process, where it outlives the render processes' swaps");
    // Before the first frame fbw_ is not known yet: the window's size, as that frame will have it.
    int ww = fbw_, wh = fbh_;
    if (ww <= 0 || wh <= 0) glfwGetFramebufferSize(window_, &ww, &wh);
    post_->Request(std::move(files), Scaled(ww), Scaled(wh));
}

// --render-process: a chain without feedback is drawn by the servers. One with a PERSISTENT target
// stays in this process, where its feedback outlives a scene's save: each server builds its chain
// afresh, so the trails would start again from black whenever another server goes on screen.
bool LiveSession::PostInServers(const std::vector<IsfFile>& files) const {
    return postInServers_ && servers_ && std::none_of(files.begin(), files.end(), IsfHasFeedback);
}

bool LiveSession::LoadPostFiles(const std::string& list, std::vector<IsfFile>* files, std::string* error) const {
    files->clear();
    for (const std::string& f : list.empty() ? std::vector<std::string>{} : SplitIsfList(list)) {
        IsfFile file;
        if (!LoadIsfFile(ResolveIsfPath(f), &file, error)) return false;
        files->push_back(std::move(file));
    }
    return true;
}

void LiveSession::SetServersPost(const std::vector<IsfFile>& files) {
    std::vector<std::string> paths;
    for (const IsfFile& f : files) paths.push_back(f.path);
    servers_->SetPost(std::move(paths));
}

void LiveSession::SetPostDecls(const std::vector<IsfFile>& files) {
    postDecls_.clear();
    for (const IsfFile& f : files)
        for (const ParamDecl& d : IsfParams(f))
            if (std::none_of(postDecls_.begin(), postDecls_.end(), [&](const ParamDecl& x) { return x.name == d.name; }))
                postDecls_.push_back(d);
}

// The header the show's parameters follow: the scene's inputs, then the post chain's.
SceneInfo LiveSession::SceneWithPost() const {
    SceneInfo s = SceneOnScreen();
    for (const ParamDecl& d : postDecls_)
        if (std::none_of(s.params.begin(), s.params.end(), [&](const ParamDecl& x) { return x.name == d.name; }))
            s.params.push_back(d);
    return s;
}

// A saved .fs or .vs of the chain: rebuilt where no frame waits; a broken save is reported with
// its file:line and the last good file of that stage stays.
void LiveSession::ReloadPost(const std::vector<std::string>& changed) {
    if (postInServers_ && servers_ && std::any_of(changed.begin(), changed.end(), IsIsfSource)) {
        std::vector<IsfFile> files;
        std::string error;   // said by the servers' check or this process's reload, with the chain on screen kept
        if (LoadPostFiles(postShown_, &files, &error)) {
            if (!postHere_) SetPostDecls(files);   // a header's new inputs; the servers rebuild (LiveServers::Update)
            if (!files.empty() && PostInServers(files) == postHere_) {   // feedback came or went
                postShown_.clear();   // UpdatePost moves the chain
                return;
            }
        }
    }
    if (!postHere_) return;
    if (!post_ || post_->Wanted().empty() || changed.empty()) return;
    std::vector<std::string> errors;
    if (post_->Reload(&errors)) postSay_ = "post reloaded";
    for (const std::string& e : errors) state_.report.Say(e + " — the last good post effect stays");
    if (errors.empty() && !post_->Busy()) postDecls_ = post_->Chain().Params();   // a header-only change
}

// --frame-budget: once the scene (and the post chain asked for) is on screen, one frame draws the
// scene and the chain at each size the budget's moves reach (BudgetScalesAhead, as many as are kept),
// so that a move later takes kept targets instead of allocating them in a frame already late; again
// when the window has held a new size for a second (a drag makes many). The kept targets are cleared
// when taken again, but for a PERSISTENT target's, which take its content at the size left, scaled.
void LiveSession::DrawScalesAhead(double now) {
    if (!scalesAheadOn_ || (fbw_ == aheadW_ && fbh_ == aheadH_)) return;
    if (aheadW_ > 0) {   // the window changed size since: wait until the new size holds
        if (fbw_ != pendingW_ || fbh_ != pendingH_) {
            pendingW_ = fbw_, pendingH_ = fbh_, pendingSince_ = now;
            return;
        }
        if (now - pendingSince_ < 1.0) return;
    }
    if (!postShown_.empty() && (!post_ || post_->Busy() || post_->Chain().Empty())) return;   // the chain first
    std::string error, list;
    const auto t0 = std::chrono::steady_clock::now();
    for (const float s : BudgetScalesAhead(budget_, renderScale_, keepSizes_)) {
        const int w = std::max(1, (int)std::lround(fbw_ * s)), h = std::max(1, (int)std::lround(fbh_ * s));
        if (!renderer_.Resize(w, h, &error)) continue;
        renderer_.Draw(*live_.Current(), live_.Scene(), in_);
        if (HasPost()) {
            IsfFrameInputs in;
            in.params = in_.params;
            for (int i = 0; i < 2; ++i) post_->Render(renderer_.Texture(), w, h, in);   // each target's two textures
        }
        char one[32];
        std::snprintf(one, sizeof one, "%s%.2f", list.empty() ? "" : ", ", s);
        list += one;
    }
    aheadW_ = fbw_, aheadH_ = fbh_;
    if (list.empty()) return;
    char ms[64];
    std::snprintf(ms, sizeof ms, " at %dx%d (%.0f ms)", fbw_, fbh_,
                  std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    state_.report.Say("frame budget: the targets of render scales " + list + " drawn ahead" + ms);
}

// renderer_'s rw x rh frame to the window: through the post chain when there is one, else a blit
// (scaled when the render scale is not 1).
void LiveSession::PresentRenderer(int rw, int rh, double now) {
    if (DrawPost(renderer_.Texture(), rw, rh, now)) return;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, renderer_.Framebuffer());
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    glBlitFramebuffer(0, 0, rw, rh, 0, 0, fbw_, fbh_, GL_COLOR_BUFFER_BIT, rw == fbw_ && rh == fbh_ ? GL_NEAREST : GL_LINEAR);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

// Runs the chain over `texture` (w x h) and draws its output to the window; false without one.
bool LiveSession::DrawPost(unsigned texture, int w, int h, double now) {
    if (!ShowDrawsPost()) return false;
    std::string error;
    if (!crossfade_.Init(&error)) return false;
    IsfFrameInputs in;
    in.time = now;
    in.timeDelta = std::max(0.0, now - postLast_);
    postLast_ = now;
    in.frame = in_.frame;
    in.date = IsfDateNow();
    in.params = in_.params;
    in.beat = in_.beat;   // the tempo the scene draws with (tap, clock, preset, audio, a leader)
    in.bpm = in_.bpm;
    if (audio_) {   // ISF audio / audioFFT inputs
        in.audioWaveform = audio_->Textures().waveform;
        in.audioSpectrum = audio_->Textures().spectrum;
    }
    FrameHitch::Scope timed(&hitch_, "draw: post chain");
    const unsigned out = post_->Render(texture, w, h, in);
    timed.Done();
    crossfade_.Draw(out, out, 0.0f, 0, fbw_, fbh_);   // the chain's output, scaled to the window
    return true;
}

}  // namespace sdfvj
