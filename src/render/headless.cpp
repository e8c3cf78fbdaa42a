// Headless EGL context: device platform, then surfaceless, then the default display.
#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <cstdlib>

#include "render/render.h"

namespace sdfvj {

namespace {

// SDFVJ_CONTEXT_PRIORITY=low|medium|high: the EGL_IMG_context_priority level to ask for (0: none
// asked, the driver's default). A render server's spares can draw at low priority so the show's
// own frames go first on a GPU both use (bench reload --modes render-process+SDFVJ_CONTEXT_PRIORITY=low).
EGLint AskedPriority(std::string* name) {
    const char* e = std::getenv("SDFVJ_CONTEXT_PRIORITY");
    *name = e ? e : "";
    if (*name == "low") return EGL_CONTEXT_PRIORITY_LOW_IMG;
    if (*name == "medium") return EGL_CONTEXT_PRIORITY_MEDIUM_IMG;
    if (*name == "high") return EGL_CONTEXT_PRIORITY_HIGH_IMG;
    return 0;
}

const char* PriorityName(EGLint level) {
    return level == EGL_CONTEXT_PRIORITY_LOW_IMG ? "low" : level == EGL_CONTEXT_PRIORITY_MEDIUM_IMG ? "medium"
         : level == EGL_CONTEXT_PRIORITY_HIGH_IMG ? "high" : "unknown";
}

// Tries one display: initialise, pick a config-less GL 4.5 core context, make it current.
// `priority`: what it says about SDFVJ_CONTEXT_PRIORITY (empty when not set).
bool TryDisplay(EGLDisplay dpy, EGLContext* ctx, std::string* why, std::string* priority) {
    if (dpy == EGL_NO_DISPLAY) { *why = "no display"; return false; }
    EGLint major = 0, minor = 0;
    if (!eglInitialize(dpy, &major, &minor)) { *why = "eglInitialize failed"; return false; }
    if (!eglBindAPI(EGL_OPENGL_API)) { *why = "no desktop OpenGL API"; eglTerminate(dpy); return false; }
    const EGLint configAttribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, 0, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint count = 0;
    eglChooseConfig(dpy, configAttribs, &config, 1, &count);   // may be none: then config-less
    std::string askedName;
    const EGLint asked = AskedPriority(&askedName);
    const bool offered = epoxy_has_egl_extension(dpy, "EGL_IMG_context_priority");
    EGLint ctxAttribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                           EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE, 0, EGL_NONE};
    if (asked && offered) {
        ctxAttribs[6] = EGL_CONTEXT_PRIORITY_LEVEL_IMG;
        ctxAttribs[7] = asked;
    }
    *ctx = eglCreateContext(dpy, count > 0 ? config : EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, ctxAttribs);
    if (*ctx == EGL_NO_CONTEXT) { *why = "no OpenGL 4.5 core context"; eglTerminate(dpy); return false; }
    priority->clear();
    if (!askedName.empty()) {
        EGLint got = 0;
        if (!asked) *priority = "context priority '" + askedName + "' ignored, expected low, medium or high";
        else if (!offered) *priority = "context priority " + askedName + " asked, the driver offers none (no EGL_IMG_context_priority)";
        else if (eglQueryContext(dpy, *ctx, EGL_CONTEXT_PRIORITY_LEVEL_IMG, &got))
            *priority = std::string("context priority ") + PriorityName(got) + " (asked " + askedName + ")";
        else *priority = "context priority " + askedName + " asked, the driver does not say what it gave";
    }
    if (!eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, *ctx)) {
        *why = "eglMakeCurrent without a surface failed";
        eglDestroyContext(dpy, *ctx);
        eglTerminate(dpy);
        return false;
    }
    return true;
}

}  // namespace

bool HeadlessContext::Create(std::string* error) {
    std::string tried;
    EGLContext ctx = EGL_NO_CONTEXT;
    auto attempt = [&](const char* name, EGLDisplay dpy) {
        std::string why, priority;
        if (TryDisplay(dpy, &ctx, &why, &priority)) {
            display_ = dpy;
            context_ = ctx;
            description_ = std::string(name) + ": " + (const char*)glGetString(GL_RENDERER) + ", " +
                           (const char*)glGetString(GL_VERSION) + (priority.empty() ? "" : "; " + priority);
            return true;
        }
        tried += std::string(tried.empty() ? "" : "; ") + name + ": " + why;
        return false;
    };
    const bool hasClientExt = epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_platform_base");
    if (hasClientExt && epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_platform_device")) {
        EGLDeviceEXT devices[16];
        EGLint n = 0;
        if (eglQueryDevicesEXT(16, devices, &n)) {
            for (EGLint i = 0; i < n; ++i)
                if (attempt("EGL device platform", eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr)))
                    return true;
        }
    }
    if (hasClientExt && epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless")) {
        if (attempt("EGL surfaceless platform", eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr)))
            return true;
    }
    if (attempt("EGL default display", eglGetDisplay(EGL_DEFAULT_DISPLAY))) return true;
    *error = "no OpenGL 4.5 available through EGL (" + (tried.empty() ? std::string("no EGL platform") : tried) + ")";
    return false;
}

bool HeadlessContext::CreateShared(const HeadlessContext& main, std::string* error, bool share) {
    if (!main.display_) {
        *error = "no main context to share with";
        return false;
    }
    const EGLint ctxAttribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                 EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    EGLContext ctx = eglCreateContext((EGLDisplay)main.display_, EGL_NO_CONFIG_KHR,
                                      share ? (EGLContext)main.context_ : EGL_NO_CONTEXT, ctxAttribs);
    if (ctx == EGL_NO_CONTEXT) {
        *error = "cannot create a shared OpenGL context";
        return false;
    }
    display_ = main.display_;
    context_ = ctx;
    shared_ = true;
    description_ = main.description_ + (share ? " (shared)" : " (second context)");
    return true;
}

bool HeadlessContext::HasEglExtension(const char* name) const {
    return display_ && epoxy_has_egl_extension((EGLDisplay)display_, name);
}

bool HeadlessContext::MakeCurrent() {
    return display_ && eglMakeCurrent((EGLDisplay)display_, EGL_NO_SURFACE, EGL_NO_SURFACE, (EGLContext)context_);
}

void HeadlessContext::ReleaseCurrent() {
    if (!display_) return;
    eglMakeCurrent((EGLDisplay)display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglReleaseThread();
}

HeadlessContext::~HeadlessContext() {
    if (!display_) return;
    if (shared_) {   // the display belongs to the main context
        eglDestroyContext((EGLDisplay)display_, (EGLContext)context_);
        return;
    }
    eglMakeCurrent((EGLDisplay)display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext((EGLDisplay)display_, (EGLContext)context_);
    eglTerminate((EGLDisplay)display_);
}

}  // namespace sdfvj
