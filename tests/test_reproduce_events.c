/* test_reproduce_events.c: the lund2013 side of `pp5 reproduce events`
 * (emu/cli/reproduce_events_lund.c): the split keeps subjects apart, pp5's
 * reading of the coders' labels gives the event counts the study published,
 * and the command runs.  SKIPs loudly without ../shared/data/gaze/lund2013. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "emu/cli/reproduce_events.h"
#include "harness.h"

static bool load(lund_set_t *set)
{
    const char *dir = pp5_test_shared_data("gaze/lund2013/trace");
    if (!dir)
        return false;
    char root[1024];
    snprintf(root, sizeof root, "%s", dir);
    *strstr(root, "/lund2013/trace") = '\0';
    REQUIRE_MSG(lund_load(root, set) == PP5_OK, "%s", pp5_error_text());
    return true;
}

TEST(reproduce_events_split_keeps_subjects_apart)
{
    lund_set_t set;
    if (!load(&set))
        SKIP("../shared/data/gaze/lund2013 is absent");
    CHECK_EQ(set.count, 34);
    size_t tune = 0;
    for (size_t i = 0; i < set.count; i++) {
        tune += set.files[i].tune;
        const char *subject = strchr(set.files[i].name, '/') + 1;
        for (size_t j = 0; j < set.count; j++)
            if (strncmp(strchr(set.files[j].name, '/') + 1, subject, 4) == 0)
                CHECK_MSG(set.files[j].tune == set.files[i].tune, "%s and %s: same subject, "
                          "different sides of the split", set.files[i].name, set.files[j].name);
    }
    CHECK_EQ(tune, 11);
    lund_free(&set);
}

TEST(reproduce_events_coder_counts_match_the_study)
{
    /* Andersson et al. 2017 Tables 3-5 (fixations, saccades, PSOs; all files)
     * as transcribed in reproduce_events.c: MN/RA fixations 380/369
     * (images), 2/13 (dots), 67/67 (video); saccades 376/372, 47/47, 116/126;
     * PSOs 312/309, 33/28, 97/89.  pp5 reads the labels independently; the
     * counts must agree within 1 % + 1. */
    static const int want[3][2][STIM_COUNT] = {{{380, 2, 67}, {369, 13, 67}},
                                               {{376, 47, 116}, {372, 47, 126}},
                                               {{312, 33, 97}, {309, 28, 89}}};
    lund_set_t set;
    if (!load(&set))
        SKIP("../shared/data/gaze/lund2013 is absent");
    static lund_tally_t t;
    t.n_methods = 0;
    REQUIRE(lund_score(&set, SPLIT_ALL, &t) == PP5_OK);
    for (int c = 0; c < 3; c++)          /* lund_classes: fixation, saccade, PSO */
        for (int r = 0; r < 2; r++)
            for (int s = 0; s < STIM_COUNT; s++) {
                long got = (long)t.dur[s][c][r].count, w = want[c][r][s];
                CHECK_MSG(labs(got - w) <= w / 100 + 1, "%s %s %s: %ld events, the study %ld",
                          r ? "RA" : "MN", events_class_name(lund_classes[c]),
                          lund_stim_names[s], got, w);
            }
    /* The study's mean fixation durations, MN: 248 ms (images), 161 (dots),
     * 318 (video); pp5 gets them when every sample counts 2 ms, as the study's
     * 500 Hz field says even for the three 200 Hz files. */
    CHECK_NEAR(duration_stats_mean_ms(&t.dur_at_500hz[STIM_IMG][0][RATER_MN]), 248, 1.0);
    CHECK_NEAR(duration_stats_mean_ms(&t.dur_at_500hz[STIM_DOTS][0][RATER_MN]), 161, 1.0);
    CHECK_NEAR(duration_stats_mean_ms(&t.dur_at_500hz[STIM_VIDEO][0][RATER_MN]), 318, 1.0);
    lund_free(&set);
}

TEST(reproduce_events_runs_and_reports_the_held_out_files)
{
    if (!pp5_test_shared_data("gaze/lund2013/trace"))
        SKIP("../shared/data/gaze/lund2013 is absent");
    char out[700];
    snprintf(out, sizeof out, "%s/out.txt", pp5_test_outdir());
    REQUIRE(pp5_test_run_cli("reproduce events", out, NULL) == 0);
    char *text = pp5_test_read_file(out);
    REQUIRE(text);
    CHECK(strstr(text, "scored here: the held-out files") != NULL);
    CHECK(strstr(text, "not found") != NULL);
    CHECK(strstr(text, "Event-level F1") != NULL);
    free(text);
    CHECK_EQ(pp5_test_run_cli("reproduce events --split sideways", NULL, NULL), 2);
    REQUIRE(pp5_test_run_cli("reproduce events --landing", out, NULL) == 0);
    text = pp5_test_read_file(out);
    REQUIRE(text);
    CHECK(strstr(text, "Landing prediction") && strstr(text, "held-out files"));
    free(text);
}
