/* cmd_trace_events.c: `pp5 trace events`: detect fixations, saccades, PSOs,
 * blinks and gaps in a trace and write them as a BIDS-style events.tsv; and
 * the event and data-quality lines of `pp5 trace info`. */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cliopt.h"
#include "emu/cli/cmd_trace.h"
#include "tracker/data_quality.h"
#include "tracker/events.h"
#include "tracker/events_score.h"

static void events_usage(FILE *out)
{
    events_params_t d;
    events_defaults(&d, EVENTS_IVT);
    fprintf(out,
        "usage: pp5 trace events TRACE [--method ivt|idt|adaptive] --out EVENTS.tsv [options]\n\n"
        "Detects fixations, saccades, post-saccadic oscillations (adaptive, at >= %.0f Hz),\n"
        "blinks (missing data lasting %.0f-%.0f ms) and gaps in a pp5 trace, and writes them as\n"
        "a BIDS-style events.tsv (onset, duration, trial_type, sample, n_samples, amplitude,\n"
        "peak_velocity, start/end positions) with a JSON sidecar beside it (EVENTS.json).\n"
        "When the trace carries labels (a coder's, or the generator's truth), prints the\n"
        "agreement with them.  Methods (tracker/events.h, tracker/ARCHITECTURE.md):\n"
        "  ivt       velocity threshold (Salvucci & Goldberg 2000)\n"
        "  idt       dispersion threshold (Salvucci & Goldberg 2000)\n"
        "  adaptive  noise-adaptive thresholds of Nystrom & Holmqvist 2010 (default)\n"
        "Options:\n"
        "  --threshold-dps V    ivt: speed threshold (default %g deg/s)\n"
        "  --dispersion-deg D   idt: dispersion threshold (default %g deg)\n"
        "  --window-ms W        idt: shortest fixation window (default %g ms)\n"
        "  --labels-out FILE    also write the trace with the detected labels\n"
        "Example:\n"
        "  pp5 trace synth --mode saccades --rate 500 --out s.trace\n"
        "  pp5 trace events s.trace --method adaptive --out s_events.tsv\n",
        d.pso_min_rate_hz, d.blink_min_s * 1e3, d.blink_max_s * 1e3, d.ivt_threshold_dps,
        d.idt_dispersion_deg, d.idt_window_s * 1e3);
}

static const int score_classes[] = {GAZE_LABEL_FIXATION, GAZE_LABEL_SACCADE, GAZE_LABEL_PSO,
                                    GAZE_LABEL_BLINK};

/* Agreement with the labels the trace came with, if any. */
static pp5_status_t print_agreement(const trace_t *t, const events_result_t *r)
{
    size_t labelled = 0;
    int *truth = malloc(t->count * sizeof *truth);
    if (!truth)
        return pp5_fail(PP5_E_NOMEM, "out of memory");
    for (size_t i = 0; i < t->count; i++) {
        truth[i] = t->samples[i].label;
        labelled += truth[i] != GAZE_LABEL_NONE;
    }
    events_list_t ref;
    pp5_status_t st = labelled ? events_from_labels(t, truth, &ref) : PP5_OK;
    if (labelled && st == PP5_OK) {
        printf("  agreement with the trace's labels (sample kappa / event F1):\n");
        for (size_t c = 0; c < sizeof score_classes / sizeof score_classes[0] && st == PP5_OK;
             c++) {
            kappa_counts_t k = {0};
            f1_counts_t f = {0};
            kappa_counts_add(&k, truth, r->labels, t->count, score_classes[c]);
            st = f1_counts_add(&f, &ref, &r->list, score_classes[c]);
            printf("    %-9s kappa %6.3f   F1 %6.3f\n", events_class_name(score_classes[c]),
                   kappa_of_counts(&k), f1_of_counts(&f));
        }
        events_list_free(&ref);
    }
    free(truth);
    return st;
}

static void print_counts(const events_result_t *r)
{
    for (int c = 1; c <= EVENTS_CLASS_MAX; c++) {
        duration_stats_t d = {0};
        duration_stats_add(&d, &r->list, c, 0);
        if (d.count)
            printf("  %-9s %5zu events, mean %6.1f ms, sd %6.1f ms\n", events_class_name(c),
                   d.count, duration_stats_mean_ms(&d), duration_stats_sd_ms(&d));
    }
}

static pp5_status_t write_labels(const char *path, const trace_t *t, const events_result_t *r)
{
    trace_t copy = *t;
    size_t bytes;
    if (!pp5_mul_size(t->count, sizeof *t->samples, &bytes) || !(copy.samples = malloc(bytes)))
        return pp5_fail(PP5_E_NOMEM, "out of memory");
    memcpy(copy.samples, t->samples, bytes);
    copy.capacity = t->count;
    for (size_t i = 0; i < t->count; i++)
        copy.samples[i].label = r->labels[i];
    pp5_status_t st = trace_write_file(path, &copy);
    free(copy.samples);
    return st;
}

/* EVENTS.tsv -> EVENTS.json (or EVENTS.json appended). */
static void sidecar_path(const char *tsv, char *out, size_t size)
{
    size_t n = strlen(tsv);
    if (n > 4 && strcmp(tsv + n - 4, ".tsv") == 0)
        snprintf(out, size, "%.*s.json", (int)(n - 4), tsv);
    else
        snprintf(out, size, "%s.json", tsv);
}

int cmd_trace_events(int argc, char **argv)
{
    static const struct option opts[] = {
        {"method", required_argument, 0, 'm'}, {"out", required_argument, 0, 'o'},
        {"threshold-dps", required_argument, 0, 'v'}, {"dispersion-deg", required_argument, 0, 'd'},
        {"window-ms", required_argument, 0, 'w'}, {"labels-out", required_argument, 0, 'l'},
        {"help", no_argument, 0, 'h'}, {0, 0, 0, 0}};
    events_method_t method = EVENTS_ADAPTIVE;
    double thr = NAN, disp = NAN, win = NAN;
    const char *outp = NULL, *labels_out = NULL;
    pp5_status_t st = PP5_OK;
    int c;
    optind = 1;
    while (st == PP5_OK && (c = getopt_long(argc, argv, "h", opts, NULL)) != -1) {
        switch (c) {
        case 'm':
            if (!events_method_parse(optarg, &method))
                st = pp5_fail(PP5_E_CONFIG, "--method: expected ivt, idt or adaptive, got '%s'",
                              optarg);
            break;
        case 'o': outp = optarg; break;
        case 'l': labels_out = optarg; break;
        case 'v': st = cliopt_double("--threshold-dps", optarg, 1, 10000, &thr); break;
        case 'd': st = cliopt_double("--dispersion-deg", optarg, 0.01, 90, &disp); break;
        case 'w': st = cliopt_double("--window-ms", optarg, 1, 10000, &win); break;
        case 'h': events_usage(stdout); return 0;
        default: events_usage(stderr); return 2;
        }
    }
    if (st == PP5_OK && (!outp || optind != argc - 1))
        st = pp5_fail(PP5_E_CONFIG, "need one TRACE and --out EVENTS.tsv; see --help");
    if (st != PP5_OK)
        return cliopt_report("trace events", st);
    events_params_t p;
    events_defaults(&p, method);
    if (!isnan(thr)) p.ivt_threshold_dps = thr;
    if (!isnan(disp)) p.idt_dispersion_deg = disp;
    if (!isnan(win)) p.idt_window_s = win / 1e3;
    trace_t t;
    if ((st = trace_read_file(argv[optind], &t)) != PP5_OK)
        return cliopt_report("trace events", st);
    events_result_t r;
    st = events_detect(&t, &p, &r);
    if (st == PP5_OK) {
        char side[1100];
        sidecar_path(outp, side, sizeof side);
        st = events_write_tsv(outp, &r.list);
        if (st == PP5_OK)
            st = events_write_sidecar(side, &p, &r, t.header.source);
        if (st == PP5_OK && labels_out)
            st = write_labels(labels_out, &t, &r);
        if (st == PP5_OK) {
            printf("%s: %zu events by %s at %.1f Hz", outp, r.list.count,
                   events_method_name(method), r.rate_hz);
            if (method == EVENTS_ADAPTIVE)
                printf(" (peak threshold %.1f deg/s, onset %.1f deg/s, PSO %s)",
                       r.peak_threshold_dps, r.onset_threshold_dps, r.pso_detected ? "on" : "off");
            printf("; sidecar %s\n", side);
            print_counts(&r);
            st = print_agreement(&t, &r);
        }
        events_result_free(&r);
    }
    trace_free(&t);
    return st == PP5_OK ? 0 : cliopt_report("trace events", st);
}

pp5_status_t trace_info_print_events(const trace_t *t)
{
    events_params_t p;
    events_defaults(&p, EVENTS_ADAPTIVE);
    events_result_t r;
    pp5_status_t st = events_detect(t, &p, &r);
    if (st != PP5_OK)
        return st;
    data_quality_params_t qp;
    data_quality_defaults(&qp);
    data_quality_t q;
    st = data_quality_measure(t, r.labels, &qp, &q);
    if (st == PP5_OK) {
        printf("data quality:  precision RMS-S2S %.4f deg, STD %.4f deg (medians over %zu "
               "detected fixations >= %.0f ms)\n", q.rms_s2s_deg, q.std_deg, q.fixations_used,
               qp.min_fixation_s * 1e3);
        printf("               data loss %.2f %% of %zu expected samples (invalid %.2f %% of "
               "delivered); rate %.2f Hz effective (median interval %.3f ms), %.2f Hz "
               "delivered, %g Hz nominal\n", 100 * q.data_loss, q.expected_samples,
               100 * q.invalid_fraction, q.effective_rate_hz, q.median_interval_s * 1e3,
               q.delivered_rate_hz, q.nominal_rate_hz);
        printf("events:        %zu by the adaptive detector (peak threshold %.1f deg/s, PSO %s)\n",
               r.list.count, r.peak_threshold_dps, r.pso_detected ? "on" : "off");
        print_counts(&r);
    }
    events_result_free(&r);
    return st;
}
