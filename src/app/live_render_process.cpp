// `live --render-process` (live_servers.h): the scene drawn by render servers, shown here through
// the post chain or blitted to the window.
#include <algorithm>
#include <cmath>

#include "app/live_app.h"

namespace sdfvj {

void LiveSession::StartServers() {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window_, &w, &h);
    servers_ = std::make_unique<LiveServers>();
    std::string error;
    if (servers_->Start(state_.wanted, std::max(1, (int)std::lround(w * renderScale_)), std::max(1, (int)std::lround(h * renderScale_)), &error))
        return;
    // Nothing on screen: the scene's fault (then it does not build here either, and the show waits
    // for the save that fixes it, drawn by a server) or the render process's (no GL of its own, say):
    // then this process draws, as without --render-process.
    live_.Request(state_.wanted);
    live_.Wait();
    if (live_.Current()) {
        servers_.reset();
        state_.report.Say("sdfvj live: no render process (" + error + "): the scene is drawn in this process");
    } else {
        state_.report.Say(error);
    }
}

void LiveSession::DrawServerScene(double now) {
    int w = 0, h = 0;
    const unsigned texture = servers_->Frame(in_, &w, &h);
    if (!texture) return;
    if (!DrawPost(texture, w, h, now)) {
        if (!serverFbo_) glGenFramebuffers(1, &serverFbo_);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, serverFbo_);
        glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture, 0);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
        glBlitFramebuffer(0, 0, w, h, 0, 0, fbw_, fbh_, GL_COLOR_BUFFER_BIT, w == fbw_ && h == fbh_ ? GL_NEAREST : GL_LINEAR);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
    }
    servers_->AfterRead(in_);
}

}  // namespace sdfvj
