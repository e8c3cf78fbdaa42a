// The on-disk program cache through the real driver (llvmpipe): a second start takes the
// program from disk and draws the same image; another source or another driver ignores it; a
// truncated or corrupt file is compiled over without a word to the performer. Each test uses a
// cache folder of its own (XDG_CACHE_HOME) and restores the fixture's "cache off" after.
#include <catch2/catch.hpp>
#include <epoxy/gl.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <thread>

#include "gl_fixture.h"
#include "render/live_program.h"
#include "render/program_cache.h"

using namespace sdfvj;
using namespace sdfvj::test;
namespace fs = std::filesystem;

namespace {

// Runs on a context of its own (same display, no shared objects): the programs loaded from
// binaries here never meet the worker contexts other tests make and destroy on the main one
// (Mesa 22.3 crashed a draw after a shared context went away once binaries had been loaded).
struct CacheRig {
    HeadlessContext own;
    fs::path folder;
    SceneInfo scene;
    VariantKey key;
    bool binaries = false;   // the driver gives program binaries (Mesa: only with its disk cache on)

    explicit CacheRig(const std::string& name) {
        RequireGl();
        std::string ownError;
        REQUIRE(own.CreateShared(*TestContext(), &ownError, false));
        REQUIRE(own.MakeCurrent());
        folder = fs::temp_directory_path() / ("sdfvj-progcache-" + name + "-" + std::to_string(::getpid()));
        fs::remove_all(folder);
        setenv("XDG_CACHE_HOME", folder.c_str(), 1);
        setenv("SDFVJ_PROGRAM_CACHE", "1", 1);
        SetProgramCacheDriver("");
        std::string err;
        REQUIRE(FindScene("mandelbulb", &scene, &err));
        key = VariantKey{scene.path, EffectSet{}, RenderPath::Fragment};
        GLint formats = 0;
        glGetIntegerv(GL_NUM_PROGRAM_BINARY_FORMATS, &formats);
        binaries = formats > 0;
        if (!binaries) WARN("the driver gives no program binaries (Mesa with MESA_SHADER_CACHE_DISABLE): nothing to cache");
    }
    ~CacheRig() {
        TestContext()->MakeCurrent();   // `own` is destroyed after this, not current
        setenv("SDFVJ_PROGRAM_CACHE", "0", 1);
        unsetenv("XDG_CACHE_HOME");
        SetProgramCacheDriver("");
        fs::remove_all(folder);
    }
    // A fresh start: a new LiveProgram (no programs in memory) showing `k`.
    std::unique_ptr<LiveProgram> Start(const VariantKey& k) {
        auto live = std::make_unique<LiveProgram>();
        live->SetTiered(false);
        live->Request(k);
        live->Wait();
        INFO(live->Error());
        REQUIRE(live->Current() != nullptr);
        CHECK(live->Error().empty());
        return live;
    }
    std::string File(const VariantKey& k) {
        ShaderSource src;
        std::string err;
        REQUIRE(AssembleProgram(scene, k, &src, &err));
        return CachedProgramFile(src.text, k.path);
    }
    Image Draw(const LiveProgram& live) {
        FrameRenderer fr;
        std::string err;
        REQUIRE(fr.Resize(48, 32, &err));
        FrameInputs in;
        in.time = 1.0;
        fr.Draw(*live.Current(), live.Scene(), in);
        return Image{fr.Width(), fr.Height(), fr.ReadPixels()};
    }
};

}  // namespace

TEST_CASE("program cache: a second start takes the program from disk and draws the same image", "[cache]") {
    CacheRig rig("second");
    if (!rig.binaries) return;
    auto first = rig.Start(rig.key);
    CHECK_FALSE(first->Current()->FromCache());
    CHECK(first->CompilesStarted() == 1);
    REQUIRE(fs::exists(rig.File(rig.key)));
    // No temp file is left behind by the atomic write.
    int files = 0;
    for (const auto& e : fs::directory_iterator(fs::path(ProgramCacheFolder()))) files += e.is_regular_file();
    CHECK(files == 1);

    auto second = rig.Start(rig.key);
    CHECK(second->Current()->FromCache());
    CHECK(second->CompilesStarted() == 0);
    const ImageDiff d = CompareImages(rig.Draw(*first), rig.Draw(*second), 0);
    CHECK(d.maxAbs == 0);
}

TEST_CASE("program cache: another source or another GL_RENDERER ignores the cached program", "[cache]") {
    CacheRig rig("keys");
    if (!rig.binaries) return;
    rig.Start(rig.key);
    REQUIRE(rig.Start(rig.key)->Current()->FromCache());

    VariantKey other = rig.key;   // another variant: other #defines, another source
    other.effects.ao = true;
    CHECK_FALSE(rig.Start(other)->Current()->FromCache());

    const std::string ours = rig.File(rig.key);
    SetProgramCacheDriver("NVIDIA Corporation | NVIDIA H200/PCIe/SSE2 | 4.6.0 NVIDIA 570.00");
    const std::string theirs = rig.File(rig.key);
    CHECK(theirs != ours);
    // Our binary under the other driver's name (a cache folder copied between machines): the key
    // inside the file does not match, so it is compiled anew and the file replaced.
    fs::copy_file(ours, theirs, fs::copy_options::overwrite_existing);
    auto started = rig.Start(rig.key);
    CHECK_FALSE(started->Current()->FromCache());
    CHECK(started->CompilesStarted() == 1);
    SetProgramCacheDriver("");
    CHECK(rig.Start(rig.key)->Current()->FromCache());   // ours is still there
}

TEST_CASE("program cache: a truncated or corrupt file falls back to a compile with no error", "[cache]") {
    CacheRig rig("corrupt");
    if (!rig.binaries) return;
    auto good = rig.Start(rig.key);
    const Image expected = rig.Draw(*good);
    const std::string file = rig.File(rig.key);
    const auto size = fs::file_size(file);

    fs::resize_file(file, size / 2);
    auto truncated = rig.Start(rig.key);
    CHECK_FALSE(truncated->Current()->FromCache());
    CHECK(truncated->Error().empty());
    CHECK(CompareImages(expected, rig.Draw(*truncated), 0).maxAbs == 0);
    CHECK(fs::file_size(file) == size);   // compiled and stored again

    {   // one byte of the binary flipped: the checksum refuses it
        std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
        f.seekg(-16, std::ios::end);
        char c = 0;
        f.get(c);
        f.seekp(-16, std::ios::end);
        f.put((char)(c ^ 0x5a));
    }
    auto flipped = rig.Start(rig.key);
    CHECK_FALSE(flipped->Current()->FromCache());
    CHECK(flipped->Error().empty());
    CHECK(CompareImages(expected, rig.Draw(*flipped), 0).maxAbs == 0);
    CHECK(rig.Start(rig.key)->Current()->FromCache());
}

TEST_CASE("program cache: SDFVJ_PROGRAM_CACHE=0 neither reads nor writes", "[cache]") {
    CacheRig rig("off");
    setenv("SDFVJ_PROGRAM_CACHE", "0", 1);
    rig.Start(rig.key);
    CHECK_FALSE(fs::exists(rig.File(rig.key)));
    if (!rig.binaries) return;
    setenv("SDFVJ_PROGRAM_CACHE", "1", 1);
    rig.Start(rig.key);
    REQUIRE(fs::exists(rig.File(rig.key)));
    setenv("SDFVJ_PROGRAM_CACHE", "0", 1);
    CHECK_FALSE(rig.Start(rig.key)->Current()->FromCache());
}

TEST_CASE("program cache: the folder keeps the most recently used programs only", "[cache]") {
    CacheRig rig("evict");
    if (!rig.binaries) return;
    setenv("SDFVJ_PROGRAM_CACHE_MAX_FILES", "2", 1);
    struct Unset { ~Unset() { unsetenv("SDFVJ_PROGRAM_CACHE_MAX_FILES"); } } unset;
    VariantKey ao = rig.key, fog = rig.key;
    ao.effects.ao = true;
    fog.effects.fog = !rig.key.effects.fog;
    rig.Start(rig.key);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));   // distinct file times
    rig.Start(ao);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    CHECK(rig.Start(rig.key)->Current()->FromCache());   // used again: now newer than `ao`
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    rig.Start(fog);                                       // a third program: the oldest goes
    CHECK(fs::exists(rig.File(rig.key)));
    CHECK(fs::exists(rig.File(fog)));
    CHECK_FALSE(fs::exists(rig.File(ao)));
}
