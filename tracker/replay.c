/* replay.c: the replay arithmetic of replay.h: which sample each frame sees,
 * when its image is shown, and how far the true gaze was from the sweet spot. */
#include "replay.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "angles.h"
#include "progress.h"

pp5_status_t replay_constant_cost(void *ctx, double gaze_x, double gaze_y,
                                  replay_frame_cost_t *out)
{
    const replay_constant_cost_t *c = ctx;
    out->frame_s = c->frame_s;
    out->rays = 0;
    out->ring_bytes = 0;
    out->image = NULL;
    return PP5_OK;
}

/* ---- named cost sources ---- */

static const replay_cost_source_t *cost_sources[REPLAY_MAX_COST_SOURCES];
static int n_cost_sources;

void replay_register_cost_source(const replay_cost_source_t *src)
{
    for (int i = 0; i < n_cost_sources; i++)
        if (strcmp(cost_sources[i]->name, src->name) == 0) {
            cost_sources[i] = src;
            return;
        }
    PP5_ASSERT(n_cost_sources < REPLAY_MAX_COST_SOURCES, "too many replay cost sources");
    cost_sources[n_cost_sources++] = src;
}

const replay_cost_source_t *replay_find_cost_source(const char *name)
{
    for (int i = 0; i < n_cost_sources; i++)
        if (strcmp(cost_sources[i]->name, name) == 0)
            return cost_sources[i];
    return NULL;
}

int replay_cost_source_count(void)
{
    return n_cost_sources;
}

const replay_cost_source_t *replay_cost_source_at(int i)
{
    return i >= 0 && i < n_cost_sources ? cost_sources[i] : NULL;
}

static pp5_status_t constant_open(const char *options, const gaze_geometry_t *display, void **ctx)
{
    double ms = REPLAY_DEFAULT_FRAME_S * 1e3;
    if (options && *options) {
        char *end;
        ms = strtod(options, &end);
        if (end == options || *end || !(ms >= 0.01 && ms <= 1e6))
            return pp5_fail(PP5_E_CONFIG, "--cost constant:MS: '%s' is not a frame time in ms "
                            "(0.01..1e6)", options);
    }
    replay_constant_cost_t *c = malloc(sizeof *c);
    if (!c)
        return pp5_fail(PP5_E_NOMEM, "out of memory");
    c->frame_s = ms / 1e3;
    *ctx = c;
    return PP5_OK;
}

static const replay_cost_source_t constant_source = {
    "constant", "every frame takes the same time; no rays, ring bytes or image (built-in "
    "stand-in, NOT the emulated machine)", constant_open, replay_constant_cost, free, NULL, NULL};

__attribute__((constructor)) static void register_constant_source(void)
{
    replay_register_cost_source(&constant_source);
}

void replay_defaults(replay_params_t *p)
{
    memset(p, 0, sizeof *p);
    p->tracker_latency_s = REPLAY_DEFAULT_TRACKER_LATENCY_S;
    p->display_latency_s = REPLAY_DEFAULT_DISPLAY_LATENCY_S;
    p->fullres_radius_deg = ANGLES_PAPER_FULLRES_DIAMETER_DEG / 2.0;
    p->gap_s = 1.0;
    angles_paper_geometry(&p->display);
    predict_defaults(&p->predict, PREDICT_NONE);
}

void replay_result_free(replay_result_t *r)
{
    free(r->frames);
    memset(r, 0, sizeof *r);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

double replay_percentile(const double *v, size_t n, double q)
{
    if (n == 0)
        return NAN;
    double *c = malloc(n * sizeof *c);
    if (!c)
        return NAN;
    memcpy(c, v, n * sizeof *c);
    qsort(c, n, sizeof *c, cmp_double);
    size_t rank = (size_t)ceil(q * (double)n);   /* nearest rank, 1-based */
    if (rank < 1)
        rank = 1;
    if (rank > n)
        rank = n;
    double r = c[rank - 1];
    free(c);
    return r;
}

/* Per-sample angles on the recording's display, computed once. */
typedef struct {
    double t_s;
    double ax, ay;     /* NaN when invalid */
    uint32_t segment;  /* counts the recording gaps (> gap_s) before this sample */
} rsample_t;

static bool sample_ok(const rsample_t *s)
{
    return !isnan(s->ax);
}

/* The true gaze at time t: linear between neighbouring valid samples that are
 * at most max_gap_s apart; the nearer valid sample when t lies within half an
 * interval of one; else unknown. *hint is a moving search position. */
static bool true_gaze_at(const rsample_t *s, size_t n, double t, double interval_s,
                         size_t *hint, double *ax, double *ay)
{
    size_t i = *hint;
    while (i + 1 < n && s[i + 1].t_s <= t)
        i++;
    *hint = i;
    if (t < s[0].t_s || t > s[n - 1].t_s)
        return false;
    const rsample_t *a = &s[i];
    const rsample_t *b = i + 1 < n ? &s[i + 1] : NULL;
    double max_gap = 2.0 * interval_s;
    if (b && sample_ok(a) && sample_ok(b) && b->t_s - a->t_s <= max_gap && b->t_s > a->t_s) {
        double f = (t - a->t_s) / (b->t_s - a->t_s);
        *ax = a->ax + f * (b->ax - a->ax);
        *ay = a->ay + f * (b->ay - a->ay);
        return true;
    }
    if (sample_ok(a) && t - a->t_s <= interval_s / 2) {
        *ax = a->ax;
        *ay = a->ay;
        return true;
    }
    if (b && sample_ok(b) && b->t_s - t <= interval_s / 2) {
        *ax = b->ax;
        *ay = b->ay;
        return true;
    }
    return false;
}

static pp5_status_t push_frame(replay_result_t *r, const replay_frame_t *f)
{
    if (r->count == r->capacity) {
        size_t cap = r->capacity ? r->capacity * 2 : 256, bytes;
        if (!pp5_mul_size(cap, sizeof *r->frames, &bytes))
            return pp5_fail(PP5_E_NOMEM, "too many frames");
        replay_frame_t *p = realloc(r->frames, bytes);
        if (!p)
            return pp5_fail(PP5_E_NOMEM, "out of memory for %zu frames", cap);
        r->frames = p;
        r->capacity = cap;
    }
    r->frames[r->count++] = *f;
    return PP5_OK;
}

/* Time inside the sweet spot while frame f is shown: each valid sample holds
 * its position until the next sample, for at most two sample intervals. */
static void measure_inside(const rsample_t *s, size_t n, double interval_s, double radius_deg,
                           double spot_ax, double spot_ay, replay_frame_t *f, size_t *hint)
{
    double a = f->display_s, b = f->shown_until_s;
    size_t i = *hint;
    while (i + 1 < n && s[i + 1].t_s <= a)
        i++;
    *hint = i;
    f->inside_s = f->valid_s = 0;
    for (; i < n && s[i].t_s < b; i++) {
        if (!sample_ok(&s[i]))
            continue;
        double hold_end = s[i].t_s + 2.0 * interval_s;
        if (i + 1 < n && s[i + 1].t_s < hold_end)
            hold_end = s[i + 1].t_s;
        double lo = s[i].t_s > a ? s[i].t_s : a;
        double hi = hold_end < b ? hold_end : b;
        if (hi <= lo)
            continue;
        f->valid_s += hi - lo;
        if (angles_between_deg(s[i].ax, s[i].ay, spot_ax, spot_ay) <= radius_deg)
            f->inside_s += hi - lo;
    }
}

static pp5_status_t check_params(const trace_t *trace, const replay_params_t *p)
{
    if (trace->count < 2)
        return pp5_fail(PP5_E_RANGE, "replay needs at least 2 samples, the trace has %zu",
                        trace->count);
    if (!(p->tracker_latency_s >= 0 && p->display_latency_s >= 0 && p->fullres_radius_deg > 0) ||
        !(p->refresh_hz >= 0 && p->refresh_hz <= 10000) || !(p->gap_s > 0) ||
        !isfinite(p->tracker_latency_s) || !isfinite(p->display_latency_s))
        return pp5_fail(PP5_E_CONFIG, "replay: latencies must be >= 0 and the radius > 0");
    return PP5_OK;
}

/* Every sample in angles on the recording's display, with its gap segment. */
static pp5_status_t prepare_samples(const trace_t *trace, const gaze_geometry_t *rec,
                                    double gap_s, rsample_t **out)
{
    size_t n = trace->count, bytes;
    if (!pp5_mul_size(n, sizeof(rsample_t), &bytes))
        return pp5_fail(PP5_E_NOMEM, "trace too long");
    rsample_t *s = malloc(bytes);
    if (!s)
        return pp5_fail(PP5_E_NOMEM, "out of memory for %zu samples", n);
    for (size_t i = 0; i < n; i++) {
        const gaze_sample_t *g = &trace->samples[i];
        s[i].t_s = g->t_ns / 1e9;
        if (g->flags & GAZE_FLAG_VALID)
            angles_px_to_deg(rec, g->x_px, g->y_px, &s[i].ax, &s[i].ay);
        else
            s[i].ax = s[i].ay = NAN;
    }
    for (size_t i = 0; i < n; i++)
        s[i].segment = i == 0 ? 0 : s[i - 1].segment + (s[i].t_s - s[i - 1].t_s > gap_s ? 1 : 0);
    *out = s;
    return PP5_OK;
}

/* What the frame loop carries from one frame to the next. */
typedef struct {
    const replay_params_t *p;
    rsample_t *s;
    size_t n;
    gaze_geometry_t rec, disp;
    double interval_s, half_w_deg, half_h_deg, t_end;
    predictor_t pred;
    size_t next;                    /* first sample not yet fed */
    bool have_gaze;
    double hold_ax, hold_ay, used_sample_t, prev_frame_s;
    uint32_t used_segment;
    size_t hint;
} replay_loop_t;

/* The samples that have arrived by time `start` go to the predictor; the
 * newest valid one is held. */
static void feed_samples(replay_loop_t *L, double start)
{
    const rsample_t *s = L->s;
    while (L->next < L->n && s[L->next].t_s + L->p->tracker_latency_s <= start) {
        const rsample_t *x = &s[L->next++];
        if (!sample_ok(x))
            continue;
        predict_update(&L->pred, x->t_s, x->ax, x->ay);
        L->hold_ax = x->ax;
        L->hold_ay = x->ay;
        L->used_sample_t = x->t_s;
        L->used_segment = x->segment;
        L->have_gaze = true;
    }
}

/* Where this frame's sweet spot goes, in angles: the held (or predicted)
 * gaze, the screen centre before any sample, kept on the rendered screen. */
static void choose_spot(replay_loop_t *L, double start, double *ax, double *ay)
{
    *ax = *ay = 0;
    if (L->have_gaze) {
        *ax = L->hold_ax;
        *ay = L->hold_ay;
        if (L->p->predict.kind != PREDICT_NONE) {
            /* The display time is not known before the frame is rendered (its
             * cost depends on the sweet spot): predict to the start plus the
             * previous frame's time plus the display latency. */
            double expect = isnan(L->prev_frame_s) ? 0 : L->prev_frame_s;
            predict_at(&L->pred, start + expect + L->p->display_latency_s, ax, ay);
        }
    }
    *ax = fmax(-L->half_w_deg, fmin(L->half_w_deg, *ax));
    *ay = fmax(-L->half_h_deg, fmin(L->half_h_deg, *ay));
}

/* When the image of a frame ending at end_s is seen: the next refresh (if
 * any) plus the display latency. */
static double display_time(const replay_loop_t *L, double end_s)
{
    double ready = end_s;
    if (L->p->refresh_hz > 0) {
        double period = 1.0 / L->p->refresh_hz, t0 = L->s[0].t_s;
        ready = ceil((end_s - t0) / period - 1e-9) * period + t0;
    }
    return ready + L->p->display_latency_s;
}

/* The true gaze when the image is seen, and the error of the spot used. */
static void score_frame(replay_loop_t *L, double use_ax, double use_ay, replay_frame_t *f)
{
    double tax, tay;
    f->true_x_px = f->true_y_px = f->error_deg = NAN;
    if (!true_gaze_at(L->s, L->n, f->display_s, L->interval_s, &L->hint, &tax, &tay))
        return;
    angles_deg_to_px(&L->rec, tax, tay, &f->true_x_px, &f->true_y_px);
    /* Across a recording gap the held gaze is from another recording block:
     * not a latency error, so not scored. */
    f->after_gap = L->have_gaze && L->s[L->hint].segment != L->used_segment;
    if (L->have_gaze && !f->after_gap)
        f->error_deg = angles_between_deg(use_ax, use_ay, tax, tay);
}

/* One frame starting at `start`: *done when the trace ends before its
 * image would be seen. */
static pp5_status_t run_frame(replay_loop_t *L, double start, size_t index,
                              replay_frame_cost_fn cost, void *cost_ctx, replay_frame_t *f,
                              const image8_t **image, bool *done)
{
    feed_samples(L, start);
    memset(f, 0, sizeof *f);
    f->index = index;
    f->start_s = start;
    f->sample_t_s = L->used_sample_t;
    double use_ax, use_ay;
    choose_spot(L, start, &use_ax, &use_ay);
    angles_deg_to_px(&L->rec, use_ax, use_ay, &f->used_x_px, &f->used_y_px);
    angles_deg_to_px(&L->disp, use_ax, use_ay, &f->spot_x_px, &f->spot_y_px);
    replay_frame_cost_t c;
    memset(&c, 0, sizeof c);
    c.want_image = !L->p->timing_only;
    pp5_status_t st = cost(cost_ctx, f->spot_x_px, f->spot_y_px, &c);
    if (st != PP5_OK)
        return st;
    if (!(c.frame_s > 0) || !isfinite(c.frame_s))
        return pp5_fail(PP5_E_RANGE, "frame %zu: the frame-cost source returned %g s", index,
                        c.frame_s);
    f->frame_s = c.frame_s;
    f->rays = c.rays;
    f->ring_bytes = c.ring_bytes;
    f->end_s = start + c.frame_s;
    f->display_s = display_time(L, f->end_s);
    *done = f->display_s > L->t_end;
    if (*done)
        return PP5_OK;
    score_frame(L, use_ax, use_ay, f);
    f->shown_until_s = f->display_s;   /* set when the next image is known */
    *image = c.image;
    L->prev_frame_s = c.frame_s;
    return PP5_OK;
}

/* The summary over all frames; each image is shown until the next one
 * appears (the last: to the trace's end). */
static pp5_status_t summarise(replay_loop_t *L, replay_result_t *out)
{
    for (size_t k = 0; k < out->count; k++)
        out->frames[k].shown_until_s =
            k + 1 < out->count ? out->frames[k + 1].display_s : L->t_end;
    double *errors = malloc(out->count * sizeof *errors);
    if (!errors)
        return pp5_fail(PP5_E_NOMEM, "out of memory");
    replay_summary_t *sum = &out->summary;
    double inside = 0, err_sum = 0, lat_sum = 0, frame_sum = 0;
    size_t nerr = 0, hint = 0;
    for (size_t k = 0; k < out->count; k++) {
        replay_frame_t *f = &out->frames[k];
        double sax, say;
        angles_px_to_deg(&L->rec, f->used_x_px, f->used_y_px, &sax, &say);
        if (!isnan(f->sample_t_s) && !f->after_gap)
            measure_inside(L->s, L->n, L->interval_s, L->p->fullres_radius_deg, sax, say, f,
                           &hint);
        sum->frames_after_gap += f->after_gap;
        inside += f->inside_s;
        sum->valid_display_s += f->valid_s;
        if (!isnan(f->error_deg)) {        /* gaps between recording blocks excluded */
            errors[nerr++] = f->error_deg;
            err_sum += f->error_deg;
            sum->max_error_deg = fmax(sum->max_error_deg, f->error_deg);
            lat_sum += f->display_s - f->sample_t_s;
        }
        frame_sum += f->frame_s;
        sum->rays += f->rays;
        sum->ring_bytes += f->ring_bytes;
    }
    sum->frames = out->count;
    sum->frames_with_error = nerr;
    sum->trace_s = L->t_end - L->s[0].t_s;
    sum->inside_fraction = sum->valid_display_s > 0 ? inside / sum->valid_display_s : NAN;
    sum->mean_error_deg = nerr ? err_sum / (double)nerr : NAN;
    sum->p95_error_deg = replay_percentile(errors, nerr, 0.95);
    if (!nerr)
        sum->max_error_deg = NAN;
    sum->mean_frame_s = frame_sum / (double)out->count;
    double span = out->frames[out->count - 1].end_s - out->frames[0].start_s;
    sum->frames_per_s = span > 0 ? (double)out->count / span : NAN;
    sum->mean_latency_s = nerr ? lat_sum / (double)nerr : NAN;
    free(errors);
    return PP5_OK;
}

static pp5_status_t loop_init(replay_loop_t *L, const trace_t *trace, const replay_params_t *p)
{
    memset(L, 0, sizeof *L);
    L->p = p;
    L->n = trace->count;
    pp5_status_t st = angles_resolve(&trace->header.geometry, &L->rec);
    if (st == PP5_OK)
        st = angles_resolve(&p->display, &L->disp);
    rsample_t *s = NULL;
    if (st == PP5_OK)
        st = prepare_samples(trace, &L->rec, p->gap_s, &s);
    if (st != PP5_OK)
        return st;
    L->s = s;
    L->interval_s = 1.0 / trace->header.sample_rate_hz;
    /* rendered display edges, in angles */
    angles_px_to_deg(&L->disp, L->disp.width_px, L->disp.height_px, &L->half_w_deg,
                     &L->half_h_deg);
    L->t_end = s[L->n - 1].t_s;
    L->used_sample_t = L->prev_frame_s = NAN;
    predict_reset(&L->pred, &p->predict);
    return PP5_OK;
}

pp5_status_t replay_run(const trace_t *trace, const replay_params_t *p, replay_frame_cost_fn cost,
                        void *cost_ctx, replay_image_fn on_image, void *image_ctx,
                        replay_result_t *out)
{
    memset(out, 0, sizeof *out);
    pp5_status_t st = check_params(trace, p);
    replay_loop_t L;
    if (st == PP5_OK)
        st = loop_init(&L, trace, p);
    if (st != PP5_OK)
        return st;
    double start = L.s[0].t_s + p->tracker_latency_s;
    progress_t pr;   /* on a terminal: the trace's time replayed, per mille */
    progress_begin(&pr, "replay", 1000);
    while (st == PP5_OK && !(p->max_frames && out->count >= p->max_frames)) {
        replay_frame_t f;
        const image8_t *image = NULL;
        bool done = false;
        st = run_frame(&L, start, out->count, cost, cost_ctx, &f, &image, &done);
        if (st != PP5_OK || done)
            break;
        if (on_image && image && (st = on_image(image_ctx, &f, image)) != PP5_OK)
            break;
        if ((st = push_frame(out, &f)) != PP5_OK)
            break;
        start = f.end_s;
        progress_set(&pr, (int)(1000 * (start - L.s[0].t_s) / fmax(L.t_end - L.s[0].t_s, 1e-9)),
                     "of the trace's time");
    }
    progress_end(&pr);
    if (st == PP5_OK && out->count == 0)
        st = pp5_fail(PP5_E_RANGE, "the trace (%.3f s) is shorter than one frame plus the latency",
                      L.t_end - L.s[0].t_s);
    if (st == PP5_OK)
        st = summarise(&L, out);
    free(L.s);
    if (st != PP5_OK)
        replay_result_free(out);
    return st;
}
