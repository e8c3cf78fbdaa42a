// `live --post a,b` or a preset's "post": an ISF filter chain (src/isf) over the raymarched frame.
// Its inputs join the scene's parameters, so OSC (/sdfvj/param/NAME), mappings, presets and the
// overlay's sliders reach them; a saved .fs reloads, and a broken one keeps its last good program.
#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <filesystem>

#include "app/live_app.h"

namespace fs = std::filesystem;

namespace sdfvj {

// Loads the chain the show asks for (state_.show.post); a chain that fails to load keeps the one
// on screen and says why.
void LiveSession::UpdatePost() {
    if (state_.show.post == postShown_) return;
    postShown_ = state_.show.post;
    if (postShown_.empty()) {
        post_ = std::make_unique<IsfChain>();
        postDecls_.clear();
        return;
    }
    auto chain = std::make_unique<IsfChain>();
    std::string error;
    const std::vector<std::string> files = SplitIsfList(postShown_);
    if (!chain->Load(files, &error)) {
        state_.report.Say(error + " — keeping the post chain on screen");
        return;
    }
    for (const std::string& line : chain->Notices()) state_.report.Say(line);
    post_ = std::move(chain);
    postDecls_ = post_->Params();
    for (const std::string& f : files) Watch(fs::path(ResolveIsfPath(f)).parent_path().string());
    state_.report.Say("post: " + postShown_);
}

// The header the show's parameters follow: the scene's inputs, then the post chain's.
SceneInfo LiveSession::SceneWithPost() const {
    SceneInfo s = SceneOnScreen();
    for (const ParamDecl& d : postDecls_)
        if (std::none_of(s.params.begin(), s.params.end(), [&](const ParamDecl& x) { return x.name == d.name; }))
            s.params.push_back(d);
    return s;
}

// A saved .fs or .vs of the chain: rebuilt; a broken save is reported with its file:line.
void LiveSession::ReloadPost(const std::vector<std::string>& changed) {
    if (!post_ || post_->Empty() || changed.empty()) return;
    std::vector<std::string> errors;
    if (post_->ReloadIfChanged(&errors)) {
        postDecls_ = post_->Params();
        state_.report.Say("post reloaded");
    }
    for (const std::string& e : errors) state_.report.Say(e + " — the last good post effect stays");
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
    if (!post_ || post_->Empty()) return false;
    std::string error;
    if (!crossfade_.Init(&error)) return false;
    IsfFrameInputs in;
    in.time = now;
    in.timeDelta = std::max(0.0, now - postLast_);
    postLast_ = now;
    in.frame = in_.frame;
    const std::time_t clock = std::time(nullptr);
    std::tm local{};
    localtime_r(&clock, &local);
    in.date = {(float)(local.tm_year + 1900), (float)(local.tm_mon + 1), (float)local.tm_mday,
               (float)(local.tm_hour * 3600 + local.tm_min * 60 + local.tm_sec)};
    in.params = in_.params;
    in.beat = in_.beat;   // the tempo the scene draws with (tap, clock, preset, audio, a leader)
    in.bpm = in_.bpm;
    if (audio_) {   // ISF audio / audioFFT inputs
        in.audioWaveform = audio_->Textures().waveform;
        in.audioSpectrum = audio_->Textures().spectrum;
    }
    const unsigned out = post_->Render(texture, w, h, in);
    crossfade_.Draw(out, out, 0.0f, 0, fbw_, fbh_);   // the chain's output, scaled to the window
    return true;
}

}  // namespace sdfvj
