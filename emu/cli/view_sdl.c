/* view_sdl.c: the viewer's SDL2 window: events in (mouse, keys, window close), frames out (view.h).
 *
 * A frame is rendered only when something changed (the gaze, the view, a
 * key, progressive refinement still growing); otherwise the loop sleeps
 * 15 ms between looks at the event queue and redraws the HUD now and then,
 * so that an idle viewer does not take a shared machine's cores. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "pp5_features.h"
#include "view.h"

#if PP5_HAVE_SDL2
#include <SDL.h>

static double now_since(double t0)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec - t0;
}

/* SDL's key symbols as the characters of the key table (view_state.c). */
static char key_char(SDL_Keycode k)
{
    switch (k) {
    case SDLK_ESCAPE: return 27;
    case SDLK_LEFT: return 1;
    case SDLK_RIGHT: return 2;
    case SDLK_UP: return 3;
    case SDLK_DOWN: return 4;
    case SDLK_KP_PLUS: return '+';
    case SDLK_KP_MINUS: return '-';
    default: return k > 0 && k < 127 ? (char)k : 0;
    }
}

typedef struct {
    SDL_Window *window;
    bool dirty;
    int last_mx, last_my;
    double last_hud_s;
} window_state_t;

static pp5_status_t save_numbered(viewer_t *v)
{
    char path[1200], tmp[1300];
    const char *dir = v->opt->screenshot_dir ? v->opt->screenshot_dir : ".";
    snprintf(path, sizeof path, "%s/pp5-view-%03d.png", dir, ++v->screenshots);
    snprintf(tmp, sizeof tmp, "%s.part.png", path);
    pp5_status_t st = viewer_screenshot(v, tmp);
    if (st == PP5_OK && rename(tmp, path) != 0)
        st = pp5_fail(PP5_E_IO, "%s: cannot save the screenshot", path);
    if (st == PP5_OK)
        printf("view: saved %s\n", path);
    else
        fprintf(stderr, "pp5 view: %s\n", pp5_error_text());
    fflush(stdout);
    return st;
}

static void handle_event(viewer_t *v, window_state_t *w, const SDL_Event *e)
{
    switch (e->type) {
    case SDL_QUIT: v->quit = true; break;
    case SDL_WINDOWEVENT:
        if (e->window.event == SDL_WINDOWEVENT_CLOSE)
            v->quit = true;
        else if (e->window.event == SDL_WINDOWEVENT_EXPOSED)
            w->dirty = true;
        break;
    case SDL_MOUSEMOTION:
        if (v->dragging)
            viewer_drag(v, e->motion.xrel, e->motion.yrel);
        v->mouse_x = e->motion.x;
        v->mouse_y = e->motion.y;
        w->dirty = true;
        break;
    case SDL_MOUSEBUTTONDOWN:
    case SDL_MOUSEBUTTONUP:
        if (e->button.button == SDL_BUTTON_LEFT)
            v->dragging = e->type == SDL_MOUSEBUTTONDOWN;
        break;
    case SDL_MOUSEWHEEL:
        w->dirty |= viewer_act(v, e->wheel.y > 0 ? VIEW_ACT_ZOOM_IN : VIEW_ACT_ZOOM_OUT, 0);
        break;
    case SDL_KEYDOWN: {
        char k = key_char(e->key.keysym.sym);
        view_action_t act = view_key_action(k);
        if (act == VIEW_ACT_SCREENSHOT)
            v->shot_pending = w->dirty = true;   /* of the picture that follows the events */
        else
            w->dirty |= viewer_act(v, act, k);
        break;
    }
    default: break;
    }
}

static pp5_status_t show(viewer_t *v, window_state_t *w)
{
    SDL_Surface *dst = SDL_GetWindowSurface(w->window);
    int W = v->settings.width, H = v->settings.height;
    SDL_Surface *src = SDL_CreateRGBSurfaceWithFormatFrom(v->argb, W, H, 32, W * 4,
                                                          SDL_PIXELFORMAT_RGB888);
    if (!dst || !src) {
        SDL_FreeSurface(src);
        return pp5_fail(PP5_E_IO, "view: SDL: %s", SDL_GetError());
    }
    SDL_BlitSurface(src, NULL, dst, NULL);
    SDL_FreeSurface(src);
    SDL_UpdateWindowSurface(w->window);
    return PP5_OK;
}

/* Whether the next frame must be rendered (not only its HUD redrawn). */
static bool wants_frame(const viewer_t *v, window_state_t *w)
{
    bool moving_source = v->gaze.kind != VIEW_GAZE_MOUSE && !v->gaze.ended;
    bool refining = v->progressive && !v->stats.full_resolution_everywhere;
    /* The mouse gaze lags by the tracker latency: one more frame after it stops. */
    bool settling = v->gaze.kind == VIEW_GAZE_MOUSE && v->opt->latency &&
                    (fabs(v->settings.gaze_x - v->mouse_x) > 0.5 ||
                     fabs(v->settings.gaze_y - v->mouse_y) > 0.5);
    return w->dirty || moving_source || refining || settling || v->frame == 0 ||
           v->opt->frames > 0;
}

static pp5_status_t loop(viewer_t *v, window_state_t *w, double t0)
{
    pp5_status_t st = PP5_OK;
    while (st == PP5_OK && !v->quit) {
        /* Polling, not SDL_WaitEventTimeout: events that Xlib has already read
         * off the connection do not wake a wait on it (seen as events taken
         * in only when the next one arrived); SDL_PollEvent pumps them. */
        SDL_Event e;
        bool any = false;
        while (SDL_PollEvent(&e)) {
            handle_event(v, w, &e);
            any = true;
        }
        if (!any && !wants_frame(v, w))
            SDL_Delay(15);
        if (v->quit)
            break;
        double now = now_since(t0);
        if (wants_frame(v, w)) {
            w->dirty = false;
            st = viewer_frame(v, now);
        } else if (now - w->last_hud_s > 0.25) {
            viewer_recompose(v);   /* the machine's figure may have arrived */
        } else {
            continue;
        }
        w->last_hud_s = now;
        if (st == PP5_OK)
            st = show(v, w);
        if (st == PP5_OK && v->shot_pending) {
            v->shot_pending = false;
            save_numbered(v);
        }
        if (st == PP5_OK && v->opt->frames > 0 && v->frame >= v->opt->frames) {
            if (v->opt->screenshot)
                st = viewer_screenshot(v, v->opt->screenshot);
            v->quit = true;
        }
    }
    return st;
}

pp5_status_t viewer_run_window(viewer_t *v)
{
    const char *x11 = getenv("DISPLAY"), *wl = getenv("WAYLAND_DISPLAY");
    if ((!x11 || !*x11) && (!wl || !*wl))
        return pp5_fail(PP5_E_UNSUPPORTED, "no display: DISPLAY and WAYLAND_DISPLAY are not set. "
                        "Run pp5 view in a desktop session (ssh -X works), or under a virtual "
                        "display (xvfb-run pp5 view ...), or give --screenshot FILE to render "
                        "without a window");
    if (!v)
        return PP5_OK;   /* only the check */
    /* The window's pixels are composed by us (cairo), so the window surface
     * is X11's own framebuffer, not a GL texture: with software GL (Mesa's
     * llvmpipe on Xvfb or over ssh -X) that path added renderer threads, and
     * under AddressSanitizer the window took in events late or not at all
     * in about half the runs; with the native framebuffer it never did.  The
     * environment variable SDL_FRAMEBUFFER_ACCELERATION still overrides. */
    SDL_SetHint(SDL_HINT_FRAMEBUFFER_ACCELERATION, "0");
    if (SDL_Init(SDL_INIT_VIDEO) != 0)
        return pp5_fail(PP5_E_UNSUPPORTED, "cannot open a window on display '%s': %s",
                        x11 && *x11 ? x11 : wl, SDL_GetError());
    char title[700];
    snprintf(title, sizeof title, "pp5 view: %s", v->job->volume_name);
    window_state_t w;
    memset(&w, 0, sizeof w);
    w.dirty = true;
    w.window = SDL_CreateWindow(title, SDL_WINDOWPOS_UNDEFINED, SDL_WINDOWPOS_UNDEFINED,
                                v->settings.width, v->settings.height, SDL_WINDOW_SHOWN);
    pp5_status_t st = PP5_OK;
    if (!w.window)
        st = pp5_fail(PP5_E_UNSUPPORTED, "cannot open a window: %s", SDL_GetError());
    if (st == PP5_OK)
        st = loop(v, &w, now_since(0));
    if (w.window)
        SDL_DestroyWindow(w.window);
    SDL_Quit();
    return st;
}

#else

pp5_status_t viewer_run_window(viewer_t *v)
{
    (void)v;
    return pp5_fail(PP5_E_UNSUPPORTED, "this pp5 was built without SDL2: install libsdl2-dev "
                    "(make deps) and run make again");
}

#endif
