// The post chain a render server draws its frames through (render/render_process.h ServerPost,
// ServerLoad::post): an IsfChain built, drawn and first used in the server's process, so that on
// NVIDIA the show's process never links or first draws a post effect's program.
#pragma once
#include <memory>

#include "render/render_process.h"

namespace sdfvj {

// For RunRenderServer: sdfvj's main and the tests that are their own render servers pass it.
std::unique_ptr<ServerPost> MakeIsfServerPost();

}  // namespace sdfvj
