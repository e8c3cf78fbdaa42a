// AudioInput: a JACK client with one input port, and the ring that carries its samples to Poll().
//
// Threads:
//   JACK process thread  Process(): copies the port's buffer into the ring and bumps `written`;
//                        when the ring is full the rest is dropped and counted (never waits,
//                        never allocates, takes no lock).
//   JACK notify thread   OnShutdown(): sets `gone`. Nothing else.
//   analysis thread      every 5 ms: reads the ring up to `written`, bumps `read`, runs the
//                        analysis (owns the AudioAnalyzer), publishes features and spectrum
//                        under `mutex` (held for a copy only).
//   caller of Poll()     copies the published features out under `mutex`; never analyses.
// The ring is single-producer single-consumer: `written` is stored with release after the
// samples, `read` with release after they were copied out, so neither side sees a torn sample.
#include <jack/jack.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <mutex>
#include <thread>

#include "audio/audio.h"
#include "audio/wav.h"

namespace sdfvj {

struct AudioInput::Impl {
    jack_client_t* client = nullptr;
    jack_port_t* port = nullptr;
    std::vector<float> ring;         // power-of-two size
    size_t mask = 0;
    std::atomic<uint64_t> written{0};
    std::atomic<uint64_t> read{0};
    std::atomic<uint64_t> overruns{0};
    std::atomic<bool> gone{false};

    std::unique_ptr<AudioAnalyzer> analyzer;   // analysis thread only (after Open)
    std::unique_ptr<WavRecorder> wav;          // desc.recordWav: what the analysis reads, as it reads it
    std::thread worker;
    std::atomic<bool> stop{false};
    std::mutex mutex;                          // guards the three below
    AudioFeatures published;                   // onset/beat: any since the last Poll
    AudioSpectrum spectrum;
    bool fresh = false;
    uint64_t recorded = 0;                     // samples in the WAV when `published` was computed

    void AnalysisLoop() {
        std::vector<float> scratch(4096);
        while (!stop.load()) {
            const uint64_t w = written.load(std::memory_order_acquire);
            uint64_t r = read.load(std::memory_order_relaxed);
            if (r < w) {
                while (r < w) {
                    const size_t n = std::min<size_t>(size_t(w - r), scratch.size());
                    for (size_t i = 0; i < n; ++i) scratch[i] = ring[(r + i) & mask];
                    r += n;
                    read.store(r, std::memory_order_release);
                    analyzer->Process(scratch.data(), n);
                    if (wav) wav->Append(scratch.data(), n);
                }
                AudioFeatures f = analyzer->TakeFeatures();
                std::lock_guard<std::mutex> lock(mutex);
                f.onset = f.onset || (fresh && published.onset);
                f.beat = f.beat || (fresh && published.beat);
                published = f;
                spectrum = analyzer->Spectrum();
                recorded = wav ? wav->Appended() : 0;
                fresh = true;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
    }

    static int Process(jack_nframes_t n, void* arg) {
        Impl& s = *static_cast<Impl*>(arg);
        const float* in = static_cast<const float*>(jack_port_get_buffer(s.port, n));
        const uint64_t w = s.written.load(std::memory_order_relaxed);
        const uint64_t r = s.read.load(std::memory_order_acquire);
        const size_t room = s.ring.size() - size_t(w - r);
        const size_t take = std::min<size_t>(n, room);
        for (size_t i = 0; i < take; ++i) s.ring[(w + i) & s.mask] = in[i];
        if (take < n) s.overruns.fetch_add(n - take, std::memory_order_relaxed);
        s.written.store(w + take, std::memory_order_release);
        return 0;
    }
    static void OnShutdown(void* arg) { static_cast<Impl*>(arg)->gone.store(true); }

    ~Impl() {
        stop = true;
        if (worker.joinable()) worker.join();
        if (client) jack_deactivate(client);
        if (wav) {   // the audio the analysis had not reached yet belongs to the show too
            const uint64_t w = written.load(std::memory_order_acquire);
            std::vector<float> rest;
            for (uint64_t r = read.load(); r < w; ++r) rest.push_back(ring[r & mask]);
            wav->Append(rest.data(), rest.size());
            wav->Close();
        }
        if (client) jack_client_close(client);
    }
};

namespace {
// libjack prints "Cannot connect to server socket" and the like on stderr while it looks for a
// server; the one line Open() returns says the same for a performer, so those are held back
// during Open() only (the previous handler comes back: RtMidi's JACK messages stay as they were).
void QuietJack(const char*) {}
struct QuietJackScope {
    void (*previous)(const char*) = jack_error_callback;
    QuietJackScope() { jack_set_error_function(QuietJack); }
    ~QuietJackScope() { jack_set_error_function(previous); }
};
}  // namespace

std::unique_ptr<AudioInput> AudioInput::Open(const AudioInputDesc& desc, std::string* status) {
    const std::string clientName = desc.clientName.empty() ? "sdfvj-audio" : desc.clientName;
    const std::string portName = desc.portName.empty() ? "in" : desc.portName;
    auto impl = std::make_unique<Impl>();
    {
        QuietJackScope quiet;
        jack_status_t js{};
        impl->client = jack_client_open(clientName.c_str(), JackNoStartServer, &js);
        if (!impl->client) {
            const char* server = std::getenv("JACK_DEFAULT_SERVER");
            *status = std::string("audio: no JACK server") + (server ? std::string(" '") + server + "'" : "") +
                      " to listen to (start jackd, or qjackctl) — the show goes on without audio";
            return nullptr;
        }
    }
    size_t size = 1;
    while (size < (desc.ringSamples ? desc.ringSamples : 65536)) size <<= 1;
    impl->ring.assign(size, 0.0f);
    impl->mask = size - 1;
    impl->port = jack_port_register(impl->client, portName.c_str(), JACK_DEFAULT_AUDIO_TYPE, JackPortIsInput, 0);
    if (!impl->port) {
        *status = "audio: JACK refused the input port '" + clientName + ":" + portName +
                  "' (a port of that name exists?) — the show goes on without audio";
        return nullptr;
    }
    jack_set_process_callback(impl->client, &Impl::Process, impl.get());
    jack_on_shutdown(impl->client, &Impl::OnShutdown, impl.get());
    if (jack_activate(impl->client) != 0) {
        *status = "audio: JACK would not activate client '" + clientName + "' — the show goes on without audio";
        return nullptr;
    }
    const int rate = int(jack_get_sample_rate(impl->client));
    const std::string full = jack_port_name(impl->port);
    *status = "audio: listening on JACK port " + full + " at " + std::to_string(rate) + " Hz";
    if (!desc.connect.empty()) {
        const int rc = jack_connect(impl->client, desc.connect.c_str(), full.c_str());
        if (rc == 0 || rc == EEXIST) *status += ", connected from " + desc.connect;
        else *status += "; cannot connect from '" + desc.connect + "' (see `jack_lsp`), connect it by hand";
    }
    // Made here (FFTW plans on the opening thread), used only by the analysis thread from now on.
    impl->analyzer = std::make_unique<AudioAnalyzer>(AudioAnalyzerDesc{rate, desc.onsetThreshold, 0});
    if (!desc.recordWav.empty()) {   // a WAV that cannot be written is a line; the show goes on
        auto wav = std::make_unique<WavRecorder>();
        std::string error;
        if (wav->Open(desc.recordWav, rate, &error)) {
            impl->wav = std::move(wav);
            *status += "; recording it to " + desc.recordWav;
        } else {
            *status += "; not recording the audio: " + error;
        }
    }
    Impl* raw = impl.get();
    impl->worker = std::thread([raw] { raw->AnalysisLoop(); });
    return std::unique_ptr<AudioInput>(new AudioInput(std::move(impl), rate));
}

AudioInput::AudioInput(std::unique_ptr<Impl> impl, int sampleRate) : impl_(std::move(impl)), rate_(sampleRate) {}

AudioInput::~AudioInput() = default;   // Impl joins the analysis thread, then closes the client

AudioFeatures AudioInput::Poll(double now) {
    Impl& s = *impl_;
    std::lock_guard<std::mutex> lock(s.mutex);
    if (!s.fresh) {
        AudioFeatures f = s.published;
        f.onset = f.beat = false;   // already reported
        if (s.wav) f.wavSample = int64_t(s.recorded);
        return f;
    }
    s.fresh = false;
    textures_ = s.spectrum;
    AudioFeatures f = s.published;
    if (s.wav) {   // the spectrum on screen at `now` ends at this sample of the WAV
        s.wav->NoteClock(now, s.recorded);
        f.wavSample = int64_t(s.recorded);
    }
    return f;
}

std::string AudioInput::PortName() const { return jack_port_name(impl_->port); }
uint64_t AudioInput::Overruns() const { return impl_->overruns.load(); }
bool AudioInput::ServerGone() const { return impl_->gone.load(); }
uint64_t AudioInput::RecordedSamples() const { return impl_->wav ? impl_->wav->Appended() : 0; }
std::string AudioInput::RecordError() const { return impl_->wav ? impl_->wav->Error() : ""; }

}  // namespace sdfvj
