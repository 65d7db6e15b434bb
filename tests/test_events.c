/* test_events.c: the event detectors (tracker/events*.c) on synthetic traces
 * whose events are known (tracker/synth.c's ground truth), the events.tsv
 * round trip and its errors, and `pp5 trace events`. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "tracker/events.h"
#include "tracker/events_score.h"
#include "tracker/synth.h"

/* 20 s of free viewing at `rate` Hz with the generator's default noise,
 * microsaccades and blinks. */
static void make_synth(double rate, uint64_t seed, trace_t *t, synth_truth_t *truth)
{
    synth_params_t p;
    synth_defaults(&p, SYNTH_SACCADES);
    p.seconds = 20;
    p.rate_hz = rate;
    p.seed = seed;
    REQUIRE(synth_generate_truth(&p, t, truth) == PP5_OK);
}

static int *truth_labels(const trace_t *t)
{
    int *l = malloc(t->count * sizeof *l);
    PP5_ASSERT(l, "alloc");
    for (size_t i = 0; i < t->count; i++)
        l[i] = t->samples[i].label;
    return l;
}

/* Share of the true saccades of at least 2 deg whose onset a detected saccade
 * has within 2 samples (a missed saccade counts as a miss). */
static double onsets_within_2(const trace_t *t, const synth_truth_t *truth,
                              const events_result_t *r, size_t *n_out)
{
    size_t n = 0, good = 0;
    for (size_t k = 0; k < truth->count; k++) {
        const synth_saccade_t *s = &truth->saccades[k];
        if (s->micro || s->amplitude_deg < 2.0)
            continue;
        size_t i0 = 0;
        while (i0 < t->count && t->samples[i0].t_ns < llround(s->t_start_s * 1e9))
            i0++;
        size_t i1 = i0;
        while (i1 + 1 < t->count && t->samples[i1 + 1].label == GAZE_LABEL_SACCADE)
            i1++;
        if (i0 == 0 || i1 + 1 >= t->count || t->samples[i0].label != GAZE_LABEL_SACCADE)
            continue;
        n++;
        for (size_t e = 0; e < r->list.count; e++) {
            const gaze_event_t *d = &r->list.events[e];
            if (d->cls == GAZE_LABEL_SACCADE && d->first <= i1 && d->last >= i0) {
                long diff = (long)d->first - (long)i0;
                good += labs(diff) <= 2;
                break;
            }
        }
    }
    *n_out = n;
    return n ? (double)good / (double)n : NAN;
}

/* Bounds, and why a perfect detector would not reach 1:
 *   saccade kappa >= 0.70: the truth counts every microsaccade (0.8 per s,
 *     0.1-0.8 deg, peak 13-89 deg/s, about a tenth of the saccade samples),
 *     which no threshold here separates from drift and noise; and a
 *     main-sequence saccade starts and ends with 1-2 samples slower than the
 *     noise (its speed grows as u^2 and dies as (1-u)^3), which no detector
 *     sees; at a median 13 samples per saccade (500 Hz) that costs ~0.15;
 *   fixation kappa >= 0.75: the same samples, seen from the other side;
 *   blink kappa >= 0.85: blinks are missing data, found exactly, but the
 *     lid rule also takes the saccade samples around them;
 *   onsets: at least 85 % of the saccades of 2 deg and more start within 2
 *     samples of the true onset (a missed saccade counts as a miss).
 * 250 and 500 Hz: at 1000 Hz two samples are 2 ms, shorter than the slow
 * start of a saccade under the 0.04 deg noise. */
static void check_method(events_method_t m, double rate)
{
    trace_t t;
    synth_truth_t truth;
    make_synth(rate, 11, &t, &truth);
    events_params_t p;
    events_defaults(&p, m);
    events_result_t r;
    REQUIRE_MSG(events_detect(&t, &p, &r) == PP5_OK, "%s", pp5_error_text());
    int *truth_l = truth_labels(&t);
    const int cls[] = {GAZE_LABEL_FIXATION, GAZE_LABEL_SACCADE, GAZE_LABEL_BLINK};
    const double bound[] = {0.75, 0.70, 0.85};
    for (int c = 0; c < 3; c++) {
        kappa_counts_t k = {0};
        kappa_counts_add(&k, truth_l, r.labels, t.count, cls[c]);
        double kap = kappa_of_counts(&k);
        CHECK_MSG(kap >= bound[c], "%s at %.0f Hz: %s kappa %.3f < %.2f", events_method_name(m),
                  rate, events_class_name(cls[c]), kap, bound[c]);
    }
    size_t n;
    double share = onsets_within_2(&t, &truth, &r, &n);
    CHECK_MSG(n >= 30, "only %zu saccades of 2 deg or more", n);
    CHECK_MSG(share >= 0.85, "%s at %.0f Hz: %.1f %% of %zu onsets within 2 samples",
              events_method_name(m), rate, 100 * share, n);
    free(truth_l);
    events_result_free(&r);
    synth_truth_free(&truth);
    trace_free(&t);
}

TEST(events_ivt_finds_synthetic_saccades_and_their_onsets)
{
    check_method(EVENTS_IVT, 500);
    check_method(EVENTS_IVT, 250);
}

TEST(events_idt_finds_synthetic_saccades_and_their_onsets)
{
    check_method(EVENTS_IDT, 500);
    check_method(EVENTS_IDT, 250);
}

TEST(events_adaptive_finds_synthetic_saccades_and_their_onsets)
{
    check_method(EVENTS_ADAPTIVE, 500);
    check_method(EVENTS_ADAPTIVE, 250);
}

TEST(events_tsv_round_trips_every_field)
{
    trace_t t;
    synth_truth_t truth;
    make_synth(500, 5, &t, &truth);
    events_params_t p;
    events_defaults(&p, EVENTS_ADAPTIVE);
    events_result_t r;
    REQUIRE(events_detect(&t, &p, &r) == PP5_OK);
    REQUIRE(r.list.count > 50);
    char a[600], b[600];
    snprintf(a, sizeof a, "%s/a.tsv", pp5_test_outdir());
    snprintf(b, sizeof b, "%s/b.tsv", pp5_test_outdir());
    REQUIRE(events_write_tsv(a, &r.list) == PP5_OK);
    events_list_t back;
    REQUIRE_MSG(events_read_tsv(a, &back) == PP5_OK, "%s", pp5_error_text());
    REQUIRE(back.count == r.list.count);
    size_t bad = 0, first_bad = 0;
    for (size_t i = 0; i < back.count; i++) {
        const gaze_event_t *x = &r.list.events[i], *y = &back.events[i];
        bool same_nan = isnan(x->amplitude_deg) == isnan(y->amplitude_deg) &&
                        isnan(x->start_x_px) == isnan(y->start_x_px);
        bool differs = x->cls != y->cls || x->first != y->first || x->last != y->last || !same_nan ||
               fabs(x->onset_s - y->onset_s) > 5e-7 || fabs(x->duration_s - y->duration_s) > 5e-7 ||
               (!isnan(x->amplitude_deg) && fabs(x->amplitude_deg - y->amplitude_deg) > 5e-5) ||
               (!isnan(x->peak_velocity_dps) &&
                fabs(x->peak_velocity_dps - y->peak_velocity_dps) > 5e-3) ||
               (!isnan(x->start_x_px) && (fabs(x->start_x_px - y->start_x_px) > 5e-4 ||
                                          fabs(x->end_y_px - y->end_y_px) > 5e-4));
        if (differs && bad++ == 0)
            first_bad = i;
    }
    CHECK_MSG(bad == 0, "%zu of %zu events differ after the TSV round trip; first: event %zu",
              bad, back.count, first_bad);
    /* Written again, the same bytes. */
    REQUIRE(events_write_tsv(b, &back) == PP5_OK);
    char *ta = pp5_test_read_file(a), *tb = pp5_test_read_file(b);
    REQUIRE(ta && tb);
    CHECK(strcmp(ta, tb) == 0);
    CHECK(strncmp(ta, "onset\tduration\ttrial_type\t", 26) == 0);
    free(ta);
    free(tb);
    events_list_free(&back);
    events_result_free(&r);
    synth_truth_free(&truth);
    trace_free(&t);
}

TEST(events_tsv_reader_names_the_problem)
{
    static const char head[] = "onset\tduration\ttrial_type\tsample\tn_samples\tamplitude\t"
                               "peak_velocity\tstart_x\tstart_y\tend_x\tend_y\n";
    static const struct {
        const char *body, *want;
    } cases[] = {
        {"0.1\t0.2\tfixation\t5\t10\t0.5\t20\t1\t2\t3\t4", "no newline"},
        {"0.1\t0.2\twink\t5\t10\t0.5\t20\t1\t2\t3\t4\n", "unknown trial_type 'wink'"},
        {"0.1\t0.2\tfixation\t5\t10\t0.5\t20\t1\t2\t3\n", "10 fields, the header has 11"},
        {"nan\t0.2\tfixation\t5\t10\t0.5\t20\t1\t2\t3\t4\n", "onset 'nan'"},
        {"0.1\t0.2\tfixation\t5\t0\t0.5\t20\t1\t2\t3\t4\n", "n_samples '0'"},
        {"0.1\t0.2\tfixation\t5\t10\tx\t20\t1\t2\t3\t4\n", "'x' is neither"},
        {"0.5\t0.2\tfixation\t5\t10\t0.5\t20\t1\t2\t3\t4\n0.1\t0.2\tsaccade\t1\t2\tn/a\tn/a\t"
         "n/a\tn/a\tn/a\tn/a\n", "before the previous"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char text[512];
        snprintf(text, sizeof text, "%s%s", head, cases[i].body);
        events_list_t l = {0};
        pp5_status_t st = events_parse_tsv(text, strlen(text), "e.tsv", &l);
        CHECK_MSG(st == PP5_E_FORMAT && strstr(pp5_error_text(), cases[i].want) &&
                  strstr(pp5_error_text(), "e.tsv:"), "case %zu: %s", i, pp5_error_text());
        CHECK(l.count == 0 && l.events == NULL);
    }
    events_list_t l;
    CHECK(events_parse_tsv("onset\tduration\n", 15, "h.tsv", &l) == PP5_E_FORMAT);
    CHECK(events_parse_tsv("", 0, "z.tsv", &l) == PP5_E_FORMAT);
    /* A file with the header and n/a values reads. */
    char ok[512];
    snprintf(ok, sizeof ok, "%s0.1\t0.2\tblink\t5\t10\tn/a\tn/a\tn/a\tn/a\tn/a\tn/a\n", head);
    REQUIRE(events_parse_tsv(ok, strlen(ok), "ok.tsv", &l) == PP5_OK);
    CHECK(l.count == 1 && l.events[0].cls == GAZE_LABEL_BLINK && l.events[0].last == 14 &&
          isnan(l.events[0].amplitude_deg));
    events_list_free(&l);
}

TEST(events_cli_writes_tsv_and_sidecar_and_rejects_bad_input)
{
    const char *dir = pp5_test_outdir();
    char args[2048], out[700], side[700], log[700];
    snprintf(out, sizeof out, "%s/s.tsv", dir);
    snprintf(side, sizeof side, "%s/s.json", dir);
    snprintf(log, sizeof log, "%s/log.txt", dir);
    snprintf(args, sizeof args, "trace synth --mode saccades --seconds 3 --rate 500 "
             "--out '%s/s.trace'", dir);
    REQUIRE(pp5_test_run_cli(args, NULL, NULL) == 0);
    for (int m = 0; m < 3; m++) {
        snprintf(args, sizeof args, "trace events '%s/s.trace' --method %s --out '%s'", dir,
                 events_method_name((events_method_t)m), out);
        CHECK_EQ(pp5_test_run_cli(args, log, NULL), 0);
        events_list_t l;
        CHECK(events_read_tsv(out, &l) == PP5_OK && l.count > 5);
        events_list_free(&l);
        char *text = pp5_test_read_file(side), *stdout_text = pp5_test_read_file(log);
        CHECK(text && strstr(text, "\"Method\"") && strstr(text, "\"onset\""));
        CHECK(stdout_text && strstr(stdout_text, "agreement with the trace's labels"));
        free(text);
        free(stdout_text);
    }
    snprintf(args, sizeof args, "trace events '%s/none.trace' --out '%s'", dir, out);
    CHECK_EQ(pp5_test_run_cli(args, NULL, log), PP5_EXIT_IO);
    char *err = pp5_test_read_file(log);
    CHECK(err && strstr(err, "none.trace"));
    free(err);
    snprintf(args, sizeof args, "trace events '%s/s.trace' --method sideways --out '%s'", dir, out);
    CHECK_EQ(pp5_test_run_cli(args, NULL, NULL), 2);
    snprintf(args, sizeof args, "trace events '%s/s.trace'", dir);
    CHECK_EQ(pp5_test_run_cli(args, NULL, NULL), 2);
}
