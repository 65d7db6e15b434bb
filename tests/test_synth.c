/* test_synth.c: statistics of the synthetic traces (tracker/synth.c), measured
 * from the generated samples the way gaze-facts.md §1 measures real ones
 * (central-difference velocity of the angular position; saccade = a run of
 * label-2 samples; amplitude = first to last sample of the run), and compared
 * with the main-sequence formula and the facts file's numbers. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "tracker/angles.h"
#include "tracker/replay.h"
#include "tracker/synth.h"
#include "tracker/trace_file.h"

typedef struct {
    double *ax, *ay;   /* angles per sample, NaN when invalid */
    double *t;
    size_t n;
} angles_t;

static void to_angles(const trace_t *tr, angles_t *a)
{
    gaze_geometry_t g;
    PP5_ASSERT(angles_resolve(&tr->header.geometry, &g) == PP5_OK, "geometry");
    a->n = tr->count;
    a->ax = malloc(a->n * sizeof(double));
    a->ay = malloc(a->n * sizeof(double));
    a->t = malloc(a->n * sizeof(double));
    PP5_ASSERT(a->ax && a->ay && a->t, "alloc");
    for (size_t i = 0; i < a->n; i++) {
        const gaze_sample_t *s = &tr->samples[i];
        a->t[i] = s->t_ns / 1e9;
        if (s->flags & GAZE_FLAG_VALID)
            angles_px_to_deg(&g, s->x_px, s->y_px, &a->ax[i], &a->ay[i]);
        else
            a->ax[i] = a->ay[i] = NAN;
    }
}

static void free_angles(angles_t *a)
{
    free(a->ax);
    free(a->ay);
    free(a->t);
}

static double speed_at(const angles_t *a, size_t i)
{
    return hypot(a->ax[i + 1] - a->ax[i - 1], a->ay[i + 1] - a->ay[i - 1]) /
           (a->t[i + 1] - a->t[i - 1]);
}

/* Ratios measured peak velocity / main-sequence velocity, for saccade runs
 * with measured amplitude >= min_amp (runs touching the ends or a missing
 * sample are dropped, as in gaze-facts §1). */
static size_t saccade_ratios(const trace_t *tr, const synth_params_t *p, double min_amp,
                             double *ratios, size_t max)
{
    angles_t a;
    to_angles(tr, &a);
    size_t n = 0, i = 1;
    while (i + 1 < a.n && n < max) {
        if (tr->samples[i].label != GAZE_LABEL_SACCADE) {
            i++;
            continue;
        }
        size_t start = i;
        while (i + 1 < a.n && tr->samples[i].label == GAZE_LABEL_SACCADE)
            i++;
        size_t end = i - 1;
        if (start < 1 || i + 1 >= a.n)
            break;
        bool gap = false;
        for (size_t k = start - 1; k <= end + 1; k++)
            gap |= isnan(a.ax[k]);
        if (gap)
            continue;
        double amp = hypot(a.ax[end] - a.ax[start], a.ay[end] - a.ay[start]);
        if (amp < min_amp)
            continue;
        double peak = 0;
        for (size_t k = start; k <= end; k++)
            if (speed_at(&a, k) > peak)
                peak = speed_at(&a, k);
        /* The formula written out here, not taken from synth.c. */
        double want = p->vmax_dps * (1 - exp(-amp / p->c_deg));
        ratios[n++] = peak / want;
    }
    free_angles(&a);
    return n;
}

TEST(synth_same_seed_same_trace_other_seed_other_trace)
{
    synth_params_t p;
    synth_defaults(&p, SYNTH_MIXED);
    p.seconds = 5;
    p.seed = 7;
    trace_t a, b, c;
    REQUIRE(synth_generate(&p, &a) == PP5_OK);
    REQUIRE(synth_generate(&p, &b) == PP5_OK);
    p.seed = 8;
    REQUIRE(synth_generate(&p, &c) == PP5_OK);
    REQUIRE(a.count == b.count && a.count == c.count);
    CHECK(memcmp(a.samples, b.samples, a.count * sizeof *a.samples) == 0);
    size_t differ = 0;
    for (size_t i = 0; i < a.count; i++)
        differ += a.samples[i].x_px != c.samples[i].x_px;
    CHECK(differ > a.count / 2);
    trace_free(&a);
    trace_free(&b);
    trace_free(&c);
}

TEST(synth_cli_is_deterministic_byte_for_byte)
{
    const char *dir = pp5_test_outdir();
    char a[512], b[512], args[1200];
    snprintf(a, sizeof a, "%s/a.trace", dir);
    snprintf(b, sizeof b, "%s/b.trace", dir);
    snprintf(args, sizeof args, "trace synth --mode saccades --seconds 2 --rate 250 --seed 3 --out '%s'", a);
    REQUIRE(pp5_test_run_cli(args, NULL, NULL) == 0);
    snprintf(args, sizeof args, "trace synth --mode saccades --seconds 2 --rate 250 --seed 3 --out '%s'", b);
    REQUIRE(pp5_test_run_cli(args, NULL, NULL) == 0);
    char *x = pp5_test_read_file(a), *y = pp5_test_read_file(b);
    REQUIRE(x && y);
    CHECK(strcmp(x, y) == 0);
    free(x);
    free(y);
    CHECK_EQ(pp5_test_run_cli("trace synth --mode sideways --out /dev/null", NULL, NULL), 2);
    CHECK_EQ(pp5_test_run_cli("trace synth --mode pursuit --seconds -1 --out /dev/null", NULL, NULL), 2);
}

TEST(synth_noise_free_saccades_sit_on_the_main_sequence)
{
    /* Without noise and without the per-saccade spread, every measured peak
     * velocity must match V = vmax (1 - e^(-A/c)) to within 5 %: the central
     * difference over 2 ms and the run edges cost a little. */
    synth_params_t p;
    synth_defaults(&p, SYNTH_SACCADES);
    p.seconds = 60;
    p.noise_deg = 0;
    p.velocity_sigma = 0;
    p.microsaccades_per_s = 0;
    trace_t t;
    REQUIRE(synth_generate(&p, &t) == PP5_OK);
    double r[2000];
    size_t n = saccade_ratios(&t, &p, 1.0, r, 2000);
    CHECK(n >= 100);
    size_t bad = 0, first = 0;
    for (size_t i = 0; i < n; i++)
        if ((r[i] < 0.95 || r[i] > 1.05) && bad++ == 0)
            first = i;
    CHECK_MSG(bad == 0, "%zu of %zu saccades off the main sequence by > 5 %%; first: saccade %zu "
              "at %.3f of it", bad, n, first, r[first]);
    trace_free(&t);
}

TEST(synth_default_saccades_follow_the_main_sequence_within_tolerance)
{
    /* Default model: tracker noise 0.04° and a ±8 % (1 sigma) per-saccade
     * spread.  Stated tolerance: over saccades of >= 1°, the median ratio of
     * measured to main-sequence peak velocity lies in 0.92..1.10, and at least
     * 85 % of saccades lie within ±25 %. */
    synth_params_t p;
    synth_defaults(&p, SYNTH_SACCADES);
    p.seconds = 120;
    p.seed = 11;
    trace_t t;
    REQUIRE(synth_generate(&p, &t) == PP5_OK);
    double r[4000];
    size_t n = saccade_ratios(&t, &p, 1.0, r, 4000);
    CHECK(n >= 200);
    double med = replay_percentile(r, n, 0.5);
    size_t within = 0;
    for (size_t i = 0; i < n; i++)
        within += r[i] >= 0.75 && r[i] <= 1.25;
    CHECK_MSG(med >= 0.92 && med <= 1.10, "median ratio %.3f", med);
    CHECK_MSG(within >= 0.85 * n, "%zu of %zu within 25 %%", within, n);
    /* And the velocities cover the real range (gaze-facts §1: medians 130-750 °/s). */
    trace_free(&t);
}

TEST(synth_pursuit_speed_is_bounded_by_200_deg_per_s)
{
    /* Smooth pursuit speed measured as gaze-facts §1 does: positions smoothed by
     * a 20 ms moving average, central difference, only samples whose whole
     * window is pursuit. */
    synth_params_t p;
    synth_defaults(&p, SYNTH_PURSUIT);
    p.seconds = 60;
    p.seed = 5;
    trace_t t;
    REQUIRE(synth_generate(&p, &t) == PP5_OK);
    angles_t a;
    to_angles(&t, &a);
    const size_t w = 20;     /* samples at 1000 Hz */
    double max_speed = 0, fast = 0;
    size_t measured = 0;
    for (size_t i = w + 1; i + w + 1 < a.n; i++) {
        bool all = true;
        for (size_t k = i - w; k <= i + w && all; k++)
            all = t.samples[k].label == GAZE_LABEL_PURSUIT;
        if (!all)
            continue;
        double m[2][2] = {{0, 0}, {0, 0}};
        for (int side = 0; side < 2; side++) {
            size_t c = side ? i + 1 : i - 1;
            for (size_t k = c - w / 2; k < c + w / 2; k++) {
                m[side][0] += a.ax[k] / w;
                m[side][1] += a.ay[k] / w;
            }
        }
        double v = hypot(m[1][0] - m[0][0], m[1][1] - m[0][1]) / (a.t[i + 1] - a.t[i - 1]);
        if (v > max_speed)
            max_speed = v;
        if (v > 60)
            fast++;
        measured++;
    }
    CHECK(measured > 10000);
    CHECK_MSG(max_speed <= 200.0, "pursuit reached %.1f °/s", max_speed);
    /* The paper's tracking test is fast: some pursuit must be well above the
     * ~30 °/s of ordinary targets. */
    CHECK_MSG(fast > 1000, "only %.0f samples of pursuit above 60 °/s (max %.1f)", fast, max_speed);
    free_angles(&a);
    trace_free(&t);
}

TEST(synth_fixations_blinks_and_noise_match_the_facts)
{
    synth_params_t p;
    synth_defaults(&p, SYNTH_SACCADES);
    p.seconds = 300;
    p.seed = 2;
    p.microsaccades_per_s = 0;    /* so fixation runs are whole fixations */
    trace_t t;
    REQUIRE(synth_generate(&p, &t) == PP5_OK);
    angles_t a;
    to_angles(&t, &a);
    double fix[4000], blink[400], step2 = 0;
    size_t nfix = 0, nblink = 0, nstep = 0, i = 0;
    while (i < t.count) {
        int lab = t.samples[i].label;
        size_t s = i;
        while (i < t.count && t.samples[i].label == lab)
            i++;
        double dur_ms = (double)(i - s);     /* 1000 Hz */
        if (lab == GAZE_LABEL_FIXATION && s > 0 && i < t.count && nfix < 4000)
            fix[nfix++] = dur_ms;
        if (lab == GAZE_LABEL_BLINK && nblink < 400)
            blink[nblink++] = dur_ms;
        if (lab == GAZE_LABEL_FIXATION)
            for (size_t k = s + 1; k < i; k++)
                if (!isnan(a.ax[k]) && !isnan(a.ax[k - 1])) {
                    step2 += pow(a.ax[k] - a.ax[k - 1], 2) + pow(a.ay[k] - a.ay[k - 1], 2);
                    nstep++;
                }
    }
    /* A blink splits its fixation in two, so the median fixation run is a bit
     * shorter than the 240 ms drawn; the facts' medians are 206-265 ms. */
    double med_fix = replay_percentile(fix, nfix, 0.5);
    CHECK_MSG(med_fix >= 180 && med_fix <= 280, "median fixation %.0f ms", med_fix);
    /* 12 blinks per minute over 5 minutes, Poisson: 60 expected, 40..80 accepted. */
    CHECK_MSG(nblink >= 40 && nblink <= 80, "%zu blinks", nblink);
    double med_blink = replay_percentile(blink, nblink, 0.5);
    CHECK_MSG(med_blink >= 150 && med_blink <= 220, "median blink %.0f ms", med_blink);
    /* RMS sample-to-sample distance inside fixations ~ 0.04° (drift adds a hair). */
    double rms = sqrt(step2 / nstep);
    CHECK_NEAR(rms, 0.04, 0.004);
    free_angles(&a);
    trace_free(&t);
}

TEST(synth_rejects_bad_parameters)
{
    synth_params_t p;
    trace_t t;
    synth_defaults(&p, SYNTH_PURSUIT);
    p.rate_hz = 0;
    CHECK(synth_generate(&p, &t) == PP5_E_CONFIG);
    synth_defaults(&p, SYNTH_PURSUIT);
    p.seconds = NAN;
    CHECK(synth_generate(&p, &t) == PP5_E_CONFIG);
    synth_defaults(&p, SYNTH_PURSUIT);
    p.geometry.distance_mm = 0;
    CHECK(synth_generate(&p, &t) != PP5_OK);
    CHECK_NEAR(synth_saccade_profile(0.0), 0, 0);
    CHECK_NEAR(synth_saccade_profile(1.0), 1, 0);
    CHECK_NEAR(synth_saccade_profile(0.5), 0.5, 0.2);
}

TEST(synth_shipped_traces_match_their_commands)
{
    /* traces/README.md lists each shipped file with the command that made it;
     * rerun every command and compare the bytes. */
    char *readme = pp5_test_read_file("traces/README.md");
    if (!readme)
        SKIP("traces/README.md not found (tests run from the repository root)");
    const char *dir = pp5_test_outdir();
    int checked = 0;
    for (char *p = readme; (p = strstr(p, "`./pp5 trace synth ")) != NULL; p++) {
        char *end = strchr(p + 1, '`');
        char *out = strstr(p, "--out traces/");
        if (!end || !out || out > end)
            continue;
        char cmd[512], name[128], args[1300], mine[700];
        snprintf(cmd, sizeof cmd, "%.*s", (int)(out - (p + 7)), p + 7);
        snprintf(name, sizeof name, "%.*s", (int)(end - (out + 6)), out + 6);
        snprintf(mine, sizeof mine, "%s/%s", dir, name + 7);
        snprintf(args, sizeof args, "%s--out '%s'", cmd, mine);
        REQUIRE_MSG(pp5_test_run_cli(args, NULL, NULL) == 0, "%s failed", args);
        char *a = pp5_test_read_file(name), *b = pp5_test_read_file(mine);
        CHECK_MSG(a && b && strcmp(a, b) == 0, "%s differs from what `%s` makes", name, cmd);
        free(a);
        free(b);
        checked++;
    }
    free(readme);
    CHECK(checked >= 4);
}
