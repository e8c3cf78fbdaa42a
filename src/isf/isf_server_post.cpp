#include "isf/isf_server_post.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <ctime>

#include "isf/isf.h"

namespace sdfvj {

namespace {

class IsfServerPost final : public ServerPost {
public:
    bool Load(const std::vector<std::string>& paths, unsigned input, int w, int h, const std::vector<float>& wave,
              const std::vector<float>& spectrum, std::string* error) override {
        if (!chain_.Load(paths, error)) return false;
        // Drawn twice at the size, so both textures of every double-buffered target have been drawn
        // (on NVIDIA a texture's first draw costs about 1 ms per MB), with the show's sound (llvmpipe
        // compiles a program again for another audio texture size), then the feedback cleared: the
        // show's first frame starts from black, as a chain built in the show does.
        IsfFrameInputs in;
        for (const ParamDecl& d : chain_.Params()) in.params.emplace_back(d.name, d.defaultValue);
        in.audioWaveform = wave;
        in.audioSpectrum = spectrum;
        for (int i = 0; i < 2; ++i) chain_.Render(input, w, h, in);
        chain_.ClearBuffers();
        glFinish();
        return true;
    }

    unsigned Render(unsigned input, int w, int h, const FrameInputs& frame, const std::vector<float>& wave,
                    const std::vector<float>& spectrum) override {
        IsfFrameInputs in;
        in.time = frame.time;
        in.timeDelta = last_ < 0 ? 0.0 : std::max(0.0, frame.time - last_);
        last_ = frame.time;
        in.frame = frame.frame;
        in.date = IsfDateNow();
        in.params = frame.params;
        in.beat = frame.beat;
        in.bpm = frame.bpm;
        in.audioWaveform = wave;
        in.audioSpectrum = spectrum;
        return chain_.Render(input, w, h, in);
    }

private:
    IsfChain chain_;
    double last_ = -1;
};

}  // namespace

std::array<float, 4> IsfDateNow() {
    const std::time_t clock = std::time(nullptr);
    std::tm local{};
    localtime_r(&clock, &local);
    return {(float)(local.tm_year + 1900), (float)(local.tm_mon + 1), (float)local.tm_mday,
            (float)(local.tm_hour * 3600 + local.tm_min * 60 + local.tm_sec)};
}

std::unique_ptr<ServerPost> MakeIsfServerPost() { return std::make_unique<IsfServerPost>(); }

}  // namespace sdfvj
