/* cmd_replay_landing.c: `pp5 replay --predict landing`'s report of the
 * landing error per amplitude bin (tracker/predict_landing.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "emu/cli/cmd_replay.h"
#include "tracker/events.h"
#include "tracker/predict_landing.h"

/* True landings: the trace's own saccade labels when it has any (a coder's,
 * or the generator's truth), else the adaptive detector's, run offline. */
static pp5_status_t true_landings(const trace_t *t, landing_truth_list_t *truth,
                                  const char **source)
{
    int *labels = malloc((t->count ? t->count : 1) * sizeof *labels);
    if (!labels)
        return pp5_fail(PP5_E_NOMEM, "out of memory");
    bool labelled = false;
    for (size_t i = 0; i < t->count; i++) {
        labels[i] = t->samples[i].label;
        labelled |= labels[i] == GAZE_LABEL_SACCADE;
    }
    pp5_status_t st = PP5_OK;
    events_result_t r = {0};
    *source = "the trace's own saccade labels";
    if (!labelled) {
        events_params_t ep;
        events_defaults(&ep, EVENTS_ADAPTIVE);
        st = events_detect(t, &ep, &r);
        *source = "saccades the adaptive detector finds offline (the trace has no labels)";
    }
    if (st == PP5_OK)
        st = landing_truth_from_labels(t, labelled ? labels : r.labels, truth);
    events_result_free(&r);
    free(labels);
    return st;
}

pp5_status_t replay_print_landing(const trace_t *t, const replay_params_t *p)
{
    landing_truth_list_t truth;
    const char *source = "";
    pp5_status_t st = true_landings(t, &truth, &source);
    if (st != PP5_OK)
        return st;
    landing_report_t rep;
    st = landing_evaluate(t, &p->predict.landing, p->predict.gap_reset_s, &truth, &rep);
    if (st == PP5_OK) {
        printf("  landing prediction per true amplitude (truth: %s; landing = mean gaze over the "
               "20 ms after the saccade and its PSO):\n", source);
        printf("    %-10s %8s %9s %14s %13s %14s %18s\n", "amplitude", "saccades", "predicted",
               "mean err (deg)", "p95 err (deg)", "last err (deg)", "newest sample (deg)");
        for (int b = 0; b < LANDING_BINS; b++) {
            char bin[32];
            if (isinf(landing_bin_edges[b + 1]))
                snprintf(bin, sizeof bin, "%.0f+ deg", landing_bin_edges[b]);
            else
                snprintf(bin, sizeof bin, "%.0f-%.0f deg", landing_bin_edges[b],
                         landing_bin_edges[b + 1]);
            printf("    %-10s %8zu %9zu %14.2f %13.2f %14.2f %18.2f\n", bin, rep.saccades[b],
                   rep.predicted[b], rep.mean_err_deg[b], rep.p95_err_deg[b],
                   rep.mean_last_err_deg[b], rep.mean_hold_err_deg[b]);
        }
        printf("    (error of the first estimate after the saccade's peak, its 95th percentile, of "
               "the last estimate in flight, and of the newest sample when the first estimate "
               "came; %zu detections matched no true saccade)\n", rep.false_alarms);
    }
    landing_truth_free(&truth);
    return st;
}
