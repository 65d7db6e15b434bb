/* events_internal.h: what the detectors (events_ivt.c, events_idt.c,
 * events_adaptive.c) share with events.c; not for other modules. */
#ifndef PP5_EVENTS_INTERNAL_H
#define PP5_EVENTS_INTERNAL_H

#include <math.h>

#include "events.h"

/* The samples in visual angle (gaze-facts.md §0), once per trace. */
typedef struct {
    size_t n;
    double *t_s;                   /* sample times, seconds */
    double *ax, *ay;               /* per-axis angle, degrees; NaN when missing */
    double *speed;                 /* central-difference speed, deg/s (gaze-facts §1):
                                      |theta(i+1) - theta(i-1)| / (t(i+1) - t(i-1)),
                                      one-sided next to a missing sample, NaN alone */
    double rate_hz;                /* effective: 1 / median interval */
    gaze_geometry_t geometry;      /* resolved (angles_resolve) */
} events_signal_t;

pp5_status_t events_signal_build(const trace_t *t, events_signal_t *s);
void events_signal_free(events_signal_t *s);

static inline bool events_sample_ok(const events_signal_t *s, size_t i)
{
    return !isnan(s->ax[i]);
}

/* Samples spanning d seconds at the signal's rate (at least 1). */
size_t events_samples_for(const events_signal_t *s, double d);

/* Each detector labels the valid samples (fixation, saccade, PSO, undefined);
 * missing samples are left GAZE_LABEL_NONE for events.c. */
pp5_status_t events_ivt(const events_signal_t *s, const events_params_t *p, int *labels,
                        events_result_t *r);
pp5_status_t events_idt(const events_signal_t *s, const events_params_t *p, int *labels,
                        events_result_t *r);
pp5_status_t events_adaptive(const events_signal_t *s, const events_params_t *p, int *labels,
                             events_result_t *r);

/* Places each saccade's first and last sample where the central-difference
 * speed leaves the fixation noise: a threshold crossing or a fixation
 * window's end lies inside the saccade (ivt, idt), and a smoothing filter
 * spreads it (adaptive).  The noise floor is mean + p->edge_noise_sigmas sd
 * of the speeds of the fixation samples.  An edge above the floor moves outwards over fixation
 * samples while the speed keeps falling and stays above the floor; an edge at
 * or below it moves inwards to the first sample above it; never further than
 * p->edge_search_s (0: off).  A saccade end that meets a PSO stays. */
void events_settle_saccade_edges(const events_signal_t *s, const events_params_t *p,
                                 int *labels);

#endif
