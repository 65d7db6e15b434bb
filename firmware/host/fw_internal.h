/* fw_internal.h: what the host session's files share: band planning and the analysis of a finished frame.
 *
 * Private to firmware/host. */
#ifndef PP5_FW_INTERNAL_H
#define PP5_FW_INTERNAL_H

#include "fw_session.h"
#include "stats.h"

/* fw_bands.c: GP g owns image rows [band_y0[g], band_y0[g+1]); starts are
 * multiples of 2^(levels2d-1) so every band begins on a texel row of every
 * 2D level. */
void fw_bands_equal(int height, int n_gp, int levels2d, int32_t *band_y0);
/* The bands of this frame for the session's plan (fw_plan_t), from the gaze
 * point, the previous frame's measured cost factors (sequences) and, for
 * FW_PLAN_SAMPLES, the volume's occupancy along a coarse ray grid. */
void fw_bands_plan(fw_session_t *s, double gx, double gy, int32_t *band_y0);
/* Object slabs: the level-0 slices each GP casts through, [slab_z0[g],
 * slab_z0[g+1]): equal shares of the volume's occupied cells when the
 * sample estimate is built (FW_PLAN_SAMPLES), else of its slices. */
void fw_slabs_plan(const fw_session_t *s, int32_t *slab_z0);
/* After a frame: each band's measured GP cycles per unit of estimate, for the
 * next frame of a sequence. */
void fw_bands_learn(fw_session_t *s, const stats_t *frame);

/* fw_estimate.c: FW_PLAN_SAMPLES, the estimated GP cycles of each band unit:
 * the acuity model's rays times the samples each draws, marched through the
 * volume's opacity on a coarse grid. */
pp5_status_t fw_estimate_init(fw_session_t *s, const render_job_t *job);
double fw_estimate_unit(fw_session_t *s, const camera_t *cam, int unit_index, double gx,
                        double gy);
/* Drops what fw_estimate_unit kept of the view's rays (the view changed). */
void fw_estimate_forget(fw_session_t *s);

/* PP5_E_FIRMWARE, naming them, when the frame went idle with GPs that never
 * finished it (a firmware that waits for a message nobody sends): its image
 * would be incomplete, so it is not reported as a frame. */
pp5_status_t fw_frame_check_finished(const fw_session_t *s, const stats_t *frame);

/* fw_analysis.c: the frame result from the statistics of the frame
 * (differences of two snapshots) and the frame's span [t0, t1]. */
void fw_frame_analyse(fw_session_t *s, const stats_t *frame, pp5_tick_t t0, pp5_tick_t t1,
                      fw_frame_result_t *r);

#endif
