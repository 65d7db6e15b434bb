/* view_gaze.c: where the viewer's gaze comes from besides the mouse: a trace replayed in real time, or a live HID eye tracker or Polhemus tracker read on a thread (view.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tracker/hid_eye.h"
#include "tracker/polhemus.h"
#include "view.h"

#define LIVE_TIMEOUT_MS 1000

static void *reader_main(void *arg)
{
    view_gaze_t *g = arg;
    for (;;) {
        pthread_mutex_lock(&g->lock);
        bool stop = g->stop;
        pthread_mutex_unlock(&g->lock);
        if (stop)
            break;
        gaze_sample_t s;
        bool got = false;
        pp5_status_t st = gaze_source_next(g->live, &s, &got);
        pthread_mutex_lock(&g->lock);
        if (st != PP5_OK || !got) {
            snprintf(g->error, sizeof g->error, "%s", st != PP5_OK ? pp5_error_text()
                                                                   : "the device closed");
            g->ended = true;
            pthread_mutex_unlock(&g->lock);
            break;
        }
        g->latest = s;
        g->have_sample = true;
        pthread_mutex_unlock(&g->lock);
    }
    return NULL;
}

static pp5_status_t open_live(view_gaze_t *g, const char *spec)
{
    const char *colon = strchr(spec, ':');
    const char *where = colon ? colon + 1 : NULL;
    pp5_status_t st;
    if (g->kind == VIEW_GAZE_HID) {
        hid_eye_t *d = NULL;
        st = hid_eye_open(where, LIVE_TIMEOUT_MS, &d);
        if (st == PP5_OK)
            st = hid_eye_source_open(d, g->width, g->height, &g->live);
    } else {
        polhemus_t *p = NULL;
        st = polhemus_open(where, LIVE_TIMEOUT_MS, &p);
        if (st == PP5_OK)
            st = polhemus_source_open(p, 1, 2, 60.0, &g->live);
    }
    if (st != PP5_OK)
        return pp5_fail(st, "--gaze-from %s: %s (see pp5 track list)", spec, pp5_error_text());
    if (pthread_create(&g->reader, NULL, reader_main, g) != 0)
        return pp5_fail(PP5_E_IO, "--gaze-from %s: cannot start the reader thread", spec);
    g->reader_running = true;
    return PP5_OK;
}

pp5_status_t view_gaze_open(view_gaze_t *g, const char *spec, int width, int height,
                            double view_distance_px)
{
    memset(g, 0, sizeof *g);
    pthread_mutex_init(&g->lock, NULL);
    trace_init(&g->trace);
    g->spec = spec;
    g->width = width;
    g->height = height;
    g->view_distance_px = view_distance_px;
    if (strcmp(spec, "mouse") == 0) {
        g->kind = VIEW_GAZE_MOUSE;
        return PP5_OK;
    }
    if (strncmp(spec, "hid", 3) == 0 && (spec[3] == '\0' || spec[3] == ':')) {
        g->kind = VIEW_GAZE_HID;
        return open_live(g, spec);
    }
    if (strncmp(spec, "polhemus", 8) == 0 && (spec[8] == '\0' || spec[8] == ':')) {
        g->kind = VIEW_GAZE_POLHEMUS;
        return open_live(g, spec);
    }
    g->kind = VIEW_GAZE_TRACE;
    pp5_status_t st = trace_read_file(spec, &g->trace);
    if (st != PP5_OK)
        return st;
    if (g->trace.count < 1)
        return pp5_fail(PP5_E_FORMAT, "--gaze-from %s: the trace has no samples", spec);
    if (g->trace.header.geometry.width_px < 1 || g->trace.header.geometry.height_px < 1)
        return pp5_fail(PP5_E_FORMAT, "--gaze-from %s: the trace names no screen size", spec);
    return PP5_OK;
}

/* A trace's pixels scaled onto the image (the same fraction of the screen). */
static void trace_to_image(const view_gaze_t *g, const gaze_sample_t *s, double *x, double *y)
{
    *x = s->x_px / g->trace.header.geometry.width_px * g->width;
    *y = s->y_px / g->trace.header.geometry.height_px * g->height;
}

static void poll_trace(view_gaze_t *g, double now_s, view_gaze_history_t *h)
{
    int64_t t0 = g->trace.samples[0].t_ns;
    while (g->next < g->trace.count) {
        const gaze_sample_t *s = &g->trace.samples[g->next];
        double t = (double)(s->t_ns - t0) * 1e-9;
        if (t > now_s)
            break;
        g->next++;
        if (s->flags & GAZE_FLAG_VALID) {
            double x, y;
            trace_to_image(g, s, &x, &y);
            view_gaze_history_add(h, t, x, y);
        }
    }
    g->ended = g->next >= g->trace.count;
}

void view_gaze_poll(view_gaze_t *g, double now_s, view_gaze_history_t *h, bool *have_rot,
                    float rot[3])
{
    *have_rot = false;
    if (g->kind == VIEW_GAZE_MOUSE)
        return;
    if (g->kind == VIEW_GAZE_TRACE) {
        poll_trace(g, now_s, h);
        return;
    }
    pthread_mutex_lock(&g->lock);
    gaze_sample_t s = g->latest;
    bool have = g->have_sample;
    pthread_mutex_unlock(&g->lock);
    if (!have)
        return;
    /* A live tracker has its own latency: its samples count from arrival. */
    if (s.flags & GAZE_FLAG_VALID) {
        view_gaze_history_add(h, now_s, s.x_px, s.y_px);
    } else if (s.flags & GAZE_FLAG_HEAD) {
        /* Head pointing: where the head's forward direction meets the screen
         * at the display's viewing distance (no eye tracker on the helmet). */
        double az = s.head.azimuth_deg * M_PI / 180, el = s.head.elevation_deg * M_PI / 180;
        view_gaze_history_add(h, now_s, 0.5 * g->width + g->view_distance_px * tan(az),
                              0.5 * g->height - g->view_distance_px * tan(el));
    }
    if (s.flags & GAZE_FLAG_HAND) {
        /* The hand turns the object, as the paper's hand-held Polhemus did. */
        rot[0] = (float)s.hand.elevation_deg;
        rot[1] = (float)s.hand.azimuth_deg;
        rot[2] = (float)s.hand.roll_deg;
        *have_rot = true;
    }
}

void view_gaze_describe(view_gaze_t *g, char *buf, size_t n)
{
    switch (g->kind) {
    case VIEW_GAZE_MOUSE: snprintf(buf, n, "gaze: the mouse"); return;
    case VIEW_GAZE_TRACE:
        snprintf(buf, n, "gaze: trace %s, sample %zu of %zu%s", g->spec, g->next, g->trace.count,
                 g->ended ? " (ended: holding the last)" : "");
        return;
    default:
        pthread_mutex_lock(&g->lock);
        snprintf(buf, n, "gaze: live %s%s%s", g->spec, g->ended ? ": stopped: " : "",
                 g->ended ? g->error : g->have_sample ? "" : " (no sample yet)");
        pthread_mutex_unlock(&g->lock);
    }
}

void view_gaze_close(view_gaze_t *g)
{
    if (g->reader_running) {
        pthread_mutex_lock(&g->lock);
        g->stop = true;
        pthread_mutex_unlock(&g->lock);
        pthread_join(g->reader, NULL);   /* a read returns within LIVE_TIMEOUT_MS */
    }
    gaze_source_close(g->live);
    trace_free(&g->trace);
    pthread_mutex_destroy(&g->lock);
    g->live = NULL;
}
