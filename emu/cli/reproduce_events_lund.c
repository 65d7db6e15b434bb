/* reproduce_events_lund.c: the lund2013 recordings for `pp5 reproduce events`:
 * loading both coders' labels, the tuning/held-out split, scoring detectors
 * against the coders, and the threshold search on the tuning files.
 *
 * The split (also in tracker/ARCHITECTURE.md): by subject, so that no person
 * whose eyes a threshold was fitted to is in the scores.  Tuning subset: every
 * file of subjects TH20, TH34, TL20, UH21 and UL27 (11 files: 4 dots, 4
 * images, 3 videos); held out: the other 23 files (7 dots, 10 images, 6
 * videos), of 18 other subjects, including all three 200 Hz recordings.
 * Coder MN's labels of UH29_img_Europe are the 2018 corrected ones
 * (label_MN_fix2018, the fix Zemblys et al. 2018 reported), as later users of
 * the data do. */
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "emu/cli/reproduce_events.h"
#include "tracker/import.h"
#include "tracker/predict_landing.h"

const int lund_classes[LUND_CLASSES] = {GAZE_LABEL_FIXATION, GAZE_LABEL_SACCADE, GAZE_LABEL_PSO,
                                        GAZE_LABEL_PURSUIT, GAZE_LABEL_BLINK};
const char *const lund_stim_names[STIM_COUNT] = {"img", "dots", "video"};
const char *const lund_tune_subjects[] = {"TH20", "TH34", "TL20", "UH21", "UL27"};
const size_t lund_tune_subject_count = sizeof lund_tune_subjects / sizeof lund_tune_subjects[0];

static int cmp_name(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

static bool tune_subject(const char *stem)
{
    for (size_t i = 0; i < lund_tune_subject_count; i++)
        if (strncmp(stem, lund_tune_subjects[i], 4) == 0 && stem[4] == '_')
            return true;
    return false;
}

void lund_free(lund_set_t *set)
{
    for (size_t i = 0; i < set->count; i++) {
        trace_free(&set->files[i].mn);
        free(set->files[i].ra);
    }
    free(set->files);
    memset(set, 0, sizeof *set);
}

static pp5_status_t load_one(const char *path, const char *stem, int stim, lund_file_t *f)
{
    memset(f, 0, sizeof *f);
    snprintf(f->name, sizeof f->name, "%s/%s", lund_stim_names[stim], stem);
    f->stim = stim;
    f->tune = tune_subject(stem);
    import_options_t o;
    import_defaults(&o);
    o.label_column = strcmp(stem, "UH29_img_Europe") == 0 ? "label_MN_fix2018" : NULL;
    pp5_status_t st = import_file(path, IMPORT_SHARED, &o, &f->mn);
    if (st != PP5_OK)
        return st;
    trace_t ra;
    o.label_column = "label_RA";
    if ((st = import_file(path, IMPORT_SHARED, &o, &ra)) != PP5_OK) {
        trace_free(&f->mn);
        return st;
    }
    if (ra.count != f->mn.count || !(f->ra = malloc(ra.count * sizeof *f->ra))) {
        st = ra.count != f->mn.count ? pp5_fail(PP5_E_FORMAT, "%s: the coders' columns differ "
                                                "in length", path)
                                     : pp5_fail(PP5_E_NOMEM, "out of memory");
        trace_free(&ra);
        trace_free(&f->mn);
        return st;
    }
    for (size_t i = 0; i < ra.count; i++)
        f->ra[i] = ra.samples[i].label;
    trace_free(&ra);
    return PP5_OK;
}

/* The *.tsv.gz stems of one stimulus folder, sorted (so the order never
 * depends on the file system). */
static pp5_status_t list_stems(const char *dir, char ***stems, size_t *n)
{
    DIR *d = opendir(dir);
    *stems = NULL;
    *n = 0;
    if (!d)
        return pp5_fail(PP5_E_IO, "%s: not found (lund2013 lives in ../shared/data/gaze; set "
                        "PP5_SHARED_DATA)", dir);
    pp5_status_t st = PP5_OK;
    size_t cap = 0;
    for (struct dirent *e; st == PP5_OK && (e = readdir(d)) != NULL;) {
        size_t len = strlen(e->d_name);
        if (len < 8 || len > 60 || strcmp(e->d_name + len - 7, ".tsv.gz") != 0)
            continue;
        if (*n == cap) {
            cap = cap ? 2 * cap : 16;
            char **grown = realloc(*stems, cap * sizeof *grown);
            if (!grown) {
                st = pp5_fail(PP5_E_NOMEM, "out of memory");
                break;
            }
            *stems = grown;
        }
        if (!((*stems)[*n] = strndup(e->d_name, len - 7)))
            st = pp5_fail(PP5_E_NOMEM, "out of memory");
        else
            (*n)++;
    }
    closedir(d);
    if (st == PP5_OK && *n)
        qsort(*stems, *n, sizeof **stems, cmp_name);
    return st;
}

pp5_status_t lund_load(const char *root, lund_set_t *set)
{
    memset(set, 0, sizeof *set);
    pp5_status_t st = PP5_OK;
    for (int s = 0; s < STIM_COUNT && st == PP5_OK; s++) {
        char dir[1024], path[1200];
        snprintf(dir, sizeof dir, "%s/lund2013/trace/%s", root, lund_stim_names[s]);
        char **stems;
        size_t n;
        st = list_stems(dir, &stems, &n);
        lund_file_t *grown = st == PP5_OK ? realloc(set->files, (set->count + n + 1) *
                                                                    sizeof *grown) : NULL;
        if (st == PP5_OK && !grown)
            st = pp5_fail(PP5_E_NOMEM, "out of memory");
        if (grown)
            set->files = grown;
        for (size_t i = 0; st == PP5_OK && i < n; i++) {
            snprintf(path, sizeof path, "%s/%s.tsv.gz", dir, stems[i]);
            if ((st = load_one(path, stems[i], s, &set->files[set->count])) == PP5_OK)
                set->count++;
        }
        for (size_t i = 0; i < n; i++)
            free(stems[i]);
        free(stems);
    }
    if (st == PP5_OK && set->count == 0)
        st = pp5_fail(PP5_E_IO, "%s/lund2013/trace: no recordings", root);
    if (st != PP5_OK)
        lund_free(set);
    return st;
}

bool lund_in_split(const lund_file_t *f, lund_split_t split)
{
    return split == SPLIT_ALL || (split == SPLIT_TUNE) == f->tune;
}

/* ------------------------------------------------------------------ scoring */

/* Durations as samples x 2 ms, events cut by the recording's ends left out. */
static void add_at_500hz(duration_stats_t *d, const events_list_t *l, int cls, size_t n)
{
    for (size_t i = 0; i < l->count; i++) {
        const gaze_event_t *e = &l->events[i];
        if (e->cls != cls || e->first == 0 || e->last + 1 >= n)
            continue;
        double s = (double)(e->last - e->first + 1) * 0.002;
        d->count++;
        d->sum_s += s;
        d->sum2_s += s * s;
    }
}

static pp5_status_t score_raters(const lund_file_t *f, int n_raters, int *const *labels,
                                 const events_list_t *lists, lund_tally_t *t)
{
    size_t n = f->mn.count;
    pp5_status_t st = PP5_OK;
    for (int c = 0; c < LUND_CLASSES && st == PP5_OK; c++) {
        int cls = lund_classes[c];
        for (int r = 0; r < n_raters && st == PP5_OK; r++) {
            duration_stats_add(&t->dur[f->stim][c][r], &lists[r], cls, n);
            if (r < 2)
                add_at_500hz(&t->dur_at_500hz[f->stim][c][r], &lists[r], cls, n);
            for (int ref = 0; ref < 2 && st == PP5_OK; ref++) {
                if (r == ref)
                    continue;
                kappa_counts_add(&t->kappa[f->stim][c][r][ref], labels[ref], labels[r], n, cls);
                st = f1_counts_add(&t->f1[f->stim][c][r][ref], &lists[ref], &lists[r], cls);
            }
        }
    }
    return st;
}

static pp5_status_t score_file(const lund_file_t *f, lund_tally_t *t)
{
    int n_raters = RATER_FIRST_METHOD + t->n_methods;
    int *labels[LUND_MAX_RATERS] = {0};
    events_list_t lists[LUND_MAX_RATERS];
    events_result_t res[LUND_MAX_METHODS];
    memset(lists, 0, sizeof lists);
    memset(res, 0, sizeof res);
    int *mn = malloc(f->mn.count * sizeof *mn);
    pp5_status_t st = mn ? PP5_OK : pp5_fail(PP5_E_NOMEM, "out of memory");
    for (size_t i = 0; mn && i < f->mn.count; i++)
        mn[i] = f->mn.samples[i].label;
    labels[RATER_MN] = mn;
    labels[RATER_RA] = f->ra;
    if (st == PP5_OK)
        st = events_from_labels(&f->mn, mn, &lists[RATER_MN]);
    if (st == PP5_OK)
        st = events_from_labels(&f->mn, f->ra, &lists[RATER_RA]);
    for (int m = 0; st == PP5_OK && m < t->n_methods; m++) {
        st = events_detect(&f->mn, &t->methods[m], &res[m]);
        if (st == PP5_OK) {
            labels[RATER_FIRST_METHOD + m] = res[m].labels;
            lists[RATER_FIRST_METHOD + m] = res[m].list;
        }
    }
    if (st == PP5_OK) {
        st = score_raters(f, n_raters, labels, lists, t);
        t->files[f->stim]++;
        t->samples[f->stim] += f->mn.count;
    }
    events_list_free(&lists[RATER_MN]);
    events_list_free(&lists[RATER_RA]);
    for (int m = 0; m < t->n_methods; m++)
        events_result_free(&res[m]);
    free(mn);
    return st;
}

pp5_status_t lund_score(const lund_set_t *set, lund_split_t split, lund_tally_t *t)
{
    int n_methods = t->n_methods;
    events_params_t methods[LUND_MAX_METHODS];
    memcpy(methods, t->methods, sizeof methods);
    memset(t, 0, sizeof *t);
    t->n_methods = n_methods;
    memcpy(t->methods, methods, sizeof methods);
    pp5_status_t st = PP5_OK;
    for (size_t i = 0; i < set->count && st == PP5_OK; i++)
        if (lund_in_split(&set->files[i], split))
            st = score_file(&set->files[i], t);
    return st;
}

/* ------------------------------------------------------------------- tuning */

/* The tuning objective: kappa of fixations and saccades (and PSOs where the
 * method finds them) against each coder, pooled over every tuning file of
 * every stimulus type, averaged. */
static pp5_status_t objective(const lund_set_t *set, const events_params_t *p, double *score)
{
    static lund_tally_t t;          /* large: kept off the stack */
    t.n_methods = 1;
    t.methods[0] = *p;
    pp5_status_t st = lund_score(set, SPLIT_TUNE, &t);
    if (st != PP5_OK)
        return st;
    int n_cls = p->method == EVENTS_ADAPTIVE ? 3 : 2;
    double sum = 0;
    for (int c = 0; c < n_cls; c++)
        for (int ref = 0; ref < 2; ref++) {
            kappa_counts_t k = {0};
            for (int s = 0; s < STIM_COUNT; s++) {
                const kappa_counts_t *x = &t.kappa[s][c][RATER_FIRST_METHOD][ref];
                k.both += x->both;
                k.only_a += x->only_a;
                k.only_b += x->only_b;
                k.neither += x->neither;
            }
            sum += kappa_of_counts(&k);
        }
    *score = sum / (2.0 * n_cls);
    return PP5_OK;
}

static pp5_status_t tune_ivt(const lund_set_t *set)
{
    events_params_t p, best;
    events_defaults(&p, EVENTS_IVT);
    best = p;
    double best_score = -2, score;
    printf("ivt: speed threshold (deg/s) -> mean kappa (fixation, saccade; vs MN and RA)\n ");
    for (double v = 20; v <= 120.001; v += 5) {
        p.ivt_threshold_dps = v;
        pp5_status_t st = objective(set, &p, &score);
        if (st != PP5_OK)
            return st;
        printf(" %.0f:%.3f", v, score);
        if (score > best_score) {
            best_score = score;
            best = p;
        }
    }
    printf("\n  best: %.0f deg/s (%.3f)\n", best.ivt_threshold_dps, best_score);
    return PP5_OK;
}

/* Windows start at the shortest fixation (min_fixation_s, 40 ms): a shorter
 * window finds fixations that the post-processing then drops. */
static pp5_status_t tune_idt(const lund_set_t *set)
{
    static const double disp[] = {0.5, 0.75, 1.0, 1.25, 1.5, 2.0, 2.5, 3.0};
    static const double win_ms[] = {40, 55, 70, 85, 100, 130, 160};
    events_params_t p, best;
    events_defaults(&p, EVENTS_IDT);
    best = p;
    double best_score = -2, score;
    printf("idt: dispersion (deg) x window (ms) -> mean kappa (fixation, saccade; vs MN and RA)\n");
    for (size_t i = 0; i < sizeof disp / sizeof disp[0]; i++) {
        printf("  %.2f:", disp[i]);
        for (size_t j = 0; j < sizeof win_ms / sizeof win_ms[0]; j++) {
            p.idt_dispersion_deg = disp[i];
            p.idt_window_s = win_ms[j] / 1e3;
            pp5_status_t st = objective(set, &p, &score);
            if (st != PP5_OK)
                return st;
            printf(" %.0f:%.3f", win_ms[j], score);
            if (score > best_score) {
                best_score = score;
                best = p;
            }
        }
        printf("\n");
    }
    printf("  best: %.2f deg, %.0f ms (%.3f)\n", best.idt_dispersion_deg, best.idt_window_s * 1e3,
           best_score);
    return PP5_OK;
}

/* The adaptive method keeps the paper's thresholds; what is chosen here is
 * only how its statistics are taken (mean/sd as published, or median/MAD)
 * and the filter window. */
static pp5_status_t tune_adaptive(const lund_set_t *set)
{
    static const double filter_ms[] = {5, 10, 15, 20};
    printf("adaptive: statistics x filter window (ms) -> mean kappa (fixation, saccade, PSO)\n");
    for (int robust = 0; robust < 2; robust++) {
        printf("  %-13s", robust ? "median/MAD:" : "mean/sd:");
        for (size_t j = 0; j < sizeof filter_ms / sizeof filter_ms[0]; j++) {
            events_params_t p;
            events_defaults(&p, EVENTS_ADAPTIVE);
            p.nh_robust = robust;
            p.nh_filter_s = filter_ms[j] / 1e3;
            double score;
            pp5_status_t st = objective(set, &p, &score);
            if (st != PP5_OK)
                return st;
            printf(" %.0f:%.3f", filter_ms[j], score);
        }
        printf("\n");
    }
    return PP5_OK;
}

/* Where saccade edges settle (events_settle_saccade_edges), for each method
 * with its tuned thresholds. */
static pp5_status_t tune_edges(const lund_set_t *set)
{
    static const double sigmas[] = {0, 1, 2, 3};
    printf("edges: noise floor (mean + k sd of fixation speeds) -> mean kappa, per method\n");
    for (int m = 0; m < 3; m++) {
        printf("  %-9s", events_method_name((events_method_t)m));
        for (size_t j = 0; j < sizeof sigmas / sizeof sigmas[0]; j++) {
            events_params_t p;
            events_defaults(&p, (events_method_t)m);
            p.edge_noise_sigmas = sigmas[j];
            double score;
            pp5_status_t st = objective(set, &p, &score);
            if (st != PP5_OK)
                return st;
            printf(" k=%.0f:%.3f", sigmas[j], score);
        }
        events_params_t off;
        events_defaults(&off, (events_method_t)m);
        off.edge_search_s = 0;
        double score;
        pp5_status_t st = objective(set, &off, &score);
        if (st != PP5_OK)
            return st;
        printf(" off:%.3f\n", score);
    }
    return PP5_OK;
}

/* The landing predictor's error model, on the tuning files: the first
 * landing estimate after each saccade's peak against coder MN's landing
 * (predict_landing.h), pooled over the files, per amplitude bin. */
static pp5_status_t landing_score(const lund_set_t *set, const landing_params_t *lp,
                                  double err[LANDING_BINS], double hold[LANDING_BINS])
{
    double esum[LANDING_BINS] = {0}, hsum[LANDING_BINS] = {0};
    size_t bn[LANDING_BINS] = {0};
    pp5_status_t st = PP5_OK;
    for (size_t i = 0; i < set->count && st == PP5_OK; i++) {
        const lund_file_t *f = &set->files[i];
        if (!f->tune)
            continue;
        int *mn = malloc(f->mn.count * sizeof *mn);
        if (!mn)
            return pp5_fail(PP5_E_NOMEM, "out of memory");
        for (size_t k = 0; k < f->mn.count; k++)
            mn[k] = f->mn.samples[k].label;
        landing_truth_list_t truth;
        landing_report_t rep;
        st = landing_truth_from_labels(&f->mn, mn, &truth);
        if (st == PP5_OK)
            st = landing_evaluate(&f->mn, lp, 0.05, &truth, &rep);
        for (int b = 0; st == PP5_OK && b < LANDING_BINS; b++)
            if (rep.predicted[b]) {
                esum[b] += rep.mean_err_deg[b] * (double)rep.predicted[b];
                hsum[b] += rep.mean_hold_err_deg[b] * (double)rep.predicted[b];
                bn[b] += rep.predicted[b];
            }
        if (st == PP5_OK)
            landing_truth_free(&truth);
        free(mn);
    }
    for (int b = 0; b < LANDING_BINS; b++) {
        err[b] = bn[b] ? esum[b] / (double)bn[b] : NAN;
        hold[b] = bn[b] ? hsum[b] / (double)bn[b] : NAN;
    }
    return st;
}

/* The landing predictor's estimators and its peak rule, on the tuning files:
 * the first estimate after each saccade's peak against coder MN's landing. */
static pp5_status_t tune_landing(const lund_set_t *set)
{
    static const char *const names[] = {"both", "main sequence", "profile"};
    static const double drop[] = {0.85, 0.7, 0.5};
    printf("landing: estimator x peak drop -> mean error (deg) of the first estimate after the "
           "peak vs MN's landing, per bin 0-2 2-5 5-10 10-20 20+ deg [newest sample then]\n");
    for (int e = 0; e < 3; e++)
        for (size_t j = 0; j < sizeof drop / sizeof drop[0]; j++) {
            landing_params_t lp;
            landing_defaults(&lp);
            lp.peak_drop = drop[j];
            if (e == 1)
                lp.profile_spread = 1e9;     /* the profile carries no weight */
            if (e == 2)
                lp.velocity_spread = 1e9;    /* nor the main sequence */
            double err[LANDING_BINS], hold[LANDING_BINS];
            pp5_status_t st = landing_score(set, &lp, err, hold);
            if (st != PP5_OK)
                return st;
            printf("  %-13s %.2f:", names[e], drop[j]);
            for (int b = 0; b < LANDING_BINS; b++)
                printf(" %5.2f [%5.2f]", err[b], hold[b]);
            printf("\n");
        }
    return PP5_OK;
}

pp5_status_t lund_tune(const lund_set_t *set)
{
    size_t n = 0;
    for (size_t i = 0; i < set->count; i++)
        n += set->files[i].tune;
    printf("tuning on the %zu files of subjects", n);
    for (size_t i = 0; i < lund_tune_subject_count; i++)
        printf(" %s", lund_tune_subjects[i]);
    printf(" only (the held-out files are not scored)\n");
    pp5_status_t st = tune_ivt(set);
    if (st == PP5_OK)
        st = tune_idt(set);
    if (st == PP5_OK)
        st = tune_adaptive(set);
    if (st == PP5_OK)
        st = tune_edges(set);
    if (st == PP5_OK)
        st = tune_landing(set);
    return st;
}

/* ------------------------------------------------------------------ landing */

/* The files of a split one after another, each 1 s after the last (longer
 * than the predictor's gap reset, so it starts afresh), with MN's labels;
 * all lund2013 files share one display. */
static pp5_status_t concatenate(const lund_set_t *set, lund_split_t split, trace_t *out,
                                int **labels)
{
    trace_init(out);
    *labels = NULL;
    size_t n = 0, k = 0;
    for (size_t i = 0; i < set->count; i++)
        if (lund_in_split(&set->files[i], split))
            n += set->files[i].mn.count;
    if (!n || !(*labels = malloc(n * sizeof **labels)))
        return pp5_fail(PP5_E_NOMEM, "out of memory");
    int64_t offset = 0;
    pp5_status_t st = PP5_OK;
    for (size_t i = 0; i < set->count && st == PP5_OK; i++) {
        const trace_t *t = &set->files[i].mn;
        if (!lund_in_split(&set->files[i], split))
            continue;
        if (!out->count)
            out->header = t->header;
        for (size_t j = 0; j < t->count && st == PP5_OK; j++) {
            gaze_sample_t s = t->samples[j];
            s.t_ns += offset;
            (*labels)[k++] = s.label;
            st = trace_append(out, &s);
        }
        offset = out->samples[out->count - 1].t_ns + 1000000000;
    }
    return st;
}

pp5_status_t lund_landing(const lund_set_t *set, lund_split_t split)
{
    trace_t all;
    int *labels;
    pp5_status_t st = concatenate(set, split, &all, &labels);
    landing_truth_list_t truth = {0};
    landing_report_t rep;
    landing_params_t lp;
    landing_defaults(&lp);
    if (st == PP5_OK)
        st = landing_truth_from_labels(&all, labels, &truth);
    if (st == PP5_OK)
        st = landing_evaluate(&all, &lp, 0.05, &truth, &rep);
    if (st == PP5_OK) {
        printf("Landing prediction (tracker/predict_landing.h, defaults) on the %s files of "
               "lund2013, against coder MN's landings:\n", split == SPLIT_TEST ? "held-out"
               : split == SPLIT_TUNE ? "tuning" : "");
        printf("  %-10s %8s %9s %14s %13s %14s %18s\n", "amplitude", "saccades", "predicted",
               "mean err (deg)", "p95 err (deg)", "last err (deg)", "newest sample (deg)");
        for (int b = 0; b < LANDING_BINS; b++)
            printf("  %4.0f-%-5.0f %8zu %9zu %14.2f %13.2f %14.2f %18.2f\n", landing_bin_edges[b],
                   landing_bin_edges[b + 1], rep.saccades[b], rep.predicted[b],
                   rep.mean_err_deg[b], rep.p95_err_deg[b], rep.mean_last_err_deg[b],
                   rep.mean_hold_err_deg[b]);
        printf("  (first estimate after the peak, its 95th percentile, the last estimate in flight,"
               " and the newest sample when the first estimate came; %zu detections matched no "
               "saccade)\n", rep.false_alarms);
    }
    landing_truth_free(&truth);
    free(labels);
    trace_free(&all);
    return st;
}
