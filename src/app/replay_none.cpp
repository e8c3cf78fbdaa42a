#include "app/replay_driver.h"

namespace sdfvj {

std::unique_ptr<ReplayDriver> MakeReplayDriver(const Show&, const std::string&, const std::string&, std::string* error) {
    *error = "--replay needs the full sdfvj build (this is the headless renderer without the input modules)";
    return nullptr;
}

}  // namespace sdfvj
