// `sdfvj bench reload --first-frame` (issue 12): a launch's first frame, from the context made to
// the first draw done, with the program cache and the drivers' disk caches as they are set.
// Render thread only.
#pragma once
#include <string>

#include "app/commands.h"
#include "scene/scene.h"

namespace sdfvj {

// Prints "sdfvj bench reload: what" to stderr and returns code (the bench's exit code).
int ReloadBenchFail(const std::string& what, int code = 2);

// How `bench reload`'s mode number `mode` builds a save (process: through a compile process), for its headings.
const char* ReloadModeHow(int mode, bool process);

// One launch's first frame of `scene` at w x h, printed; cacheLine says how the drivers' caches are set.
int ReloadFirstFrame(const ReloadBenchOptions& o, const SceneInfo& scene, int w, int h, const std::string& cacheLine);

}  // namespace sdfvj
