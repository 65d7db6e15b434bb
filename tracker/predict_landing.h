/* predict_landing.h: saccade-landing prediction from the samples that have
 * arrived (`pp5 replay --predict landing`), and its scoring against true
 * landing points.
 *
 * During a saccade the eye is effectively blind (saccadic suppression), and
 * its landing point follows from the start of its velocity profile: gaze
 * contingent displays since the 1990 paper place the sweet spot there.  The
 * predictor watches the arrived samples (per-axis visual angle, as replay
 * feeds predict.h):
 *   speed     |p(i) - p(i-k)| / (t(i) - t(i-k)), the central difference of
 *             gaze-facts §1 centred k/2 samples back, k = 2 or as many as span
 *             3.5 ms (4 at 1000 Hz: the noise of a 2 ms difference at 1000 Hz
 *             is as large as a slow saccade's onset);
 *   onset     the speed above max(onset_dps, onset_noise x the median speed of
 *             the last 64 samples outside saccades) twice in a row: a fixed
 *             floor plus a noise-adaptive part, as detectors do (events.h);
 *             the onset point is the sample before the first fast one;
 *   flight    the direction is onset point -> newest sample; the amplitude is
 *             estimated two ways and the two weighed by their expected error:
 *               main sequence: V = vmax (1 - exp(-A / C)) inverted for the
 *                 highest speed so far, A = -C ln(1 - V / vmax); default
 *                 vmax 563 deg/s, C 4.31 deg, the fit to the human-labelled
 *                 Lund saccades (gaze-facts §1; central-difference peaks, the
 *                 definition used here); its error grows as V nears vmax;
 *               profile: once the speed has stayed under peak_drop x its peak
 *                 for two samples (one noisy dip is not the peak), the share
 *                 u of the duration gone by follows from speed / peak on the
 *                 decelerating side of a profile u^2 (1-u)^3 whose peak is at
 *                 40 % of the duration (skewed, gaze-facts §2 [S5, S6]), and
 *                 A = distance covered / F(u), F the covered share; its error
 *                 shrinks as the saccade nears its end;
 *             before the peak has passed, the main sequence of the fastest
 *             speed so far (a lower bound) or the distance covered, whichever
 *             is larger;
 *   end       predicted at onset + the duration fit D = 2.55 ms/deg A +
 *             17.6 ms (gaze-facts §1, Lund); the flight is over when the
 *             speed falls under half the onset threshold twice, or after
 *             max_flight_s, or at a missing sample.
 * Not modelled: curved saccades (the landing is on the line from the onset
 * point through the newest sample), PSOs (the landing is the saccade's end),
 * saccades that change target in flight. */
#ifndef PP5_PREDICT_LANDING_H
#define PP5_PREDICT_LANDING_H

#include <stdbool.h>
#include <stddef.h>
#include "status.h"
#include "trace_file.h"

typedef struct {
    double onset_dps;              /* fixed part of the onset threshold (60 deg/s) */
    double onset_noise;            /* adaptive part: x median recent speed (6) */
    double vmax_dps, c_deg;        /* main sequence (563 deg/s, 4.31 deg) */
    double velocity_spread;        /* relative sd of peak velocity about the main
                                      sequence (0.15, gaze-facts §5's +-15 %) */
    double profile_spread;         /* relative sd of the profile estimate (0.10) */
    double duration_ms_per_deg, duration_ms;   /* D = 2.55 A + 17.6 ms */
    double peak_drop;              /* the peak has passed below this x peak (0.85) */
    double max_flight_s;           /* a longer "saccade" is something else (0.15 s) */
} landing_params_t;

#define LANDING_HISTORY 64
#define LANDING_SAMPLES 9

typedef struct {
    bool in_flight, have_estimate, peak_passed;
    int fast, slow, falling;       /* consecutive fast / slow / below-peak speeds */
    double t[LANDING_SAMPLES], x[LANDING_SAMPLES], y[LANDING_SAMPLES];   /* newest first */
    int nsamples;                  /* how many of them are filled */
    double recent[LANDING_HISTORY];   /* speeds outside saccades (ring) */
    int nrecent, recent_head;
    double threshold_dps;          /* onset threshold in force */
    double t0, x0, y0;             /* onset time and point */
    double peak_dps;
    double amp_deg, land_x, land_y, t_end;   /* the estimate */
} landing_state_t;

void landing_defaults(landing_params_t *p);
void landing_reset(landing_state_t *s);
/* A valid sample at t_s (non-decreasing), x_deg, y_deg. */
void landing_update(landing_state_t *s, const landing_params_t *p, double t_s, double x_deg,
                    double y_deg);
/* A sample without gaze: whatever was in flight is abandoned. */
void landing_lost(landing_state_t *s);
/* A saccade in flight with an estimate: its landing point, predicted end and
 * amplitude; false otherwise. */
bool landing_estimate(const landing_state_t *s, double *x_deg, double *y_deg, double *t_end_s,
                      double *amp_deg);

/* ---- scoring against true landings ---- */

/* A true saccade: onset and end times, start and landing points (per-axis
 * degrees on the trace's display). */
typedef struct {
    double t_start_s, t_end_s;
    double x0, y0, x1, y1;
    double amplitude_deg;
} landing_truth_t;

typedef struct {
    landing_truth_t *saccades;
    size_t count, capacity;
} landing_truth_list_t;

void landing_truth_free(landing_truth_list_t *l);
pp5_status_t landing_truth_append(landing_truth_list_t *l, const landing_truth_t *s);
/* True saccades from a label sequence: each run of saccade samples (with the
 * PSO run after it, if any) is one; the landing point is the mean gaze over
 * the first 20 ms after it, the start point the first sample's; saccades that
 * touch missing data or the trace's ends are left out. */
pp5_status_t landing_truth_from_labels(const trace_t *t, const int *labels,
                                       landing_truth_list_t *out);

/* Amplitude bins of the report (gaze-facts §1's): 0-2, 2-5, 5-10, 10-20, 20+ deg. */
#define LANDING_BINS 5
extern const double landing_bin_edges[LANDING_BINS + 1];

typedef struct {
    size_t saccades[LANDING_BINS];     /* true saccades */
    size_t predicted[LANDING_BINS];    /* with an estimate after the peak, before the end */
    double mean_err_deg[LANDING_BINS]; /* of the first estimate after the peak */
    double p95_err_deg[LANDING_BINS];
    double mean_last_err_deg[LANDING_BINS];   /* of the last estimate in flight */
    double mean_hold_err_deg[LANDING_BINS];   /* newest sample when the first estimate came */
    size_t false_alarms;               /* flights matching no true saccade */
} landing_report_t;

/* Runs the predictor over every sample of t (as they arrive, in order; a
 * pause longer than gap_reset_s restarts it) and scores it against truth. */
pp5_status_t landing_evaluate(const trace_t *t, const landing_params_t *p, double gap_reset_s,
                              const landing_truth_list_t *truth, landing_report_t *out);

#endif
