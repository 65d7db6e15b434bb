/* fw_session.h: the host workstation's side of the gaze-directed volume renderer on the emulated machine: load once, then one call per frame.
 *
 * fw_session_init takes a resolved render job (render/render_job.h), loads the
 * volume slabs and the GP program and runs the per-sequence setup (the GPs
 * build the 3D mip map and write it into the renderers' backing store);
 * fw_session_frame runs one frame for a gaze point and returns the image, the
 * emulated frame time with its critical-path breakdown, rays, samples and
 * ring bytes.  A sequence of frames reuses the setup.  How the work is divided
 * between GPs, PPs and ring is the session's division (fw_options_t,
 * firmware/ARCHITECTURE.md "Work divisions").  Every figure comes from emu's
 * named statistics (emu/stats.h), taken as differences around the frame. */
#ifndef PP5_FW_SESSION_H
#define PP5_FW_SESSION_H

#include <stdbool.h>
#include <stdint.h>
#include "firmware/common/vr_config.h"
#include "machine.h"
#include "render/render_job.h"

/* How the frame's work is divided (firmware/ARCHITECTURE.md). */
typedef enum {
    FW_DIVISION_IMAGE_BANDS = 0,   /* image-space bands, bricks fetched per frame (baseline) */
    FW_DIVISION_RESIDENT,          /* image-space bands, blocks kept across frames */
    FW_DIVISION_OBJECT_SLABS,      /* object-space slabs, ray segments composited */
    FW_DIVISION_COUNT
} fw_division_t;

/* How the host plans a frame's bands. */
typedef enum {
    FW_PLAN_RAYS = 0,              /* the acuity model's rays per row */
    FW_PLAN_SAMPLES,               /* rays times samples, from the octree along a coarse ray grid */
} fw_plan_t;

typedef struct {
    fw_division_t division;
    int split;                     /* VR_SPLIT_PP (paper) or VR_SPLIT_GP */
    fw_plan_t plan;
    bool level_tables;             /* 2DLevel by the paper's two lookup tables (§4), not exactly */
    int unit_edge;                 /* resident: largest edge of a fetched unit, voxels (default 8) */
    int tiles;                     /* resident: ray groups per pass cast as their units arrive (4) */
    int max_pass_bricks;           /* cap bricks per pass below the memory limit (0: off) */
    bool timeline;
} fw_options_t;

void fw_options_default(fw_options_t *o);
const char *fw_division_name(fw_division_t d);
/* One firmware setting given as KEY=VALUE among the --set items (division,
 * split, plan, level_tables, unit_edge, tiles).  *taken is false, and nothing is changed, for a
 * key that is not the firmware's (a machine parameter); a bad value is an
 * error naming the key, the value and the choices. */
pp5_status_t fw_options_set(fw_options_t *o, const char *key_eq_value, bool *taken);
/* The same settings as text, "division=resident split=pp ...", for reports. */
void fw_options_format(const fw_options_t *o, char *buf, size_t n);

typedef enum {
    FW_PHASE_HOST_START = 0,   /* host -> GP frame parameters and FRAME_START */
    FW_PHASE_GP_PREP,          /* 2DLevel, texel marking, footprint, PP stream build */
    FW_PHASE_PP_SHADE,         /* waiting while the renderers shade (viewpoint-dependent) */
    FW_PHASE_RING_FETCH,       /* waiting for shaded bricks over the ring (data class) */
    FW_PHASE_GP_RECEIVE,       /* taking in bricks, forwarding requests, GP-side shading */
    FW_PHASE_GP_CAST,          /* gaze-directed ray casting into the 2D mip map (the GPs' mean) */
    FW_PHASE_GP_IMBALANCE,     /* the critical GP's compute beyond the mean GP's */
    FW_PHASE_GP_EXCHANGE,      /* waiting for the neighbour's boundary texel rows */
    FW_PHASE_GP_RESAMPLE,      /* RenderPixel at display resolution + sections sent */
    FW_PHASE_FB_TRANSFER,      /* last sections in flight to the frame buffer */
    FW_PHASE_COUNT
} fw_phase_t;

const char *fw_phase_name(fw_phase_t p);
/* Short column/JSON key of a phase ("gp_cast_s", ...). */
const char *fw_phase_key(fw_phase_t p);

/* One GP's part of a frame (from its published statistics). */
typedef struct {
    int band_y0, band_y1;
    uint64_t rays, samples, bricks_fetched;
    uint64_t cycles_prep, cycles_pp_stream_build, cycles_forward, cycles_receive, cycles_shade,
        cycles_cast, cycles_resample;
    double busy_s, done_s;
    uint64_t mem_peak_bytes;
} fw_gp_frame_t;

typedef struct {
    double frame_time_s;
    double phase_s[FW_PHASE_COUNT];   /* critical-path split: sums to frame_time_s */
    int critical_gp;                  /* the GP that finished last */
    int critical_path_gp;             /* whose prep/fetch/cast the path runs through */
    const char *bottleneck;           /* the largest phase */
    uint64_t rays, samples, samples_skipped;
    uint64_t bricks_fetched, bytes_fetched, pp_stream_words;
    bool full_resolution_everywhere;  /* every pixel at 2D level 0 (progressive) */
    uint64_t passes_max;              /* passes of the GP that needed most (memory) */
    uint64_t ring_bytes[RING_CLASS_COUNT];
    uint64_t ring_bytes_total;
    double ring_util[RING_CLASS_COUNT];   /* class bytes / (aggregate bandwidth x frame time) */
    double ring_util_total;
    double gp_util_mean, gp_util_max, rn_util_mean, rn_util_max;
    double gp_imbalance;              /* busiest GP's busy time / the mean GP's (1 = balanced) */
    uint64_t rn_exec_cycles_max;
    uint64_t dcache_hits, dcache_misses;   /* the GPs' data-cache line lookups in this frame */
    /* Blends (firmware/ARCHITECTURE.md "Blends"): DEMIP's ray-2 samples
     * (within samples), MIP/DEMIP rays stopped at material 1, DEMIP reading
     * B rays at an occluder, MIDA rays stopped early. */
    uint64_t ray2_samples, rays_saturated, rays_occluded, rays_terminated;
    bool ok;
} fw_frame_result_t;

typedef struct {
    machine_t m;
    bool m_ok;
    pp5_params_t params;
    fw_options_t opts;
    vr_config_t cfg;
    render_settings_t rs;
    shade_params_t shade;
    mip3d_t dims;                     /* level-0 dims and spacing only (no data): for camera_setup */
    float value_min, value_max;       /* the volume's value range (a blend's default window) */
    gaze_model_t gaze;
    double setup_s;
    uint64_t setup_ring_bytes;
    unsigned frames;
    unsigned prog_index;              /* frames of the current progressive sequence */
    fw_frame_result_t last;
    fw_gp_frame_t last_gp[VR_MAX_GPS];
    int32_t last_bands[VR_MAX_GPS + 1];
    /* Load balancing: per band unit (2^(levels-1) rows), the estimated work of
     * the current frame and the previous frame's measured cost factor. */
    int n_units;
    double *unit_weight, *unit_factor;
    /* FW_PLAN_SAMPLES: opacity per level-0 voxel length on a coarse grid
     * (cells of coarse_f^3 voxels), and GP cycles per ray / sample / pixel. */
    float *coarse_alpha;
    uint8_t *coarse_occ[8];           /* its occupancy pyramid (fw_estimate.c) */
    int coarse_nx, coarse_ny, coarse_nz, coarse_f;
    double cycles_ray, cycles_sample, cycles_skip, cycles_pixel;
    /* The coarse march's samples and skips per (band unit, column, 2D
     * level), two doubles each, kept while the view stays: a moving gaze
     * picks other levels of the same rays (host speed only: the same
     * doubles as a new march).  work_known: which entries hold one. */
    double *work_memo;
    uint8_t *work_known;
    size_t work_entries;
} fw_session_t;

pp5_status_t fw_session_init(fw_session_t *s, const render_job_t *job, const pp5_params_t *p,
                             const fw_options_t *o);
/* One frame at gaze (gx, gy) (ignored in full mode).  img (may be NULL) is
 * allocated here. */
pp5_status_t fw_session_frame(fw_session_t *s, double gx, double gy, image8_t *img,
                              fw_frame_result_t *r);
void fw_session_free(fw_session_t *s);
/* Between frames: a new view (rotation, zoom; the projection is fixed per
 * sequence) or, for a moving object, a new light direction in eye space (a
 * fixed light is shaded into the mip map at setup: PP5_E_UNSUPPORTED). */
pp5_status_t fw_session_set_view(fw_session_t *s, const view_params_t *view);
pp5_status_t fw_session_set_light(fw_session_t *s, const float light_dir[3]);

/* The replay helper's frame-cost callback shape (ctx = fw_session_t *). */
typedef struct {
    double frame_time_s;
    uint64_t rays, samples, ring_bytes;
    image8_t *image;                  /* optional: when non-NULL, filled (caller frees) */
} fw_replay_cost_t;
pp5_status_t fw_replay_frame_cost(void *ctx, double gaze_x, double gaze_y, fw_replay_cost_t *out);

#endif
