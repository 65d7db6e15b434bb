/* synth.h: synthetic gaze traces from a seed (fixations, main-sequence
 * saccades, smooth pursuit with catch-up saccades, blinks, tracker noise).
 *
 * Numbers and where they come from (gaze-facts.md; "§1" = measured on the
 * stored recordings, "§5" = the suggested generator defaults):
 *   saccade peak velocity V = vmax (1 - exp(-A / c)), vmax 600 °/s, c 5.0°
 *     (inside §5's 560-640 °/s and 4.3-5.6°; the Lund/IRF fits of §1 are
 *     563/4.31 and 636/5.64), times a per-saccade factor exp(N(0, 0.08)) (§5's
 *     ±15 %).  The definition reproduced is the *central-difference peak
 *     velocity of the positions at 1000 Hz*, as §1 measures it.
 *   velocity profile 60 u^2 (1-u)^3: peak at 40 % of the duration (skewed,
 *     §2 [S5, S6]); its peak/mean ratio 2.0736 fixes the duration
 *     D = 2.0736 A / V, which gives 21 ms at 2° and 40 ms at 10° (the §1 fits
 *     D = 2.38-2.55 ms/° A + 14-18 ms give 19-23 and 38-43 ms).
 *   saccade amplitude lognormal, median 4.7°, 10-90 % 1.3-11.1° (§1, Lund images).
 *   fixation duration lognormal, median 240 ms, 10-90 % 126-425 ms (§1, Lund
 *     images 224 ms; reading 206 ms), clamped to 80-2000 ms; drift a random walk
 *     of 0.1 °/sqrt(s) per axis [assumption] (drift_deg_per_sqrt_s);
 *     microsaccades 0.8 /s of 0.1-0.8° (§1 IRF).
 *   blinks 12 per minute (§2 [S23]), lognormal duration median 180 ms, 10-90 %
 *     148-229 ms (§1 IRF); samples missing (status blink, label 5); they start
 *     inside fixations, or anywhere in pursuit (which continues behind the lids).
 *   pursuit: the target (the paper's cursor, §6) moves in straight runs of
 *     0.4-1.5 s at speeds up to max_pursuit_dps (default
 *     200 °/s, the paper's "up to 200°/sec"); the smooth eye velocity follows
 *     gain x target velocity through an 80 ms first-order lag, also during
 *     catch-up saccades [assumption]; run speeds are log-uniform in 5..max;
 *     gain 1 up to 30 °/s, falling linearly to 0.8 at 100 °/s and 0.7 at
 *     200 °/s (§2: gain <= 1 and falling at speed [S17]; the values are an
 *     assumption); a catch-up saccade fires when the position error exceeds
 *     1° (§2 [S14]: above ~30 °/s pursuit needs catch-up saccades), at least
 *     60 ms after the previous one ends [assumption].
 *   noise: white, per axis sigma = noise_deg / 2, so that the RMS
 *     sample-to-sample distance is noise_deg (§1: 0.028-0.049°; default 0.04°).
 * Not modelled: post-saccadic oscillations, pursuit onset latency, blink-induced
 * lid artefacts, vergence, head movement. */
#ifndef PP5_SYNTH_H
#define PP5_SYNTH_H

#include <stdint.h>
#include "gaze.h"
#include "status.h"
#include "trace_file.h"

typedef enum { SYNTH_PURSUIT, SYNTH_SACCADES, SYNTH_MIXED } synth_mode_t;

typedef struct {
    synth_mode_t mode;
    double seconds;            /* > 0 */
    double rate_hz;            /* sample rate, > 0 */
    uint64_t seed;
    gaze_geometry_t geometry;  /* default: the paper's display (angles.h) */
    double noise_deg;          /* RMS sample-to-sample distance of the noise (0 = none) */
    double vmax_dps, c_deg;    /* main sequence */
    double velocity_sigma;     /* per-saccade log-normal spread of the peak velocity */
    double max_pursuit_dps;    /* top target speed in pursuit */
    double blinks_per_min;     /* 0 = no blinks */
    double microsaccades_per_s;
    double drift_deg_per_sqrt_s; /* fixational drift random walk per axis (default 0.1) */
} synth_params_t;

void synth_defaults(synth_params_t *p, synth_mode_t mode);
bool synth_mode_parse(const char *name, synth_mode_t *mode);
const char *synth_mode_name(synth_mode_t mode);

/* Profile shared with tests: fraction of the amplitude covered at u in [0,1]. */
double synth_saccade_profile(double u);
/* Main-sequence peak velocity for amplitude a_deg (no per-saccade spread). */
double synth_main_sequence(const synth_params_t *p, double a_deg);

/* Generates a trace (header filled; source text describes the parameters). */
pp5_status_t synth_generate(const synth_params_t *p, trace_t *out);

/* The generator's ground truth for every saccade it made (microsaccades and
 * catch-up saccades included), in visual angle on the trace's display
 * (angles.h; the clean eye, before noise).  Samples with t in [t_start_s,
 * t_end_s) carry label 2; the eye sits at (x1, y1) from t_end_s on. */
typedef struct {
    double t_start_s, t_end_s;
    double x0_deg, y0_deg, x1_deg, y1_deg;
    double amplitude_deg;
    double peak_dps;           /* the model's peak velocity (main sequence x spread) */
    bool micro;                /* a fixational microsaccade */
} synth_saccade_t;

typedef struct {
    synth_saccade_t *saccades;
    size_t count, capacity;
} synth_truth_t;

void synth_truth_free(synth_truth_t *t);
/* As synth_generate, and also fills *truth (freed by synth_truth_free; the
 * trace is byte-for-byte the one synth_generate makes). */
pp5_status_t synth_generate_truth(const synth_params_t *p, trace_t *out, synth_truth_t *truth);

/* The generator's PRNG (xoshiro256**, seeded through splitmix64): public so
 * other modules can make reproducible streams. */
typedef struct { uint64_t s[4]; } synth_rng_t;
void synth_rng_seed(synth_rng_t *r, uint64_t seed);
uint64_t synth_rng_next(synth_rng_t *r);
double synth_rng_uniform(synth_rng_t *r);     /* [0, 1) */
double synth_rng_normal(synth_rng_t *r);      /* N(0, 1) */

#endif
