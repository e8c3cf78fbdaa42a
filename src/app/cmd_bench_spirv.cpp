// `sdfvj bench spirv`: is a scene's program built faster from SPIR-V than from GLSL (issue 12,
// "try SPIR-V through glslang where the driver compiles it faster")? Each round builds the scene's
// compute program both ways, interleaved, each time with its first constant nudged (a program no
// cache has seen; the drivers' disk caches off), and times every step to the first dispatch:
//   glsl   glShaderSource + glCompileShader, glLinkProgram, first use (a 1x1 dispatch, glFinish)
//   spirv  glslangValidator (-G: SPIR-V for OpenGL, locations and bindings mapped), then
//          glShaderBinary + glSpecializeShader, glLinkProgram, first use
// glslangValidator runs as a process of its own (Debian's glslang-tools; --glslang PATH, else next
// to this binary, else on PATH): its time would shrink in-process, the driver's would not.
// Timing only: whether the SPIR-V program draws the same picture is not checked here.
#include <epoxy/gl.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <unistd.h>

#include "app/bench_build.h"
#include "app/bench_support.h"
#include "app/commands.h"
#include "render/live_program.h"
#include "render/render.h"
#include "scene/scene.h"
#include "shader/shader.h"

namespace sdfvj {

namespace fs = std::filesystem;

namespace {

BuildSteps BuildSpirv(const std::string& text, const std::string& glslang, const fs::path& work, int round) {
    BuildSteps s;
    const fs::path in = work / ("round" + std::to_string(round) + ".comp"), out = work / ("round" + std::to_string(round) + ".spv");
    std::ofstream(in, std::ios::binary) << text;
    const std::string cmd = "'" + glslang + "' -G --auto-map-locations --auto-map-bindings -S comp -o '" + out.string() + "' '" +
                            in.string() + "' > '" + (work / "glslang.log").string() + "' 2>&1";
    auto t0 = Clock::now();
    const int rc = std::system(cmd.c_str());
    s.front = MsSince(t0);
    std::ifstream bin(out, std::ios::binary);
    const std::string spirv((std::istreambuf_iterator<char>(bin)), std::istreambuf_iterator<char>());
    if (rc != 0 || spirv.size() < 20) {
        std::ifstream log(work / "glslang.log");
        s.error = "glslangValidator: " + std::string((std::istreambuf_iterator<char>(log)), std::istreambuf_iterator<char>()).substr(0, 600);
        return s;
    }
    const double front = s.front;
    s = TimedBuild([&](unsigned sh) {
        glShaderBinary(1, &sh, GL_SHADER_BINARY_FORMAT_SPIR_V_ARB, spirv.data(), (GLsizei)spirv.size());
        glSpecializeShaderARB(sh, "main", 0, nullptr, nullptr);
    }, "glSpecializeShader");
    s.front = front;
    return s;
}

std::string FindGlslang(const std::string& given) {
    if (!given.empty()) return given;
    std::error_code ec;
    const fs::path beside = fs::read_symlink("/proc/self/exe", ec).parent_path() / "glslangValidator";
    if (!ec && fs::exists(beside)) return beside.string();
    for (const char* dir : {"/usr/bin", "/usr/local/bin"})
        if (fs::exists(fs::path(dir) / "glslangValidator")) return (fs::path(dir) / "glslangValidator").string();
    return "";
}

}  // namespace

int RunSpirvBench(const SpirvBenchOptions& o) {
    const fs::path work = fs::temp_directory_path() / ("sdfvj-spirv-" + std::to_string(::getpid()));
    fs::create_directories(work);
    const std::string caches = SetDriverCaches("off", work, false);
    HeadlessContext gl;
    std::string error;
    if (!gl.Create(&error)) {
        std::fprintf(stderr, "sdfvj bench spirv: %s\n", error.c_str());
        return 2;
    }
    std::printf("# sdfvj bench spirv: %s on %s, %s\n%s\n", o.scene.c_str(), (const char*)glGetString(GL_RENDERER),
                (const char*)glGetString(GL_VERSION), caches.c_str());
    if (!epoxy_has_gl_extension("GL_ARB_gl_spirv") && epoxy_gl_version() < 46) {
        std::printf("this driver takes no SPIR-V (no GL_ARB_gl_spirv, OpenGL < 4.6): nothing to compare\n");
        return 0;
    }
    const std::string glslang = FindGlslang(o.glslang);
    if (glslang.empty()) {
        std::fprintf(stderr, "sdfvj bench spirv: no glslangValidator (Debian: glslang-tools; or --glslang PATH)\n");
        return 2;
    }
    SceneInfo scene;
    ShaderSource src;
    if (!FindScene(o.scene, &scene, &error) || !AssembleProgram(scene, VariantKey{scene.path, scene.effects, RenderPath::Compute}, &src, &error)) {
        std::fprintf(stderr, "sdfvj bench spirv: %s\n", error.c_str());
        return 2;
    }
    std::printf("each round: the scene's compute program (its own effects) with its first constant nudged, GLSL then SPIR-V "
                "(alternating which goes first); ms\n\n| round | form | front end | compile / specialize | link | first use | total |\n"
                "|---:|---|---:|---:|---:|---:|---:|\n");
    std::vector<double> totals[2], links[2], fronts[2], uses[2];
    for (int round = 1; round <= o.rounds; ++round) {
        for (int k = 0; k < 2; ++k) {
            const int form = (round % 2 == 0) ? 1 - k : k;   // 0 glsl, 1 spirv
            bool nudged = false;
            const std::string text = NudgeFirstConstant(src.text, 1e-4 * (10 * round + form + 1), &nudged);
            const BuildSteps s = form == 0 ? TimedGlslBuild(text) : BuildSpirv(text, glslang, work, round);
            if (!s.ok) {
                std::printf("| %d | %s | failed: %s |\n", round, form ? "spirv" : "glsl", s.error.c_str());
                continue;
            }
            std::printf("| %d | %s | %.1f | %.1f | %.1f | %.1f | %.1f |\n", round, form ? "spirv" : "glsl", s.front, s.compile, s.link,
                        s.use, s.Total());
            totals[form].push_back(s.Total());
            links[form].push_back(s.compile + s.link);
            fronts[form].push_back(s.front);
            uses[form].push_back(s.use);
        }
        std::fflush(stdout);
    }
    std::printf("\nmedians: glsl %.1f ms (driver compile + link %.1f, first use %.1f); spirv %.1f ms (glslangValidator %.1f, "
                "driver specialize + link %.1f, first use %.1f)\n",
                MedianMs(totals[0]), MedianMs(links[0]), MedianMs(uses[0]), MedianMs(totals[1]), MedianMs(fronts[1]), MedianMs(links[1]), MedianMs(uses[1]));
    std::error_code ec;
    fs::remove_all(work, ec);
    return 0;
}

}  // namespace sdfvj
