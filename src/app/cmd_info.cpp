// `sdfvj info`: what this machine gives sdfvj, for a bug report or before a show. The headless
// GL context (EGL platform, driver, versions), the features the renderer and the reload path
// lean on (compute shaders, program binaries, the driver's parallel compile), what another
// process could share images through (memory objects and semaphores exported as file
// descriptors, dma-buf EGL images, fences), the drivers' shader disk caches as the environment
// sets them, and where sdfvj's own program cache and data live.
#include <epoxy/gl.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "app/commands.h"
#include "render/program_cache.h"
#include "render/render.h"
#include "scene/scene.h"

namespace sdfvj {

namespace {

void Line(const char* name, const std::string& value) { std::printf("  %-34s %s\n", name, value.c_str()); }

std::string Yes(bool b) { return b ? "yes" : "no"; }

std::string Env(const char* name) {
    const char* v = std::getenv(name);
    return v ? std::string(v) : "(unset)";
}

}  // namespace

int RunInfo() {
    std::printf("sdfvj info\n");
    HeadlessContext gl;
    std::string error;
    if (!gl.Create(&error)) {
        std::fprintf(stderr, "sdfvj info: %s\n", error.c_str());
        return 2;
    }
    auto str = [](GLenum e) {
        const GLubyte* s = glGetString(e);
        return s ? std::string((const char*)s) : std::string("(none)");
    };
    std::printf("OpenGL (headless, as render and bench open it):\n");
    Line("context", gl.Description());
    Line("GL_VENDOR", str(GL_VENDOR));
    Line("GL_RENDERER", str(GL_RENDERER));
    Line("GL_VERSION", str(GL_VERSION));
    Line("GL_SHADING_LANGUAGE_VERSION", str(GL_SHADING_LANGUAGE_VERSION));
    GLint extensions = 0, binaryFormats = 0;
    glGetIntegerv(GL_NUM_EXTENSIONS, &extensions);
    glGetIntegerv(GL_NUM_PROGRAM_BINARY_FORMATS, &binaryFormats);
    Line("GL extensions", std::to_string(extensions));
    std::printf("What the renderer and reloads use:\n");
    Line("compute shaders (GL 4.3)", Yes(epoxy_gl_version() >= 43 || epoxy_has_gl_extension("GL_ARB_compute_shader")));
    Line("program binary formats", std::to_string(binaryFormats) + (binaryFormats == 0 ? " (no program cache: compiles every launch)" : ""));
    Line("GL_KHR_parallel_shader_compile", Yes(epoxy_has_gl_extension("GL_KHR_parallel_shader_compile")));
    Line("GL_ARB_parallel_shader_compile", Yes(epoxy_has_gl_extension("GL_ARB_parallel_shader_compile")));
    Line("GL_ARB_timer_query", Yes(epoxy_gl_version() >= 33 || epoxy_has_gl_extension("GL_ARB_timer_query")));
    std::printf("Sharing images with another process (a second render process):\n");
    for (const char* e : {"GL_EXT_memory_object", "GL_EXT_memory_object_fd", "GL_EXT_semaphore", "GL_EXT_semaphore_fd",
                          "GL_NV_draw_vulkan_image", "GL_OES_EGL_image", "GL_EXT_EGL_image_storage"})
        Line(e, Yes(epoxy_has_gl_extension(e)));
    for (const char* e : {"EGL_KHR_image_base", "EGL_KHR_gl_texture_2D_image", "EGL_MESA_image_dma_buf_export",
                          "EGL_EXT_image_dma_buf_import", "EGL_KHR_fence_sync", "EGL_ANDROID_native_fence_sync",
                          "EGL_KHR_stream", "EGL_KHR_stream_cross_process_fd", "EGL_IMG_context_priority"})
        Line(e, Yes(gl.HasEglExtension(e)));
    std::printf("Shader disk caches (as this environment sets them):\n");
    Line("MESA_SHADER_CACHE_DISABLE", Env("MESA_SHADER_CACHE_DISABLE"));
    Line("__GL_SHADER_DISK_CACHE", Env("__GL_SHADER_DISK_CACHE"));
    Line("__GL_SHADER_DISK_CACHE_PATH", Env("__GL_SHADER_DISK_CACHE_PATH"));
    std::printf("sdfvj:\n");
    Line("data root", DataRoot());
    const std::string cache = ProgramCacheFolder();
    size_t files = 0;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(cache, ec)) files += entry.is_regular_file(ec) ? 1 : 0;
    Line("program cache", ProgramCacheEnabled() ? cache + " (" + std::to_string(files) + " programs)" : "off (SDFVJ_PROGRAM_CACHE)");
    return 0;
}

}  // namespace sdfvj
