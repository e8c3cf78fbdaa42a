// F11 in `sdfvj live` under Xvfb: a real key press (XTest) takes the window to the screen's size
// and a second one brings it back to its own. The window is watched from outside, through Xlib.
// (X11 headers define None, Bool, Status...: this file includes nothing of sdfvj's but helpers.)
#include "live_util.h"

#include <X11/Xlib.h>
#include <X11/Xutil.h>
#include <X11/Xatom.h>
#include <X11/extensions/XTest.h>
#include <X11/keysym.h>

#include <cstring>

using namespace sdfvj::test;

namespace {

// Other live tests on the same display open and close windows while this one walks the tree: a
// window gone between XQueryTree and the next request is a BadWindow, which Xlib's default handler
// answers by ending the test process. Such a window is simply not ours: ignore the error.
int IgnoreXError(::Display*, XErrorEvent*) { return 0; }

// The process that owns a window (_NET_WM_PID, which GLFW sets), or 0.
long PidOf(::Display* dpy, Window w) {
    const Atom atom = XInternAtom(dpy, "_NET_WM_PID", True);
    if (atom == 0) return 0;   // "None": no client has set it yet
    Atom type = 0;
    int format = 0;
    unsigned long items = 0, after = 0;
    unsigned char* data = nullptr;
    long pid = 0;
    if (XGetWindowProperty(dpy, w, atom, 0, 1, False, XA_CARDINAL, &type, &format, &items, &after, &data) == Success &&
        data && items == 1 && format == 32)
        pid = (long)*reinterpret_cast<unsigned long*>(data);
    if (data) XFree(data);
    return pid;
}

// The viewable top-level window named `name` that process `pid` owns, or 0. ctest runs other
// live tests beside this one on the same display: their windows are called sdfvj too.
Window FindWindow(::Display* dpy, const char* name, long pid) {
    Window root = DefaultRootWindow(dpy), parent = 0, *children = nullptr, found = 0;
    unsigned n = 0;
    if (!XQueryTree(dpy, root, &root, &parent, &children, &n)) return 0;
    for (unsigned i = 0; i < n && !found; ++i) {
        char* title = nullptr;
        XWindowAttributes a;
        if (XFetchName(dpy, children[i], &title) && title) {
            if (std::strcmp(title, name) == 0 && PidOf(dpy, children[i]) == pid &&
                XGetWindowAttributes(dpy, children[i], &a) && a.map_state == IsViewable)
                found = children[i];
            XFree(title);
        }
    }
    if (children) XFree(children);
    return found;
}

struct Size {
    int w = 0, h = 0;
};

Size SizeOf(::Display* dpy, Window w) {
    XWindowAttributes a;
    if (!XGetWindowAttributes(dpy, w, &a)) return {};
    return {a.width, a.height};
}

// A key pressed and released on the window (focus given to it first: Xvfb has no window manager),
// held for `holdMs`; 0 is a tap that press and release reach the show in one poll of events.
void PressKey(::Display* dpy, Window w, KeySym key, int holdMs) {
    XSetInputFocus(dpy, w, RevertToPointerRoot, CurrentTime);
    const KeyCode code = XKeysymToKeycode(dpy, key);
    XTestFakeKeyEvent(dpy, code, True, CurrentTime);
    if (holdMs > 0) XFlush(dpy);
    std::this_thread::sleep_for(std::chrono::milliseconds(holdMs));
    XTestFakeKeyEvent(dpy, code, False, CurrentTime);
    XFlush(dpy);
}

}  // namespace

TEST_CASE("live_fullscreen: F11 takes the window to the screen's size and back (Xvfb, XTest key presses)") {
    const std::string display = sdfvj::test::Display();
    const std::string dir = FreshDir(SDFVJ_LIVE_OUT, "fullscreen"), log = dir + "/live.log", params = dir + "/params.log";
    pid_t pid = Spawn({SDFVJ_BIN, "live", "--scene", "midi", "--size", "320x180", "--seconds", "60", "--path", "fragment",
                       "--effects", "none", "--osc-port", "0", "--midi", "no-such-controller", "--log-params", params},
                      log, {{"DISPLAY", display}, {"JACK_NO_START_SERVER", "1"}});
    ::Display* dpy = XOpenDisplay(display.c_str());
    REQUIRE(dpy != nullptr);
    XSetErrorHandler(IgnoreXError);
    int event = 0, error = 0, major = 0, minor = 0;
    REQUIRE(XTestQueryExtension(dpy, &event, &error, &major, &minor));
    const Screen* screen = DefaultScreenOfDisplay(dpy);
    const Size screenSize{WidthOfScreen(screen), HeightOfScreen(screen)};
    REQUIRE((screenSize.w != 320 || screenSize.h != 180));   // else fullscreen would not show

    Window w = 0;
    INFO(ReadText(log));
    REQUIRE(PollFor(30.0, [&] { return (w = FindWindow(dpy, "sdfvj", (long)pid)) != 0; }));
    CHECK(SizeOf(dpy, w).w == 320);
    CHECK(SizeOf(dpy, w).h == 180);
    // Keys go to a show that runs: wait for frames drawn after each change (one log line a frame).
    auto framesAfter = [&](size_t n) {
        const size_t now = CountInFile(params, "\n");
        REQUIRE(PollFor(30.0, [&] { return CountInFile(params, "\n") >= now + n; }));
    };
    framesAfter(5);

    PressKey(dpy, w, XK_F11, 150);   // held across a few frames
    CHECK(PollFor(10.0, [&] {
        const Size s = SizeOf(dpy, w);
        return s.w == screenSize.w && s.h == screenSize.h;
    }));
    CHECK(PollFor(5.0, [&] { return CountInFile(log, "fullscreen") > 0; }));
    framesAfter(10);

    PressKey(dpy, w, XK_F11, 0);   // a tap inside one frame counts too (sticky keys)
    CHECK(PollFor(10.0, [&] {
        const Size s = SizeOf(dpy, w);
        return s.w == 320 && s.h == 180;
    }));
    CHECK(PollFor(5.0, [&] { return CountInFile(log, "windowed 320x180") > 0; }));

    PressKey(dpy, w, XK_Escape, 0);   // the show ends as a performer ends it, however short the tap
    XCloseDisplay(dpy);
    const int rc = WaitExit(pid, 30);
    INFO(ReadText(log));
    CHECK(rc == 0);
}
