/* reproduce_events.c: `pp5 reproduce events`: pp5's event detectors scored
 * against the two human coders of lund2013, beside the coders' agreement with
 * each other and the ten algorithms of Andersson, Larsson, Holmqvist, Stridh &
 * Nystrom 2017, "One algorithm to rule them all?", Behavior Research Methods
 * 49:616-637, who scored them against the same coders on the same samples.
 * Loading, the split and the scoring are in reproduce_events_lund.c. */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cliopt.h"
#include "emu/cli/reproduce_events.h"
#include "registry.h"
#include "render/scene.h"

/* ---- the study's figures ----
 * Tables 3-6 of Andersson et al. 2017 (event durations: mean, sd in ms, and
 * number of events, per stimulus type, over all 34 files), as transcribed by
 * hand in github psychoinformatics-de/paper-remodnav, code/mk_figuresnstats.py
 * (commit 020a38d179ee30700004bde427714517bb23d0b0; its comment says the
 * same statistics are in the study's repository as
 * matlab_analysis_code/20150807.mat, which pp5 cannot read as text).
 * The study's per-class Cohen's kappa (its Table 7) was not found in any
 * stored source; see KAPPA_NOTE. */
typedef struct {
    const char *who;
    int mean[STIM_COUNT], sd[STIM_COUNT], n[STIM_COUNT];   /* img, dots, video */
} study_row_t;

static const study_row_t study_fix[] = {
    {"MN", {248, 161, 318}, {271, 30, 289}, {380, 2, 67}},
    {"RA", {242, 131, 240}, {273, 99, 189}, {369, 13, 67}},
    {"CDT", {397, 60, 213}, {559, 127, 297}, {251, 165, 211}},
    {"IDT", {399, 323, 554}, {328, 146, 454}, {242, 8, 48}},
    {"IKF", {174, 217, 228}, {239, 184, 296}, {513, 72, 169}},
    {"IMST", {304, 268, 526}, {293, 140, 825}, {333, 12, 71}},
    {"IHMM", {133, 214, 234}, {216, 286, 319}, {701, 67, 194}},
    {"IVT", {114, 203, 202}, {204, 282, 306}, {827, 71, 227}},
    {"NH", {258, 380, 429}, {299, 333, 336}, {292, 30, 83}},
    {"BIT", {209, 189, 248}, {136, 113, 215}, {423, 67, 170}},
    {NULL, {0}, {0}, {0}}};
static const study_row_t study_sac[] = {
    {"MN", {30, 23, 26}, {17, 10, 13}, {376, 47, 116}},
    {"RA", {31, 22, 25}, {15, 11, 12}, {372, 47, 126}},
    {"EM", {25, 17, 20}, {22, 14, 16}, {787, 93, 252}},
    {"IDT", {35, 32, 24}, {15, 14, 53}, {258, 10, 41}},
    {"IKF", {62, 60, 55}, {37, 26, 20}, {353, 29, 107}},
    {"IMST", {17, 13, 18}, {10, 5, 10}, {335, 18, 76}},
    {"IHMM", {48, 41, 42}, {26, 17, 18}, {368, 27, 109}},
    {"IVT", {41, 36, 36}, {22, 14, 16}, {373, 28, 112}},
    {"NH", {50, 43, 44}, {20, 16, 18}, {344, 42, 1104}},
    {"LNS", {29, 26, 28}, {12, 11, 12}, {390, 53, 122}},
    {NULL, {0}, {0}, {0}}};
static const study_row_t study_pso[] = {
    {"MN", {21, 15, 20}, {11, 5, 11}, {312, 33, 97}},
    {"RA", {21, 15, 17}, {9, 8, 8}, {309, 28, 89}},
    {"NH", {28, 24, 28}, {13, 12, 13}, {237, 17, 78}},
    {"LNS", {25, 20, 24}, {9, 9, 10}, {319, 31, 87}},
    {NULL, {0}, {0}, {0}}};
static const study_row_t study_pur[] = {
    {"MN", {363, 375, 521}, {187, 256, 347}, {3, 37, 50}},
    {"RA", {305, 378, 472}, {184, 364, 319}, {16, 33, 68}},
    {NULL, {0}, {0}, {0}}};

#define KAPPA_NOTE \
    "  the study's algorithms (its Table 7): not found in any stored source.  A draft of the\n" \
    "  REMoDNaV paper (github psychoinformatics-de/paper-remodnav, main.tex at commit\n" \
    "  00092adab65cebddcd593377bf5ec36c0f303a2b) summarises it: LNS, the best saccade and PSO\n" \
    "  detector, \"achieved Cohens Kappas between .75 and .81 for saccades, and between .59\n" \
    "  and .64 for PSOs\"; the best fixation detectors \"between .5 and .7 for the image\n" \
    "  category, but at maximum .13 for any of the dynamic categories\" (all files, vs the\n" \
    "  coders; the per-algorithm values are not given there).\n"

static const char *rater_name(const lund_tally_t *t, int r)
{
    if (r == RATER_MN)
        return "MN";
    if (r == RATER_RA)
        return "RA";
    return events_method_name(t->methods[r - RATER_FIRST_METHOD].method);
}

static void print_value(double v)
{
    if (isnan(v))
        printf("    -  ");
    else
        printf(" %6.3f", v);
}

/* kappa (f1 = false) or event F1 (true), per class, stimulus and rater. */
static void print_agreement(const lund_tally_t *t, bool f1)
{
    int n_raters = RATER_FIRST_METHOD + t->n_methods;
    printf("  %-9s %-9s", "class", "rater");
    for (int s = 0; s < STIM_COUNT; s++)
        printf("  %-6s vs MN  vs RA", lund_stim_names[s]);
    printf("\n");
    for (int c = 0; c < LUND_CLASSES; c++) {
        for (int r = RATER_RA; r < n_raters; r++) {
            printf("  %-9s %-9s", r == RATER_RA ? events_class_name(lund_classes[c]) : "",
                   r == RATER_RA ? "RA (coder)" : rater_name(t, r));
            for (int s = 0; s < STIM_COUNT; s++) {
                printf("       ");
                for (int ref = 0; ref < 2; ref++) {
                    double v = f1 ? f1_of_counts(&t->f1[s][c][r][ref])
                                  : kappa_of_counts(&t->kappa[s][c][r][ref]);
                    if (r == ref)
                        printf("    -  ");
                    else
                        print_value(v);
                }
            }
            printf("\n");
        }
        if (!f1 && lund_classes[c] <= GAZE_LABEL_PSO)
            printf("  %-9s %-20s not found (see below)\n", "", "the study's 10 algs");
        if (!f1 && lund_classes[c] == GAZE_LABEL_PURSUIT)
            printf("  %-9s %-20s none: they detect no pursuit\n", "", "the study's 10 algs");
    }
}

static void print_study_rows(const study_row_t *rows)
{
    for (const study_row_t *row = rows; row->who; row++) {
        printf("    %-16s", row->who);
        for (int s = 0; s < STIM_COUNT; s++)
            printf("   %5d %5d %5d", row->mean[s], row->sd[s], row->n[s]);
        printf("\n");
    }
}

static void print_durations(const lund_tally_t *ours, const lund_tally_t *all_files)
{
    static const study_row_t *const study[LUND_CLASSES] = {study_fix, study_sac, study_pso,
                                                           study_pur, NULL};
    int n_raters = RATER_FIRST_METHOD + ours->n_methods;
    for (int c = 0; c < LUND_CLASSES; c++) {
        printf("  %s durations (ms): mean, sd, number of events\n    %-16s",
               events_class_name(lund_classes[c]), "");
        for (int s = 0; s < STIM_COUNT; s++)
            printf("   %-17s", lund_stim_names[s]);
        printf("\n");
        for (int r = 0; r < n_raters; r++) {
            char who[48];
            snprintf(who, sizeof who, "%s%s", rater_name(ours, r), r < RATER_FIRST_METHOD
                     ? " (coder)" : "");
            printf("    %-16s", who);
            for (int s = 0; s < STIM_COUNT; s++) {
                const duration_stats_t *d = &ours->dur[s][c][r];
                printf("   %5.0f %5.0f %5zu", duration_stats_mean_ms(d), duration_stats_sd_ms(d),
                       d->count);
            }
            printf("\n");
        }
        if (study[c]) {
            printf("   all 34 files, pp5's reading of the coders' labels:\n");
            for (int r = 0; r < RATER_FIRST_METHOD; r++) {
                printf("    %-16s", rater_name(all_files, r));
                for (int s = 0; s < STIM_COUNT; s++) {
                    const duration_stats_t *d = &all_files->dur[s][c][r];
                    printf("   %5.0f %5.0f %5zu", duration_stats_mean_ms(d),
                           duration_stats_sd_ms(d), d->count);
                }
                printf("\n");
            }
            printf("   all 34 files, the coders' labels with every sample counted as 2 ms:\n");
            for (int r = 0; r < RATER_FIRST_METHOD; r++) {
                printf("    %-16s", rater_name(all_files, r));
                for (int s = 0; s < STIM_COUNT; s++) {
                    const duration_stats_t *d = &all_files->dur_at_500hz[s][c][r];
                    printf("   %5.0f %5.0f %5zu", duration_stats_mean_ms(d),
                           duration_stats_sd_ms(d), d->count);
                }
                printf("\n");
            }
            printf("   all 34 files, Andersson et al. 2017 Tables 3-6 (transcribed, see "
                   "reproduce_events.c):\n");
            print_study_rows(study[c]);
        }
    }
    printf("  Notes: events cut by a recording's first or last sample are left out, as the study\n"
           "  does (inferred: with that rule pp5's counts of the coders' events are the study's).\n"
           "  Durations are samples x sample interval.  Where pp5 and the study disagree, the\n"
           "  study counts every sample as 2 ms: its image and video durations treat the three\n"
           "  200 Hz recordings (*47, 5 ms steps; their files say 500 Hz) as 500 Hz; counted\n"
           "  that way (the rows \"every sample counted as 2 ms\") pp5 gets the study's figures,\n"
           "  e.g. MN's image fixations 248 ms against 272 ms in real time.  The study's NH video\n"
           "  saccade count (1104) is as transcribed, ten times its neighbours: probably 104.\n");
}

static void reproduce_events_usage(void)
{
    printf("usage: pp5 reproduce events [--split test|tune|all] [--tune] [--landing]\n\n"
           "Scores pp5's event detectors (ivt, idt, adaptive; tracker/events.h) against the two\n"
           "human coders of lund2013 (../shared/data/gaze/lund2013: images, moving dots, video,\n"
           "500 Hz), beside the coders' agreement with each other and the figures of Andersson et\n"
           "al. 2017, who scored ten algorithms against the same coders.  Per stimulus type and\n"
           "class: sample-level Cohen's kappa and event-level F1 against each coder, and event\n"
           "durations and numbers.  Thresholds were tuned on a fixed subset of subjects only;\n"
           "the scores are on the other files (reproduce_events_lund.c, tracker/ARCHITECTURE.md).\n"
           "  --split S   test: the held-out files (default); tune: the tuning files; all\n"
           "  --tune      rerun the threshold search on the tuning files and print it\n"
           "  --landing   instead: the landing predictor's error per amplitude bin against\n"
           "              coder MN's landings (replay --predict landing)\n"
           "Example: pp5 reproduce events\n");
}

static void print_header(const lund_set_t *set, lund_split_t split, const lund_tally_t *t)
{
    printf("Event detection against the lund2013 coders (Andersson et al. 2017, BRM 49:616-637)\n");
    printf("split: thresholds tuned on subjects");
    for (size_t i = 0; i < lund_tune_subject_count; i++)
        printf(" %s", lund_tune_subjects[i]);
    printf("; scored here: %s files\n", split == SPLIT_TEST ? "the held-out"
           : split == SPLIT_TUNE ? "the TUNING (not held-out)" : "ALL (tuning included)");
    for (int s = 0; s < STIM_COUNT; s++) {
        printf("  %-5s %2zu files, %6zu samples:", lund_stim_names[s], t->files[s], t->samples[s]);
        for (size_t i = 0; i < set->count; i++)
            if (set->files[i].stim == s && lund_in_split(&set->files[i], split))
                printf(" %s", strchr(set->files[i].name, '/') + 1);
        printf("\n");
    }
    for (int m = 0; m < t->n_methods; m++) {
        const events_params_t *p = &t->methods[m];
        if (p->method == EVENTS_IVT)
            printf("  ivt: %.0f deg/s\n", p->ivt_threshold_dps);
        else if (p->method == EVENTS_IDT)
            printf("  idt: %.2f deg over %.0f ms\n", p->idt_dispersion_deg, p->idt_window_s * 1e3);
        else
            printf("  adaptive: Nystrom & Holmqvist 2010 as published (thresholds from each "
                   "trace's own noise)\n");
    }
}

static int reproduce_events(const pp5_reproduce_opts_t *o)
{
    static const struct option opts[] = {{"split", required_argument, 0, 's'},
                                         {"tune", no_argument, 0, 't'},
                                         {"landing", no_argument, 0, 'l'},
                                         {"help", no_argument, 0, 'h'}, {0, 0, 0, 0}};
    lund_split_t split = SPLIT_TEST;
    bool tune = false, landing = false;
    int c;
    optind = 1;
    while ((c = getopt_long(o->argc, o->argv, "h", opts, NULL)) != -1) {
        switch (c) {
        case 's':
            if (strcmp(optarg, "test") == 0) split = SPLIT_TEST;
            else if (strcmp(optarg, "tune") == 0) split = SPLIT_TUNE;
            else if (strcmp(optarg, "all") == 0) split = SPLIT_ALL;
            else return cliopt_report("reproduce events", pp5_fail(PP5_E_CONFIG, "--split: test, "
                                      "tune or all, got '%s'", optarg));
            break;
        case 't': tune = true; break;
        case 'l': landing = true; break;
        case 'h': reproduce_events_usage(); return 0;
        default: reproduce_events_usage(); return 2;
        }
    }
    char root[1024];
    snprintf(root, sizeof root, "%s/gaze", scene_data_root());
    lund_set_t set;
    pp5_status_t st = lund_load(root, &set);
    if (st != PP5_OK)
        return cliopt_report("reproduce events", st);
    if (tune || landing) {
        st = tune ? lund_tune(&set) : lund_landing(&set, split);
        lund_free(&set);
        return st == PP5_OK ? 0 : cliopt_report("reproduce events", st);
    }
    static lund_tally_t ours, all_files;     /* large: kept off the stack */
    ours.n_methods = 3;
    events_defaults(&ours.methods[0], EVENTS_IVT);
    events_defaults(&ours.methods[1], EVENTS_IDT);
    events_defaults(&ours.methods[2], EVENTS_ADAPTIVE);
    all_files.n_methods = 0;
    st = lund_score(&set, split, &ours);
    if (st == PP5_OK)
        st = lund_score(&set, SPLIT_ALL, &all_files);
    if (st == PP5_OK) {
        print_header(&set, split, &ours);
        printf("\nSample-level Cohen's kappa (each class against the rest, summed over the files "
               "of a stimulus type, as the study computes it):\n");
        print_agreement(&ours, false);
        printf(KAPPA_NOTE);
        printf("\nEvent-level F1 (events matched one to one by largest overlap, Hooge et al. "
               "2018):\n");
        print_agreement(&ours, true);
        printf("\n");
        print_durations(&ours, &all_files);
    }
    lund_free(&set);
    return st == PP5_OK ? 0 : cliopt_report("reproduce events", st);
}

PP5_REPRODUCE(events, "event detection vs the two lund2013 coders and Andersson et al. 2017",
              reproduce_events)
