/* fw_session.h: the host workstation's API to the gaze-directed volume renderer on the emulated machine: load once, then one call per frame.
 *
 * fw_session_init loads the volume slabs and the program onto the GPs and runs
 * the per-sequence setup (the GPs build the 3D mip map and write it into the
 * renderers' backing store); fw_session_frame runs one frame for a gaze point
 * and returns the image, the emulated frame time with its breakdown, rays,
 * samples and ring bytes.  A sequence of frames reuses the setup.
 * fw_replay_frame_cost has the shape of the gaze replay's
 * replay_frame_cost_fn, so the replay can drive the machine directly. */
#ifndef PP5_FW_SESSION_H
#define PP5_FW_SESSION_H

#include <stdbool.h>
#include <stdint.h>
#include "firmware/common/vr_config.h"
#include "machine.h"
#include "render/renderer_native.h"

typedef enum {
    FW_PHASE_HOST_START = 0,   /* host -> GP frame parameters and FRAME_START */
    FW_PHASE_GP_PREP,          /* 2DLevel, texel marking, footprint, PP stream build */
    FW_PHASE_PP_SHADE,         /* waiting while the renderers shade (viewpoint-dependent) */
    FW_PHASE_RING_FETCH,       /* waiting for shaded bricks over the ring (data class) */
    FW_PHASE_GP_RECEIVE,       /* unpacking bricks, forwarding requests, GP-side shading */
    FW_PHASE_GP_CAST,          /* gaze-directed ray casting into the 2D mip map */
    FW_PHASE_GP_EXCHANGE,      /* waiting for the neighbour's boundary texel rows */
    FW_PHASE_GP_RESAMPLE,      /* RenderPixel at display resolution + sections sent */
    FW_PHASE_FB_TRANSFER,      /* last sections in flight to the frame buffer */
    FW_PHASE_COUNT
} fw_phase_t;

const char *fw_phase_name(fw_phase_t p);
/* Short column/JSON key of a phase ("gp_cast_s", ...). */
const char *fw_phase_key(fw_phase_t p);

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
    double ring_util[RING_CLASS_COUNT];   /* class bytes / (aggregate bandwidth x frame time) */
    double ring_util_total;
    double gp_util_mean, gp_util_max, rn_util_mean, rn_util_max;
    uint64_t rn_exec_cycles_max;
    bool ok;
} fw_frame_result_t;

typedef struct {
    int split;                        /* VR_SPLIT_PP (paper) or VR_SPLIT_GP */
    int max_pass_bricks;              /* cap bricks per pass below the memory limit (0: off) */
    bool timeline;
} fw_options_t;

typedef struct {
    machine_t m;
    bool m_ok;
    pp5_params_t params;
    vr_config_t cfg;
    render_settings_t rs;
    shade_params_t shade;
    mip3d_t dims;                     /* level-0 dims and spacing only (no data): for camera_setup */
    gaze_model_t gaze;
    double setup_s;
    uint64_t setup_ring_bytes;
    unsigned frames;
    unsigned prog_index;              /* frames of the current progressive sequence */
    fw_frame_result_t last;
    int32_t last_bands[VR_MAX_GPS + 1];
    /* Load balancing: per band unit (2^(levels-1) rows), the estimated work of
     * the current frame and the previous frame's measured cost factor. */
    int n_units;
    double *unit_weight, *unit_factor;
} fw_session_t;

void fw_options_default(fw_options_t *o);
pp5_status_t fw_session_init(fw_session_t *s, const volume_t *v, const classify_tf_t *tf,
                             const shade_params_t *shade, const render_settings_t *rs,
                             const pp5_params_t *p, const fw_options_t *o);
/* One frame at gaze (gx, gy) (ignored in full mode).  img (may be NULL) is
 * allocated here. */
pp5_status_t fw_session_frame(fw_session_t *s, double gx, double gy, image8_t *img,
                              fw_frame_result_t *r);
void fw_session_free(fw_session_t *s);

/* The replay helper's frame-cost callback shape (ctx = fw_session_t *). */
typedef struct {
    double frame_time_s;
    uint64_t rays, samples, ring_bytes;
    image8_t *image;                  /* optional: when non-NULL, filled (caller frees) */
} fw_replay_cost_t;
pp5_status_t fw_replay_frame_cost(void *ctx, double gaze_x, double gaze_y, fw_replay_cost_t *out);

/* Like-for-like native reference: the native renderer on a 3D mip map whose
 * viewpoint-dependent shading was applied per voxel (as the PPs do) for the
 * view in rs; quantised = true reproduces the machine's fixed-point formats
 * exactly, false keeps floats.  For the diffuse case it only quantises. */
pp5_status_t fw_reference_init(native_renderer_t *nr, const volume_t *v, const classify_tf_t *tf,
                               const shade_params_t *shade, const render_settings_t *rs,
                               bool quantised);

/* Image rows of GP g's band for an image of height h on n_gp GPs. */
void fw_bands(int height, int n_gp, int levels2d, int32_t *band_y0);
/* Bands of equal estimated work (acuity model on a subsampled grid, times
 * unit_factor when given: the previous frame's measured cost per unit of
 * estimate); unit_weight (may be NULL) receives the unweighted estimate. */
void fw_bands_balanced(const gaze_model_t *gm, bool gaze, double gx, double gy, int width,
                       int height, int n_gp, int levels2d, const double *unit_factor,
                       double *unit_weight, int32_t *band_y0);

#endif
