/* test_data_quality.c: precision, data loss and rate (tracker/data_quality.c)
 * on traces whose answers are known from how they were made. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "tracker/angles.h"
#include "tracker/data_quality.h"
#include "tracker/synth.h"

TEST(data_quality_precision_of_synthetic_white_noise)
{
    /* synth adds white noise of sd noise/2 per axis (synth.h).  Between two
     * samples each axis differs by sd noise/2 * sqrt 2, so the squared
     * distance has mean 2 * 2 (noise/2)^2 = noise^2: RMS-S2S = noise.  The
     * positions about their mean have var x + var y = 2 (noise/2)^2: STD =
     * noise / sqrt 2.  Drift, microsaccades and blinks are off, and the
     * generator's own fixation labels say which samples are fixation. */
    synth_params_t p;
    synth_defaults(&p, SYNTH_SACCADES);
    p.seconds = 30;
    p.rate_hz = 500;
    p.noise_deg = 0.1;
    p.drift_deg_per_sqrt_s = 0;
    p.microsaccades_per_s = 0;
    p.blinks_per_min = 0;
    trace_t t;
    REQUIRE(synth_generate(&p, &t) == PP5_OK);
    int *labels = malloc(t.count * sizeof *labels);
    REQUIRE(labels);
    for (size_t i = 0; i < t.count; i++)
        labels[i] = t.samples[i].label;
    data_quality_params_t qp;
    data_quality_defaults(&qp);
    data_quality_t q;
    REQUIRE(data_quality_measure(&t, labels, &qp, &q) == PP5_OK);
    CHECK(q.fixations_used > 50);
    /* Medians over ~100 fixations of ~100 samples each: a few per cent of
     * spread (the noise is added in the same per-axis angles that are
     * measured, so the display geometry adds nothing). */
    CHECK_NEAR(q.rms_s2s_deg, 0.1, 0.006);
    CHECK_NEAR(q.std_deg, 0.1 / sqrt(2.0), 0.005);
    CHECK_NEAR(q.data_loss, 0.0, 1e-12);
    CHECK_NEAR(q.effective_rate_hz, 500, 1e-6);
    free(labels);
    trace_free(&t);
}

TEST(data_quality_loss_and_rate_of_a_hand_made_trace)
{
    /* 100 Hz for 9.99 s would be 1000 samples; samples 200-249 are never
     * delivered (a 0.5 s hole) and 30 of the others carry no gaze.
     * Delivered 950; valid 920; data loss = 1 - 920/1000 = 8 %; invalid =
     * 30/950; median interval 10 ms; delivered rate 949 / 9.99 s. */
    trace_t t;
    trace_init(&t);
    snprintf(t.header.source, sizeof t.header.source, "hand-made");
    t.header.sample_rate_hz = 100;
    angles_paper_geometry(&t.header.geometry);
    for (int i = 0; i < 1000; i++) {
        if (i >= 200 && i < 250)
            continue;
        gaze_sample_t s;
        gaze_sample_invalid(&s, (int64_t)i * 10000000);
        if (!(i >= 500 && i < 530)) {
            s.x_px = 640;
            s.y_px = 512;
            s.flags = GAZE_FLAG_VALID;
        }
        REQUIRE(trace_append(&t, &s) == PP5_OK);
    }
    int *labels = calloc(t.count, sizeof *labels);
    REQUIRE(labels);
    data_quality_params_t qp;
    data_quality_defaults(&qp);
    data_quality_t q;
    REQUIRE(data_quality_measure(&t, labels, &qp, &q) == PP5_OK);
    CHECK_EQ(q.expected_samples, 1000);
    CHECK_NEAR(q.data_loss, 0.08, 1e-12);
    CHECK_NEAR(q.invalid_fraction, 30.0 / 950.0, 1e-12);
    CHECK_NEAR(q.median_interval_s, 0.010, 1e-12);
    CHECK_NEAR(q.delivered_rate_hz, 949.0 / 9.99, 1e-9);
    CHECK_EQ(q.fixations_used, 0);
    CHECK(isnan(q.rms_s2s_deg) && isnan(q.std_deg));
    free(labels);
    trace_free(&t);
}
