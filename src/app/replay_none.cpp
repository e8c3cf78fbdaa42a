#include "app/replay_driver.h"

namespace sdfvj {

std::unique_ptr<ReplayDriver> MakeReplayDriver(const Show&, const std::string& take, const std::string&, std::string* error,
                                               const ShowOptions*) {
    *error = take.empty() ? "scripted presets need the full sdfvj build (this is the headless renderer without automation)"
                          : "--replay needs the full sdfvj build (this is the headless renderer without the input modules)";
    return nullptr;
}

}  // namespace sdfvj
