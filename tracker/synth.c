/* synth.c: synthetic gaze traces (the model and its sources are in synth.h).
 *
 * The eye's clean position is simulated in visual angle at each sample time by
 * a small state machine (fixate, saccade, pursue, blink); noise is added last
 * and the result is projected onto the display's pixels. */
#include "synth.h"
#include "input_limits.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "angles.h"

/* ---------------------------------------------------------------- PRNG */

static uint64_t splitmix64(uint64_t *x)
{
    uint64_t z = (*x += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

void synth_rng_seed(synth_rng_t *r, uint64_t seed)
{
    for (int i = 0; i < 4; i++)
        r->s[i] = splitmix64(&seed);
}

static uint64_t rotl(uint64_t x, int k)
{
    return (x << k) | (x >> (64 - k));
}

uint64_t synth_rng_next(synth_rng_t *r)
{
    uint64_t *s = r->s;
    uint64_t result = rotl(s[1] * 5, 7) * 9;
    uint64_t t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = rotl(s[3], 45);
    return result;
}

double synth_rng_uniform(synth_rng_t *r)
{
    return (double)(synth_rng_next(r) >> 11) * 0x1.0p-53;
}

double synth_rng_normal(synth_rng_t *r)
{
    /* Box-Muller, one value per call (no cached state: simpler to reason about). */
    double u1 = synth_rng_uniform(r), u2 = synth_rng_uniform(r);
    if (u1 < 1e-300)
        u1 = 1e-300;
    return sqrt(-2.0 * log(u1)) * cos(2.0 * M_PI * u2);
}

static double lognormal(synth_rng_t *r, double median, double sigma)
{
    return median * exp(sigma * synth_rng_normal(r));
}

/* ------------------------------------------------------------ parameters */

void synth_defaults(synth_params_t *p, synth_mode_t mode)
{
    memset(p, 0, sizeof *p);
    p->mode = mode;
    p->seconds = 10;
    p->rate_hz = 1000;
    p->seed = 1;
    angles_paper_geometry(&p->geometry);
    p->noise_deg = 0.04;
    p->vmax_dps = 600;
    p->c_deg = 5.0;
    p->velocity_sigma = 0.08;
    p->max_pursuit_dps = 200;
    p->blinks_per_min = 12;
    p->microsaccades_per_s = 0.8;
    p->drift_deg_per_sqrt_s = 0.1;
}

static const char *const mode_names[] = {"pursuit", "saccades", "mixed"};

bool synth_mode_parse(const char *name, synth_mode_t *mode)
{
    for (int i = 0; i < 3; i++)
        if (strcmp(name, mode_names[i]) == 0) {
            *mode = (synth_mode_t)i;
            return true;
        }
    return false;
}

const char *synth_mode_name(synth_mode_t mode)
{
    return (unsigned)mode < 3 ? mode_names[mode] : "?";
}

double synth_saccade_profile(double u)
{
    if (u <= 0)
        return 0;
    if (u >= 1)
        return 1;
    /* integral of 60 u^2 (1-u)^3 */
    double u2 = u * u, u3 = u2 * u;
    return 60.0 * (u3 / 3.0 - 3.0 * u3 * u / 4.0 + 3.0 * u3 * u2 / 5.0 - u3 * u3 / 6.0);
}

#define PROFILE_PEAK 2.0736   /* max of 60 u^2 (1-u)^3, at u = 0.4 */

double synth_main_sequence(const synth_params_t *p, double a_deg)
{
    return p->vmax_dps * (1.0 - exp(-a_deg / p->c_deg));
}

/* ------------------------------------------------------------ simulation */

typedef enum { ST_FIX, ST_SACC, ST_PURSUE, ST_BLINK } state_t;

typedef struct {
    const synth_params_t *p;
    synth_rng_t rng;
    double lim_x, lim_y;       /* field half-size for targets, degrees */
    state_t st;
    double t_end;              /* end of the current fixation / blink / saccade */
    double ex, ey;             /* eye position, degrees */
    /* saccade */
    double s0x, s0y, s1x, s1y, s_t0, s_dur;
    state_t after_sacc;
    /* pursuit: target and smooth eye velocity */
    bool pursuing;
    double tx, ty, tvx, tvy, run_end, evx, evy;
    double episode_end;        /* mixed mode: end of the current episode */
    double next_micro;         /* time of the next microsaccade */
    double blink_at, blink_dur;
    double resume_end;         /* end of a fixation interrupted by a microsaccade or blink; 0 none */
    bool blink_in_pursuit;     /* the current blink interrupted pursuit */
    synth_truth_t *truth;      /* NULL: not recorded */
    bool truth_failed;         /* out of memory while recording */
} sim_t;

static double clampd(double v, double lo, double hi)
{
    return v < lo ? lo : v > hi ? hi : v;
}

/* Records one saccade of the ground truth (no PRNG draws: the trace does not
 * depend on whether truth is recorded). */
static void record_saccade(sim_t *s, double v, bool micro)
{
    synth_truth_t *tr = s->truth;
    if (!tr || s->truth_failed)
        return;
    void *items = tr->saccades;
    s->truth_failed = pp5_grow(&items, &tr->capacity, tr->count, sizeof *tr->saccades,
                               "saccades") != PP5_OK;
    tr->saccades = items;
    if (s->truth_failed)
        return;
    synth_saccade_t *e = &tr->saccades[tr->count++];
    e->t_start_s = s->s_t0;
    e->t_end_s = s->s_t0 + s->s_dur;
    e->x0_deg = s->s0x;
    e->y0_deg = s->s0y;
    e->x1_deg = s->s1x;
    e->y1_deg = s->s1y;
    e->amplitude_deg = hypot(s->s1x - s->s0x, s->s1y - s->s0y);
    e->peak_dps = v;
    e->micro = micro;
}

static void start_saccade(sim_t *s, double t, double tx, double ty, state_t after, bool micro)
{
    double a = hypot(tx - s->ex, ty - s->ey);
    double v = synth_main_sequence(s->p, a) * exp(s->p->velocity_sigma * synth_rng_normal(&s->rng));
    s->s0x = s->ex;
    s->s0y = s->ey;
    s->s1x = tx;
    s->s1y = ty;
    s->s_t0 = t;
    s->s_dur = v > 0 ? PROFILE_PEAK * a / v : 0.001;
    s->st = ST_SACC;
    s->t_end = t + s->s_dur;
    s->after_sacc = after;
    record_saccade(s, v, micro);
}

static void start_fixation(sim_t *s, double t)
{
    const synth_params_t *p = s->p;
    double d = clampd(lognormal(&s->rng, 0.240, 0.47), 0.080, 2.0);
    s->st = ST_FIX;
    s->t_end = t + d;
    s->next_micro = p->microsaccades_per_s > 0
                        ? t + 0.1 - log(1.0 - synth_rng_uniform(&s->rng)) / p->microsaccades_per_s
                        : INFINITY;
    s->blink_at = INFINITY;
    /* Blinks start inside fixations, as a Poisson process of the set rate. */
    if (p->blinks_per_min > 0 && synth_rng_uniform(&s->rng) < p->blinks_per_min / 60.0 * d) {
        s->blink_at = t + synth_rng_uniform(&s->rng) * d;
        s->blink_dur = clampd(lognormal(&s->rng, 0.180, 0.17), 0.080, 0.9);
    }
}

static void new_saccade_target(sim_t *s, double *tx, double *ty)
{
    for (int tries = 0; tries < 20; tries++) {
        double a = clampd(lognormal(&s->rng, 4.7, 0.84), 0.5, 30.0);
        double dir = 2.0 * M_PI * synth_rng_uniform(&s->rng);
        *tx = s->ex + a * cos(dir);
        *ty = s->ey + a * sin(dir);
        if (fabs(*tx) <= s->lim_x && fabs(*ty) <= s->lim_y)
            return;
    }
    /* Near an edge: aim back towards the middle. */
    *tx = s->ex * 0.5;
    *ty = s->ey * 0.5;
}

static double pursuit_gain(double speed)
{
    if (speed <= 30)
        return 1.0;
    if (speed <= 100)
        return 1.0 - 0.2 * (speed - 30) / 70.0;
    return 0.8 - 0.1 * (speed - 100) / 100.0;
}

static void new_target_run(sim_t *s, double t)
{
    /* Log-uniform: slow runs common, fast ones present up to the maximum. */
    double speed = 5.0 * pow(s->p->max_pursuit_dps / 5.0, synth_rng_uniform(&s->rng));
    double dir = 2.0 * M_PI * synth_rng_uniform(&s->rng);
    s->tvx = speed * cos(dir);
    s->tvy = speed * sin(dir);
    s->run_end = t + 0.4 + 1.1 * synth_rng_uniform(&s->rng);
}

static void start_pursuit(sim_t *s, double t)
{
    s->pursuing = true;
    s->st = ST_PURSUE;
    s->tx = s->ex;
    s->ty = s->ey;
    s->evx = s->evy = 0;
    new_target_run(s, t);
}

/* The smooth eye velocity follows gain x target velocity with an 80 ms lag. */
static void pursue_velocity(sim_t *s, double dt)
{
    double g = pursuit_gain(hypot(s->tvx, s->tvy));
    double k = dt / 0.080;
    if (k > 1)
        k = 1;
    s->evx += (g * s->tvx - s->evx) * k;
    s->evy += (g * s->tvy - s->evy) * k;
}

/* Advances the target by dt, bouncing off the field edges. */
static void move_target(sim_t *s, double t, double dt)
{
    if (t >= s->run_end)
        new_target_run(s, t);
    s->tx += s->tvx * dt;
    s->ty += s->tvy * dt;
    if (fabs(s->tx) > s->lim_x) {
        s->tx = copysign(s->lim_x, s->tx);
        s->tvx = -s->tvx;
    }
    if (fabs(s->ty) > s->lim_y) {
        s->ty = copysign(s->lim_y, s->ty);
        s->tvy = -s->tvy;
    }
}

/* Next behaviour after a fixation or a pursuit episode, by mode. */
static void choose_next(sim_t *s, double t)
{
    const synth_params_t *p = s->p;
    if (p->mode == SYNTH_PURSUIT) {
        start_pursuit(s, t);
        return;
    }
    if (p->mode == SYNTH_MIXED && t >= s->episode_end) {
        bool was_pursuit = s->pursuing;
        s->episode_end = t + (was_pursuit ? 2.0 : 1.0) + 2.0 * synth_rng_uniform(&s->rng);
        if (!was_pursuit) {
            start_pursuit(s, t);
            return;
        }
        s->pursuing = false;
    }
    double tx, ty;
    new_saccade_target(s, &tx, &ty);
    start_saccade(s, t, tx, ty, ST_FIX, false);
}

/* Advances the clean eye to time t (dt since the last call); returns the label. */
static int sim_step(sim_t *s, double t, double dt, bool *blink)
{
    const synth_params_t *p = s->p;
    *blink = false;
    for (int guard = 0; guard < 8; guard++) {
        switch (s->st) {
        case ST_FIX:
            if (t >= s->blink_at) {
                s->blink_at = INFINITY;
                s->resume_end = s->t_end;
                s->st = ST_BLINK;
                s->t_end = t + s->blink_dur;
                continue;
            }
            if (t >= s->t_end) {
                choose_next(s, t);
                continue;
            }
            if (t >= s->next_micro) {
                double a = 0.1 + 0.7 * synth_rng_uniform(&s->rng);
                double dir = 2.0 * M_PI * synth_rng_uniform(&s->rng);
                s->resume_end = s->t_end;
                s->next_micro = INFINITY;
                start_saccade(s, t, s->ex + a * cos(dir), s->ey + a * sin(dir), ST_FIX, true);
                continue;
            }
            /* Drift: a random walk. */
            s->ex += p->drift_deg_per_sqrt_s * sqrt(dt) * synth_rng_normal(&s->rng);
            s->ey += p->drift_deg_per_sqrt_s * sqrt(dt) * synth_rng_normal(&s->rng);
            return GAZE_LABEL_FIXATION;
        case ST_SACC: {
            double u = (t - s->s_t0) / s->s_dur;
            if (u >= 1) {
                s->ex = s->s1x;
                s->ey = s->s1y;
                if (s->after_sacc == ST_PURSUE) {
                    s->st = ST_PURSUE;
                } else if (s->resume_end > t) {
                    s->st = ST_FIX;              /* back to the interrupted fixation */
                    s->t_end = s->resume_end;
                    s->resume_end = 0;
                } else {
                    s->resume_end = 0;
                    start_fixation(s, t);
                }
                continue;
            }
            double f = synth_saccade_profile(u);
            s->ex = s->s0x + f * (s->s1x - s->s0x);
            s->ey = s->s0y + f * (s->s1y - s->s0y);
            if (s->pursuing) {
                move_target(s, t, dt);
                pursue_velocity(s, dt);   /* the smooth system keeps running */
            }
            return GAZE_LABEL_SACCADE;
        }
        case ST_BLINK:
            if (s->blink_in_pursuit) {
                /* Pursuit goes on behind closed lids; only the samples are lost. */
                move_target(s, t, dt);
                pursue_velocity(s, dt);
                s->ex += s->evx * dt;
                s->ey += s->evy * dt;
            }
            if (t >= s->t_end) {
                if (s->blink_in_pursuit) {
                    s->blink_in_pursuit = false;
                    s->st = ST_PURSUE;
                    continue;
                }
                if (s->resume_end > t) {
                    s->st = ST_FIX;
                    s->t_end = s->resume_end;
                    s->next_micro = INFINITY;
                } else {
                    choose_next(s, t);
                }
                s->resume_end = 0;
                continue;
            }
            *blink = true;
            return GAZE_LABEL_BLINK;
        case ST_PURSUE: {
            if (p->mode == SYNTH_MIXED && t >= s->episode_end) {
                s->pursuing = true;             /* choose_next flips it to free viewing */
                choose_next(s, t);
                continue;
            }
            if (p->blinks_per_min > 0 && synth_rng_uniform(&s->rng) < p->blinks_per_min / 60.0 * dt) {
                s->st = ST_BLINK;
                s->blink_in_pursuit = true;
                s->t_end = t + clampd(lognormal(&s->rng, 0.180, 0.17), 0.080, 0.9);
                continue;
            }
            move_target(s, t, dt);
            pursue_velocity(s, dt);
            s->ex += s->evx * dt;
            s->ey += s->evy * dt;
            double err = hypot(s->tx - s->ex, s->ty - s->ey);
            /* No catch-up saccade within 60 ms of the last one [assumption:
             * saccades are not issued back to back]. */
            if (err > 1.0 && t - (s->s_t0 + s->s_dur) >= 0.060) {
                /* Catch-up saccade to where the target will be when it lands:
                 * the duration depends on the amplitude and the amplitude on
                 * the duration, so iterate a few times (it converges fast). */
                double tx = s->tx, ty = s->ty;
                for (int it = 0; it < 4; it++) {
                    double a = hypot(tx - s->ex, ty - s->ey), v = synth_main_sequence(p, a);
                    double d = v > 0 ? PROFILE_PEAK * a / v : 0;
                    tx = clampd(s->tx + s->tvx * d, -s->lim_x, s->lim_x);
                    ty = clampd(s->ty + s->tvy * d, -s->lim_y, s->lim_y);
                }
                start_saccade(s, t, tx, ty, ST_PURSUE, false);
                continue;
            }
            return GAZE_LABEL_PURSUIT;
        }
        }
    }
    return GAZE_LABEL_NONE;
}

void synth_truth_free(synth_truth_t *t)
{
    free(t->saccades);
    memset(t, 0, sizeof *t);
}

pp5_status_t synth_generate(const synth_params_t *p, trace_t *out)
{
    return synth_generate_truth(p, out, NULL);
}

pp5_status_t synth_generate_truth(const synth_params_t *p, trace_t *out, synth_truth_t *truth)
{
    if (!(p->seconds > 0 && p->seconds <= 86400))
        return pp5_fail(PP5_E_CONFIG, "synth: --seconds %g is outside (0, 86400]", p->seconds);
    if (!(p->rate_hz >= 10 && p->rate_hz <= 10000))
        return pp5_fail(PP5_E_CONFIG, "synth: --rate %g Hz is outside 10..10000", p->rate_hz);
    if (!(p->noise_deg >= 0 && p->noise_deg <= 5) || !(p->vmax_dps > 0) || !(p->c_deg > 0) ||
        !(p->max_pursuit_dps >= 5 && p->max_pursuit_dps <= 1000) || !(p->blinks_per_min >= 0) ||
        !(p->microsaccades_per_s >= 0) || !(p->velocity_sigma >= 0) ||
        !(p->drift_deg_per_sqrt_s >= 0 && p->drift_deg_per_sqrt_s <= 10))
        return pp5_fail(PP5_E_CONFIG, "synth: a model parameter is out of range");
    gaze_geometry_t g;
    pp5_status_t st = angles_resolve(&p->geometry, &g);
    if (st != PP5_OK)
        return st;
    double n_d = floor(p->seconds * p->rate_hz) + 1;
    if (n_d > (double)pp5_limit(PP5_LIMIT_TRACE_SAMPLES))
        return pp5_limit_check(PP5_LIMIT_TRACE_SAMPLES, (uint64_t)n_d, "synth");
    size_t n = (size_t)n_d;

    trace_t t;
    trace_init(&t);
    snprintf(t.header.source, sizeof t.header.source,
             "pp5 trace synth --mode %s --seconds %g --rate %g --seed %llu", synth_mode_name(p->mode),
             p->seconds, p->rate_hz, (unsigned long long)p->seed);
    snprintf(t.header.tracker, sizeof t.header.tracker, "synthetic (tracker/synth.c)");
    t.header.sample_rate_hz = p->rate_hz;
    t.header.geometry = p->geometry;

    sim_t s;
    memset(&s, 0, sizeof s);
    s.p = p;
    if (truth) {
        memset(truth, 0, sizeof *truth);
        s.truth = truth;
    }
    synth_rng_seed(&s.rng, p->seed);
    double half_x, half_y;
    angles_px_to_deg(&g, g.width_px, g.height_px, &half_x, &half_y);
    s.lim_x = half_x * 0.85;            /* keep targets off the very edge */
    s.lim_y = half_y * 0.85;
    s.episode_end = 0;
    start_fixation(&s, 0.0);
    if (p->mode == SYNTH_PURSUIT)
        start_pursuit(&s, 0.0);
    else if (p->mode == SYNTH_MIXED)
        s.episode_end = 1.5;
    double sigma = p->noise_deg / 2.0;  /* per axis: RMS step = sqrt(4 sigma^2) */
    double prev_t = 0;
    for (size_t i = 0; i < n && st == PP5_OK; i++) {
        double ts = (double)i / p->rate_hz;
        bool blink;
        int label = sim_step(&s, ts, ts - prev_t, &blink);
        prev_t = ts;
        gaze_sample_t smp;
        gaze_sample_invalid(&smp, llround(ts * 1e9));
        smp.label = label;
        /* The noise draws happen for every sample so the stream does not depend
         * on which samples are blinks. */
        double nx = sigma * synth_rng_normal(&s.rng), ny = sigma * synth_rng_normal(&s.rng);
        if (blink) {
            smp.flags = GAZE_FLAG_BLINK;
        } else {
            angles_deg_to_px(&g, s.ex + nx, s.ey + ny, &smp.x_px, &smp.y_px);
            smp.flags = GAZE_FLAG_VALID;
        }
        st = trace_append(&t, &smp);
    }
    if (st == PP5_OK && s.truth_failed)
        st = pp5_fail(PP5_E_NOMEM, "synth: out of memory for the ground truth");
    if (st != PP5_OK) {
        trace_free(&t);
        if (truth)
            synth_truth_free(truth);
        return st;
    }
    t.complete = true;
    *out = t;
    return PP5_OK;
}
