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
#include "json.h"
#include "outfile.h"
#include "registry.h"
#include "tracker/replay.h"
#include "tracker/trace_file.h"

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
        "  --frame-time-ms X        shorthand for --cost constant:X (a stand-in; %.1f ms is the\n"
        "                           paper's 15 frames/s)\n"
        "  --tracker-latency-ms T   sample age when it reaches the renderer (default %.0f) [U]\n"
        "  --display-latency-ms D   from frame end to the image on the screen (default %.0f) [U]\n"
        "  --latency-ms T           shorthand: tracker latency T, display latency 0\n"
        "  --radius-deg R           full-resolution radius (default 6: the paper's 12 deg circle)\n"
        "  --refresh-hz HZ          images wait for the next refresh (e.g. 60); default: none\n"
        "  --gap-s G                a pause in the samples longer than G s (default 1) splits\n"
        "                           the trace: frames whose gaze predates it are not scored\n"
        "  --predict P              none (default), linear, alphabeta, kalman\n"
        "  --timing-only            do not ask the frame source for images\n"
        "  --max-frames N           stop after N frames\n"
        "  --report FILE.json       summary and parameters\n"
        "  --csv FILE.csv           one line per frame\n"
        "  --plot FILE.png          error and frame time over the trace\n"
        "  --live DEVICE            record live gaze from DEVICE (as `pp5 track record --device`:\n"
        "                           hid, hid:/dev/hidrawN, polhemus, polhemus:BUS:ADDR) for\n"
        "                           --seconds S (default 10), keep it in /tmp, then replay it\n"
        "  --frames-dir DIR         write each frame's image as DIR/frame_NNNNN.png (only when\n"
        "                           the cost source renders images; the constant one does not)\n",
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

static pp5_status_t write_report(const char *path, const char *trace_path, const trace_t *t,
                                 const replay_params_t *p, const replay_cost_source_t *cs,
                                 const char *cost_options, const replay_summary_t *s)
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
    json_kv_bool(&j, "timing_only", p->timing_only);
    json_key(&j, "summary");
    json_begin_object(&j);
    json_kv_uint(&j, "frames", s->frames);
    json_kv_uint(&j, "frames_with_error", s->frames_with_error);
    json_kv_uint(&j, "frames_after_gap", s->frames_after_gap);
    json_kv_double(&j, "trace_s", s->trace_s);
    json_kv_double(&j, "valid_display_s", s->valid_display_s);
    json_kv_double(&j, "inside_fraction", s->inside_fraction);
    json_kv_double(&j, "mean_error_deg", s->mean_error_deg);
    json_kv_double(&j, "p95_error_deg", s->p95_error_deg);
    json_kv_double(&j, "max_error_deg", s->max_error_deg);
    json_kv_double(&j, "frames_per_s", s->frames_per_s);
    json_kv_double(&j, "mean_frame_ms", s->mean_frame_s * 1e3);
    json_kv_double(&j, "mean_latency_ms", s->mean_latency_s * 1e3);
    json_kv_uint(&j, "rays", s->rays);
    json_kv_uint(&j, "ring_bytes", s->ring_bytes);
    json_end_object(&j);
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
        st = plot_write_png(&p, path, 900, 450);
    plot_free(&p);
    free(x);
    return st;
#else
    (void)r;
    return pp5_fail(PP5_E_UNSUPPORTED, "--plot %s: this branch has no emu/util/plot.h yet (it "
                    "comes with the integration); the CSV and JSON were written", path);
#endif
}

static int cmd_replay(int argc, char **argv)
{
    static const struct option opts[] = {
        {"frame-time-ms", required_argument, 0, 'f'}, {"tracker-latency-ms", required_argument, 0, 't'},
        {"display-latency-ms", required_argument, 0, 'd'}, {"latency-ms", required_argument, 0, 'l'},
        {"radius-deg", required_argument, 0, 'r'}, {"predict", required_argument, 0, 'p'},
        {"timing-only", no_argument, 0, 'T'}, {"max-frames", required_argument, 0, 'n'},
        {"report", required_argument, 0, 'j'}, {"csv", required_argument, 0, 'c'},
        {"plot", required_argument, 0, 'P'}, {"cost", required_argument, 0, 'C'},
        {"refresh-hz", required_argument, 0, 'R'}, {"gap-s", required_argument, 0, 'g'},
        {"frames-dir", required_argument, 0, 'F'}, {"live", required_argument, 0, 'L'},
        {"seconds", required_argument, 0, 'S'}, {"help", no_argument, 0, 'h'}, {0, 0, 0, 0}};
    replay_params_t p;
    replay_defaults(&p);
    /* The emulated machine when it is built in (firmware/host/replay_machine.c
     * registers it); the constant stand-in otherwise. */
    char cost_spec[256] = "constant";
    if (replay_find_cost_source("machine"))
        snprintf(cost_spec, sizeof cost_spec, "machine");
    const char *report = NULL, *csv = NULL, *plot = NULL, *frames_dir = NULL;
    const char *live = NULL, *live_seconds = "10";
    pp5_status_t st = PP5_OK;
    double ms;
    long nf;
    int c;
    optind = 1;
    while (st == PP5_OK && (c = getopt_long(argc, argv, "h", opts, NULL)) != -1) {
        switch (c) {
        case 'f':
            if ((st = cliopt_double("--frame-time-ms", optarg, 0.01, 1e6, &ms)) == PP5_OK)
                snprintf(cost_spec, sizeof cost_spec, "constant:%s", optarg);
            break;
        case 'C':
            if (strlen(optarg) >= sizeof cost_spec)
                st = pp5_fail(PP5_E_CONFIG, "--cost: too long");
            else
                snprintf(cost_spec, sizeof cost_spec, "%s", optarg);
            break;
        case 'F': frames_dir = optarg; break;
        case 'L': live = optarg; break;
        case 'S': st = cliopt_double("--seconds", optarg, 0.1, 86400, &ms); live_seconds = optarg; break;
        case 'R': st = cliopt_double("--refresh-hz", optarg, 0, 10000, &p.refresh_hz); break;
        case 'g': st = cliopt_double("--gap-s", optarg, 0.001, 1e6, &p.gap_s); break;
        case 't':
            if ((st = cliopt_double("--tracker-latency-ms", optarg, 0, 1e6, &ms)) == PP5_OK)
                p.tracker_latency_s = ms / 1e3;
            break;
        case 'd':
            if ((st = cliopt_double("--display-latency-ms", optarg, 0, 1e6, &ms)) == PP5_OK)
                p.display_latency_s = ms / 1e3;
            break;
        case 'l':
            if ((st = cliopt_double("--latency-ms", optarg, 0, 1e6, &ms)) == PP5_OK) {
                p.tracker_latency_s = ms / 1e3;
                p.display_latency_s = 0;
            }
            break;
        case 'r': st = cliopt_double("--radius-deg", optarg, 0.01, 180, &p.fullres_radius_deg); break;
        case 'p': {
            predict_kind_t k;
            if (!predict_kind_parse(optarg, &k))
                st = pp5_fail(PP5_E_CONFIG, "--predict: expected none, linear, alphabeta or "
                              "kalman, got '%s'", optarg);
            else
                predict_defaults(&p.predict, k);
            break;
        }
        case 'T': p.timing_only = true; break;
        case 'n':
            if ((st = cliopt_long("--max-frames", optarg, 1, 100000000L, &nf)) == PP5_OK)
                p.max_frames = (size_t)nf;
            break;
        case 'j': report = optarg; break;
        case 'c': csv = optarg; break;
        case 'P': plot = optarg; break;
        case 'h': usage(stdout); return 0;
        default: usage(stderr); return 2;
        }
    }
    if (st == PP5_OK && !live && optind != argc - 1)
        st = pp5_fail(PP5_E_CONFIG, "need exactly one TRACE file (or --live DEVICE); see --help");
    if (st == PP5_OK && live && optind != argc)
        st = pp5_fail(PP5_E_CONFIG, "--live records its own trace: give no TRACE file");
    /* Outputs are checked before the (possibly long) replay starts. */
    if (st == PP5_OK)
        st = outpath_check_all("--report", report, "--csv", csv, "--plot", plot, NULL);
    if (st == PP5_OK && frames_dir)
        st = outpath_check_dir("--frames-dir", frames_dir);
    if (st != PP5_OK)
        return cliopt_report("replay", st);
    const char *path = live ? NULL : argv[optind];
    char live_path[] = "/tmp/pp5-live-XXXXXX.trace";
    if (live) {
        /* Record first, then replay: the emulated machine runs slower than
         * real time, so a live session is recorded (flushed as it goes, by
         * `pp5 track record`) and then replayed frame by frame. */
        int fd = mkstemps(live_path, 6);
        if (fd < 0)
            return cliopt_report("replay", pp5_fail(PP5_E_IO, "--live: cannot make a temporary "
                                                    "trace file in /tmp"));
        close(fd);
        const pp5_command_t *track = pp5_find_command("track");
        if (!track)
            return cliopt_report("replay", pp5_fail(PP5_E_UNSUPPORTED, "--live: this build has "
                                                    "no `pp5 track`"));
        char *track_argv[] = {"track", "record", "--device", (char *)live, "--seconds",
                              (char *)live_seconds, "--out", live_path, NULL};
        fprintf(stderr, "replay: recording %s s of live gaze from %s into %s\n", live_seconds,
                live, live_path);
        optind = 0;
        int rc = track->fn(8, track_argv);
        optind = 1;
        if (rc != 0) {
            /* A device that stopped (timeout, unplugged) leaves what arrived:
             * replay that, saying so, unless there is nothing to replay. */
            trace_t partial;
            bool usable = trace_read_file(live_path, &partial) == PP5_OK && partial.count >= 2;
            if (usable)
                trace_free(&partial);
            if (!usable) {
                fprintf(stderr, "pp5 replay: --live %s: the recording failed (see above) and "
                        "holds too little to replay (%s)\n", live, live_path);
                return rc;
            }
            fprintf(stderr, "replay: the live recording ended early (see above); replaying what "
                    "arrived\n");
        }
        path = live_path;
    }
    /* NAME[:OPTIONS] */
    char *colon = strchr(cost_spec, ':');
    const char *cost_options = "";
    if (colon) {
        *colon = '\0';
        cost_options = colon + 1;
    }
    const replay_cost_source_t *cs = replay_find_cost_source(cost_spec);
    if (!cs)
        return cliopt_report("replay", pp5_fail(PP5_E_CONFIG, "--cost: no frame-cost source "
                                                "'%s' in this build (see --help)", cost_spec));
    trace_t t;
    st = trace_read_file(path, &t);
    if (st != PP5_OK)
        return cliopt_report("replay", st);
    void *ctx = NULL;
    st = cs->open(cost_options, &p.display, &ctx);
    if (st != PP5_OK) {
        trace_free(&t);
        return cliopt_report("replay", st);
    }
    frames_out_t fo = {frames_dir, 0};
    replay_result_t r;
    st = replay_run(&t, &p, cs->cost, ctx, frames_dir ? save_frame : NULL, &fo, &r);
    if (st == PP5_OK) {
        const replay_summary_t *s = &r.summary;
        printf("replay %s (%s)\n", path, t.header.source);
        printf("  frame source: %s%s%s: %s; mean frame %.1f ms\n", cs->name,
               cost_options[0] ? ":" : "", cost_options, cs->summary, s->mean_frame_s * 1e3);
        printf("  latency: tracker %.1f ms + frame + display %.1f ms; mean sample age at display "
               "%.1f ms\n", p.tracker_latency_s * 1e3, p.display_latency_s * 1e3,
               s->mean_latency_s * 1e3);
        printf("  prediction: %s\n", predict_kind_name(p.predict.kind));
        printf("  frames: %zu (%.2f frames/s) over %.3f s of trace\n", s->frames, s->frames_per_s,
               s->trace_s);
        printf("  error at display time: mean %.2f deg, 95th percentile %.2f deg, max %.2f deg "
               "(%zu frames measurable; %zu not scored: shown after a recording gap > %.1f s)\n",
               s->mean_error_deg, s->p95_error_deg, s->max_error_deg, s->frames_with_error,
               s->frames_after_gap, p.gap_s);
        printf("  true gaze inside the %.1f deg full-resolution radius: %.1f %% of %.3f s with "
               "gaze data\n", p.fullres_radius_deg, 100.0 * s->inside_fraction,
               s->valid_display_s);
        if (frames_dir)
            printf("  frames written to %s: %zu (the cost source renders %s)\n", frames_dir,
                   fo.written, fo.written ? "images" : "no images");
        if (csv)
            st = write_csv(csv, &r);
        if (st == PP5_OK && report)
            st = write_report(report, path, &t, &p, cs, cost_options, s);
        if (st == PP5_OK && plot)
            st = write_plot(plot, &r);
        replay_result_free(&r);
    }
    if (cs->close)
        cs->close(ctx);
    trace_free(&t);
    return st == PP5_OK ? 0 : cliopt_report("replay", st);
}

PP5_COMMAND(replay, "replay a gaze trace with latency: error and time in the sweet spot", cmd_replay)
