/* events_idt.c: I-DT, the dispersion-threshold identification of Salvucci &
 * Goldberg 2000 (ETRA 2000, §3.3): a window spanning the shortest fixation is
 * a fixation when its dispersion D = (max x - min x) + (max y - min y) is at
 * most the threshold; it then grows while D stays under it, and the next
 * window starts after it.  A window over the threshold drops its first
 * sample, which is a saccade sample.
 * pp5's reading: D in degrees of visual angle (per-axis angles, gaze-facts
 * §0); a window never spans a missing sample or a pause in time; saccade edges
 * move to where the speed leaves the fixation noise (events_settle_saccade_edges),
 * because a window that closes when D crosses the threshold ends a few
 * samples into the saccade.  Threshold and window are tuned on the tuning
 * files of lund2013 only (reproduce_events.c). */
#include "events_internal.h"

typedef struct {
    double min_x, max_x, min_y, max_y;
} extent_t;

static void extent_start(extent_t *e, const events_signal_t *s, size_t i)
{
    e->min_x = e->max_x = s->ax[i];
    e->min_y = e->max_y = s->ay[i];
}

static void extent_add(extent_t *e, const events_signal_t *s, size_t i)
{
    if (s->ax[i] < e->min_x) e->min_x = s->ax[i];
    if (s->ax[i] > e->max_x) e->max_x = s->ax[i];
    if (s->ay[i] < e->min_y) e->min_y = s->ay[i];
    if (s->ay[i] > e->max_y) e->max_y = s->ay[i];
}

static double dispersion(const extent_t *e)
{
    return (e->max_x - e->min_x) + (e->max_y - e->min_y);
}

/* Sample i+1 continues the window: valid and not across a pause. */
static bool continues(const events_signal_t *s, size_t i)
{
    return i + 1 < s->n && events_sample_ok(s, i + 1) &&
           s->t_s[i + 1] - s->t_s[i] <= 3.0 / s->rate_hz;
}

pp5_status_t events_idt(const events_signal_t *s, const events_params_t *p, int *labels,
                        events_result_t *r)
{
    size_t n = s->n, span = events_samples_for(s, p->idt_window_s);
    size_t i = 0;
    while (i < n) {
        if (!events_sample_ok(s, i)) {
            i++;
            continue;
        }
        /* The shortest window from i: span samples, all valid and contiguous. */
        extent_t e;
        extent_start(&e, s, i);
        size_t j = i;
        while (j + 1 - i < span && continues(s, j))
            extent_add(&e, s, ++j);
        if (j + 1 - i < span) {
            /* Too little data before a gap or the end to tell. */
            for (size_t k = i; k <= j; k++)
                labels[k] = GAZE_LABEL_NOISE;
            i = j + 1;
            continue;
        }
        if (dispersion(&e) > p->idt_dispersion_deg) {
            labels[i++] = GAZE_LABEL_SACCADE;
            continue;
        }
        while (continues(s, j)) {
            extent_t grown = e;
            extent_add(&grown, s, j + 1);
            if (dispersion(&grown) > p->idt_dispersion_deg)
                break;
            e = grown;
            j++;
        }
        for (size_t k = i; k <= j; k++)
            labels[k] = GAZE_LABEL_FIXATION;
        i = j + 1;
    }
    events_settle_saccade_edges(s, p, labels);
    r->peak_threshold_dps = r->onset_threshold_dps = NAN;
    return PP5_OK;
}
