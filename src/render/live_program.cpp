#include "render/live_program.h"

#include <algorithm>
#include <filesystem>

namespace fs = std::filesystem;

namespace sdfvj {

void LiveProgram::Request(const VariantKey& key) {
    key_ = key;
    auto it = cache_.find(key);
    if (it != cache_.end()) {
        pending_.Cancel();
        current_ = it->second.program;
        scene_ = it->second.scene;
        error_.clear();
        return;
    }
    Rebuild();
}

void LiveProgram::Rebuild() {
    SceneInfo scene;
    std::string error;
    if (!LoadScene(key_.scenePath, &scene, &error)) {
        error_ = error + " — still showing the previous shader";
        return;
    }
    ShaderSource src;
    if (!AssembleProgram(scene, key_, &src, &error)) {
        error_ = error + " — still showing the previous shader";
        return;
    }
    auto it = cache_.find(key_);
    if (it != cache_.end() && it->second.program->Source().hash == src.hash) {
        // A no-op save, or a broken save undone: the cached program is the right one again.
        pending_.Cancel();
        current_ = it->second.program;
        scene_ = it->second.scene;
        error_.clear();
        return;
    }
    if (pending_.Active() && pendingKey_ == key_ && pendingHash_ == src.hash) return;
    pendingScene_ = scene;
    pendingKey_ = key_;
    pendingHash_ = src.hash;
    pending_.Begin(src, key_.path);
    ++compiles_;
}

void LiveProgram::Finish() {
    auto program = std::make_unique<Program>();
    std::string log;
    if (!pending_.Finish(program.get(), &log)) {
        error_ = log;
        return;
    }
    error_.clear();
    Cached& slot = cache_[pendingKey_];
    slot.program = std::move(program);
    slot.scene = pendingScene_;
    if (pendingKey_ == key_) {
        current_ = slot.program;
        scene_ = slot.scene;
    }
}

bool LiveProgram::Update(const std::vector<std::string>& changedFiles) {
    const Program* before = current_.get();
    if (!changedFiles.empty()) {
        bool affectsCurrent = false;
        for (const std::string& changed : changedFiles) {
            std::string canon = fs::weakly_canonical(changed).string();
            auto uses = [&](const Program& p) {
                const auto& files = p.Source().files;
                return std::find(files.begin(), files.end(), canon) != files.end();
            };
            // Owners of the changed file other than the variant asked for are dropped from the
            // cache; they rebuild when requested again. The program on screen may be one of them
            // (an effect toggle is still compiling): current_ keeps it alive until replaced.
            for (auto it = cache_.begin(); it != cache_.end();) {
                if (uses(*it->second.program) && it->first != key_) it = cache_.erase(it);
                else ++it;
            }
            if ((current_ && uses(*current_)) || canon == fs::weakly_canonical(key_.scenePath).string() ||
                (pending_.Active() && std::find(pending_.Source().files.begin(), pending_.Source().files.end(), canon) !=
                                          pending_.Source().files.end()) ||
                !error_.empty())   // after a failed build any save may be the fix
                affectsCurrent = true;
        }
        if (affectsCurrent) Rebuild();
    }
    if (pending_.Active() && pending_.Ready()) Finish();
    return current_.get() != before;
}

void LiveProgram::Wait() {
    if (pending_.Active()) Finish();
}

}  // namespace sdfvj
