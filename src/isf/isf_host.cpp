// IsfHost (isf_host.h): post chains built, first drawn and drawn by the thread whose context
// they live in.
#include "isf/isf_host.h"

#include <epoxy/gl.h>

#include <chrono>
#include <cstdlib>
#include <deque>

#include "render/live_program.h"
#include "render/render.h"

namespace sdfvj {


// A thread that makes one context current once and runs tasks on it, in order, until it ends.
// Everything the two threads share lives here (no promise on a caller's stack that the other
// thread could still be touching as the caller returns).
class IsfHost::ContextThread {
public:
    explicit ContextThread(IsfHostContext context) {
        thread_ = std::thread([this, context] {
            const bool current = context.makeCurrent();
            {
                std::lock_guard<std::mutex> lock(mutex_);
                started_ = true;
                ok_ = current;
            }
            done_.notify_all();
            if (!current) return;
            for (;;) {
                std::function<void()> task;
                {
                    std::unique_lock<std::mutex> lock(mutex_);
                    wake_.wait(lock, [&] { return stop_ || !tasks_.empty(); });
                    if (tasks_.empty()) break;   // stopped, nothing left to run
                    task = std::move(tasks_.front());
                    tasks_.pop_front();
                }
                task();
                {
                    std::lock_guard<std::mutex> lock(mutex_);
                    ++ran_;
                }
                done_.notify_all();
            }
            context.release();
        });
        std::unique_lock<std::mutex> lock(mutex_);
        done_.wait(lock, [&] { return started_; });
    }
    ~ContextThread() {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stop_ = true;
        }
        wake_.notify_all();
        thread_.join();
    }
    bool Ok() const { return ok_; }
    // Queues `task`; returns its number in the queue's order.
    uint64_t Post(std::function<void()> task) {
        uint64_t n = 0;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            tasks_.push_back(std::move(task));
            n = ++posted_;
        }
        wake_.notify_all();
        return n;
    }
    // Runs `task` there and waits for it (after the tasks posted before it).
    void Run(const std::function<void()>& task) {
        const uint64_t n = Post([&task] { task(); });
        std::unique_lock<std::mutex> lock(mutex_);
        done_.wait(lock, [&] { return ran_ >= n; });
    }

private:
    std::thread thread_;
    std::mutex mutex_;
    std::condition_variable wake_, done_;
    std::deque<std::function<void()>> tasks_;
    uint64_t posted_ = 0, ran_ = 0;
    bool stop_ = false, ok_ = false, started_ = false;
};

namespace {
// SpareTargets' default.
bool SpareByDefault() { return EnvSwitch("SDFVJ_POST_SPARE", !IsSoftwareRenderer()); }
}  // namespace

IsfHost::IsfHost() : chain_(std::make_unique<IsfChain>()), spare_(SpareByDefault()) {}

IsfHost::IsfHost(std::array<IsfHostContext, 2> contexts, IsfDrawIn drawIn)
    : chain_(std::make_unique<IsfChain>()), spare_(SpareByDefault()) {
    if (drawIn == IsfDrawIn::Auto) {
        const char* env = std::getenv("SDFVJ_POST_DRAW");
        const std::string forced = env ? env : "";
        // Mesa's software rasterizers compile a program's pixel code again in each context.
        drawIn = forced == "own"            ? IsfDrawIn::OwnContexts
                 : forced == "render"       ? IsfDrawIn::RenderThread
                 : IsSoftwareRenderer()     ? IsfDrawIn::OwnContexts
                                            : IsfDrawIn::RenderThread;
    }
    if (!contexts[0].makeCurrent || !contexts[1].makeCurrent) return;
    for (size_t i = 0; i < 2; ++i) threads_[i] = std::make_unique<ContextThread>(contexts[i]);
    own_ = threads_[0]->Ok() && threads_[1]->Ok();
    if (!own_) threads_ = {};
    drawHere_ = own_ && drawIn == IsfDrawIn::RenderThread;
}

IsfHost::~IsfHost() {
    if (drawHere_) threads_ = {};   // the builds end first; every chain is drawn here
    if (!own_ || drawHere_) {   // the render thread, its context current
        chain_.reset();
        result_.chain.reset();
        pool_.Clear();
        if (buildInput_.texture) glDeleteTextures(1, &buildInput_.texture);
        return;
    }
    // Each chain goes on the thread whose context it lives in.
    threads_[(size_t)current_]->Run([&] {
        chain_.reset();
        glFinish();
    });
    threads_[(size_t)current_ ^ 1]->Run([&] {
        result_.chain.reset();
        copyFrom_.reset();
        pool_.Clear();
        if (buildInput_.texture) glDeleteTextures(1, &buildInput_.texture);
        glFinish();
    });
    threads_ = {};
}

bool IsfHost::Busy() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return running_ || result_.done || queued_;
}

void IsfHost::Request(std::vector<IsfFile> files, int w, int h) {
    if (w > 0 && h > 0) {
        lastW_ = w;
        lastH_ = h;
    }
    hashes_.clear();
    for (const IsfFile& f : files) hashes_.push_back(IsfFilesHash(f.path));
    wanted_ = files;
    Submit(std::move(files), {});
}

bool IsfHost::Reload(std::vector<std::string>* errors) {
    if (wanted_.empty()) return false;
    std::vector<IsfFile> next = wanted_;
    bool changed = false, program = false;
    for (size_t i = 0; i < wanted_.size(); ++i) {
        const uint64_t hash = IsfFilesHash(wanted_[i].path);
        if (hash == hashes_[i]) continue;
        hashes_[i] = hash;   // read once: one report per save
        IsfFile file;
        IsfSources src, was;
        std::string error;
        if (!LoadIsfFile(wanted_[i].path, &file, &error) || !TranslateIsf(file, &src, &error)) {
            errors->push_back(error + " — still showing the previous shader");
            continue;
        }
        changed = true;
        if (!TranslateIsf(wanted_[i], &was, &error) || src.vertex.hash != was.vertex.hash ||
            src.fragment.hash != was.fragment.hash || !file.imports.empty())
            program = true;
        next[i] = std::move(file);
    }
    if (!changed) return false;
    const std::vector<IsfFile> fallback = wanted_;
    wanted_ = next;
    // The GLSL on screen already (a header-only change, or the last good file put back after a
    // broken save): the chain on screen takes the new headers without compiling.
    if (!program && !Busy() && chain_->Size() == next.size()) {
        auto apply = [&] {
            for (size_t i = 0; i < next.size(); ++i) {
                std::string error;
                if (!chain_->Stage(i).LoadParsed(next[i], &error)) errors->push_back(error + " — still showing the previous shader");
            }
        };
        if (own_ && !drawHere_) threads_[(size_t)current_]->Run(apply);
        else apply();
        shown_ = next;
        return false;
    }
    Submit(std::move(next), fallback);
    return true;
}

void IsfHost::Submit(std::vector<IsfFile> files, std::vector<IsfFile> fallback) {
    Job job;
    job.files = std::move(files);
    job.fallback = std::move(fallback);
    job.w = lastW_ > 0 ? lastW_ : 64;
    job.h = lastH_ > 0 ? lastH_ : 64;
    job.inputFormat = lastFormat_;
    job.waveSamples = lastWave_;
    job.spectrumBins = lastSpectrum_;
    if (!own_) {   // here and now: this frame waits for the build
        Result r;
        Build(job, &r);
        std::lock_guard<std::mutex> lock(mutex_);
        result_ = std::move(r);
        result_.done = true;
        return;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    if (running_ || result_.done) {   // one build at a time: this one follows the running one
        queued_ = true;
        queuedFallback_ = std::move(job.fallback);
        return;
    }
    // The thread of the context the chain on screen is not in builds it.
    running_ = true;
    threads_[(size_t)current_ ^ 1]->Post([this, job = std::move(job)] {
        Result r;
        Build(job, &r);
        std::lock_guard<std::mutex> lock(mutex_);
        result_ = std::move(r);
        result_.done = true;
        running_ = false;
    });
}

void IsfHost::Build(const Job& job, Result* out) {
    const auto start = std::chrono::steady_clock::now();
    std::vector<IsfFile> files = job.files;
    auto chain = std::make_unique<IsfChain>();
    if (!files.empty()) {
        // Stage by stage, so a stage that does not compile falls back to its last good file.
        for (size_t i = 0; i < files.size(); ++i) {
            auto effect = std::make_unique<IsfEffect>();
            std::string error;
            if (!effect->LoadParsed(files[i], &error)) {
                out->errors.push_back(error + " — still showing the previous shader");
                const IsfFile* last = nullptr;
                for (const IsfFile& f : job.fallback)
                    if (f.path == files[i].path) last = &f;
                effect = std::make_unique<IsfEffect>();
                if (!last || !effect->LoadParsed(*last, &error)) return;   // nothing good to build: the chain on screen stays
                files[i] = *last;
            }
            chain->Add(std::move(effect));
        }
        // The first draw, as the show's frames will draw it: the driver's compile at first use
        // happens here. The same size, input format and audio texture formats as the last frame.
        unsigned input = 0;
        if (job.inputFormat) {
            Scratch& in = buildInput_;
            if (in.texture && (in.w != job.w || in.h != job.h || in.format != job.inputFormat)) {
                glDeleteTextures(1, &in.texture);
                in = Scratch{};
            }
            if (!in.texture) {
                glCreateTextures(GL_TEXTURE_2D, 1, &in.texture);
                glTextureStorage2D(in.texture, 1, job.inputFormat, job.w, job.h);
                in.w = job.w;
                in.h = job.h;
                in.format = job.inputFormat;
            }
            input = in.texture;
        }
        chain->SetTexturePool(&pool_);
        chain->SetKeptSizes(keepSizes_);
        IsfFrameInputs in;
        std::vector<float> wave((size_t)job.waveSamples, 0.0f), spectrum((size_t)job.spectrumBins, 0.0f);
        in.audioWaveform = wave;
        in.audioSpectrum = spectrum;
        auto draw = [&] { chain->Render(input, job.w, job.h, in); };
        const int missed = pool_.Misses();
        draw();
        if (pool_.Misses() > missed) {   // new textures: their first draws here, not in the show's frames
            draw();   // each target's other texture
            if (spare_) {   // a second set, drawn twice too, for the next build to take from the pool
                IsfTexturePool first;
                chain->GiveTextures(first);
                draw();
                draw();
                const size_t bytes = chain->GiveTextures(pool_);
                chain->SetTexturePool(&first);
                draw();   // the first set back, drawn already
                chain->SetTexturePool(&pool_);
                first.Clear();
                pool_.SetCap(bytes);
                pool_.Seal();
                out->spareMade = true;
            }
        }
        chain->ClearBuffers();   // what that draw left in PERSISTENT targets is not the show's
        if (drawHere_) chain->ReleaseContextObjects();   // the render thread draws it, in its context
        glFinish();
    }
    ++built_;
    out->chain = std::move(chain);
    out->files = std::move(files);
    out->buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// The pool keeps the retired chain's targets (what the next build most likely asks for) and lets
// older ones go; a build in another context waits for this one's last use of them (Seal).
void IsfHost::Pool(IsfChain& retired) {
    const size_t bytes = retired.GiveTextures(pool_);
    if (bytes == 0) return;   // the empty chain a first build replaces: the pool keeps what it has (a spare set)
    pool_.SetCap(bytes);
    pool_.Seal();
}

void IsfHost::Retire(std::unique_ptr<IsfChain> chain, int context, bool pool) {
    IsfChain* c = chain.release();
    threads_[(size_t)context]->Post([this, c, pool] {
        if (pool) Pool(*c);
        delete c;
        glFinish();
    });
}

void IsfHost::Adopt(Result& r) {
    std::unique_ptr<IsfChain> old = std::move(chain_);
    chain_ = std::move(r.chain);
    shown_ = std::move(r.files);
    if (!own_ || drawHere_) {
        chain_->CopyBuffersFrom(*old);
        // A build that made a spare set found none of its sizes in the pool: the old chain's targets
        // are of other sizes, and the pool keeps the spare set instead.
        if (!r.spareMade) Pool(*old);
        return;
    }
    current_ ^= 1;   // the next build goes to the context the old chain leaves
    // The next frame copies the feedback (PERSISTENT targets) on the new chain's thread, then the
    // old chain is deleted by its own.
    if (copyFrom_) Retire(std::move(copyFrom_), current_, copyFromPool_);
    copyFrom_ = std::move(old);
    copyFromPool_ = !r.spareMade;   // as above: the pool keeps a spare set
}

bool IsfHost::Poll(Done* done) {
    Result r;
    bool next = false;
    std::vector<IsfFile> nextFallback;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!result_.done) return false;
        r = std::move(result_);
        result_ = Result{};
        next = queued_;
        queued_ = false;
        nextFallback = std::move(queuedFallback_);
        queuedFallback_.clear();
    }
    *done = Done{};
    done->errors = r.errors;
    done->buildMs = r.buildMs;
    if (r.chain) {
        const auto t0 = std::chrono::steady_clock::now();
        Adopt(r);
        done->adoptMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        done->adopted = true;
    }
    if (next) {
        Submit(wanted_, nextFallback);
    } else if (wanted_.size() != shown_.size() || !done->adopted) {
        // A request that failed: what is on screen is what the next save edits.
        wanted_ = shown_;
        hashes_.clear();
        for (const IsfFile& f : wanted_) hashes_.push_back(IsfFilesHash(f.path));
    } else {
        wanted_ = shown_;   // a stage that fell back to its last good file is that file again
    }
    return true;
}

unsigned IsfHost::Render(unsigned input, int w, int h, const IsfFrameInputs& in) {
    lastW_ = w;
    lastH_ = h;
    lastWave_ = (int)in.audioWaveform.size();
    lastSpectrum_ = (int)in.audioSpectrum.size();
    if (input != lastInput_) {   // what the next build's first draw reads: the same format
        lastInput_ = input;
        int format = 0;
        if (input) glGetTextureLevelParameteriv(input, 0, GL_TEXTURE_INTERNAL_FORMAT, &format);
        lastFormat_ = (unsigned)format;
    }
    if (chain_->Empty()) return input;
    using Ms = std::chrono::duration<double, std::milli>;
    const auto t0 = std::chrono::steady_clock::now();
    if (!own_ || drawHere_) {
        const unsigned out = chain_->Render(input, w, h, in);
        split_ = {0.0, Ms(std::chrono::steady_clock::now() - t0).count()};
        return out;
    }
    GLsync ready = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0), drawn = nullptr;
    glFlush();
    unsigned out = input;
    double draw = 0.0;
    threads_[(size_t)current_]->Run([&] {
        const auto d0 = std::chrono::steady_clock::now();
        if (ready) glWaitSync(ready, 0, GL_TIMEOUT_IGNORED);
        if (copyFrom_) chain_->CopyBuffersFrom(*copyFrom_);   // a swap's first frame: the feedback carries over
        out = chain_->Render(input, w, h, in);
        drawn = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
        glFlush();
        draw = Ms(std::chrono::steady_clock::now() - d0).count();
    });
    if (ready) glDeleteSync(ready);
    if (drawn) {
        glWaitSync(drawn, 0, GL_TIMEOUT_IGNORED);
        glDeleteSync(drawn);
    }
    if (copyFrom_) Retire(std::move(copyFrom_), current_ ^ 1, copyFromPool_);
    split_ = {Ms(std::chrono::steady_clock::now() - t0).count() - draw, draw};
    return out;
}

}  // namespace sdfvj
