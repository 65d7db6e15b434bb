/* events_ivt.c: I-VT, the velocity-threshold identification of Salvucci &
 * Goldberg 2000 ("Identifying fixations and saccades in eye-tracking
 * protocols", ETRA 2000, §3.1): a sample faster than the threshold is a
 * saccade sample, a slower one a fixation sample.
 * pp5's reading: the speed is the central difference of gaze-facts §1
 * (events_signal_t); a dip below the threshold shorter than min_saccade_s
 * inside a saccade stays saccade (noise on a fast eye); saccade runs shorter
 * than min_saccade_s become fixation; saccade edges move to where the speed
 * leaves the fixation noise (events_settle_saccade_edges).  The threshold is tuned
 * on the tuning files of lund2013 only (reproduce_events.c). */
#include "events_internal.h"

pp5_status_t events_ivt(const events_signal_t *s, const events_params_t *p, int *labels,
                        events_result_t *r)
{
    size_t n = s->n, short_run = events_samples_for(s, p->min_saccade_s);
    for (size_t i = 0; i < n; i++) {
        if (!events_sample_ok(s, i))
            continue;
        labels[i] = s->speed[i] > p->ivt_threshold_dps ? GAZE_LABEL_SACCADE : GAZE_LABEL_FIXATION;
    }
    /* Short slow dips between two saccade runs join the saccade. */
    for (size_t i = 1; i < n; i++) {
        if (labels[i] != GAZE_LABEL_FIXATION || labels[i - 1] != GAZE_LABEL_SACCADE)
            continue;
        size_t b = i;
        while (b + 1 < n && labels[b + 1] == GAZE_LABEL_FIXATION && b + 1 - i < short_run)
            b++;
        if (b + 1 < n && labels[b + 1] == GAZE_LABEL_SACCADE && b + 1 - i < short_run)
            for (size_t k = i; k <= b; k++)
                labels[k] = GAZE_LABEL_SACCADE;
        i = b;
    }
    /* Too-short saccades are noise on a fixation. */
    for (size_t i = 0; i < n; i++) {
        if (labels[i] != GAZE_LABEL_SACCADE)
            continue;
        size_t b = i;
        while (b + 1 < n && labels[b + 1] == GAZE_LABEL_SACCADE)
            b++;
        if (b + 1 - i < short_run)
            for (size_t k = i; k <= b; k++)
                labels[k] = GAZE_LABEL_FIXATION;
        i = b;
    }
    events_settle_saccade_edges(s, p, labels);
    r->peak_threshold_dps = r->onset_threshold_dps = p->ivt_threshold_dps;
    return PP5_OK;
}
