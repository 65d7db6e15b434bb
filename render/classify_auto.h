/* classify_auto.h: the default transfer function of a volume file, chosen from its histogram (volume_histogram.h) so that data of any value range gives a picture.
 *
 * Two of Levoy's iso-value contours (classify.h), placed between the
 * histogram's landmarks the way the CThead preset was read off its histogram:
 *   outer surface  halfway between the background's peak and the foreground's
 *                  median (for CT: air and soft tissue, i.e. the skin),
 *                  opacity 0.3 (0.8 when it is the only one), warm white;
 *   dense surface  halfway between the foreground's median and its 99th
 *                  percentile (for CT: bone), opacity 0.85, white; left out
 *                  when the two are closer than 2 % of the foreground's
 *                  1st-99th percentile window (a nearly uniform object).
 * Contours, not a table, so that the machine's firmware renders the same
 * function (it classifies by contours only). */
#ifndef PP5_CLASSIFY_AUTO_H
#define PP5_CLASSIFY_AUTO_H

#include "classify.h"
#include "volume_histogram.h"

typedef struct {
    double background_max, background_peak;
    uint64_t n_background, n_foreground;
    double window_lo, window_hi;      /* 1st and 99th percentiles of the foreground */
    double median;                    /* the foreground's */
} classify_auto_info_t;

/* The function for a histogram; PP5_E_RANGE with a message when the volume
 * has no foreground (every voxel background, e.g. a constant volume). */
pp5_status_t classify_tf_auto(const volume_histogram_t *h, classify_tf_t *tf,
                              classify_auto_info_t *info);
/* One line saying how it was chosen, for the user. */
void classify_auto_describe(const classify_auto_info_t *info, char *buf, size_t n);

#endif
