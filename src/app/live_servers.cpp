#include "app/live_servers.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "isf/isf.h"
#include "render/field_morph.h"
#include "render/live_program.h"
#include "scene/scene.h"
#include "shader/shader.h"

namespace sdfvj {

namespace {

VariantKey KeyOf(const ServerLoad& load) { return VariantKey{load.scenePath, load.effects, load.path}; }

// A scene's or a post effect's source (an ISF .fs, or the .vs beside one) among the files saved.
bool ShaderSaved(const std::vector<std::string>& changed) {
    for (const std::string& f : changed)
        if (f.ends_with(".glsl") || IsIsfSource(f)) return true;
    return false;
}

}  // namespace

// The load a server gets for a variant at a size: its effects as the show wants them, the post chain.
ServerLoad LiveServers::LoadFor(const VariantKey& key, int w, int h) const {
    ServerLoad load{key.scenePath, false, key.effects, key.path, w, h};
    load.post = post_;
    return load;
}

// Frames come over on the GPU where both ends can (the server falls back, and says why), each one
// drawn while the show waits: a frame shown is the frame of its inputs, as in-process drawing.
LiveServers::LiveServers(bool tiered, bool literalTier) : show_(FrameTransport::VkMemory, false, tiered), literalTier_(literalTier) {
    show_.SetKeepPrevious(true);
}
LiveServers::~LiveServers() = default;

bool LiveServers::Check(const VariantKey& key, SceneInfo* scene, uint64_t* hash, std::string* error, ShaderSource* lifted,
                        uint64_t* sceneHash) const {
    ShaderSource src;
    if (!LoadScene(key.scenePath, scene, error) || !AssembleProgram(*scene, key, &src, error)) return false;
    *hash = src.hash;
    if (sceneHash) *sceneHash = src.hash;
    for (const std::string& f : post_) {   // a broken post file is said as file:line before any server is asked
        IsfFile file;
        if (!LoadIsfFile(f, &file, error)) return false;
        *hash = (*hash ^ IsfFilesHash(f)) * 0x100000001b3ULL;
    }
    if (lifted && !AssembleProgram(*scene, key, lifted, error, true)) *lifted = ShaderSource{};
    error->clear();
    return true;
}

// After an optimized program went on screen and nothing else builds: a spare builds its variant
// lifted and holds it (one at a time, each lifted source once).
void LiveServers::PrepareLiteralTier(std::vector<std::string>* say) {
    if (show_.HasPrepared()) {
        const bool ready = show_.PreparedReady();   // drops one that failed or died
        if (!show_.HasPrepared()) {
            say->push_back("sdfvj live: literal tier not built: " + show_.PreparedError().substr(0, 300));
        } else if (ready && !preparedSaid_) {
            preparedSaid_ = true;
            std::fprintf(stderr, "sdfvj live: %s: a save that changes only numbers in its functions shows at once (literal tier, held by a render process)\n",
                         DisplayPath(key_.scenePath).c_str());
        }
    }
    if (!wantPrepare_ || !OnScreen() || show_.OnScreenQuick() || show_.Building() || !error_.empty()) return;
    wantPrepare_ = false;
    ShaderSource lifted;
    std::string error;
    if (!AssembleProgram(scene_, key_, &lifted, &error, true) || lifted.literals.empty() ||
        (lifted.hash == preparedHash_ && show_.PreparedLoad().post == show_.OnScreenLoad().post))   // held already, with this chain
        return;
    ServerLoad load = show_.OnScreenLoad();
    load.lifted = true;
    preparedHash_ = lifted.hash;
    preparedSaid_ = false;
    if (!show_.Prepare(load, &error)) say->push_back("sdfvj live: literal tier not built: " + error);
}

bool LiveServers::Start(const VariantKey& key, int w, int h, std::string* error) {
    wanted_ = LoadFor(key, w, h);
    if (!Check(key, &buildingScene_, &buildingHash_, error, nullptr, &buildingSceneHash_)) {
        error_ = *error;
        return false;
    }
    lastLoad_ = wanted_;
    if (!show_.Start(lastLoad_, error)) {
        error_ = *error;
        return false;
    }
    key_ = key;
    scene_ = buildingScene_;
    hash_ = buildingHash_;
    sceneHash_ = buildingSceneHash_;
    wantPrepare_ = literalTier_;
    const RenderProcess::Ready& r = show_.Shown().back();
    std::fprintf(stderr, "sdfvj live: the scene is drawn by a render process (frames by %s%s%s; build %.0f ms, first use %.0f ms)\n",
                 FrameTransportName(show_.Transport()), show_.Note().empty() ? "" : (": " + show_.Note()).c_str(),
                 r.importThreadMs >= 0 ? ", its images imported by a thread of their own" : "", r.buildMs, r.useMs);
    return true;
}

// A newer load waits for the build in flight (nothing of it on screen yet) to finish, at most
// 1 s (SDFVJ_LOAD_WAIT_MS) after it was sent; then the newest variant asked for is sent. Each load takes a
// process (started, its GL and Vulkan set up, its program loaded and first used): a storm of
// effect pads and presets (the soak's 40 a second) started 7 a second on llvmpipe, each one
// superseding the last before it was done, so none reached the screen while they took more
// than a core of 2 from the frames. A quick tier on screen is not waited on: its optimized
// build is dropped for the next edit at once. SDFVJ_LOAD_WAIT_MS=0: each load at once, as before.
bool LiveServers::WaitForBuild(std::chrono::steady_clock::time_point now) const {
    static const int waitMs = EnvInt("SDFVJ_LOAD_WAIT_MS", 1000, 0, 10000);
    return show_.Building() && !(OnScreen() && show_.OnScreenLoad() == lastLoad_) && now - lastSentAt_ < std::chrono::milliseconds(waitMs);
}

void LiveServers::Update(const VariantKey& want, const std::vector<std::string>& changed, int w, int h, std::vector<std::string>* say) {
    std::string error;
    // Said once the late frame came (or its server went), at most once a second: the counts add up meanwhile.
    const auto now = std::chrono::steady_clock::now();
    if (show_.LateFrames() > 0 && !show_.StillLate() && now - lateSaidAt_ >= std::chrono::seconds(1)) {
        lateSaidAt_ = now;
        char line[200];
        std::snprintf(line, sizeof line, "render process late: its last image was shown again %d time%s, up to %.0f ms after a frame was asked for",
                      show_.LateFrames(), show_.LateFrames() == 1 ? "" : "s", show_.LongestLateMs());
        say->push_back(line);
        show_.ResetLate();
    }
    const bool wasQuick = show_.OnScreenQuick();
    FrameHitch::Scope timedPoll(hitch_, "render processes: poll");
    const bool polled = show_.Poll(&error);
    timedPoll.Done();
    if (polled) {   // a build went on screen (or a replacement of the same program)
        if (show_.OnScreenLoad() == lastLoad_) {
            sceneChanged_ = lastLoad_.scenePath != key_.scenePath;
            previousScene_ = scene_;
            key_ = KeyOf(lastLoad_);
            scene_ = buildingScene_;
            hash_ = buildingHash_;
            sceneHash_ = buildingSceneHash_;
        }
        if (!sceneChanged_ && !wasQuick) show_.DropPrevious();   // after a quick tier: the one it replaced is gone already
        const RenderProcess::Ready& r = show_.Shown().back();
        cacheServes_ = cacheServes_ || r.fromCache;
        if (!show_.OnScreenQuick() && show_.OnScreenLoad() == lastLoad_) optimizedShown_.insert({sceneHash_, lastLoad_.path});
        char line[260];
        std::snprintf(line, sizeof line, "shader reloaded%s (its render process: build %.0f ms%s, first use %.0f ms, first frame %.0f ms)%s",
                      show_.OnScreenQuick() ? ", quick tier" : "", r.buildMs,
                      r.fromStandby ? " (the program held ready by a standby)" : r.fromCache ? " from the program cache" : "", r.useMs,
                      r.firstFrameMs, show_.OnScreenQuick() ? "; the optimized program follows" : "");
        say->push_back(line);
        error_.clear();
        wantPrepare_ = literalTier_;
        standbySaid_ = false;
    } else if (!error.empty()) {
        error_ = error;
        say->push_back(error);
    }
    if (literalTier_) PrepareLiteralTier(say);
    if (show_.StandbyReady() && !standbySaid_) {   // once per program on screen
        standbySaid_ = true;
        std::fprintf(stderr, "sdfvj live: %s: a render process holds it ready (standby): a post effect's save or a new size builds only what changed\n",
                     DisplayPath(key_.scenePath).c_str());
    }
    SayBuiltAhead(say);
    const ServerLoad load = LoadFor(want, w, h);
    const bool nothingNew = load == wanted_ && !ShaderSaved(changed);
    if (nothingNew && (!loadDeferred_ || WaitForBuild(now))) return;
    wanted_ = load;
    loadDeferred_ = false;
    SceneInfo scene;
    uint64_t hash = 0, sceneHash = 0;
    ShaderSource lifted;
    FrameHitch::Scope timedCheck(hitch_, "render processes: check");
    const bool checked = Check(want, &scene, &hash, &error, literalTier_ ? &lifted : nullptr, &sceneHash);
    timedCheck.Done();
    if (!checked) {   // a broken header or include: said once, nothing built
        if (error != error_) say->push_back(error);
        error_ = error;
        return;
    }
    if (OnScreen() && hash == hash_ && load == show_.OnScreenLoad() && !show_.Building()) {
        if (!error_.empty()) say->push_back("shader reloaded (the saved source is the program on screen)");
        error_.clear();   // back to what is on screen
        return;
    }
    if (show_.Building() && hash == buildingHash_ && load == show_.BuildingLoad()) return;   // already building it
    // Only numbers changed: the held lifted program goes on screen with them now.
    ServerLoad liftedLoad = load;
    liftedLoad.lifted = true;
    if (literalTier_ && lifted.hash != 0 && lifted.hash == preparedHash_ && show_.HasPrepared() &&
        show_.PreparedLoad() == liftedLoad && show_.PromotePrepared(lifted.literals)) {
        preparedHash_ = 0;   // used: built again once the optimized program is on screen
        key_ = want;
        scene_ = scene;
        error_.clear();
        say->push_back("shader retuned: the new numbers are on screen (read from uniforms by a render process), its optimized program builds behind them");
    }
    if (WaitForBuild(now)) {   // checked (a broken file is said at once), sent once the build in flight is done
        loadDeferred_ = true;
        return;
    }
    buildingScene_ = std::move(scene);
    buildingHash_ = hash;
    buildingSceneHash_ = sceneHash;
    lastLoad_ = load;
    // Only the post chain changed (its save, or another chain) in the variant and size on screen: the
    // scene's program is the one on screen, so no quick tier of it.
    ServerLoad sameScene = load;
    sameScene.post = show_.OnScreenLoad().post;
    const bool postOnly = OnScreen() && sceneHash == sceneHash_ && sameScene == show_.OnScreenLoad();
    const bool cached = cacheServes_ && optimizedShown_.count({sceneHash, load.path}) > 0;
    lastSentAt_ = now;
    FrameHitch::Scope timedLoad(hitch_, "render processes: load sent");
    const bool sent = show_.Load(load, &error, !postOnly && !cached);
    timedLoad.Done();
    if (!sent) {
        error_ = "sdfvj live: " + error;
        say->push_back(error_);
    }
}

void LiveServers::PrepareMorph(const VariantKey& to, int w, int h) {
    ServerLoad load{to.scenePath, false, UnionEffects(key_.effects, to.effects), to.path, w, h};
    load.post = post_;
    load.morphFrom = key_.scenePath;
    std::string error;
    show_.Prepare(load, &error, ServerShow::Held::Morph);   // a failure is said by MorphState's caller
}

LiveServers::Morph LiveServers::MorphState() {
    if (show_.PreparedReady(ServerShow::Held::Morph)) return Morph::Ready;
    if (show_.HasPrepared(ServerShow::Held::Morph)) return Morph::Building;
    return show_.PreparedError(ServerShow::Held::Morph).empty() ? Morph::None : Morph::Failed;
}

bool LiveServers::MorphFor(const std::string& fromPath, const std::string& toPath) const {
    const ServerLoad& load = show_.PreparedLoad(ServerShow::Held::Morph);
    return load.morphFrom == fromPath && load.scenePath == toPath;
}

size_t LiveServers::BuildAhead(const std::vector<VariantKey>& keys) {
    std::vector<ServerLoad> loads;
    for (const VariantKey& key : keys) {
        const ServerLoad load = LoadFor(key, show_.OnScreenLoad().width, show_.OnScreenLoad().height);
        if (!(load == show_.OnScreenLoad()) && std::find(loads.begin(), loads.end(), load) == loads.end()) loads.push_back(load);
    }
    aheadSaid_ = show_.BuiltAheadLoads().size();
    show_.BuildAhead(loads);
    return loads.size();
}

void LiveServers::SayBuiltAhead(std::vector<std::string>* say) {
    const auto& built = show_.BuiltAheadLoads();
    if (aheadSaid_ == built.size() || show_.BuildAheadLeft() > 0) return;
    int ok = 0, cached = 0;
    double ms = 0;
    for (size_t i = aheadSaid_; i < built.size(); ++i) {
        const RenderProcess::BuiltAhead& b = built[i].built;
        ok += b.ok ? 1 : 0;
        cached += b.ok && b.fromCache ? 1 : 0;
        ms += b.buildMs;
        if (!b.ok)   // a variant that does not build says why when it is asked for: only a short line here
            say->push_back("sdfvj live: a variant built ahead did not build (" + b.text.substr(0, b.text.find('\n')) + ")");
    }
    char line[200];
    std::snprintf(line, sizeof line, "sdfvj live: %d variants an effect pad or a preset reaches are in the program cache (%d built ahead in %.1f s, %d there already)",
                  ok, ok - cached, ms / 1000.0, cached);
    say->push_back(line);
    aheadSaid_ = built.size();
}

// A server's frame later than three of its draws (at least 50 ms, at most 120 ms) is not waited
// for: the last image is shown again and the loop goes on (the overlay, the input, the post chain in
// this process), collecting it at a later frame; silent for a second, the server is replaced.
// SDFVJ_SERVER_LATE=0: wait for every frame up to the second, as before; SDFVJ_SERVER_LATE_MAX_MS:
// the 120 ms (1000: no cap, as before session 43; measured: docs/reliability.md).
int LiveServers::LateMs(double serverMs) {
    static const bool notWaited = EnvSwitch("SDFVJ_SERVER_LATE", true);
    static const int capMs = EnvInt("SDFVJ_SERVER_LATE_MAX_MS", 120, 50, kServerDeadMs);
    return notWaited ? (int)std::clamp(3.0 * serverMs, 50.0, (double)capMs) : kServerDeadMs;
}

unsigned LiveServers::Frame(const FrameInputs& in, int* w, int* h) {
    show_.Frame(in, LateMs(show_.LastServerMs()), kServerDeadMs);
    *w = show_.OnScreenLoad().width;
    *h = show_.OnScreenLoad().height;
    return show_.Texture();
}

}  // namespace sdfvj
