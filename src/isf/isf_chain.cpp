// IsfChain (effects in order, each reading the previous one's output) and IsfTexturePool (render
// targets a rebuilt chain takes over from the chain it replaced). GL calls: a context current.
#include <epoxy/gl.h>

#include <algorithm>
#include <iterator>

#include "isf/isf.h"

namespace sdfvj {

size_t IsfTexturePool::BytesOf(int w, int h, unsigned format) {
    const size_t texel = format == GL_RGBA32F ? 16 : format == GL_RGBA16F ? 8 : 4;
    return (size_t)std::max(w, 0) * (size_t)std::max(h, 0) * texel;
}

unsigned IsfTexturePool::Take(int w, int h, unsigned format) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (auto it = entries_.rbegin(); it != entries_.rend(); ++it) {   // the newest first
        if (it->w != w || it->h != h || it->format != format) continue;
        const unsigned t = it->texture;
        bytes_ -= BytesOf(w, h, format);
        entries_.erase(std::next(it).base());
        if (sealed_) glWaitSync((GLsync)sealed_, 0, GL_TIMEOUT_IGNORED);
        return t;
    }
    ++misses_;
    return 0;
}

int IsfTexturePool::Misses() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return misses_;
}

void IsfTexturePool::Put(unsigned texture, int w, int h, unsigned format) {
    if (!texture) return;
    std::lock_guard<std::mutex> lock(mutex_);
    entries_.push_back({texture, w, h, format});
    bytes_ += BytesOf(w, h, format);
}

void IsfTexturePool::Seal() {
    GLsync fence = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    glFlush();   // so that another context's wait on it can end
    std::lock_guard<std::mutex> lock(mutex_);
    if (sealed_) glDeleteSync((GLsync)sealed_);   // deleted once no wait is pending on it
    sealed_ = fence;
}

void IsfTexturePool::SetCap(size_t capBytes) {
    std::lock_guard<std::mutex> lock(mutex_);
    cap_ = capBytes;
    Trim();
}

void IsfTexturePool::Trim() {
    while (!entries_.empty() && bytes_ > cap_) {
        glDeleteTextures(1, &entries_.front().texture);
        bytes_ -= BytesOf(entries_.front().w, entries_.front().h, entries_.front().format);
        entries_.erase(entries_.begin());
    }
}

void IsfTexturePool::Clear() {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const Entry& e : entries_) glDeleteTextures(1, &e.texture);
    entries_.clear();
    bytes_ = 0;
    if (sealed_) glDeleteSync((GLsync)sealed_);
    sealed_ = nullptr;
}

bool IsfChain::Load(const std::vector<std::string>& paths, std::string* error) {
    std::vector<std::unique_ptr<IsfEffect>> loaded;
    for (const std::string& p : paths) {
        auto e = std::make_unique<IsfEffect>();
        if (!e->Load(p, error)) return false;
        loaded.push_back(std::move(e));
    }
    effects_ = std::move(loaded);
    return true;
}

void IsfChain::ClearBuffers() {
    for (auto& e : effects_) e->ClearBuffers();
}

void IsfChain::SetTexturePool(IsfTexturePool* pool) {
    for (auto& e : effects_) e->SetTexturePool(pool);
}

void IsfChain::SetKeptSizes(int n) {
    for (auto& e : effects_) e->SetKeptSizes(n);
}

void IsfChain::ReleaseContextObjects() {
    for (auto& e : effects_) e->ReleaseContextObjects();
}

size_t IsfChain::GiveTextures(IsfTexturePool& pool) {
    size_t bytes = 0;
    for (auto& e : effects_) bytes += e->GiveTextures(pool);
    return bytes;
}

void IsfChain::CopyBuffersFrom(const IsfChain& other) {
    for (size_t i = 0; i < effects_.size() && i < other.effects_.size(); ++i)
        if (effects_[i]->File().path == other.effects_[i]->File().path) effects_[i]->CopyBuffersFrom(*other.effects_[i]);
}

std::vector<std::string> IsfChain::Notices() const {
    std::vector<std::string> out;
    for (const auto& e : effects_)
        for (const std::string& n : e->File().notices) out.push_back(n);
    return out;
}

std::vector<ParamDecl> IsfChain::Params() const {
    std::vector<ParamDecl> out;
    for (const auto& e : effects_)
        for (const ParamDecl& d : e->Params())
            if (std::none_of(out.begin(), out.end(), [&](const ParamDecl& o) { return o.name == d.name; })) out.push_back(d);
    return out;
}

unsigned IsfChain::Render(unsigned input, int w, int h, const IsfFrameInputs& in) {
    unsigned t = input;
    for (auto& e : effects_) t = e->Render(t, w, h, in);
    return t;
}

bool IsfChain::ReloadIfChanged(std::vector<std::string>* errors) {
    bool any = false;
    for (auto& e : effects_) {
        std::string error;
        const int r = e->ReloadIfChanged(&error);
        if (r > 0) any = true;
        if (r < 0) errors->push_back(error + " — still showing the previous shader");
    }
    return any;
}

}  // namespace sdfvj
