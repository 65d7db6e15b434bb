/* vr_config.h: what the host hands the volume-rendering GP program (per sequence and per frame), and the brick layout both sides compute.
 *
 * Shared by firmware/gp (runs on the GPs) and firmware/host (the workstation),
 * so it may include only standard headers and emu/api.  Layout and message
 * sequence are described in firmware/ARCHITECTURE.md. */
#ifndef PP5_VR_CONFIG_H
#define PP5_VR_CONFIG_H

#include <stdint.h>

#define VR_MAGIC 0x56523031u           /* "VR01" */
#define VR_MAX_LEVELS 16
#define VR_MAX_CONTOURS 4
#define VR_MAX_GPS 64
#define VR_MAX_2D_LEVELS 8
#define VR_BRICK_VOXELS 16384u         /* one backing-store block of every PP of a renderer */
#define VR_LUT_LEVELS 8
#define VR_LUT_SIZE 1024

enum { VR_LIGHT_DIFFUSE = 0, VR_LIGHT_SPECULAR = 1, VR_LIGHT_MOVING = 2 };
enum { VR_SPLIT_PP = 0, VR_SPLIT_GP = 1 };   /* where viewpoint-dependent shading runs */
enum { VR_MODE_FULL = 0, VR_MODE_GAZE = 1 };
/* The work divisions (firmware/ARCHITECTURE.md "Work divisions"). */
enum { VR_DIVISION_IMAGE_BANDS = 0, VR_DIVISION_RESIDENT = 1, VR_DIVISION_OBJECT_SLABS = 2 };
/* What a ray does with its samples (render/blend.h; firmware/ARCHITECTURE.md
 * "Blends"): compositing the mip map, or MIP, DEMIP and MIDA on the value
 * pyramid. */
enum { VR_BLEND_COMPOSITE = 0, VR_BLEND_MIP = 1, VR_BLEND_DEMIP = 2, VR_BLEND_MIDA = 3 };
enum { VR_PYRAMID_MAX = 0, VR_PYRAMID_BOX = 1 };          /* how levels 1.. reduce values */
enum { VR_DEPTH_EXACT = 0, VR_DEPTH_ENTRY_PLUS_LENGTH = 1 }; /* DEMIP's depth (§3.2) */
enum { VR_READING_A = 0, VR_READING_B = 1 };                /* where eq. (1) applies */
#define VR_TILES_MAX 8                 /* ray groups per pass (resident) */

/* GP_USER sub-kinds (args[0]). */
enum {
    VR_MSG_FRAME_PARAMS = 1,   /* host -> GP: vr_frame_t payload */
    VR_MSG_LEVELK,             /* GP -> GP 0: level-K slab components (floats) */
    VR_MSG_OCC,                /* GP -> all: occupancy bits of a level's slab part */
    VR_MSG_REQUEST,            /* GP -> driver GP: bricks wanted (uint32 brick ids) */
    VR_MSG_BOUNDARY,           /* GP g -> GP g-1: texel colours of g's first texel rows */
    VR_MSG_SETUP_DONE,         /* GP -> host: bricks written (setup barrier) */
    VR_MSG_SLAB,               /* host -> GP: the slab's volume slices (floats) */
    VR_MSG_NEED,               /* object slabs: band owner -> all GPs: its needed texels (bits) */
    VR_MSG_PARTIAL             /* object slabs: GP -> band owner: segment colours of its texels */
};

typedef struct {
    float value, opacity, width_vox, rgb[3];
} vr_contour_t;

/* Per sequence: the HOST_LOAD data block (the slab follows as VR_MSG_SLAB). */
typedef struct {
    uint32_t magic;
    int32_t nx, ny, nz;                 /* volume dims */
    float spacing[3], inv_spacing[3];   /* object units per voxel and inverse (mip3d.h) */
    int32_t levels;                     /* 3D mip levels (to 1x1x1) */
    int32_t slab_t, slab_k;             /* level-0 slab thickness; levels built locally */
    int32_t n_slab_gps;
    int32_t data_z0, data_z1;           /* slices in the data block [z0, z1) */
    int32_t lighting, split;
    int32_t tf_count;
    vr_contour_t tf[VR_MAX_CONTOURS];
    float ambient, diffuse, specular, specular_exponent, light_dir[3];
    int32_t two_sided;
    /* Image and 2D mip map */
    int32_t width, height, levels2d;    /* levels2d = gaze max level + 1 (1 in full mode) */
    int32_t band_y0[VR_MAX_GPS + 1];    /* GP g owns pixel rows [band_y0[g], band_y0[g+1]) */
    float sample_step, early_termination;
    int32_t use_octree;
    int32_t perspective;                /* projection of the sequence (selects the octree grids) */
    int32_t max_pass_bricks;            /* cap on bricks per pass (0: local memory decides) */
    int32_t level_tables;               /* 2DLevel by the paper's tables (vr_kernels.h), else exact */
    int32_t division;                   /* VR_DIVISION_*: how the frame's work is divided */
    int32_t unit_edge;                  /* resident: largest unit edge in voxels (0: whole bricks) */
    int32_t tiles;                      /* resident: ray groups per pass cast as their units arrive */
    /* Gaze model constants (render/gaze2d.h gaze_model_t), from the host. */
    double g_inches_per_px, g_view_distance_in, g_e_full_deg, g_e_edge_deg, g_sigma_deg,
        g_rho_min, g_r_zero_px, g_r_max_px;
    int32_t g_max_level;
    int32_t fb_x0, fb_y0;               /* where the image lands in the frame buffer */
    /* Blends (VR_BLEND_*): the settings of render/blend_ray.h's blend_frame_t
     * that hold for the sequence, computed by the host with render/'s own
     * code so that both sides use the same floats. */
    int32_t blend, pyramid, reading, depth;
    float window_lo, window_inv_width;  /* material = clamp((v - lo) inv_width, 0, 1) */
    float eps, dw, sw;                  /* DEMIP's tolerance, depth and sphere weights */
    float sphere_pole[3], sphere_front[3], sphere_back[3];
    /* A voxel whose value is <= cold_below gives material 0 to every sample
     * whose corners are all such voxels (the margin below window_lo covers
     * the trilinear rounding); -inf when nothing may be skipped.  The octree
     * grids of a blend mark the other voxels (firmware/ARCHITECTURE.md). */
    float cold_below;
} vr_config_t;

/* Per frame: the view (camera basis computed by the host from the user's
 * rotation, raycast.h camera_t), the gaze point and the mode. */
typedef struct {
    int32_t frame, mode, projection;
    int32_t progressive_keep;           /* bit 0: keep the 2D mip map after; bit 1: reuse the kept one */
    double gaze_x, gaze_y, gaze_scale;
    float right[3], down[3], forward[3], centre[3], eye[3], box_hi[3];
    float pixel_size, eye_distance, radius;
    float light_dir[3];                 /* this frame's light: object space (fixed light) or
                                           eye space (moving object), as shade_params_t */
    /* GP g casts the rays of and resamples pixel rows [band_y0[g], band_y0[g+1]);
     * the host balances the bands for the gaze point (firmware/ARCHITECTURE.md). */
    int32_t band_y0[VR_MAX_GPS + 1];
    /* Object slabs: GP g casts the ray segments whose samples lie in level-0
     * slices [slab_z0[g], slab_z0[g+1]) (firmware/ARCHITECTURE.md). */
    int32_t slab_z0[VR_MAX_GPS + 1];
    /* DEMIP's depth normalisation for this view (blend_frame_t): exact depth
     * (distance, or view-axis depth under parallel projection) and the
     * view-axis depth, nearest bounding-box corner 0, farthest 1. */
    float exact_near, exact_inv_range, axis_near, axis_inv_range;
} vr_frame_t;

/* Level dims, brick dims and brick grid, computed identically on host and GPs. */
typedef struct {
    int nx, ny, nz;
    int bx, by, bz;                     /* brick dims in this level's voxels */
    int gx, gy, gz;                     /* bricks per axis */
    int slab_t;                         /* slab thickness at this level (0: GP 0 owns it all) */
} vr_level_geom_t;

static inline int vr_lowbit(int v) { return v & -v; }

/* Fills geom[0..levels) for the config; returns levels. */
static inline int vr_geometry(const vr_config_t *c, vr_level_geom_t *geom)
{
    int nx = c->nx, ny = c->ny, nz = c->nz;
    for (int n = 0; n < c->levels; n++) {
        vr_level_geom_t *g = &geom[n];
        g->nx = nx;
        g->ny = ny;
        g->nz = nz;
        g->slab_t = n <= c->slab_k ? (c->slab_t >> n) : 0;
        int bz = g->slab_t ? vr_lowbit(g->slab_t) : nz;
        if (bz > 8)
            bz = 8;
        if (bz > nz)
            bz = nz;
        int bx = nx < 64 ? nx : 64;
        int by = (int)(VR_BRICK_VOXELS / (unsigned)(bx * bz));
        /* Level 0 is built in strips of 2^slab_k rows, so that each strip
         * holds whole rows of every level up to slab_k; a brick row must
         * be a whole number of strips (vr_setup.c build_slab).  A brick
         * narrower than 64 voxels would otherwise get a height like 42. */
        if (n == 0)
            by &= ~((1 << c->slab_k) - 1);
        if (by > ny)
            by = ny;
        g->bx = bx;
        g->by = by;
        g->bz = bz;
        g->gx = (nx + bx - 1) / bx;
        g->gy = (ny + by - 1) / by;
        g->gz = (nz + bz - 1) / bz;
        nx = (nx + 1) / 2;
        ny = (ny + 1) / 2;
        nz = (nz + 1) / 2;
    }
    return c->levels;
}

/* Which GP builds (owns) the level-n voxels of slice z. */
static inline int vr_slab_owner(const vr_config_t *c, const vr_level_geom_t *g, int z)
{
    return g->slab_t ? z / g->slab_t : 0;
}

#endif
