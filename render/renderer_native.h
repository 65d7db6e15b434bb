/* renderer_native.h: the native frame API of the gaze-directed volume
 * renderer (Levoy & Whitaker 1990): settings in, image + counts + timings out.
 *
 * Pipeline (ARCHITECTURE.md): native_renderer_init builds the 3D mip map
 * (mip3d.h) and the skipping octree (octree.h) once per volume/transfer
 * function/lighting; native_renderer_frame then, per frame,
 *   1. computes 2DLevel for every pixel (gaze2d.h; 0 everywhere in full mode),
 *   2. marks the 2D mip-map texels those levels need and casts each unflagged
 *      one once (raycast.h), in parallel over texel rows,
 *   3. reconstructs every pixel by RenderPixel (bilinear + linear), in
 *      parallel over image rows.
 * Every ray and pixel writes only its own outputs and counters are per-thread
 * integers, so the image and counts are identical for any thread count. */
#ifndef PP5_RENDERER_NATIVE_H
#define PP5_RENDERER_NATIVE_H

#include <stdbool.h>
#include <stdint.h>
#include "blend.h"
#include "classify.h"
#include "gaze2d.h"
#include "mip3d.h"
#include "octree.h"
#include "png_io.h"
#include "raycast.h"
#include "blend_bricks.h"
#include "scalar_pyramid.h"
#include "shade.h"
#include "volume.h"

typedef enum { RENDER_MODE_FULL, RENDER_MODE_GAZE } render_mode_t;

typedef struct {
    int width, height;
    render_mode_t mode;
    double gaze_x, gaze_y;        /* pixel coordinates of the fixated pixel centre */
    view_params_t view;
    gaze_display_t display;
    int threads;                  /* 0 = all online CPUs */
    /* Progressive refinement (paper §7): keep the 2D mip map while the view is
     * unchanged; each further frame the sweet-spot radius grows by
     * `progressive_growth` and every pixel keeps the finest level it has had. */
    bool progressive;
    double progressive_growth;
    /* 2DLevel by the paper's lookup tables (gaze2d.h) instead of exactly: how
     * the machine computes it by default, for like-for-like comparisons. */
    bool level_tables;
    /* What each ray does with its samples (blend.h); compositing by default.
     * MIP, DEMIP and MIDA need native_renderer_build_scalar first. */
    blend_settings_t blend;
    /* How the 3D mip map is stored (mip3d.h; F32 by default): read when the
     * renderer is built (native_renderer_init_format), not per frame. */
    mip3d_format_t voxel_format;
} render_settings_t;

void render_settings_defaults(render_settings_t *s);
const char *render_mode_name(render_mode_t m);

typedef struct {
    uint64_t rays, samples, samples_skipped;
    uint64_t samples_retraced;    /* MIP/DEMIP only: see raycast_counts_t */
    double ms_levels, ms_cast, ms_reconstruct, ms_total;
    int frame_index;              /* 0 for the first frame of a view */
    bool full_resolution_everywhere; /* every pixel at 2D level 0 */
} render_stats_t;

typedef struct {
    classify_tf_t tf;
    shade_params_t shade;
    mip3d_t mip;
    octree_t octree;
    double ms_build_mip, ms_build_octree;
    int threads;
    /* The value pyramid MIP, DEMIP and MIDA rays sample (scalar_pyramid.h). */
    scalar_pyramid_t scalar;
    bool have_scalar;
    double ms_build_scalar;
    /* Per-view state kept between progressive frames. */
    mip2d_t mip2d;
    float *level_best;            /* per pixel: finest 2DLevel so far */
    float *level_now;
    int frame_index;
    bool have_view;
    render_settings_t last;       /* view of the previous frame */
    gaze_model_t gaze;
    gaze_level_tables_t tables;   /* built for the image size when level_tables is set */
    gaze_display_t tables_display;   /* the display they were built for */
    /* MIP and DEMIP in brick order: each 2D level's bins, rebuilt every
     * frame in memory kept from the last (blend_bricks.h). */
    blend_bins_t bins[MIP2D_MAX_LEVELS];
} native_renderer_t;

/* Builds the 3D mip map and octree (the per-volume preprocessing). */
pp5_status_t native_renderer_init(native_renderer_t *r, const volume_t *v, const classify_tf_t *tf,
                           const shade_params_t *shade, int threads);
/* The same with the mip map in a reduced-precision format (mip3d.h: U16,
 * U8; F32 is native_renderer_init). */
pp5_status_t native_renderer_init_format(native_renderer_t *r, const volume_t *v,
                                         const classify_tf_t *tf, const shade_params_t *shade,
                                         mip3d_format_t format, int threads);
void native_renderer_free(native_renderer_t *r);
/* Builds (or rebuilds) the value pyramid of `v` for --blend mip|demip|mida:
 * per volume, independent of the transfer function and the window. */
pp5_status_t native_renderer_build_scalar(native_renderer_t *r, const volume_t *v,
                                          scalar_pyramid_kind_t kind);
/* Renders one frame into `out` (allocated here, RGB). */
pp5_status_t native_renderer_frame(native_renderer_t *r, const render_settings_t *s, image8_t *out,
                            render_stats_t *stats);
/* The 2D level each pixel was reconstructed at in the last frame (W*H). */
const float *native_renderer_levels(const native_renderer_t *r);

/* 8-bit conversion used for every output: round(clamp(v, 0, 1) * 255). */
static inline uint8_t render_to_u8(float v)
{
    if (!(v > 0.0f))
        return 0;
    if (v >= 1.0f)
        return 255;
    return (uint8_t)(v * 255.0f + 0.5f);
}

#endif
