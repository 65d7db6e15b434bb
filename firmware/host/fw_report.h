/* fw_report.h: the machine render's JSON report: the session, every frame's time and ring bytes, the last frame's breakdown per phase and per GP, and the image comparison.
 *
 * emu's own run report (every unit's statistics, emu/report.h) is written
 * beside it as FILE.machine.json. */
#ifndef PP5_FW_REPORT_H
#define PP5_FW_REPORT_H

#include "fw_session.h"

/* One frame of a sequence, as the report lists it. */
typedef struct {
    double gaze_x, gaze_y;
    fw_frame_result_t result;
} fw_frame_record_t;

/* The comparison with render/ (filled by the command that ran both). */
typedef struct {
    bool have;
    double psnr_native_db, max_diff_native;       /* vs render/ itself */
    double psnr_like_db, max_diff_like;           /* vs render/ on the machine's formats */
    uint64_t native_rays, native_samples;
} fw_compare_t;

/* Writes the report (cmp may be NULL); frames[n_frames - 1] is the frame
 * broken down in detail. */
pp5_status_t fw_report_write(const char *path, const fw_session_t *s, const fw_frame_record_t *frames,
                             int n_frames, const char *volume_name, const fw_compare_t *cmp);

#endif
