/* events_score.h: how well two labellings of the same samples agree.
 *
 * Sample level: Cohen's kappa (1960), computed the way Andersson et al. 2017
 * (BRM 49:616-637) score detectors against their coders (their repository's
 * matlab_analysis_code/callKappa6.m with kappa.m): for one class, each sample
 * is "this class" or "not"; the 2x2 table is summed over every file of a
 * stimulus type; kappa = (po - pe) / (1 - pe) of the summed table.
 * Event level: F1 after Hooge et al. 2018 (BRM 50:1864-1881, "Is human
 * classification by experienced untrained observers a gold standard in
 * fixation detection?"): an event of the class in one list matches the event
 * of that class in the other that it overlaps most (in samples), each event
 * at most once, greedily from the largest overlap (ties: earliest events);
 * F1 = 2 TP / (2 TP + FP + FN).
 * Durations: count, mean and sample standard deviation (n - 1) per class;
 * optionally without the events cut by the recording's first or last sample
 * (the study counts that way: with the rule, pp5's counts of the coders'
 * fixations are the study's, 381/2/67 against 380/2/67 for coder MN). */
#ifndef PP5_EVENTS_SCORE_H
#define PP5_EVENTS_SCORE_H

#include <stddef.h>
#include "events.h"

typedef struct {
    double both, only_a, only_b, neither;   /* samples: class in a and b, a only, b only, none */
} kappa_counts_t;

/* Adds n samples of labellings a and b for class cls. */
void kappa_counts_add(kappa_counts_t *k, const int *a, const int *b, size_t n, int cls);
/* NaN when kappa is undefined (no samples, or chance agreement is 1). */
double kappa_of_counts(const kappa_counts_t *k);
/* Cohen's kappa of a k x k table of counts (row-major: rows one rater,
 * columns the other); NaN when undefined. */
double kappa_of_table(const double *table, int k);

typedef struct {
    size_t tp, fp, fn;   /* test events matched, test events unmatched, ref events unmatched */
} f1_counts_t;

pp5_status_t f1_counts_add(f1_counts_t *f, const events_list_t *ref, const events_list_t *test,
                           int cls);
double f1_of_counts(const f1_counts_t *f);   /* NaN with no events on either side */

typedef struct {
    size_t count;
    double sum_s, sum2_s;
} duration_stats_t;

/* n_samples > 0: skip events touching sample 0 or n_samples - 1. */
void duration_stats_add(duration_stats_t *d, const events_list_t *l, int cls, size_t n_samples);
double duration_stats_mean_ms(const duration_stats_t *d);   /* NaN when empty */
double duration_stats_sd_ms(const duration_stats_t *d);     /* NaN below 2 events */

#endif
