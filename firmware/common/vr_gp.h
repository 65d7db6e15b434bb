/* vr_gp.h: the volume-rendering GP program and the per-GP figures it records (read by the host for reports).
 *
 * The probe is bookkeeping of the emulation, not machine state the real GP
 * would send anywhere: the host reads it after a frame to split the frame
 * time by phase (firmware/host/fw_report.c). */
#ifndef PP5_VR_GP_H
#define PP5_VR_GP_H

#include <stdint.h>
#include "fw_api.h"

typedef struct {
    /* Emulated picoseconds of the last frame's phase boundaries on this GP. */
    uint64_t t_start, t_prep_done, t_data_done, t_cast_done, t_boundary, t_done;
    /* Summed over passes: waiting for a pass's bricks, casting it. */
    uint64_t wait_ps, cast_ps, passes;
    /* i860 cycles charged per phase in the last frame. */
    uint64_t cyc_prep, cyc_exec_build, cyc_forward, cyc_unpack, cyc_shade, cyc_cast, cyc_pixels;
    /* Work of the last frame. */
    uint64_t rays, samples, skipped, bricks_fetched, bytes_fetched, fb_bytes;
    uint64_t pp_stream_words;
    /* Setup (once per sequence). */
    uint64_t setup_cycles, setup_bricks_written, setup_voxels_built;
    uint64_t n_bricks_total, n_bricks_nonempty, max_slots_used;
    int frame_done;
    int all_level0;                   /* every own pixel at 2D level 0 (progressive) */
} vr_probe_t;

extern const fw_program_t vr_program;

/* The probe of a GP running vr_program (state pointer from fw_state). */
const vr_probe_t *vr_probe(const void *state);

#endif
