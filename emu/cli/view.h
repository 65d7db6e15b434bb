/* view.h: `pp5 view`, the interactive viewer: a window on the gaze-directed renderer whose sweet spot follows the mouse, a replayed trace or a live tracker, with the emulated Pixel-Planes 5's cost of the same frame in a heads-up display.
 *
 * The parts, each in its own file:
 *   view_state.c    what the keys do (a table, so that new modes are one row),
 *                   the view (rotation, zoom) and the gaze history that the
 *                   replay's latency model reads (no window needed: tested
 *                   directly);
 *   view_gaze.c     gaze from a trace in real time, or a live HID eye tracker
 *                   or Polhemus tracker (a reader thread);
 *   view_machine.c  the emulated machine's cost of the shown frame, on a worker
 *                   thread so that the window never waits for it (and its
 *                   pixels with --machine);
 *   view_frame.c    one frame: the pixels, the sweet-spot circles, the 2D
 *                   mip-map levels (figure 6 as an overlay) and the HUD text,
 *                   drawn with cairo into the window's pixel buffer;
 *   view_sdl.c      the SDL2 window and its event loop;
 *   cmd_view.c      the options. */
#ifndef PP5_VIEW_H
#define PP5_VIEW_H

#include <pthread.h>
#include <stdbool.h>
#include <stdint.h>
#include "render_cmd.h"
#include "tracker/gaze.h"
#include "tracker/replay.h"
#include "tracker/trace_file.h"

/* ---- modes and keys (view_state.c) ---- */

/* One row per rendering mode the `m` key cycles through and its own key
 * selects.  MIP/DEMIP add rows here when render/ has them. */
typedef struct {
    char key;
    const char *name;             /* shown in the HUD */
    render_mode_t mode;
} view_mode_t;

const view_mode_t *view_modes(int *count);

typedef enum {
    VIEW_ACT_NONE, VIEW_ACT_QUIT, VIEW_ACT_MODE, VIEW_ACT_NEXT_MODE, VIEW_ACT_PROGRESSIVE,
    VIEW_ACT_CIRCLES, VIEW_ACT_LEVELS, VIEW_ACT_HUD, VIEW_ACT_SCREENSHOT, VIEW_ACT_RESET,
    VIEW_ACT_ZOOM_IN, VIEW_ACT_ZOOM_OUT, VIEW_ACT_ROT_LEFT, VIEW_ACT_ROT_RIGHT, VIEW_ACT_ROT_UP,
    VIEW_ACT_ROT_DOWN
} view_action_t;

/* The key table as help text, one "KEY  what" line each. */
const char *view_keys_help(void);

/* ---- gaze history: the replay's latency model ---- */

#define VIEW_GAZE_HISTORY 512

typedef struct {
    double t_s[VIEW_GAZE_HISTORY], x[VIEW_GAZE_HISTORY], y[VIEW_GAZE_HISTORY];
    int head, count;
} view_gaze_history_t;

void view_gaze_history_add(view_gaze_history_t *h, double t_s, double x, double y);
/* The gaze the replay's rule gives at time now_s: the newest sample whose
 * arrival (t + latency_s) is at or before now_s; false when none has arrived. */
bool view_gaze_history_at(const view_gaze_history_t *h, double now_s, double latency_s, double *x,
                          double *y);

/* ---- gaze sources (view_gaze.c) ---- */

typedef enum { VIEW_GAZE_MOUSE, VIEW_GAZE_TRACE, VIEW_GAZE_HID, VIEW_GAZE_POLHEMUS } view_gaze_kind_t;

typedef struct {
    view_gaze_kind_t kind;
    const char *spec;             /* as given to --gaze-from */
    int width, height;            /* the image the gaze lands on */
    double view_distance_px;      /* for head pointing (Polhemus) */
    trace_t trace;                /* VIEW_GAZE_TRACE */
    size_t next;                  /* next trace sample to deliver */
    gaze_source_t *live;          /* VIEW_GAZE_HID / _POLHEMUS */
    pthread_t reader;
    bool reader_running, stop;
    pthread_mutex_t lock;
    bool have_sample, have_hand, ended;
    double t0_s;
    gaze_sample_t latest;         /* under lock */
    char error[256];              /* under lock: what stopped the live source */
} view_gaze_t;

/* Opens the source --gaze-from names: "mouse", "hid[:PATH]", "polhemus[:BUS:ADDR]"
 * or a trace file. */
pp5_status_t view_gaze_open(view_gaze_t *g, const char *spec, int width, int height,
                            double view_distance_px);
/* Samples up to now_s (seconds since the viewer started) into the history;
 * a live hand pose (Polhemus station 2) into *rot (degrees) when present. */
void view_gaze_poll(view_gaze_t *g, double now_s, view_gaze_history_t *h, bool *have_rot,
                    float rot[3]);
/* One line for the HUD: what the gaze comes from and its state. */
void view_gaze_describe(view_gaze_t *g, char *buf, size_t n);
void view_gaze_close(view_gaze_t *g);

/* ---- the emulated machine's cost (view_machine.c) ---- */

typedef struct {
    double gaze_x, gaze_y;
    view_params_t view;
    render_mode_t mode;
    bool progressive;
    long frame;                   /* the viewer's frame number */
} view_machine_request_t;

typedef struct {
    bool valid;
    long frame;                   /* which request it answers */
    fw_frame_result_t result;
    image8_t image;               /* with --machine */
} view_machine_answer_t;

typedef struct {
    const render_job_t *job;
    pp5_params_t params;
    fw_options_t opts;
    bool want_image;              /* --machine: the pixels too */
    pthread_t thread;
    bool started;
    pthread_mutex_t lock;
    pthread_cond_t wake, done;
    bool stop, pending, busy;
    view_machine_request_t request;     /* under lock */
    view_machine_answer_t answer;       /* under lock: the newest */
    char status[256];                   /* under lock: setting up, failed, ... */
    bool failed;
} view_machine_t;

pp5_status_t view_machine_start(view_machine_t *m, const render_job_t *job, const render_cmd_t *c,
                                bool want_image);
/* Asks for the cost of a frame; replaces a request not yet taken up. */
void view_machine_request(view_machine_t *m, const view_machine_request_t *r);
/* Waits until the request for `frame` is answered (or the worker failed). */
void view_machine_wait(view_machine_t *m, long frame);
/* A copy of the newest answer (image not copied) and the status line. */
void view_machine_peek(view_machine_t *m, view_machine_answer_t *a, char *status, size_t n,
                       bool *busy);
/* The newest answer's image, moved out to the caller (NULL when none new). */
bool view_machine_take_image(view_machine_t *m, image8_t *img, long *frame);
void view_machine_stop(view_machine_t *m);

/* ---- the viewer (view_frame.c, view_sdl.c) ---- */

#define VIEW_HUD_LINES 8

typedef struct {
    render_cmd_t cmd;             /* the render options (input, choices, machine) */
    const char *gaze_from;        /* "mouse" (default) or a source */
    const char *screenshot;       /* --screenshot FILE */
    int frames;                   /* --frames N: render N frames, save, exit (0: interactive) */
    bool machine_cost;            /* compute the emulated cost (default on) */
    bool latency;                 /* apply the replay's tracker latency to the gaze */
    bool hud, circles, levels;    /* initial overlays */
    const char *screenshot_dir;   /* where the s key saves pp5-view-NNN.png (default .) */
} view_options_t;

typedef struct {
    const view_options_t *opt;
    const render_job_t *job;
    native_renderer_t native;
    view_machine_t machine;
    view_gaze_t gaze;
    view_gaze_history_t history;
    replay_params_t latency;      /* the replay's latency model */
    render_settings_t settings;   /* the current view, mode and gaze */
    view_params_t home;           /* the job's view, for reset */
    int mode_index;
    bool circles, levels, hud, progressive;
    long frame;
    double host_frame_s, host_fps; /* the last frame's host time and the running rate */
    render_stats_t stats;
    image8_t image;               /* the frame's pixels (native or machine) */
    const char *pixels_from;      /* which engine made them */
    long machine_image_frame;
    int screenshots;
    bool shot_pending;            /* the s key: saved after the next picture */
    char hud_text[VIEW_HUD_LINES][400]; /* the HUD's lines as last drawn ("": none) */
    uint32_t *argb;               /* the window's pixels, width x height */
    bool quit;
    double mouse_x, mouse_y;
    bool dragging;
} viewer_t;

/* Applies one action (a key's); returns true when the frame must be redrawn. */
bool viewer_act(viewer_t *v, view_action_t act, char key);
/* The action of a key (SDL key names for the special keys are mapped by
 * view_sdl.c to these characters: 27 escape, 1..4 the arrows). */
view_action_t view_key_action(char key);
/* Dragging with the left button: dx, dy pixels turn the object. */
void viewer_drag(viewer_t *v, int dx, int dy);
/* Renders the frame for the current state and composes the window's pixels. */
pp5_status_t viewer_frame(viewer_t *v, double now_s);
/* Composes the window's pixels again (overlays, HUD) without rendering. */
void viewer_recompose(viewer_t *v);
/* The window's pixels as a PNG. */
pp5_status_t viewer_screenshot(const viewer_t *v, const char *path);
pp5_status_t viewer_init(viewer_t *v, const view_options_t *opt, const render_job_t *job);
void viewer_free(viewer_t *v);
/* The window and its loop (view_sdl.c); PP5_E_UNSUPPORTED without SDL2 or
 * without a display.  v = NULL only checks for those two. */
pp5_status_t viewer_run_window(viewer_t *v);

#endif
