// `live --render-process` (live_servers.h): the scene drawn by render servers, shown here through
// the post chain or blitted to the window.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "app/live_app.h"
#include "render/live_program.h"

namespace sdfvj {

void LiveSession::StartServers() {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    servers_ = std::make_unique<LiveServers>(LiveProgram::TieredCompileDefault(), live_.LiteralTier());
    servers_->SetImporter(importer_);   // null: this thread imports each server's images
    servers_->SetHitch(&hitch_);
    // On a GPU a spare holds the program on screen ready (its binary load's first draw took 90-300 ms
    // on NVIDIA); on llvmpipe it would compile it again beside the frames.
    servers_->SetStandby(EnvSwitch("SDFVJ_STANDBY", !softwareGl_));
    std::string error;
    postInServers_ = EnvSwitch("SDFVJ_POST_IN_SERVER", !softwareGl_);   // on llvmpipe the show's own contexts measured better (docs/isf.md)
    std::vector<IsfFile> files;
    if (postInServers_ && !state_.show.post.empty() && LoadPostFiles(state_.show.post, &files, &error) && PostInServers(files)) {   // in the first build
        SetServersPost(files);
        if (!o_.audio.empty())   // --audio (opened after this): the chain's first draws with the sound's sizes, silent
            servers_->SetAudio(std::vector<float>(kAudioBins, 0.0f), std::vector<float>(kAudioBins, 0.0f));
    }
    error.clear();   // a broken post file: said by UpdatePost
    if (servers_->Start(state_.wanted, Scaled(w), Scaled(h), &error))
        return;
    // Nothing on screen: the scene's fault (then it does not build here either, and the show waits
    // for the save that fixes it, drawn by a server) or the render process's (no GL of its own, say):
    // then this process draws, as without --render-process.
    live_.Request(state_.wanted);
    live_.Wait();
    if (live_.Current()) {
        servers_.reset();
        postInServers_ = false;   // the chain in this process too
        state_.report.Say("sdfvj live: no render process (" + error + "): the scene is drawn in this process");
    } else {
        state_.report.Say(error);
    }
}

// A scene change morphs: the two fields in one program where the preset asks for it and both scenes
// allow it (drawn by a server held for it, live_morph.cpp), else as a crossfade from the frames of
// the scene before, whose server goes on drawing with its last values until the fade ends.
void LiveSession::FadeServersIfSceneChanged(double now) {
    if (!servers_->TakeSceneChange()) return;
    const MorphDesc& how = state_.show.preset.automation.morph;
    std::string error;
    if (how.seconds > 0 && how.easing != Easing::Cut && crossfade_.Init(&error)) {
        fade_ = Fade{nullptr, servers_->PreviousScene(), in_.params, now, how.seconds, how.easing};
        fade_.server = true;
        if (ServerFadeMorphsFields()) return;
        char seconds[32];
        std::snprintf(seconds, sizeof seconds, "%.2f", how.seconds);
        state_.report.Say("scene morph: " + fade_.scene.name + " -> " + servers_->Scene().name + ", a crossfade of their render processes' frames over " +
                          seconds + " s");
        return;
    }
    if (!error.empty()) state_.report.Say("sdfvj live: " + error + " — scene changes cut instead of fading");
    fade_ = Fade{};
    servers_->DropPrevious();
}

void LiveSession::DrawServerScene(double now, int rw, int rh) {
    if (DrawServerFieldFade(now)) return;
    int w = 0, h = 0;
    unsigned texture = 0;
    Guard("draw: render process's frame", [&] { texture = servers_->Frame(in_, &w, &h); });
    if (!texture) return;
    const double t = fade_.server ? (now - fade_.start) / fade_.seconds : 1.0;
    if (t < 1.0) {
        FrameInputs old = in_;
        old.params = fade_.params;
        unsigned before = 0;
        Guard("draw: the scene before's frame", [&] { before = servers_->PreviousFrame(old, true); });
        if (before) {
            std::string error;
            const bool post = ShowDrawsPost() && postInput_.Resize(rw, rh, &error);
            Guard("draw: crossfade", [&] {
                crossfade_.Draw(before, texture, Ease(fade_.easing, t), post ? postInput_.Framebuffer() : 0, post ? rw : fbw_, post ? rh : fbh_);
            });
            if (post) DrawPost(postInput_.Texture(), rw, rh, now);
            glBindFramebuffer(GL_FRAMEBUFFER, 0);
            servers_->AfterRead(in_);
            return;
        }
    }
    if (fade_.server) {   // done, or the server before failed: it may go
        fade_ = Fade{};
        servers_->DropPrevious();
    }
    Guard("draw: to the window", [&] { PresentServerTexture(texture, w, h, now, servers_->FrameReadFramebuffer()); });
    Guard("draw: next frame asked", [&] { servers_->AfterRead(in_); });
}

// A server's frame (w x h) to the window: through the post chain, or blitted (from readFbo, a
// framebuffer that already reads it, where the caller has one).
void LiveSession::PresentServerTexture(unsigned texture, int w, int h, double now, unsigned readFbo) {
    if (DrawPost(texture, w, h, now)) return;
    if (readFbo) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, readFbo);
    } else {
        if (!serverFbo_) glGenFramebuffers(1, &serverFbo_);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, serverFbo_);
        glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture, 0);
    }
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    glBlitFramebuffer(0, 0, w, h, 0, 0, fbw_, fbh_, GL_COLOR_BUFFER_BIT, w == fbw_ && h == fbh_ ? GL_NEAREST : GL_LINEAR);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

}  // namespace sdfvj
