/* cmd_replay_sweep.c: `pp5 replay TRACE --sweep-latency`: the share of display
 * time with the true gaze inside the sweet spot as the total eye-to-image
 * latency goes from 10 to 200 ms, and which machine configuration first meets
 * the latency that research since the paper finds tolerable.
 *
 * Latencies (marked in the output):
 *   paper      "System latency is estimated at between 100 and 150 ms" (the
 *              seed paper §6, gaze-facts.md §0);
 *   tolerable  a total system latency of 50-70 ms: Albert, Patney, Luebke &
 *              Kim 2017, "Latency requirements for foveated rendering in
 *              virtual reality", ACM TAP 14(4):25 (abstract: added eye-tracking
 *              latency of 80-150 ms reduced the acceptable foveation, 20-40 ms
 *              did not, "suggesting that a total system latency of 50-70ms
 *              could be tolerated").
 * The sweep's model of a latency L: the gaze that sets an image is L old when
 * the image appears (tracker + frame + display), and images follow each other
 * every frame (one 60 Hz refresh, 16.7 ms, or L itself when shorter): frame
 * F = min(16.7 ms, L), tracker latency L - F, display latency 0.
 * Machine configurations: each is a list of machine settings (preset=NAME and
 * anything `pp5 machine --set` takes: gp.count=32, ring.channels=16, and the
 * work divisions' division=NAME when the build has them), handed unchanged to
 * the machine frame source; its emulated frame time F for the paper's
 * workload (128x128x109 volume, gaze-directed, 210x210 image) gives the
 * total T + F + D with the replay's tracker and display latencies. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "emu/cli/cmd_replay.h"

#define SWEEP_REFRESH_S (1.0 / 60.0)
#define PAPER_LO_MS 100.0
#define PAPER_HI_MS 150.0
#define TOLERABLE_LO_MS 50.0
#define TOLERABLE_HI_MS 70.0

void replay_sweep_defaults(replay_sweep_t *s)
{
    memset(s, 0, sizeof *s);
    s->from_ms = 10;
    s->to_ms = 200;
    s->step_ms = 10;
    s->machine_frames = 4;
}

static const char *mark(double ms)
{
    if (ms >= PAPER_LO_MS && ms <= PAPER_HI_MS)
        return "  <- the paper's system (100-150 ms)";
    if (ms >= TOLERABLE_LO_MS && ms <= TOLERABLE_HI_MS)
        return "  <- tolerable (50-70 ms, Albert et al. 2017)";
    return "";
}

/* One replay with constant frames: the summary. */
static pp5_status_t replay_constant(const trace_t *t, const replay_params_t *base, double frame_s,
                                    double tracker_s, double display_s, replay_summary_t *out)
{
    replay_params_t p = *base;
    p.tracker_latency_s = tracker_s;
    p.display_latency_s = display_s;
    p.timing_only = true;
    p.max_frames = 0;
    replay_constant_cost_t c = {frame_s};
    replay_result_t r;
    pp5_status_t st = replay_run(t, &p, replay_constant_cost, &c, NULL, NULL, &r);
    if (st == PP5_OK) {
        *out = r.summary;
        replay_result_free(&r);
    }
    return st;
}

static pp5_status_t sweep_curve(const trace_t *t, const replay_params_t *p, const replay_sweep_t *s)
{
    printf("  total latency: the age of the gaze an image is made from when it appears; frames\n"
           "  every %.1f ms (or the latency, when shorter), the rest is tracker latency; "
           "prediction %s\n", SWEEP_REFRESH_S * 1e3, predict_kind_name(p->predict.kind));
    printf("    %10s %9s %10s %9s %9s\n", "latency", "inside", "mean err", "p95 err",
           "measured");
    for (double ms = s->from_ms; ms <= s->to_ms + 1e-9; ms += s->step_ms) {
        double frame = ms / 1e3 < SWEEP_REFRESH_S ? ms / 1e3 : SWEEP_REFRESH_S;
        replay_summary_t r;
        pp5_status_t st = replay_constant(t, p, frame, ms / 1e3 - frame, 0, &r);
        if (st != PP5_OK)
            return st;
        printf("    %7.0f ms %7.1f %% %6.2f deg %5.2f deg %6.1f ms%s\n", ms,
               100 * r.inside_fraction, r.mean_error_deg, r.p95_error_deg,
               r.mean_latency_s * 1e3, mark(ms));
    }
    printf("    (inside: share of display time with the true gaze within %.1f deg of the spot; "
           "measured: mean sample age at display, which adds the wait for the next sample)\n",
           p->fullres_radius_deg);
    return PP5_OK;
}

/* "preset=gaze1990-literal gp.count=32" -> "preset=gaze1990-literal,set=gp.count=32". */
static pp5_status_t machine_options(const char *spec, char *out, size_t size)
{
    char buf[1024];
    if (strlen(spec) >= sizeof buf)
        return pp5_fail(PP5_E_CONFIG, "--machine '%s': too long", spec);
    snprintf(buf, sizeof buf, "%s", spec);
    out[0] = '\0';
    size_t len = 0;
    for (char *save = NULL, *item = strtok_r(buf, " ,", &save); item;
         item = strtok_r(NULL, " ,", &save)) {
        if (!strchr(item, '=') || item[0] == '=')
            return pp5_fail(PP5_E_CONFIG, "--machine '%s': '%s' is not KEY=VALUE", spec, item);
        bool preset = strncmp(item, "preset=", 7) == 0;
        int n = snprintf(out + len, size - len, "%s%s%s", len ? "," : "", preset ? "" : "set=",
                         item);
        if (n < 0 || (size_t)n >= size - len)
            return pp5_fail(PP5_E_CONFIG, "--machine '%s': too long", spec);
        len += (size_t)n;
    }
    return PP5_OK;
}

/* The emulated frame time of one configuration: the first frames of the trace. */
static pp5_status_t machine_frame_time(const trace_t *t, const replay_params_t *base,
                                       const char *spec, size_t frames, double *frame_s)
{
    const replay_cost_source_t *cs = replay_find_cost_source("machine");
    if (!cs)
        return pp5_fail(PP5_E_UNSUPPORTED, "--machine: this build has no emulated machine "
                        "frame source");
    char options[2048];
    pp5_status_t st = machine_options(spec, options, sizeof options);
    void *ctx = NULL;
    if (st == PP5_OK)
        st = cs->open(options, &base->display, &ctx);
    if (st != PP5_OK)
        return pp5_fail(st, "--machine '%s': %s", spec, pp5_error_text());
    replay_params_t p = *base;
    p.timing_only = true;
    p.max_frames = frames;
    replay_result_t r;
    st = replay_run(t, &p, cs->cost, ctx, NULL, NULL, &r);
    if (st == PP5_OK) {
        *frame_s = r.summary.mean_frame_s;
        replay_result_free(&r);
    }
    if (cs->close)
        cs->close(ctx);
    return st;
}

static pp5_status_t sweep_machines(const trace_t *t, const replay_params_t *p,
                                   const replay_sweep_t *s)
{
    double t_ms = p->tracker_latency_s * 1e3, d_ms = p->display_latency_s * 1e3;
    printf("\n  machine configurations (emulated frame time, mean of the first %zu frames of the "
           "trace; total = tracker %.0f ms + frame + display %.0f ms):\n", s->machine_frames,
           t_ms, d_ms);
    printf("    %-44s %10s %10s %9s\n", "configuration", "frame", "total", "inside");
    int first_hi = -1, first_lo = -1, fastest = -1;
    double best = INFINITY;
    for (int i = 0; i < s->n_machines; i++) {
        double frame_s;
        pp5_status_t st = machine_frame_time(t, p, s->machines[i], s->machine_frames, &frame_s);
        if (st == PP5_E_FIRMWARE || st == PP5_E_RANGE) {
            /* A configuration that cannot run the workload is a result too. */
            printf("    %-44s cannot run it: %s\n", s->machines[i], pp5_error_text());
            continue;
        }
        replay_summary_t r;
        if (st == PP5_OK)
            st = replay_constant(t, p, frame_s, p->tracker_latency_s, p->display_latency_s, &r);
        if (st != PP5_OK)
            return st;
        double total = t_ms + frame_s * 1e3 + d_ms;
        printf("    %-44s %7.1f ms %7.1f ms %7.1f %%%s\n", s->machines[i], frame_s * 1e3, total,
               100 * r.inside_fraction, mark(total));
        if (total <= TOLERABLE_HI_MS && first_hi < 0)
            first_hi = i;
        if (total <= TOLERABLE_LO_MS && first_lo < 0)
            first_lo = i;
        if (total < best) {
            best = total;
            fastest = i;
        }
    }
    if (first_hi >= 0)
        printf("  first to meet 70 ms (the tolerable range's upper end): %s\n",
               s->machines[first_hi]);
    else if (fastest < 0)
        printf("  none meets 70 ms: no configuration could run the workload\n");
    else
        printf("  none meets 70 ms: the fastest, %s, totals %.1f ms; with these tracker and "
               "display latencies a frame must take at most %.1f ms\n", s->machines[fastest],
               best, TOLERABLE_HI_MS - t_ms - d_ms);
    if (first_lo >= 0)
        printf("  first to meet 50 ms: %s\n", s->machines[first_lo]);
    return PP5_OK;
}

pp5_status_t replay_sweep_latency(const trace_t *t, const replay_params_t *p,
                                  const replay_sweep_t *s)
{
    if (!(s->from_ms > 0 && s->step_ms > 0 && s->to_ms >= s->from_ms && s->to_ms <= 10000 &&
          (s->to_ms - s->from_ms) / s->step_ms <= 1000))
        return pp5_fail(PP5_E_CONFIG, "--sweep-ms: need 0 < FROM <= TO <= 10000 and STEP > 0 "
                        "(at most 1000 points)");
    if (t->count < 2)
        return pp5_fail(PP5_E_RANGE, "replay needs at least 2 samples, the trace has %zu",
                        t->count);
    printf("latency sweep of %s (%s)\n", t->header.source, t->header.tracker);
    pp5_status_t st = sweep_curve(t, p, s);
    if (st == PP5_OK && s->n_machines > 0)
        st = sweep_machines(t, p, s);
    return st;
}
