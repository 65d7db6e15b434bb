/* test_events_score.c: kappa, event F1 and duration statistics
 * (tracker/events_score.c) on hand-made label sequences whose answers are
 * worked out by hand in the comments. */
#include <math.h>
#include <string.h>

#include "harness.h"
#include "tracker/events_score.h"

TEST(events_kappa_binary_by_hand)
{
    /* Class 1: both at samples 0,1,2,6 (4); a only at 3,7 (2); b only none;
     * neither at 4,5,8,9 (4).  po = 8/10; p(a=1) = 6/10, p(b=1) = 4/10;
     * pe = 0.6*0.4 + 0.4*0.6 = 0.48; kappa = 0.32 / 0.52 = 8/13. */
    const int a[] = {1, 1, 1, 1, 2, 2, 1, 1, 0, 0};
    const int b[] = {1, 1, 1, 2, 2, 2, 1, 0, 0, 0};
    kappa_counts_t k = {0};
    kappa_counts_add(&k, a, b, 10, 1);
    CHECK_EQ(k.both, 4);
    CHECK_EQ(k.only_a, 2);
    CHECK_EQ(k.only_b, 0);
    CHECK_EQ(k.neither, 4);
    CHECK_NEAR(kappa_of_counts(&k), 8.0 / 13.0, 1e-12);
    /* Class 2 of the same: both 4,5; a only none; b only 3; neither 7.
     * po = 9/10; p(a=2) = 2/10, p(b=2) = 3/10; pe = 0.06 + 0.56 = 0.62;
     * kappa = 0.28 / 0.38 = 14/19. */
    kappa_counts_t k2 = {0};
    kappa_counts_add(&k2, a, b, 10, 2);
    CHECK_NEAR(kappa_of_counts(&k2), 14.0 / 19.0, 1e-12);
}

TEST(events_kappa_sums_files_before_dividing)
{
    /* Two files added to one table give the kappa of the concatenation, not
     * the mean of the two files' kappas (the study's way). */
    const int a1[] = {1, 1, 0, 0}, b1[] = {1, 0, 0, 0};
    const int a2[] = {1, 0, 1, 0}, b2[] = {1, 0, 0, 1};
    const int a[] = {1, 1, 0, 0, 1, 0, 1, 0}, b[] = {1, 0, 0, 0, 1, 0, 0, 1};
    kappa_counts_t k = {0}, whole = {0};
    kappa_counts_add(&k, a1, b1, 4, 1);
    kappa_counts_add(&k, a2, b2, 4, 1);
    kappa_counts_add(&whole, a, b, 8, 1);
    CHECK_NEAR(kappa_of_counts(&k), kappa_of_counts(&whole), 1e-15);
    /* By hand: both 2, a only 2, b only 1, neither 3; po = 5/8;
     * pe = (4/8)(3/8) + (4/8)(5/8) = 0.5; kappa = 0.125 / 0.5 = 0.25. */
    CHECK_NEAR(kappa_of_counts(&k), 0.25, 1e-12);
}

TEST(events_kappa_table_limits_and_a_worked_example)
{
    /* A 3x3 table: N = 200, agreement 88 + 40 + 12 = 140, po = 0.7; rows 120,
     * 60, 20; columns 100, 60, 40; pe = (12000 + 3600 + 800) / 40000 = 0.41;
     * kappa = 0.29 / 0.59. */
    const double t[9] = {88, 14, 18, 10, 40, 10, 2, 6, 12};
    CHECK_NEAR(kappa_of_table(t, 3), 0.29 / 0.59, 1e-12);
    /* Perfect agreement is 1; chance agreement 0; one class everywhere is
     * undefined (pe = 1). */
    const int a[] = {1, 1, 0, 0}, b[] = {1, 0, 1, 0};
    kappa_counts_t same = {0}, chance = {0}, flat = {0};
    kappa_counts_add(&same, a, a, 4, 1);
    kappa_counts_add(&chance, a, b, 4, 1);
    kappa_counts_add(&flat, a, a, 4, 7);
    CHECK_NEAR(kappa_of_counts(&same), 1.0, 1e-15);
    CHECK_NEAR(kappa_of_counts(&chance), 0.0, 1e-15);
    CHECK(isnan(kappa_of_counts(&flat)));
}

static void add_event(events_list_t *l, int cls, size_t first, size_t last)
{
    gaze_event_t e;
    memset(&e, 0, sizeof e);
    e.cls = cls;
    e.first = first;
    e.last = last;
    e.onset_s = first * 0.002;
    e.duration_s = (last - first + 1) * 0.002;
    REQUIRE(events_list_append(l, &e) == PP5_OK);
}

TEST(events_f1_matches_one_to_one_by_largest_overlap)
{
    /* Reference fixations [0,9] [20,29] [40,49]; test fixations [0,4] [5,9]
     * [22,35] [60,69], and a test saccade [10,19] that must not count.
     * [0,9] overlaps [0,4] and [5,9] by 5 each: the earlier wins, [5,9] is a
     * false positive; [20,29]-[22,35] overlap 8: a hit; [40,49] is missed;
     * [60,69] is a false positive.  TP 2, FP 2, FN 1: F1 = 4 / 7. */
    events_list_t ref = {0}, test = {0};
    add_event(&ref, 1, 0, 9);
    add_event(&ref, 1, 20, 29);
    add_event(&ref, 1, 40, 49);
    add_event(&test, 1, 0, 4);
    add_event(&test, 1, 5, 9);
    add_event(&test, 2, 10, 19);
    add_event(&test, 1, 22, 35);
    add_event(&test, 1, 60, 69);
    f1_counts_t f = {0};
    REQUIRE(f1_counts_add(&f, &ref, &test, 1) == PP5_OK);
    CHECK_EQ(f.tp, 2);
    CHECK_EQ(f.fp, 2);
    CHECK_EQ(f.fn, 1);
    CHECK_NEAR(f1_of_counts(&f), 4.0 / 7.0, 1e-12);
    /* Saccades: none in the reference, one in the test: F1 0. */
    f1_counts_t s = {0};
    REQUIRE(f1_counts_add(&s, &ref, &test, 2) == PP5_OK);
    CHECK_EQ(s.fp, 1);
    CHECK_NEAR(f1_of_counts(&s), 0.0, 0);
    f1_counts_t none = {0};
    CHECK(isnan(f1_of_counts(&none)));
    events_list_free(&ref);
    events_list_free(&test);
}

TEST(events_duration_statistics_by_hand)
{
    /* Fixations of 10, 20 and 30 samples at 2 ms: 20, 40, 60 ms; mean 40 ms,
     * sample sd sqrt(((-20)^2 + 0 + 20^2) / 2) = 20 ms. */
    events_list_t l = {0};
    add_event(&l, 1, 0, 9);
    add_event(&l, 2, 10, 14);
    add_event(&l, 1, 15, 34);
    add_event(&l, 1, 35, 64);
    duration_stats_t d = {0};
    duration_stats_add(&d, &l, 1, 0);
    CHECK_EQ(d.count, 3);
    CHECK_NEAR(duration_stats_mean_ms(&d), 40.0, 1e-9);
    CHECK_NEAR(duration_stats_sd_ms(&d), 20.0, 1e-9);
    /* In a recording of 65 samples the first and last fixations touch its
     * ends: only the 40 ms one is left. */
    duration_stats_t inner = {0};
    duration_stats_add(&inner, &l, 1, 65);
    CHECK_EQ(inner.count, 1);
    CHECK_NEAR(duration_stats_mean_ms(&inner), 40.0, 1e-9);
    duration_stats_t none = {0};
    CHECK(isnan(duration_stats_mean_ms(&none)));
    events_list_free(&l);
}
