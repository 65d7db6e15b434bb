/* data_quality.h: the data-quality figures gaze tools report for a recording
 * (the measures of Holmqvist, Nystrom & Mulvey 2012, "Eye tracker data
 * quality: what it is and how to measure it", ETRA 2012):
 *   precision as RMS-S2S: the root mean square of the angular distances
 *     between consecutive samples, inside each fixation, in degrees;
 *   precision as STD: sqrt(var x + var y) of the positions inside each
 *     fixation, in degrees;
 *     (both per fixation of at least min_fixation_s with at least 10 valid
 *     samples, and reported as the median over fixations, as gaze-facts.md
 *     §1 reports noise; pairs across a missing sample or a pause are skipped);
 *   data loss: the share of the samples the nominal rate promises over the
 *     recording's span that carry no gaze (missing or never delivered);
 *   invalid samples: the share of delivered samples without gaze;
 *   effective rate: 1 / median interval, and delivered samples per second.
 * Which samples are "fixation" is the caller's choice: a detector's labels
 * (pp5 trace info uses the adaptive one) or a trace's own. */
#ifndef PP5_DATA_QUALITY_H
#define PP5_DATA_QUALITY_H

#include <stddef.h>
#include "status.h"
#include "trace_file.h"

typedef struct {
    double min_fixation_s;         /* fixations used for precision (default 0.1 s) */
} data_quality_params_t;

typedef struct {
    double rms_s2s_deg;            /* median over fixations; NaN when none qualified */
    double std_deg;                /* median over fixations; NaN when none qualified */
    size_t fixations_used;
    double data_loss;              /* 0..1 of the expected samples */
    double invalid_fraction;       /* 0..1 of the delivered samples */
    double median_interval_s;
    double effective_rate_hz;      /* 1 / median interval */
    double delivered_rate_hz;      /* (samples - 1) / span */
    double nominal_rate_hz;        /* the header's */
    size_t expected_samples;
} data_quality_t;

void data_quality_defaults(data_quality_params_t *p);
/* labels: one per sample (GAZE_LABEL_FIXATION marks fixation samples). */
pp5_status_t data_quality_measure(const trace_t *t, const int *labels,
                                  const data_quality_params_t *p, data_quality_t *out);

#endif
