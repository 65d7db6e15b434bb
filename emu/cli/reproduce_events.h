/* reproduce_events.h: what reproduce_events.c (the command, the tables) and
 * reproduce_events_lund.c (loading lund2013, scoring, tuning) share. */
#ifndef PP5_REPRODUCE_EVENTS_H
#define PP5_REPRODUCE_EVENTS_H

#include <stdbool.h>
#include <stddef.h>
#include "tracker/events.h"
#include "tracker/events_score.h"
#include "tracker/trace_file.h"

enum { STIM_IMG, STIM_DOTS, STIM_VIDEO, STIM_COUNT };
/* Raters: the two coders, then the detectors in the order they were given. */
enum { RATER_MN, RATER_RA, RATER_FIRST_METHOD };
#define LUND_MAX_METHODS 3
#define LUND_MAX_RATERS (RATER_FIRST_METHOD + LUND_MAX_METHODS)
/* Classes scored: fixation, saccade, PSO, pursuit, blink. */
#define LUND_CLASSES 5
extern const int lund_classes[LUND_CLASSES];
extern const char *const lund_stim_names[STIM_COUNT];

typedef struct {
    char name[64];                 /* e.g. "img/UH29_img_Europe" */
    int stim;
    bool tune;                     /* in the tuning subset */
    trace_t mn;                    /* samples with coder MN's labels */
    int *ra;                       /* coder RA's labels, one per sample */
} lund_file_t;

typedef struct {
    lund_file_t *files;
    size_t count;
} lund_set_t;

typedef enum { SPLIT_TEST, SPLIT_TUNE, SPLIT_ALL } lund_split_t;

typedef struct {
    int n_methods;
    events_params_t methods[LUND_MAX_METHODS];
    /* [stim][class][rater][vs MN, vs RA] */
    kappa_counts_t kappa[STIM_COUNT][LUND_CLASSES][LUND_MAX_RATERS][2];
    f1_counts_t f1[STIM_COUNT][LUND_CLASSES][LUND_MAX_RATERS][2];
    duration_stats_t dur[STIM_COUNT][LUND_CLASSES][LUND_MAX_RATERS];
    /* the coders' events again, each sample counted as 2 ms: how the study
     * timed them (its three 200 Hz files claim 500 Hz, reproduce_events.c) */
    duration_stats_t dur_at_500hz[STIM_COUNT][LUND_CLASSES][2];
    size_t files[STIM_COUNT], samples[STIM_COUNT];
} lund_tally_t;

/* The tuning subset: every file of these subjects (reproduce_events_lund.c). */
extern const char *const lund_tune_subjects[];
extern const size_t lund_tune_subject_count;

/* Loads every trace of lund2013 under `root` (the gaze folder); a clear error
 * naming the folder when it is absent. */
pp5_status_t lund_load(const char *root, lund_set_t *set);
void lund_free(lund_set_t *set);
bool lund_in_split(const lund_file_t *f, lund_split_t split);
/* Scores the files of a split with t->methods (t->n_methods set by the caller). */
pp5_status_t lund_score(const lund_set_t *set, lund_split_t split, lund_tally_t *t);
/* `pp5 reproduce events --tune`: the grid searches, on the tuning files only. */
pp5_status_t lund_tune(const lund_set_t *set);
/* `pp5 reproduce events --landing`: the landing predictor against coder MN's
 * landings on the files of a split, per amplitude bin. */
pp5_status_t lund_landing(const lund_set_t *set, lund_split_t split);

#endif
