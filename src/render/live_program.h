// LiveProgram: the program on screen, kept current while files change and effects switch.
//
//   LiveProgram live;
//   live.Request(key);                       // a variant: scene + effects + path
//   each frame: live.Update(watcher.Poll()); if (live.Current()) draw(*live.Current(), live.Scene());
//
// Compiles to the side and swaps only on success: a broken save keeps the last good program on
// screen and Error() says "shaders/scenes/midi.glsl:42: ..." until the file is fixed. A save
// that leaves the assembled source unchanged (same content hash) compiles nothing. A change to
// an #included file rebuilds every variant that includes it. Variants are cached by VariantKey.
// Render thread only (GL).
#pragma once
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "render/render.h"

namespace sdfvj {

class LiveProgram {
public:
    // Switches to a variant: from the cache at once, else compiled asynchronously while the
    // previous program keeps rendering. The scene header is re-read.
    void Request(const VariantKey& key);
    // Feeds changed file paths (absolute) and finishes a pending compile when it is ready.
    // Returns true when the program on screen changed this call.
    bool Update(const std::vector<std::string>& changedFiles);
    // Blocks until no compile is pending (offline renders, tests).
    void Wait();

    const Program* Current() const { return current_.get(); }
    // The program on screen, shared: a crossfade keeps the old scene's program alive while it
    // fades out, whatever the cache does meanwhile.
    std::shared_ptr<const Program> CurrentShared() const { return current_; }
    const SceneInfo& Scene() const { return scene_; }
    const VariantKey& Key() const { return key_; }
    const std::string& Error() const { return error_; }   // empty when the last build succeeded
    int CompilesStarted() const { return compiles_; }
    bool Pending() const { return pending_.Active(); }

private:
    // Programs are shared between the cache and the screen: evicting a cache entry (its files
    // changed) never frees the program still on screen while its replacement compiles.
    struct Cached {
        std::shared_ptr<const Program> program;
        SceneInfo scene;
    };
    void Rebuild();   // reassemble key_ and compile when the source hash differs
    void Finish();

    VariantKey key_;
    SceneInfo scene_;                       // header of the program on screen
    SceneInfo pendingScene_;
    VariantKey pendingKey_;
    std::shared_ptr<const Program> current_;
    std::map<VariantKey, Cached> cache_;
    PendingProgram pending_;
    uint64_t pendingHash_ = 0;
    std::string error_;
    int compiles_ = 0;
};

}  // namespace sdfvj
