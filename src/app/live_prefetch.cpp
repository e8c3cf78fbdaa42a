// live_prefetch.cpp - the variants an effect pad or a preset can ask for next, built ahead of the
// performer (LiveProgram::Prefetch): once the show has asked for nothing new for a few seconds,
// the one-effect toggles of the variant on screen and every preset's variant are queued, at most
// the cache's room; the first pad hit or preset switch to one of them then shows it at once.
// With --render-process they are built into the program cache by a render server of their own
// (LiveServers::BuildAhead): a hit is then a cache load in its spare.
// On by default where the GPU compiles beside the frame (not on llvmpipe, whose compiles share the
// CPU with the frame); SDFVJ_PREFETCH=1 or 0 forces it.
#include <filesystem>

#include "app/live_app.h"

namespace fs = std::filesystem;

namespace sdfvj {

void LiveSession::PrefetchReachable(double now) {
    static const bool wanted = o_.warmAhead || EnvSwitch("SDFVJ_PREFETCH", !softwareGl_);
    if (!wanted || state_.show.isfScene) return;
    if (!(state_.wanted == prefetchFor_)) {   // something new was asked for: wait until it settles
        prefetchFor_ = state_.wanted;
        prefetchQuietSince_ = now;
        prefetchQueued_ = false;
        return;
    }
    const bool busy = servers_ ? servers_->Building() || !servers_->OnScreen() : live_.Pending() || !live_.Current();
    if (prefetchQueued_ || now - prefetchQuietSince_ < 3.0 || busy) return;
    prefetchQueued_ = true;
    std::vector<VariantKey> keys;
    for (const EffectSet& e : OneEffectToggles(state_.wanted.effects)) keys.push_back({state_.wanted.scenePath, e, state_.wanted.path});
    for (const std::string& name : ListPresets()) {   // a preset that does not load is skipped: asked for, it says why
        ShowOptions so = state_.options;
        so.scene.clear();
        so.params.clear();
        so.preset = (fs::path(DataRoot()) / "presets" / name).string();
        Show next;
        std::string error;
        if (PrepareShow(so, &next, &error) && !next.isfScene) keys.push_back({next.scene.path, next.effects, state_.wanted.path});
    }
    if (servers_) {
        std::fprintf(stderr, "sdfvj live: %zu variants an effect pad or a preset reaches build ahead, into the program cache, in a render process of their own\n",
                     servers_->BuildAhead(keys));
        return;
    }
    live_.Prefetch(keys);
    std::fprintf(stderr, "sdfvj live: %zu variants an effect pad or a preset reaches compile in the background%s\n",
                 live_.PrefetchQueued(),
                 o_.warmAhead && !softwareGl_ ? "; --warm-ahead: the picture stops as each is drawn once (on NVIDIA up to "
                                                "1.5 s a variant), then a hit shows it in one frame"
                                              : "");
}

}  // namespace sdfvj
