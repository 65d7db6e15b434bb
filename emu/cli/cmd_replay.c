/* cmd_replay.c: `pp5 replay TRACE`: replay a gaze trace with latency and report
 * where the eye was when each image reached the screen (tracker/replay.h). */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "tracker/angles.h"
#include "cliopt.h"
#include "emu/cli/cmd_replay.h"
#include "json.h"
#include "outfile.h"
#include "registry.h"
#include "tracker/replay.h"
#include "tracker/trace_file.h"
#include "workunit.h"

#if defined(__has_include)
#if __has_include("plot.h")
#include "plot.h"
#define REPLAY_HAVE_PLOT 1
#endif
#endif

static void usage(FILE *out)
{
    fprintf(out,
        "usage: pp5 replay TRACE [options]\n"
        "       pp5 replay --live DEVICE [--seconds S] [options]\n\n"
        "Replays a pp5 gaze trace frame after frame: each frame starts with the newest sample\n"
        "that has arrived after the tracker latency, takes its frame time, and is shown at its\n"
        "end plus the display latency.  Reports the angle between the gaze used and the true\n"
        "gaze at display time, and how much of the time the true gaze was inside the\n"
        "full-resolution region.\n\n"
        "  --cost NAME[:OPTIONS]    where frame times come from (default machine when this build\n"
        "                           has it, else constant):\n");
    for (int i = 0; i < replay_cost_source_count(); i++)
        fprintf(out, "                             %-10s %s\n", replay_cost_source_at(i)->name,
                replay_cost_source_at(i)->summary);
    fprintf(out,
        "  --scene FILE             shorthand for --cost polygons:scene=FILE: the emulated machine\n"
        "                           draws the polygon scene FILE (as pp5 render --scene reads, or\n"
        "                           gen:spheres100k), each object at the level of detail the gaze\n"
        "                           allows; a changed triangle list's transfer over the ring is\n"
        "                           counted inside the frame that needs it (time and ring bytes),\n"
        "                           and the summary says how often and at what cost it changed.\n"
        "                           With --cost polygons:OPTIONS, scene=FILE is added to them\n"
        "  --mesh FILE              the same for one mesh (.obj/.off/.ply or gen:NAME, as pp5\n"
        "                           render --mesh): --cost polygons:mesh=FILE\n"
        "  --frame-time-ms X        shorthand for --cost constant:X (a stand-in; %.1f ms is the\n"
        "                           paper's 15 frames/s)\n"
        "  --tracker-latency-ms T   sample age when it reaches the renderer (default %.0f) [U]\n"
        "  --display-latency-ms D   from frame end to the image on the screen (default %.0f) [U]\n"
        "  --latency-ms T           shorthand: tracker latency T, display latency 0\n"
        "  --radius-deg R           full-resolution radius (default 6: the paper's 12 deg circle)\n"
        "  --refresh-hz HZ          images wait for the next refresh (e.g. 60); default: none\n"
        "  --gap-s G                a pause in the samples longer than G s (default 1) splits\n"
        "                           the trace: frames whose gaze predates it are not scored\n"
        "  --predict P              none (default), linear, alphabeta, kalman, or landing: the\n"
        "                           landing point of a saccade in flight (main sequence and\n"
        "                           velocity profile, tracker/predict_landing.h), with the\n"
        "                           landing error per amplitude bin; landing:kalman (etc.)\n"
        "                           uses that predictor outside saccades (default: none)\n"
        "  --timing-only            do not ask the frame source for images\n"
        "  --max-frames N           stop after N frames\n"
        "  --report FILE.json       summary and parameters\n"
        "  --csv FILE.csv           one line per frame\n"
        "  --plot FILE.png|.svg|.pdf  error and frame time over the trace\n"
        "  --live DEVICE            record live gaze from DEVICE (as `pp5 track record --device`:\n"
        "                           hid, hid:/dev/hidrawN, polhemus, polhemus:BUS:ADDR) for\n"
        "                           --seconds S (default 10), keep it in /tmp, then replay it\n"
        "  --frames-dir DIR         write each frame's image as DIR/frame_NNNNN.png (only when\n"
        "                           the cost source renders images; the constant one does not)\n"
        "  --sweep-latency          instead of one replay: the share of time inside the sweet\n"
        "                           spot as the total latency goes 10..200 ms (the paper's\n"
        "                           100-150 ms and the tolerable 50-70 ms marked), and which\n"
        "                           --machine configuration first meets 70 ms\n"
        "  --sweep-ms FROM:TO:STEP  the sweep's latencies (default 10:200:10)\n"
        "  --machine SPEC           a machine configuration for the sweep, repeatable, in order:\n"
        "                           machine settings as pp5 machine takes them, e.g.\n"
        "                           \"gp.count=32 ring.channels=16\" or \"preset=gaze1990-literal\"\n"
        "                           (default: the literal ring, 16 GPs, 32 GPs, 32 GPs with 16\n"
        "                           ring channels; \"none\": no machines)\n"
        "  --machine-frames N       frames emulated per configuration (default 4)\n"
        "  --batch LIST             instead of one replay: each line of LIST is a replay, a TRACE\n"
        "                           and its options (those above; given on the command line\n"
        "                           they apply to every line; '#' starts a comment).  One\n"
        "                           summary row per line into --out FILE.csv (default\n"
        "                           batch.csv), per-line JSON into --report; --resume,\n"
        "                           --shard K/N and --accounting FILE work as in pp5 sweep, and\n"
        "                           mpirun -n N shares the lines among N ranks with the same\n"
        "                           outputs.  A line that fails is a row with its error (exit 8)\n"
        "Examples:\n"
        "  pp5 replay traces/saccades_10s_250hz.trace --predict landing --report r.json\n"
        "  pp5 replay traces/saccades_10s_250hz.trace --scene gen:spheres100k --max-frames 50\n"
        "  pp5 replay traces/pursuit_10s_250hz.trace --sweep-latency --machine \"gp.count=16\" \\\n"
        "      --machine \"gp.count=32\"\n"
        "  mpirun -n 2 pp5 replay --batch runs.list --max-frames 50 --out runs.csv\n",
        REPLAY_DEFAULT_FRAME_S * 1e3, REPLAY_DEFAULT_TRACKER_LATENCY_S * 1e3,
        REPLAY_DEFAULT_DISPLAY_LATENCY_S * 1e3);
}

typedef struct {
    const char *dir;
    size_t written;
} frames_out_t;

static pp5_status_t save_frame(void *ctx, const replay_frame_t *f, const image8_t *img)
{
    frames_out_t *fo = ctx;
    char path[1024];
    snprintf(path, sizeof path, "%s/frame_%05zu.png", fo->dir, f->index);
    pp5_status_t st = png_write(path, img);
    fo->written += st == PP5_OK;
    return st;
}

static pp5_status_t write_csv(const char *path, const replay_result_t *r)
{
    outfile_t o;
    pp5_status_t st = outfile_open(&o, path, false);
    if (st != PP5_OK)
        return st;
    FILE *f = o.f;
    fprintf(f, "frame,start_ms,end_ms,display_ms,shown_until_ms,sample_ms,used_x_px,used_y_px,"
               "spot_x_px,spot_y_px,true_x_px,true_y_px,error_deg,inside_ms,valid_ms,frame_ms,"
               "rays,ring_bytes,after_gap\n");
    for (size_t k = 0; k < r->count; k++) {
        const replay_frame_t *q = &r->frames[k];
        fprintf(f, "%zu,%.3f,%.3f,%.3f,%.3f,%.3f,%.2f,%.2f,%.2f,%.2f,%.2f,%.2f,%.4f,%.3f,%.3f,"
                   "%.3f,%llu,%llu,%d\n",
                q->index, q->start_s * 1e3, q->end_s * 1e3, q->display_s * 1e3,
                q->shown_until_s * 1e3, q->sample_t_s * 1e3, q->used_x_px, q->used_y_px,
                q->spot_x_px, q->spot_y_px, q->true_x_px, q->true_y_px, q->error_deg,
                q->inside_s * 1e3, q->valid_s * 1e3, q->frame_s * 1e3,
                (unsigned long long)q->rays, (unsigned long long)q->ring_bytes, q->after_gap ? 1 : 0);
    }
    return outfile_commit(&o);
}

void replay_summary_json(json_writer_t *j, const replay_summary_t *s)
{
    json_key(j, "summary");
    json_begin_object(j);
    json_kv_uint(j, "frames", s->frames);
    json_kv_uint(j, "frames_with_error", s->frames_with_error);
    json_kv_uint(j, "frames_after_gap", s->frames_after_gap);
    json_kv_double(j, "trace_s", s->trace_s);
    json_kv_double(j, "valid_display_s", s->valid_display_s);
    json_kv_double(j, "inside_fraction", s->inside_fraction);
    json_kv_double(j, "mean_error_deg", s->mean_error_deg);
    json_kv_double(j, "p95_error_deg", s->p95_error_deg);
    json_kv_double(j, "max_error_deg", s->max_error_deg);
    json_kv_double(j, "frames_per_s", s->frames_per_s);
    json_kv_double(j, "mean_frame_ms", s->mean_frame_s * 1e3);
    json_kv_double(j, "mean_latency_ms", s->mean_latency_s * 1e3);
    json_kv_uint(j, "rays", s->rays);
    json_kv_uint(j, "ring_bytes", s->ring_bytes);
    json_end_object(j);
}

static pp5_status_t write_report(const char *path, const char *trace_path, const trace_t *t,
                                 const replay_params_t *p, const replay_cost_source_t *cs,
                                 void *cost_ctx, const char *cost_options,
                                 const replay_summary_t *s)
{
    outfile_t o;
    pp5_status_t st = outfile_open(&o, path, false);
    if (st != PP5_OK)
        return st;
    FILE *f = o.f;
    json_writer_t j;
    json_init(&j, f, true);
    json_begin_object(&j);
    json_kv_string(&j, "trace", trace_path);
    json_kv_string(&j, "trace_source", t->header.source);
    json_kv_double(&j, "trace_sample_rate_hz", t->header.sample_rate_hz);
    json_kv_string(&j, "frame_cost_source", cs->name);
    json_kv_string(&j, "frame_cost_options", cost_options);
    json_kv_string(&j, "frame_cost_source_is", cs->summary);
    json_kv_double(&j, "tracker_latency_ms", p->tracker_latency_s * 1e3);
    json_kv_double(&j, "display_latency_ms", p->display_latency_s * 1e3);
    json_kv_double(&j, "fullres_radius_deg", p->fullres_radius_deg);
    json_kv_double(&j, "refresh_hz", p->refresh_hz);
    json_kv_double(&j, "gap_s", p->gap_s);
    json_kv_string(&j, "predict", predict_kind_name(p->predict.kind));
    if (p->predict.kind == PREDICT_LANDING)
        json_kv_string(&j, "predict_outside_saccades",
                       predict_kind_name(p->predict.landing_fallback));
    json_kv_bool(&j, "timing_only", p->timing_only);
    if (cs->report_json) {
        json_key(&j, "frame_cost_details");
        json_begin_object(&j);
        cs->report_json(cost_ctx, &j);
        json_end_object(&j);
    }
    replay_summary_json(&j, s);
    json_end_object(&j);
    fputc('\n', f);
    return outfile_commit(&o);
}

static pp5_status_t write_plot(const char *path, const replay_result_t *r)
{
#ifdef REPLAY_HAVE_PLOT
    size_t n = r->count, bytes;
    if (!pp5_mul_size(n, 3 * sizeof(double), &bytes))
        return pp5_fail(PP5_E_NOMEM, "too many frames to plot");
    double *x = malloc(bytes);
    if (!x)
        return pp5_fail(PP5_E_NOMEM, "out of memory");
    double *err = x + n, *ft = x + 2 * n;
    int m = 0;
    for (size_t k = 0; k < n; k++)
        if (!isnan(r->frames[k].error_deg)) {
            x[m] = r->frames[k].display_s;
            err[m] = r->frames[k].error_deg;
            ft[m] = r->frames[k].frame_s * 1e3 / 10.0;
            m++;
        }
    if (m == 0) {
        free(x);
        return pp5_fail(PP5_E_RANGE, "--plot: no frame has a measurable error");
    }
    plot_t p;
    plot_init(&p, "Gaze replay: error at display time", "trace time (s)", "deg");
    pp5_status_t st = plot_add_series(&p, "error (deg)", x, err, m);
    if (st == PP5_OK)
        st = plot_add_series(&p, "frame time (ms / 10)", x, ft, m);
    if (st == PP5_OK)
        st = plot_write(&p, path, 900, 450);
    plot_free(&p);
    free(x);
    return st;
#else
    (void)r;
    return pp5_fail(PP5_E_UNSUPPORTED, "--plot %s: this branch has no emu/util/plot.h yet (it "
                    "comes with the integration); the CSV and JSON were written", path);
#endif
}

/* none | linear | alphabeta | kalman | landing[:FALLBACK]. */
static pp5_status_t parse_predict(const char *text, predict_params_t *p)
{
    char name[32];
    const char *colon = strchr(text, ':');
    snprintf(name, sizeof name, "%.*s", colon ? (int)(colon - text) : (int)strlen(text), text);
    predict_kind_t k, fallback = PREDICT_NONE;
    if (!predict_kind_parse(name, &k) || (colon && (k != PREDICT_LANDING ||
                                                    !predict_kind_parse(colon + 1, &fallback) ||
                                                    fallback == PREDICT_LANDING)))
        return pp5_fail(PP5_E_CONFIG, "--predict: expected none, linear, alphabeta, kalman or "
                        "landing[:none|linear|alphabeta|kalman], got '%s'", text);
    predict_defaults(p, k);
    p->landing_fallback = fallback;
    return PP5_OK;
}

/* FROM:TO:STEP in ms. */
static pp5_status_t parse_sweep_ms(const char *text, replay_sweep_t *s)
{
    char extra;
    if (sscanf(text, "%lf:%lf:%lf%c", &s->from_ms, &s->to_ms, &s->step_ms, &extra) != 3 ||
        !isfinite(s->from_ms) || !isfinite(s->to_ms) || !isfinite(s->step_ms))
        return pp5_fail(PP5_E_CONFIG, "--sweep-ms: expected FROM:TO:STEP in ms (e.g. 10:200:10), "
                        "got '%s'", text);
    return PP5_OK;
}

/* The sweep's default machine configurations, in the order asked. */
static void default_machines(replay_sweep_t *s)
{
    static const char *const defaults[] = {"preset=gaze1990-literal", "gp.count=16", "gp.count=32",
                                           "gp.count=32 ring.channels=16"};
    if (s->n_machines == 1 && strcmp(s->machines[0], "none") == 0)
        s->n_machines = 0;
    else if (s->n_machines == 0)
        for (size_t i = 0; i < sizeof defaults / sizeof defaults[0]; i++)
            s->machines[s->n_machines++] = defaults[i];
}

static const struct option replay_opts[] = {
    {"frame-time-ms", required_argument, 0, 'f'}, {"tracker-latency-ms", required_argument, 0, 't'},
    {"display-latency-ms", required_argument, 0, 'd'}, {"latency-ms", required_argument, 0, 'l'},
    {"radius-deg", required_argument, 0, 'r'}, {"predict", required_argument, 0, 'p'},
    {"timing-only", no_argument, 0, 'T'}, {"max-frames", required_argument, 0, 'n'},
    {"report", required_argument, 0, 'j'}, {"csv", required_argument, 0, 'c'},
    {"plot", required_argument, 0, 'P'}, {"cost", required_argument, 0, 'C'},
    {"refresh-hz", required_argument, 0, 'R'}, {"gap-s", required_argument, 0, 'g'},
    {"frames-dir", required_argument, 0, 'F'}, {"live", required_argument, 0, 'L'},
    {"seconds", required_argument, 0, 'S'}, {"sweep-latency", no_argument, 0, 'W'},
    {"sweep-ms", required_argument, 0, 'w'}, {"machine", required_argument, 0, 'M'},
    {"machine-frames", required_argument, 0, 'm'}, {"help", no_argument, 0, 'h'},
    {"batch", required_argument, 0, 'B'}, {"out", required_argument, 0, 'o'},
    {"resume", no_argument, 0, 'e'}, {"shard", required_argument, 0, 'k'},
    {"accounting", required_argument, 0, 'a'}, {"scene", required_argument, 0, 'Z'},
    {"mesh", required_argument, 0, 'X'},
    {0, 0, 0, 0}};

/* The latency and geometry options. */
static pp5_status_t parse_latency_option(int c, const char *arg, replay_params_t *p)
{
    double ms;
    pp5_status_t st = PP5_OK;
    switch (c) {
    case 'R': return cliopt_double("--refresh-hz", arg, 0, 10000, &p->refresh_hz);
    case 'g': return cliopt_double("--gap-s", arg, 0.001, 1e6, &p->gap_s);
    case 'r': return cliopt_double("--radius-deg", arg, 0.01, 180, &p->fullres_radius_deg);
    case 't':
        if ((st = cliopt_double("--tracker-latency-ms", arg, 0, 1e6, &ms)) == PP5_OK)
            p->tracker_latency_s = ms / 1e3;
        return st;
    case 'd':
        if ((st = cliopt_double("--display-latency-ms", arg, 0, 1e6, &ms)) == PP5_OK)
            p->display_latency_s = ms / 1e3;
        return st;
    default:   /* 'l' */
        if ((st = cliopt_double("--latency-ms", arg, 0, 1e6, &ms)) == PP5_OK) {
            p->tracker_latency_s = ms / 1e3;
            p->display_latency_s = 0;
        }
        return st;
    }
}

/* One option; *done set (with *rc) for --help and unknown options. */
pp5_status_t replay_cli_option(int c, const char *arg, replay_cli_t *o, bool *done, int *rc)
{
    double ms;
    long nf;
    pp5_status_t st = PP5_OK;
    switch (c) {
    case 'f':
        if ((st = cliopt_double("--frame-time-ms", arg, 0.01, 1e6, &ms)) == PP5_OK)
            snprintf(o->cost_spec, sizeof o->cost_spec, "constant:%s", arg);
        o->cost_given = true;
        return st;
    case 'C':
        if (strlen(arg) >= sizeof o->cost_spec)
            return pp5_fail(PP5_E_CONFIG, "--cost: too long");
        snprintf(o->cost_spec, sizeof o->cost_spec, "%s", arg);
        o->cost_given = true;
        return PP5_OK;
    case 'Z': o->scene = arg; return PP5_OK;
    case 'X': o->mesh = arg; return PP5_OK;
    case 'R': case 'g': case 'r': case 't': case 'd': case 'l':
        return parse_latency_option(c, arg, &o->p);
    case 'F': o->frames_dir = arg; return PP5_OK;
    case 'L': o->live = arg; return PP5_OK;
    case 'S': o->live_seconds = arg; return cliopt_double("--seconds", arg, 0.1, 86400, &ms);
    case 'p': return parse_predict(arg, &o->p.predict);
    case 'T': o->p.timing_only = true; return PP5_OK;
    case 'W': o->sweep = true; return PP5_OK;
    case 'w': return parse_sweep_ms(arg, &o->sw);
    case 'M':
        if (o->sw.n_machines >= REPLAY_SWEEP_MAX_MACHINES)
            return pp5_fail(PP5_E_CONFIG, "--machine: at most %d", REPLAY_SWEEP_MAX_MACHINES);
        o->sw.machines[o->sw.n_machines++] = arg;
        return PP5_OK;
    case 'm':
        if ((st = cliopt_long("--machine-frames", arg, 1, 10000, &nf)) == PP5_OK)
            o->sw.machine_frames = (size_t)nf;
        return st;
    case 'n':
        if ((st = cliopt_long("--max-frames", arg, 1, 100000000L, &nf)) == PP5_OK)
            o->p.max_frames = (size_t)nf;
        return st;
    case 'j': o->report = arg; return PP5_OK;
    case 'c': o->csv = arg; return PP5_OK;
    case 'B': o->batch = arg; return PP5_OK;
    case 'o': o->out = arg; return PP5_OK;
    case 'e': o->resume = true; return PP5_OK;
    case 'a': o->accounting = arg; return PP5_OK;
    case 'k': return workunit_parse_shard(arg, &o->shard_k, &o->shard_n);
    case 'P': {
        plot_format_t fmt;
        o->plot = arg;
        return plot_format_from_name(arg, &fmt);   /* refused before the replay runs */
    }
    case 'h':
        if (o->in_list)
            return pp5_fail(PP5_E_CONFIG, "--help has no place in a list");
        usage(stdout);
        *done = true;
        *rc = 0;
        return PP5_OK;
    default:
        if (o->in_list)
            return pp5_fail(PP5_E_CONFIG, "unknown option or missing value");
        usage(stderr);
        *done = true;
        *rc = 2;
        return PP5_OK;
    }
}

/* Records a live session into live_path (flushed as it goes, by `pp5 track
 * record`), to be replayed frame by frame: the emulated machine runs slower
 * than real time.  Returns 0, or the exit code to stop with. */
static int record_live(const char *live, const char *seconds, char *live_path)
{
    int fd = mkstemps(live_path, 6);
    if (fd < 0)
        return cliopt_report("replay", pp5_fail(PP5_E_IO, "--live: cannot make a temporary "
                                                "trace file in /tmp"));
    close(fd);
    const pp5_command_t *track = pp5_find_command("track");
    if (!track)
        return cliopt_report("replay", pp5_fail(PP5_E_UNSUPPORTED, "--live: this build has no "
                                                "`pp5 track`"));
    char *track_argv[] = {"track", "record", "--device", (char *)live, "--seconds",
                          (char *)seconds, "--out", live_path, NULL};
    fprintf(stderr, "replay: recording %s s of live gaze from %s into %s\n", seconds, live,
            live_path);
    optind = 0;
    int rc = track->fn(8, track_argv);
    optind = 1;
    if (rc == 0)
        return 0;
    /* A device that stopped (timeout, unplugged) leaves what arrived: replay
     * that, saying so, unless there is nothing to replay. */
    trace_t partial;
    bool usable = trace_read_file(live_path, &partial) == PP5_OK && partial.count >= 2;
    if (usable)
        trace_free(&partial);
    if (!usable) {
        fprintf(stderr, "pp5 replay: --live %s: the recording failed (see above) and holds too "
                "little to replay (%s)\n", live, live_path);
        return rc;
    }
    fprintf(stderr, "replay: the live recording ended early (see above); replaying what "
            "arrived\n");
    return 0;
}

static void print_summary(const char *path, const trace_t *t, const replay_params_t *p,
                          const replay_cost_source_t *cs, void *cost_ctx,
                          const char *cost_options, const replay_summary_t *s)
{
    printf("replay %s (%s)\n", path, t->header.source);
    printf("  frame source: %s%s%s: %s; mean frame %.1f ms\n", cs->name,
           cost_options[0] ? ":" : "", cost_options, cs->summary, s->mean_frame_s * 1e3);
    if (cs->describe)
        cs->describe(cost_ctx, stdout);
    printf("  latency: tracker %.1f ms + frame + display %.1f ms; mean sample age at display "
           "%.1f ms\n", p->tracker_latency_s * 1e3, p->display_latency_s * 1e3,
           s->mean_latency_s * 1e3);
    printf("  prediction: %s\n", predict_kind_name(p->predict.kind));
    printf("  frames: %zu (%.2f frames/s) over %.3f s of trace\n", s->frames, s->frames_per_s,
           s->trace_s);
    printf("  error at display time: mean %.2f deg, 95th percentile %.2f deg, max %.2f deg "
           "(%zu frames measurable; %zu not scored: shown after a recording gap > %.1f s)\n",
           s->mean_error_deg, s->p95_error_deg, s->max_error_deg, s->frames_with_error,
           s->frames_after_gap, p->gap_s);
    printf("  true gaze inside the %.1f deg full-resolution radius: %.1f %% of %.3f s with "
           "gaze data\n", p->fullres_radius_deg, 100.0 * s->inside_fraction, s->valid_display_s);
}

/* The replay proper, on the trace at path, with its outputs. */
static pp5_status_t run_replay(replay_cli_t *o, const char *path)
{
    char *colon = strchr(o->cost_spec, ':');
    const char *cost_options = "";
    if (colon) {
        *colon = '\0';
        cost_options = colon + 1;
    }
    const replay_cost_source_t *cs = replay_find_cost_source(o->cost_spec);
    if (!cs)
        return pp5_fail(PP5_E_CONFIG, "--cost: no frame-cost source '%s' in this build (see "
                        "--help)", o->cost_spec);
    trace_t t;
    pp5_status_t st = trace_read_file(path, &t);
    if (st != PP5_OK)
        return st;
    if (o->sweep) {
        default_machines(&o->sw);
        st = replay_sweep_latency(&t, &o->p, &o->sw);
        trace_free(&t);
        return st;
    }
    void *ctx = NULL;
    if ((st = cs->open(cost_options, &o->p.display, &ctx)) != PP5_OK) {
        trace_free(&t);
        return st;
    }
    frames_out_t fo = {o->frames_dir, 0};
    replay_result_t r;
    st = replay_run(&t, &o->p, cs->cost, ctx, o->frames_dir ? save_frame : NULL, &fo, &r);
    if (st == PP5_OK) {
        print_summary(path, &t, &o->p, cs, ctx, cost_options, &r.summary);
        if (o->frames_dir)
            printf("  frames written to %s: %zu (the cost source renders %s)\n", o->frames_dir,
                   fo.written, fo.written ? "images" : "no images");
        if (o->p.predict.kind == PREDICT_LANDING)
            st = replay_print_landing(&t, &o->p);
        if (st == PP5_OK && o->csv)
            st = write_csv(o->csv, &r);
        if (st == PP5_OK && o->report)
            st = write_report(o->report, path, &t, &o->p, cs, ctx, cost_options, &r.summary);
        if (st == PP5_OK && o->plot)
            st = write_plot(o->plot, &r);
        replay_result_free(&r);
    }
    if (cs->close)
        cs->close(ctx);
    trace_free(&t);
    return st;
}

void replay_cli_defaults(replay_cli_t *o)
{
    memset(o, 0, sizeof *o);
    replay_defaults(&o->p);
    replay_sweep_defaults(&o->sw);
    o->live_seconds = "10";
    /* The emulated machine when it is built in (firmware/host/replay_machine.c
     * registers it); the constant stand-in otherwise. */
    snprintf(o->cost_spec, sizeof o->cost_spec, "%s",
             replay_find_cost_source("machine") ? "machine" : "constant");
}

/* --scene FILE / --mesh FILE as the polygons source's scene=/mesh= option,
 * added to --cost polygons:OPTIONS when that was given.  Cleared once
 * folded, so a batch line parsed on top of these options adds it once. */
static pp5_status_t fold_scene(replay_cli_t *o)
{
    if (!o->scene && !o->mesh)
        return PP5_OK;
    if (o->scene && o->mesh)
        return pp5_fail(PP5_E_CONFIG, "--scene and --mesh: give one of them");
    const char *key = o->scene ? "scene" : "mesh", *file = o->scene ? o->scene : o->mesh;
    size_t name_len = strcspn(o->cost_spec, ":");
    bool polygons = name_len == 8 && strncmp(o->cost_spec, "polygons", 8) == 0;
    if (o->cost_given && !polygons)
        return pp5_fail(PP5_E_CONFIG, "--%s draws with --cost polygons; it does not go with "
                        "--cost %.*s", key, (int)name_len, o->cost_spec);
    char spec[sizeof o->cost_spec];
    int n = polygons && o->cost_spec[name_len] == ':' && o->cost_spec[name_len + 1]
                ? snprintf(spec, sizeof spec, "%s,%s=%s", o->cost_spec, key, file)
                : snprintf(spec, sizeof spec, "polygons:%s=%s", key, file);
    if (n < 0 || (size_t)n >= sizeof spec)
        return pp5_fail(PP5_E_CONFIG, "--%s %s: the name is too long", key, file);
    memcpy(o->cost_spec, spec, sizeof spec);
    o->cost_given = true;
    o->scene = o->mesh = NULL;
    return PP5_OK;
}

pp5_status_t replay_cli_parse(replay_cli_t *o, int argc, char **argv, bool *done, int *rc)
{
    pp5_status_t st = PP5_OK;
    int c;
    *done = false;
    *rc = 0;
    optind = 1;
    opterr = !o->in_list;
    while (st == PP5_OK && !*done && (c = getopt_long(argc, argv, "h", replay_opts, NULL)) != -1)
        st = replay_cli_option(c, optarg, o, done, rc);
    opterr = 1;
    return st == PP5_OK && !*done ? fold_scene(o) : st;
}

static int cmd_replay(int argc, char **argv)
{
    static replay_cli_t o;      /* large (the sweep's list): kept off the stack */
    replay_cli_defaults(&o);
    bool done = false;
    int rc = 0;
    pp5_status_t st = replay_cli_parse(&o, argc, argv, &done, &rc);
    if (done)
        return rc;
    if (st == PP5_OK && o.batch)
        return optind == argc ? replay_batch_main(&o)
                              : cliopt_report("replay", pp5_fail(PP5_E_CONFIG, "--batch: the "
                                              "traces are in the list; give no TRACE file"));
    if (st == PP5_OK && (o.out || o.resume || o.shard_n || o.accounting))
        st = pp5_fail(PP5_E_CONFIG, "--out, --resume, --shard and --accounting go with --batch "
                      "(one replay writes --csv and --report)");
    if (st == PP5_OK && !o.live && optind != argc - 1)
        st = pp5_fail(PP5_E_CONFIG, "need exactly one TRACE file (or --live DEVICE); see --help");
    if (st == PP5_OK && o.live && optind != argc)
        st = pp5_fail(PP5_E_CONFIG, "--live records its own trace: give no TRACE file");
    /* Outputs are checked before the (possibly long) replay starts. */
    if (st == PP5_OK)
        st = outpath_check_all("--report", o.report, "--csv", o.csv, "--plot", o.plot, NULL);
    if (st == PP5_OK && o.frames_dir)
        st = outpath_check_dir("--frames-dir", o.frames_dir);
    if (st != PP5_OK)
        return cliopt_report("replay", st);
    char live_path[] = "/tmp/pp5-live-XXXXXX.trace";
    if (o.live && (rc = record_live(o.live, o.live_seconds, live_path)) != 0)
        return rc;
    st = run_replay(&o, o.live ? live_path : argv[optind]);
    return st == PP5_OK ? 0 : cliopt_report("replay", st);
}

PP5_COMMAND(replay, "replay a gaze trace with latency: error and time in the sweet spot", cmd_replay)
