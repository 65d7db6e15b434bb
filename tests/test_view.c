/* test_view.c: `pp5 view` as a user meets it, on a virtual X display (Xvfb):
 * the pointer is moved and keys are pressed through the XTEST extension, as
 * a person's mouse and keyboard would, and the effects are read from the
 * viewer's own screenshots: the yellow 12-degree circle is centred on the
 * pointer and follows it; full-resolution mode has no sweet spot (no circle);
 * q and closing the window end the program with status 0; with no display it
 * says so and fails cleanly.  Plus the key table and the latency rule, which
 * need no window. */
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "emu/cli/view.h"
#include "emu/util/status.h"
#include "harness.h"
#include "png_io.h"

#if PP5_HAVE_XTEST
#include <X11/Xlib.h>
#include <X11/Xutil.h>
#include <X11/extensions/XTest.h>
#include <X11/keysym.h>
#endif

TEST(view_keys_and_modes_table)
{
    int n;
    const view_mode_t *m = view_modes(&n);
    REQUIRE(n >= 2);
    /* Every mode's key selects it, and no two keys clash. */
    for (int i = 0; i < n; i++)
        CHECK_EQ(view_key_action(m[i].key), VIEW_ACT_MODE);
    CHECK_EQ(view_key_action('q'), VIEW_ACT_QUIT);
    CHECK_EQ(view_key_action(27), VIEW_ACT_QUIT);
    CHECK_EQ(view_key_action('p'), VIEW_ACT_PROGRESSIVE);
    CHECK_EQ(view_key_action('x'), VIEW_ACT_NONE);
    CHECK(strstr(view_keys_help(), "gaze-directed mode") != NULL);
}

TEST(view_gaze_history_follows_the_replay_latency_rule)
{
    /* Samples at 0, 10, 20, ... ms; with 33 ms of latency, at 100 ms the
     * newest arrived sample is the one from 60 ms (60 + 33 <= 100 < 70 + 33). */
    view_gaze_history_t h;
    memset(&h, 0, sizeof h);
    for (int k = 0; k <= 10; k++)
        view_gaze_history_add(&h, k * 0.010, k, -k);
    double x, y;
    REQUIRE(view_gaze_history_at(&h, 0.100, 0.033, &x, &y));
    CHECK_NEAR(x, 6, 0);
    CHECK_NEAR(y, -6, 0);
    REQUIRE(view_gaze_history_at(&h, 0.100, 0.0, &x, &y));
    CHECK_NEAR(x, 10, 0);
    CHECK(!view_gaze_history_at(&h, 0.020, 0.033, &x, &y));   /* nothing has arrived yet */
}

TEST(view_without_a_display_says_so)
{
    const char *dir = pp5_test_outdir();
    char err[1200];
    snprintf(err, sizeof err, "%s/err.txt", dir);
    char args[1400];
    /* env -u DISPLAY: the shell that runs pp5 has no display. */
    snprintf(args, sizeof args, "view --phantom sphere-shell");
    char cmd[4096];
    const char *bin = getenv("PP5_BIN") ? getenv("PP5_BIN") : "./pp5";
    snprintf(cmd, sizeof cmd, "env -u DISPLAY -u WAYLAND_DISPLAY %s %s >/dev/null 2>%s", bin, args,
             err);
    int status = system(cmd);
    REQUIRE(status != -1);
    /* Not available here (exit 7), as a feature not built in would be. */
    CHECK_MSG(WIFEXITED(status) && WEXITSTATUS(status) == PP5_EXIT_UNSUPPORTED, "status %d", status);
    char *text = pp5_test_read_file(err);
    CHECK_MSG(text && strstr(text, "no display") && strstr(text, "xvfb-run"), "stderr: %s",
              text ? text : "(none)");
    free(text);
}

#if PP5_HAVE_XTEST

typedef struct {
    pid_t xvfb, viewer;
    Display *dpy;
    char display[16];
    char dir[1024];
} xsession_t;

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void sleep_s(double s)
{
    struct timespec ts = {(time_t)s, (long)((s - (double)(time_t)s) * 1e9)};
    nanosleep(&ts, NULL);
}

static pid_t spawn(const char *cmd)
{
    pid_t pid = fork();
    if (pid == 0) {
        execl("/bin/sh", "sh", "-c", cmd, (char *)NULL);
        _exit(127);
    }
    return pid;
}

/* Exit status of pid within timeout_s, or -1 (then it is killed). */
static int wait_exit(pid_t pid, double timeout_s)
{
    double end = now_s() + timeout_s;
    int status;
    while (now_s() < end) {
        pid_t r = waitpid(pid, &status, WNOHANG);
        if (r == pid)
            return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        sleep_s(0.05);
    }
    kill(pid, SIGKILL);
    waitpid(pid, &status, 0);
    return -1;
}

/* Whether an X server holds the display of this lock file: one left by a
 * server that was killed (its process gone) does not count; Xvfb replaces it. */
static bool display_taken(const char *lock)
{
    FILE *f = fopen(lock, "r");
    if (!f)
        return access(lock, F_OK) == 0;
    long pid = 0;
    bool read = fscanf(f, "%ld", &pid) == 1;
    fclose(f);
    return !read || pid <= 0 || kill((pid_t)pid, 0) == 0 || errno != ESRCH;
}

/* A private Xvfb on the first free display number from 71. */
static bool start_xvfb(xsession_t *x)
{
    if (system("command -v Xvfb >/dev/null 2>&1") != 0)
        SKIP("Xvfb is not installed (Debian package xvfb; make test installs it as root)");
    for (int n = 71; n < 99; n++) {
        char lock[64], cmd[256];
        snprintf(lock, sizeof lock, "/tmp/.X%d-lock", n);
        if (display_taken(lock))
            continue;
        snprintf(x->display, sizeof x->display, ":%d", n);
        snprintf(cmd, sizeof cmd, "exec Xvfb %s -screen 0 800x600x24 -nolisten tcp "
                 ">/dev/null 2>&1", x->display);
        x->xvfb = spawn(cmd);
        for (double end = now_s() + 10; now_s() < end; sleep_s(0.1)) {
            x->dpy = XOpenDisplay(x->display);
            if (x->dpy)
                return true;
        }
        kill(x->xvfb, SIGTERM);
        wait_exit(x->xvfb, 5);
    }
    return false;
}

/* Ends the session: the viewer (killed if it still runs: a failed check
 * must not leave it or the server behind), then the X server. */
static void stop_xvfb(xsession_t *x)
{
    if (x->viewer > 0 && waitpid(x->viewer, NULL, WNOHANG) == 0) {
        kill(x->viewer, SIGKILL);
        waitpid(x->viewer, NULL, 0);
    }
    x->viewer = 0;
    if (x->dpy)
        XCloseDisplay(x->dpy);
    if (x->xvfb > 0) {
        kill(x->xvfb, SIGTERM);
        wait_exit(x->xvfb, 5);
    }
}

static Window find_named(Display *d, Window w, const char *prefix)
{
    char *name = NULL;
    if (XFetchName(d, w, &name) && name) {
        bool hit = strncmp(name, prefix, strlen(prefix)) == 0;
        XFree(name);
        if (hit)
            return w;
    }
    Window root, parent, *kids = NULL;
    unsigned n = 0;
    Window found = 0;
    if (XQueryTree(d, w, &root, &parent, &kids, &n)) {
        for (unsigned i = 0; i < n && !found; i++)
            found = find_named(d, kids[i], prefix);
        XFree(kids);
    }
    return found;
}

/* The viewer's window, once it is mapped (the first frame can take a while
 * on a shared machine), and its top-left corner on the screen. */
static Window wait_window(xsession_t *x, int *ox, int *oy)
{
    for (double end = now_s() + 60; now_s() < end; sleep_s(0.2)) {
        Window w = find_named(x->dpy, DefaultRootWindow(x->dpy), "pp5 view");
        XWindowAttributes a;
        if (w && XGetWindowAttributes(x->dpy, w, &a) && a.map_state == IsViewable) {
            Window child;
            XTranslateCoordinates(x->dpy, w, DefaultRootWindow(x->dpy), 0, 0, ox, oy, &child);
            return w;
        }
        if (waitpid(x->viewer, NULL, WNOHANG) == x->viewer)
            return 0;
    }
    return 0;
}

static void key(xsession_t *x, KeySym sym)
{
    KeyCode k = XKeysymToKeycode(x->dpy, sym);
    XTestFakeKeyEvent(x->dpy, k, True, 0);
    XTestFakeKeyEvent(x->dpy, k, False, 0);
    XFlush(x->dpy);
}

/* Presses s and reads the screenshot it saves (number n). */
static bool screenshot(xsession_t *x, int n, image8_t *img)
{
    key(x, XK_s);
    char path[1200];
    snprintf(path, sizeof path, "%s/pp5-view-%03d.png", x->dir, n);
    for (double end = now_s() + 60; now_s() < end; sleep_s(0.1))
        if (access(path, F_OK) == 0)
            return png_read(path, img, 3) == PP5_OK;
    return false;
}

/* Centre of the yellow pixels (the 12-degree circle); false when none. */
static bool yellow_centre(const image8_t *img, double *cx, double *cy)
{
    double sx = 0, sy = 0;
    long n = 0;
    for (int y = 0; y < img->height; y++)
        for (int x = 0; x < img->width; x++) {
            const uint8_t *p = img->pixels + ((size_t)y * img->width + x) * 3;
            if (p[0] > 200 && p[1] > 200 && p[2] < 60) {
                sx += x;
                sy += y;
                n++;
            }
        }
    if (n < 20)
        return false;
    *cx = sx / (double)n;
    *cy = sy / (double)n;
    return true;
}

/* Starts the viewer on a small generated phantom with its screenshots in
 * the test's folder; no HUD (it would cover pixels) and no emulator. */
static bool start_viewer(xsession_t *x, int *ox, int *oy, Window *w)
{
    const char *bin = getenv("PP5_BIN") ? getenv("PP5_BIN") : "./pp5";
    char cmd[8192];
    snprintf(cmd, sizeof cmd, "%s volume phantom shepp-logan --size 48x48x40 --out %s/sl.nrrd "
             ">/dev/null", bin, x->dir);
    if (system(cmd) != 0)
        return false;
    snprintf(cmd, sizeof cmd,
             "LSAN_OPTIONS=\"suppressions=$PWD/tests/fixtures/view/lsan.supp:print_suppressions=0\" "
             /* SDL unloads the X11 libraries it opened at SDL_Quit, so LeakSanitizer
              * cannot name (or suppress) their allocations: leak checks are off
              * for the windowed viewer; the offscreen test below keeps them on
              * for the same frames, overlays and HUD. */
             "ASAN_OPTIONS=\"${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0\" "
             "DISPLAY=%s exec %s view --volume %s/sl.nrrd --tf shepp-logan --size 200x200 "
             "--no-hud --no-machine-cost --no-latency --threads 1 --screenshot-dir %s "
             ">%s/out.txt 2>%s/err.txt", x->display, bin, x->dir, x->dir, x->dir, x->dir);
    x->viewer = spawn(cmd);
    *w = wait_window(x, ox, oy);
    return *w != 0;
}

static void move_pointer(xsession_t *x, int ox, int oy, int px, int py)
{
    XTestFakeMotionEvent(x->dpy, -1, ox + px, oy + py, 0);
    XFlush(x->dpy);
    sleep_s(0.3);
}

/* Moves the pointer to (px, py) in the window and takes screenshots until
 * the circle is centred there (at most 4 tries); false when it never is. */
static bool pointer_shot(xsession_t *x, int ox, int oy, int px, int py, int *shot, image8_t *img,
                         double *cx, double *cy)
{
    for (int attempt = 0; attempt < 4; attempt++) {
        if (attempt > 0)   /* a motion to where the pointer already is makes no event */
            move_pointer(x, ox, oy, px + 7, py + 7);
        move_pointer(x, ox, oy, px, py);
        image8_free(img);
        if (!screenshot(x, ++*shot, img))
            return false;
        if (yellow_centre(img, cx, cy) && fabs(*cx - px) < 2 && fabs(*cy - py) < 2)
            return true;
    }
    return false;
}

TEST(view_under_xvfb_follows_the_mouse_switches_mode_and_quits)
{
    xsession_t x;
    memset(&x, 0, sizeof x);
    snprintf(x.dir, sizeof x.dir, "%s", pp5_test_outdir());
    REQUIRE_MSG(start_xvfb(&x), "could not start Xvfb");
    int ox = 0, oy = 0;
    Window w;
    bool up = start_viewer(&x, &ox, &oy, &w);
    char errp[1200];
    snprintf(errp, sizeof errp, "%s/err.txt", x.dir);
    if (!up) {
        char *e = pp5_test_read_file(errp);
        CHECK_MSG(up, "no viewer window; stderr: %s", e ? e : "(none)");
        free(e);
        stop_xvfb(&x);
        return;
    }
    image8_t a = {0}, b = {0}, c = {0}, d = {0};
    double ax = NAN, ay = NAN, bx = NAN, by = NAN, dx, dy;
    int shot = 0;
    /* The circle's centre is the pointer's pixel.  The first motion can reach
     * the window before SDL has taken the pointer in (a loaded machine):
     * the pointer is moved again, a few times at most. */
    bool first = pointer_shot(&x, ox, oy, 60, 70, &shot, &a, &ax, &ay);
    CHECK_MSG(first, "first circle at (%.1f, %.1f), pointer at (60, 70)", ax, ay);
    bool second = pointer_shot(&x, ox, oy, 140, 120, &shot, &b, &bx, &by);
    CHECK_MSG(second, "second circle at (%.1f, %.1f), pointer at (140, 120)", bx, by);
    /* f: full resolution everywhere, no sweet spot to draw; g brings it back. */
    key(&x, XK_f);
    bool got = screenshot(&x, ++shot, &c);
    CHECK_MSG(got, "no screenshot after f");
    CHECK_MSG(got && !yellow_centre(&c, &dx, &dy), "full mode still shows a circle");
    key(&x, XK_g);
    got = screenshot(&x, ++shot, &d);
    CHECK_MSG(got && yellow_centre(&d, &dx, &dy), "no circle after g (screenshot %s)",
              got ? "taken" : "missing");
    /* The picture itself changed with the mode (outside the circles too). */
    long differ = 0;
    for (size_t i = 0; i < (size_t)200 * 200 * 3 && c.pixels && b.pixels; i++)
        differ += c.pixels[i] != b.pixels[i];
    CHECK_MSG(differ > 1000, "full and gaze-directed frames differ in %ld values", differ);
    key(&x, XK_q);
    int rc = wait_exit(x.viewer, 30);
    x.viewer = 0;   /* waited for (or killed) */
    char *e = pp5_test_read_file(errp);
    CHECK_MSG(rc == 0, "q: exit status %d; stderr: %s", rc, e ? e : "(none)");
    free(e);
    image8_free(&a);
    image8_free(&b);
    image8_free(&c);
    image8_free(&d);
    stop_xvfb(&x);
}

TEST(view_under_xvfb_exits_cleanly_when_its_window_is_closed)
{
    xsession_t x;
    memset(&x, 0, sizeof x);
    snprintf(x.dir, sizeof x.dir, "%s", pp5_test_outdir());
    REQUIRE_MSG(start_xvfb(&x), "could not start Xvfb");
    int ox, oy;
    Window w;
    if (!start_viewer(&x, &ox, &oy, &w)) {
        CHECK_MSG(false, "no viewer window");
        stop_xvfb(&x);
        return;
    }
    /* What a window manager's close button sends: WM_DELETE_WINDOW. */
    XEvent ev;
    memset(&ev, 0, sizeof ev);
    ev.xclient.type = ClientMessage;
    ev.xclient.window = w;
    ev.xclient.message_type = XInternAtom(x.dpy, "WM_PROTOCOLS", False);
    ev.xclient.format = 32;
    ev.xclient.data.l[0] = (long)XInternAtom(x.dpy, "WM_DELETE_WINDOW", False);
    ev.xclient.data.l[1] = CurrentTime;
    XSendEvent(x.dpy, w, False, NoEventMask, &ev);
    XFlush(x.dpy);
    int rc = wait_exit(x.viewer, 30);
    x.viewer = 0;   /* waited for (or killed) */
    char errp[1200];
    snprintf(errp, sizeof errp, "%s/err.txt", x.dir);
    char *e = pp5_test_read_file(errp);
    CHECK_MSG(rc == 0, "close: exit status %d; stderr: %s", rc, e ? e : "(none)");
    free(e);
    stop_xvfb(&x);
}

#endif

TEST(view_screenshot_frames_writes_the_picture_and_the_machines_figures)
{
    const char *dir = pp5_test_outdir();
    char args[4096], out[1200], png[1200];
    snprintf(png, sizeof png, "%s/shot.png", dir);
    snprintf(out, sizeof out, "%s/out.txt", dir);
    snprintf(args, sizeof args, "volume phantom sphere-shell --size 32x32x32 --out %s/s.nrrd", dir);
    REQUIRE(pp5_test_run_cli(args, NULL, NULL) == 0);
    /* No display: the frames are rendered without a window. */
    snprintf(args, sizeof args, "view --volume %s/s.nrrd --tf sphere-shell --size 128x96 "
             "--frames 2 --screenshot %s", dir, png);
    char cmd[8192];
    const char *bin = getenv("PP5_BIN") ? getenv("PP5_BIN") : "./pp5";
    snprintf(cmd, sizeof cmd, "env -u DISPLAY -u WAYLAND_DISPLAY %s %s >%s 2>/dev/null", bin, args,
             out);
    int status = system(cmd);
    CHECK_MSG(WIFEXITED(status) && WEXITSTATUS(status) == 0, "status %d", status);
    image8_t img;
    REQUIRE(png_read(png, &img, 3) == PP5_OK);
    CHECK(img.width == 128 && img.height == 96);
    image8_free(&img);
    char *text = pp5_test_read_file(out);
    /* The HUD's figures of the last frame: the emulated frame time, and the
     * latency that adds up the replay's tracker and display terms around it. */
    CHECK_MSG(text && strstr(text, "hud: emulated Pixel-Planes 5: ") &&
                  strstr(text, " ms (") && strstr(text, "tracker 33 + frame "),
              "stdout: %s", text ? text : "(none)");
    free(text);
}

/* Progress lines (emu/util/progress.h): on a terminal a long build shows one;
 * with stderr in a file, or with --quiet, there is none.  `script` (bsdutils,
 * in every Debian) gives the run a terminal. */
TEST(progress_lines_only_on_a_terminal_and_not_with_quiet)
{
    const char *dir = pp5_test_outdir();
    const char *bin = getenv("PP5_BIN") ? getenv("PP5_BIN") : "./pp5";
    char cmd[4096], path[1200];
    /* Lines appear at once (no half-second wait), so small work shows them. */
    const char *work = "render --phantom sphere-shell --size 32x32";
    setenv("PP5_PROGRESS_DELAY_S", "0", 1);
    snprintf(path, sizeof path, "%s/err.txt", dir);
    snprintf(cmd, sizeof cmd, "%s %s >/dev/null 2>%s", bin, work, path);
    REQUIRE(system(cmd) == 0);
    char *text = pp5_test_read_file(path);
    CHECK_MSG(text && strstr(text, "3D mip map") == NULL && strchr(text, '\r') == NULL,
              "stderr to a file: %s", text ? text : "(none)");
    free(text);
    if (system("command -v script >/dev/null 2>&1") != 0)
        SKIP("script (bsdutils) is not installed: cannot give pp5 a terminal");
    snprintf(path, sizeof path, "%s/tty.txt", dir);
    snprintf(cmd, sizeof cmd, "script -qec '%s %s' /dev/null >%s 2>&1", bin, work, path);
    REQUIRE(system(cmd) == 0);
    text = pp5_test_read_file(path);
    CHECK_MSG(text && strstr(text, "\r3D mip map: ") && strstr(text, "done in"),
              "on a terminal: %.300s", text ? text : "(none)");
    free(text);
    snprintf(cmd, sizeof cmd, "script -qec '%s %s --quiet' /dev/null >%s 2>&1", bin, work, path);
    REQUIRE(system(cmd) == 0);
    text = pp5_test_read_file(path);
    CHECK_MSG(text && strstr(text, "done in") == NULL, "--quiet: %.300s", text ? text : "(none)");
    free(text);
    unsetenv("PP5_PROGRESS_DELAY_S");
}
