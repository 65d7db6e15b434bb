/* predict.h: gaze prediction for replay (the paper's §7 remedy for lag: "If lag
 * time proves problematic, we can employ predictive tracking").
 *
 * A predictor is fed the valid samples in time order, as (time, per-axis
 * visual angle), and asked where the gaze will be at a later time.  Kinds:
 *   none       the newest sample, held (what the 1990 system did)
 *   linear     extrapolation with the velocity over the last window_s
 *   alphabeta  steady-state alpha-beta filter; gains from the tracking index
 *              lambda = accel_sigma * dt^2 / noise_sigma (Kalata 1984 relations)
 *   kalman     constant-velocity Kalman filter per axis, white-acceleration
 *              process noise, with the covariance propagated over irregular dt
 *   landing    while a saccade is in flight in the arrived samples, its
 *              predicted landing point, for images shown after its predicted
 *              end (predict_landing.h); otherwise the `landing_fallback` kind
 *              (default none: the newest sample, the best of the others on
 *              the recorded traces, traces/README.md)
 * Every kind resets after a gap (blink, track loss) longer than gap_reset_s,
 * because a velocity from before a blink says nothing about after it.
 * Saccade gate: when the estimated speed exceeds max_speed_dps the predictor
 * holds the current position instead of extrapolating: the paper's tracking
 * mode goes "up to 200°/sec" (§6), and extrapolating a saccade (up to ~700°/s)
 * for 100 ms would throw the sweet spot off the screen.  (A first version
 * clamped the speed to max_speed_dps instead; on the recorded traces it gave
 * larger errors than the gate, see the report in traces/README.md.) */
#ifndef PP5_PREDICT_H
#define PP5_PREDICT_H

#include <stdbool.h>
#include "predict_landing.h"

typedef enum {
    PREDICT_NONE, PREDICT_LINEAR, PREDICT_ALPHABETA, PREDICT_KALMAN, PREDICT_LANDING
} predict_kind_t;

typedef struct {
    predict_kind_t kind;
    double window_s;         /* linear: velocity baseline (default 0.020 s) */
    double noise_sigma_deg;  /* measurement noise per axis (default 0.03°, gaze-facts §1 noise) */
    double accel_sigma_dps2; /* process noise, acceleration (default 1000 °/s², an assumption) */
    double max_speed_dps;    /* above this speed: hold, do not extrapolate (default 200 °/s) */
    double gap_reset_s;      /* reset after a gap longer than this (default 0.05 s) */
    landing_params_t landing;            /* landing: the saccade model */
    predict_kind_t landing_fallback;     /* landing: outside saccades (not LANDING) */
} predict_params_t;

#define PREDICT_HISTORY 512

typedef struct {
    predict_params_t p;
    bool have;
    double last_t;
    double x[2], v[2];       /* state per axis: angle (deg), velocity (deg/s) */
    double P[2][2][2];       /* kalman covariance per axis */
    /* linear: recent samples */
    double ht[PREDICT_HISTORY], hx[PREDICT_HISTORY], hy[PREDICT_HISTORY];
    int hhead, hcount;
    landing_state_t landing;
} predictor_t;

void predict_defaults(predict_params_t *p, predict_kind_t kind);
/* "none", "linear", "alphabeta", "kalman", "landing" -> kind; false if unknown. */
bool predict_kind_parse(const char *name, predict_kind_t *kind);
const char *predict_kind_name(predict_kind_t kind);

void predict_reset(predictor_t *pr, const predict_params_t *p);
/* A valid sample at t_s (seconds, non-decreasing) at angles x_deg, y_deg. */
void predict_update(predictor_t *pr, double t_s, double x_deg, double y_deg);
/* Where the gaze will be at t_s (>= the last update).  False before any sample. */
bool predict_at(const predictor_t *pr, double t_s, double *x_deg, double *y_deg);

#endif
