// LiveServers: `live --render-process` (issue 12). The scene is drawn by render servers
// (render/server_show.h), so a save, an effect pad or a new render size builds its program in a
// spare process while the one on screen goes on drawing; the show's own process never compiles or
// first uses a scene program, which is what stalled its frames on NVIDIA for 150-300 ms a save.
//
// The show still reads each scene itself (header and includes, no GL): its parameters, what the
// next program's source is, and a broken header or include said as file:line before any server is
// asked; a program that does not compile comes back from its server with the driver's log, mapped
// to file:line. Either way the program on screen stays.
// The variants an effect pad or a preset reaches are built ahead into the program cache by a server
// of their own (BuildAhead), so that a hit is a cache load in its spare.
// "measure costs" asks the server on screen to time its program's draws (TimeDraw).
// A preset's scene change with a field morph draws both fields in one program, built and drawn by a
// server held for it (PrepareMorph), as in-process.
// Render thread only.
#pragma once
#include <chrono>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "app/frame_hitch.h"
#include "render/server_show.h"

namespace sdfvj {

class LiveServers {
public:
    // tiered: every build also builds the quick tier in a second spare (LiveProgram::TieredCompileDefault:
    // NVIDIA), on screen until the optimized program is.
    // literalTier: once the optimized program is on screen, a spare builds the same variant with the
    // scene's float literals as uniforms and holds it; a save that changes only those numbers puts it
    // on screen with them at once, while the save's optimized program builds (LiveProgram's literal
    // tier, across processes).
    LiveServers(bool tiered, bool literalTier);
    ~LiveServers();
    // The first program at w x h, waited for. False: *error says why (a scene that does not build:
    // the show goes on and the next save that builds goes on screen).
    bool Start(const VariantKey& key, int w, int h, std::string* error);
    // The thread that imports each server's frame images (ServerShow::SetImporter). Before Start.
    void SetImporter(ImportThread* importer) { show_.SetImporter(importer); }
    // Update's parts (poll, check, load sent) timed as stages of the show's --hitch-ms.
    void SetHitch(FrameHitch* hitch) { hitch_ = hitch; }
    // Each frame: the variant the show wants, the files saved since the last frame and the render
    // size. Lines for the show's report go to *say (a build that failed, a server replaced, a
    // program on screen).
    void Update(const VariantKey& want, const std::vector<std::string>& changed, int w, int h, std::vector<std::string>* say);
    // The post chain the servers draw each frame through (ServerLoad::post: resolved ISF paths; empty:
    // none), from the next Update on: a change, or a save of one of its files, builds in a spare
    // server as a scene save does, and one that does not build leaves the chain on screen.
    void SetPost(std::vector<std::string> paths) { post_ = std::move(paths); }
    const std::vector<std::string>& Post() const { return post_; }
    bool PostOnScreen() const { return !show_.OnScreenLoad().post.empty(); }
    void SetAudio(std::vector<float> wave, std::vector<float> spectrum) { show_.SetAudio(std::move(wave), std::move(spectrum)); }
    // A spare holding the program on screen ready (ServerShow::SetStandby): a post effect's save or a
    // new render size then builds only the chain. Before Start.
    void SetStandby(bool on) { show_.SetStandby(on); }
    // This frame's image: the texture, and its size (the size it was built for, until a build at the
    // new size is on screen). 0 when there is none yet.
    // How long a server on screen may stay silent before it is replaced (a late frame is not waited for: Frame).
    static constexpr int kServerDeadMs = 1000;
    // How long a frame of a server that draws in serverMs is waited for (Frame).
    static int LateMs(double serverMs);
    unsigned Frame(const FrameInputs& in, int* w, int* h);
    unsigned FrameReadFramebuffer() { return show_.ReadFramebuffer(); }   // one reading Frame()'s texture, kept per image
    void AfterRead(const FrameInputs& in) { show_.AfterRead(in); }
    void FrameDone() { show_.FrameDone(); }   // after the swap: the servers this frame retired end now
    // A build of another scene went on screen (its quick tier, or the optimized program): true once,
    // and the server of the scene before is kept (for a crossfade from its frames) until
    // DropPrevious. A build of the same scene ends the one it replaced at once.
    bool TakeSceneChange() { return std::exchange(sceneChanged_, false); }
    const SceneInfo& PreviousScene() const { return previousScene_; }
    // The scene before's frame, waited for as the one on screen's (Frame): not when late. Under a
    // crossfade (`behind`) not at all: its image fades out a frame behind its inputs, and the frame's
    // wait is the new scene's alone.
    unsigned PreviousFrame(const FrameInputs& in, bool behind = false) {
        return show_.PreviousFrame(in, behind ? 0 : LateMs(show_.PreviousServerMs()), kServerDeadMs) ? show_.PreviousTexture() : 0;
    }
    void DropPrevious() { show_.DropPrevious(); }

    // A field morph (render/field_morph.h) from the scene on screen to `to`'s: a spare builds the two
    // fields' program (every effect of either variant) at w x h and holds it; MorphFrame draws it
    // with MorphParamValues. One at a time: a new one replaces it.
    enum class Morph { None, Building, Ready, Failed };
    void PrepareMorph(const VariantKey& to, int w, int h);
    Morph MorphState();   // never blocks
    bool MorphFor(const std::string& fromPath, const std::string& toPath) const;
    const std::string& MorphError() const { return show_.PreparedError(ServerShow::Held::Morph); }
    unsigned MorphFrame(const FrameInputs& in) {
        const ServerShow::Held morph = ServerShow::Held::Morph;
        return show_.HeldFrame(morph, in, LateMs(show_.HeldServerMs(morph)), kServerDeadMs) ? show_.HeldTexture(morph) : 0;
    }
    void DropMorph() { show_.DropHeld(ServerShow::Held::Morph); }
    // Builds these variants ahead (ServerShow::BuildAhead) at the size on screen; the one on screen
    // is left out. Returns how many are queued. When all are done, Update says so once.
    size_t BuildAhead(const std::vector<VariantKey>& keys);
    bool Building() const { return show_.Building(); }
    // The program on screen drawn once more offscreen by its server and timed there ("measure costs").
    double TimeDraw(const FrameInputs& in) { return show_.TimeDraw(in); }
    bool OnScreen() const { return show_.OnScreen(); }
    const SceneInfo& Scene() const { return scene_; }    // the scene on screen
    const VariantKey& Key() const { return key_; }       // its variant
    const std::string& Error() const { return error_; }  // why the last save is not on screen; "" when it is
    const ServerShow& Servers() const { return show_; }

private:
    std::chrono::steady_clock::time_point lateSaidAt_{};   // the last "render process late" line
    // Reads the scene and assembles the program's source (no GL): *hash, or *error as file:line;
    // with `lifted`, its literal tier's source too.
    // The post chain's files are parsed too (no GL) and hashed with it.
    // *sceneHash: the scene's program alone (without the chain).
    bool Check(const VariantKey& key, SceneInfo* scene, uint64_t* hash, std::string* error, ShaderSource* lifted = nullptr,
               uint64_t* sceneHash = nullptr) const;
    ServerLoad LoadFor(const VariantKey& key, int w, int h) const;
    void PrepareLiteralTier(std::vector<std::string>* say);
    void SayBuiltAhead(std::vector<std::string>* say);   // once, when a BuildAhead list is done   // the held lifted program, when it is time
    bool literalTier_ = false, wantPrepare_ = false, preparedSaid_ = false, standbySaid_ = false;
    uint64_t preparedHash_ = 0;   // the lifted source the held program was built from
    ServerShow show_;
    VariantKey key_;
    std::vector<std::string> post_;
    ServerLoad wanted_;     // what the show asked for last (variant and size), built or not
    ServerLoad lastLoad_;   // the last program sent to a server: its scene and hash are building*_
    SceneInfo scene_, buildingScene_, previousScene_;
    bool sceneChanged_ = false;
    size_t aheadSaid_ = 0;   // BuiltAheadLoads() already reported
    uint64_t hash_ = 0, buildingHash_ = 0;
    uint64_t sceneHash_ = 0, buildingSceneHash_ = 0;   // the scene's program alone, on screen and building
    // Scene programs (hash, path) whose optimized build was on screen: once a load has come from the
    // program cache (it works here), a load of one of them sends no quick tier, which would be one
    // more process for a program that loads from the cache at once (a preset storm: half the spawns).
    std::set<std::pair<uint64_t, RenderPath>> optimizedShown_;
    bool cacheServes_ = false;
    bool loadDeferred_ = false;   // a newer load waits for the build in flight (WaitForBuild)
    bool WaitForBuild(std::chrono::steady_clock::time_point now) const;
    FrameHitch* hitch_ = nullptr;   // Update's parts timed as stages (SetHitch)
    std::chrono::steady_clock::time_point lastSentAt_{};
    std::string error_;
};

}  // namespace sdfvj
