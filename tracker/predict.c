/* predict.c: gaze predictors for replay (see predict.h). */
#include "predict.h"

#include <math.h>
#include <string.h>

void predict_defaults(predict_params_t *p, predict_kind_t kind)
{
    p->kind = kind;
    p->window_s = 0.020;
    p->noise_sigma_deg = 0.03;
    p->accel_sigma_dps2 = 1000.0;
    p->max_speed_dps = 200.0;
    p->gap_reset_s = 0.050;
    landing_defaults(&p->landing);
    p->landing_fallback = PREDICT_NONE;
}

static const char *const kind_names[] = {"none", "linear", "alphabeta", "kalman", "landing"};
#define KIND_COUNT (int)(sizeof kind_names / sizeof kind_names[0])

bool predict_kind_parse(const char *name, predict_kind_t *kind)
{
    for (int i = 0; i < KIND_COUNT; i++)
        if (strcmp(name, kind_names[i]) == 0) {
            *kind = (predict_kind_t)i;
            return true;
        }
    return false;
}

const char *predict_kind_name(predict_kind_t kind)
{
    return (unsigned)kind < (unsigned)KIND_COUNT ? kind_names[kind] : "?";
}

/* The filter that runs outside saccades (all of the time, for the classic kinds). */
static predict_kind_t base_kind(const predict_params_t *p)
{
    return p->kind == PREDICT_LANDING ? p->landing_fallback : p->kind;
}

void predict_reset(predictor_t *pr, const predict_params_t *p)
{
    memset(pr, 0, sizeof *pr);
    pr->p = *p;
}

static void start_at(predictor_t *pr, double t_s, double x, double y)
{
    predict_params_t p = pr->p;
    predict_reset(pr, &p);
    pr->have = true;
    pr->last_t = t_s;
    pr->x[0] = x;
    pr->x[1] = y;
    double r = p.noise_sigma_deg * p.noise_sigma_deg;
    for (int a = 0; a < 2; a++) {
        pr->P[a][0][0] = r;
        pr->P[a][1][1] = 100.0 * 100.0;   /* velocity unknown: (100 °/s)^2 */
    }
    pr->ht[0] = t_s;
    pr->hx[0] = x;
    pr->hy[0] = y;
    pr->hhead = 0;
    pr->hcount = 1;
}

static void update_linear(predictor_t *pr, double t_s, double x, double y)
{
    pr->hhead = (pr->hhead + 1) % PREDICT_HISTORY;
    pr->ht[pr->hhead] = t_s;
    pr->hx[pr->hhead] = x;
    pr->hy[pr->hhead] = y;
    if (pr->hcount < PREDICT_HISTORY)
        pr->hcount++;
    /* Baseline: the newest sample at least window_s older than this one (or
     * the oldest kept, if the history is shorter). */
    int base = -1;
    for (int k = 1; k < pr->hcount; k++) {
        int i = (pr->hhead - k + PREDICT_HISTORY) % PREDICT_HISTORY;
        base = i;
        if (t_s - pr->ht[i] >= pr->p.window_s)
            break;
    }
    pr->x[0] = x;
    pr->x[1] = y;
    if (base >= 0 && t_s > pr->ht[base]) {
        double dt = t_s - pr->ht[base];
        pr->v[0] = (x - pr->hx[base]) / dt;
        pr->v[1] = (y - pr->hy[base]) / dt;
    }
}

static void update_alphabeta(predictor_t *pr, double dt, const double z[2])
{
    if (dt <= 0) {
        pr->x[0] = z[0];
        pr->x[1] = z[1];
        return;
    }
    double lambda = pr->p.accel_sigma_dps2 * dt * dt / pr->p.noise_sigma_deg;
    double r = (4.0 + lambda - sqrt(8.0 * lambda + lambda * lambda)) / 4.0;
    double alpha = 1.0 - r * r;
    double beta = 2.0 * (2.0 - alpha) - 4.0 * sqrt(1.0 - alpha);
    for (int a = 0; a < 2; a++) {
        double xp = pr->x[a] + pr->v[a] * dt;
        double res = z[a] - xp;
        pr->x[a] = xp + alpha * res;
        pr->v[a] += beta / dt * res;
    }
}

static void update_kalman(predictor_t *pr, double dt, const double z[2])
{
    double q = pr->p.accel_sigma_dps2 * pr->p.accel_sigma_dps2;
    double r = pr->p.noise_sigma_deg * pr->p.noise_sigma_deg;
    for (int a = 0; a < 2; a++) {
        double (*P)[2] = pr->P[a];
        /* Predict: F = [1 dt; 0 1], Q = q [dt^4/4 dt^3/2; dt^3/2 dt^2]. */
        double x = pr->x[a] + pr->v[a] * dt, v = pr->v[a];
        double p00 = P[0][0] + dt * (P[1][0] + P[0][1]) + dt * dt * P[1][1] + q * dt * dt * dt * dt / 4;
        double p01 = P[0][1] + dt * P[1][1] + q * dt * dt * dt / 2;
        double p11 = P[1][1] + q * dt * dt;
        /* Update with H = [1 0]. */
        double s = p00 + r;
        double k0 = p00 / s, k1 = p01 / s;
        double res = z[a] - x;
        pr->x[a] = x + k0 * res;
        pr->v[a] = v + k1 * res;
        P[0][0] = (1 - k0) * p00;
        P[0][1] = P[1][0] = (1 - k0) * p01;
        P[1][1] = p11 - k1 * p01;
    }
}

void predict_update(predictor_t *pr, double t_s, double x_deg, double y_deg)
{
    if (!pr->have || t_s - pr->last_t > pr->p.gap_reset_s || t_s < pr->last_t) {
        start_at(pr, t_s, x_deg, y_deg);
        if (pr->p.kind == PREDICT_LANDING)
            landing_update(&pr->landing, &pr->p.landing, t_s, x_deg, y_deg);
        return;
    }
    double dt = t_s - pr->last_t;
    double z[2] = {x_deg, y_deg};
    if (pr->p.kind == PREDICT_LANDING)
        landing_update(&pr->landing, &pr->p.landing, t_s, x_deg, y_deg);
    switch (base_kind(&pr->p)) {
    case PREDICT_LANDING:
    case PREDICT_NONE:
        pr->x[0] = x_deg;
        pr->x[1] = y_deg;
        break;
    case PREDICT_LINEAR:
        update_linear(pr, t_s, x_deg, y_deg);
        break;
    case PREDICT_ALPHABETA:
        update_alphabeta(pr, dt, z);
        break;
    case PREDICT_KALMAN:
        update_kalman(pr, dt, z);
        break;
    }
    pr->last_t = t_s;
}

bool predict_at(const predictor_t *pr, double t_s, double *x_deg, double *y_deg)
{
    if (!pr->have)
        return false;
    double lx, ly, t_end, amp;
    if (pr->p.kind == PREDICT_LANDING &&
        landing_estimate(&pr->landing, &lx, &ly, &t_end, &amp) && t_s >= t_end) {
        *x_deg = lx;           /* shown after the saccade ends: where it lands */
        *y_deg = ly;
        return true;
    }
    double h = t_s - pr->last_t;
    if (h < 0)
        h = 0;
    double vx = pr->v[0], vy = pr->v[1];
    predict_kind_t k = base_kind(&pr->p);
    if (k == PREDICT_NONE || k == PREDICT_LANDING)
        vx = vy = 0;
    double speed = sqrt(vx * vx + vy * vy);
    if (speed > pr->p.max_speed_dps)
        vx = vy = 0;      /* a saccade in flight: hold, do not extrapolate it */
    *x_deg = pr->x[0] + vx * h;
    *y_deg = pr->x[1] + vy * h;
    return true;
}
