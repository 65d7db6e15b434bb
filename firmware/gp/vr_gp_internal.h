/* vr_gp_internal.h: the state of the volume-rendering GP program and the functions its phases share (setup, plan, fetch, cast, resample).
 *
 * Private to firmware/gp: the host sees only common/vr_gp.h.  Everything here
 * lives in the GP's local memory (fw_alloc) and is reached only through
 * fw_api.h. */
#ifndef PP5_VR_GP_INTERNAL_H
#define PP5_VR_GP_INTERNAL_H

#include <math.h>
#include <stdbool.h>
#include <stdint.h>

#include "common/vr_config.h"
#include "common/vr_cost.h"
#include "common/vr_gp.h"
#include "common/vr_kernels.h"
#include "common/vr_shade_fixed.h"
#include "common/vr_shade_pp.h"
#include "common/vr_stats.h"
#include "fw_api.h"
#include "pp_encode.h"
#include "ring_msg.h"


/* A bit volume with rows padded to 64-bit words. */
typedef struct {
    int nx, ny, nz, wpr;
    uint64_t *w;
} bits_t;

typedef struct {
    int heights;
    bits_t occ[VR_MAX_LEVELS];
} octgrid_t;

/* The unit a GP fetches and keeps: a box of one brick.  Under image-bands a
 * unit is the whole brick; under resident it is a smaller box, so that only
 * what the rays can touch crosses the ring (firmware/ARCHITECTURE.md
 * "Blocks").  Unit dims divide the brick dims, so units tile each level on a
 * regular grid. */
typedef struct {
    int ux, uy, uz;                       /* dims in this level's voxels */
    int kx, ky, kz;                       /* units per brick along each axis */
    int ugx, ugy, ugz;                    /* units along each axis of the level */
} vr_unit_geom_t;

/* Object slabs: a needed texel of some band (its 2D level m, column i, row j,
 * and its index in that band's texel numbering), and one GP's segment colour
 * and opacity for it. */
typedef struct {
    uint32_t code;
    uint16_t i, j;
    uint8_t m;
} vr_texel_ref_t;

typedef struct {
    vr_texel_ref_t *t;
    size_t n;
} vr_texel_list_t;

typedef struct {
    uint32_t code;
    float rgba[4];
} vr_partial_t;

/* Object slabs: one band's texel rows per 2D level (any GP can compute any
 * band's from the frame parameters). */
typedef struct {
    int jlo[VR_MAX_2D_LEVELS], jhi[VR_MAX_2D_LEVELS], tw[VR_MAX_2D_LEVELS];
    uint32_t base[VR_MAX_2D_LEVELS + 1];  /* first texel code of each level; base[levels] = total */
} vr_band_geom_t;

#define VR_MAX_TILES VR_TILES_MAX        /* ray groups of a pass cast as their units arrive */

typedef struct {
    vr_config_t cfg;
    vr_level_geom_t geom[VR_MAX_LEVELS];
    int g, n_gp, n_r, stride, blocks_per_slot;
    const float *slab;                    /* host data: slices [data_z0, data_z1) */
    /* setup */
    float *strip[VR_MAX_LEVELS];          /* current strip of each local level */
    uint32_t *qa[VR_MAX_LEVELS], *qn[VR_MAX_LEVELS]; /* quantised slab of levels 1..K */
    float *upper[VR_MAX_LEVELS];          /* GP 0: levels K..top, whole */
    bits_t occ[VR_MAX_LEVELS];            /* GP 0: global occupancy */
    int levk_pending, occ_pending;
    /* shared after setup */
    uint8_t *brick_nonempty[VR_MAX_LEVELS];
    int brick_base[VR_MAX_LEVELS];        /* global brick id of a level's first brick */
    int n_bricks;
    octgrid_t grid[VR_MAX_LEVELS], exact[VR_MAX_LEVELS];
    bool have_octree;
    float alpha_lut[VR_LUT_LEVELS][VR_LUT_SIZE + 1];
    float u8_to_f[256];
    /* frame */
    vr_frame_t fr;
    int frame;
    bool exec_sent;
    bool exec_this_frame;                 /* the PPs shade this frame (requests go via drivers) */
    vr_level_tables_t level_tables;       /* 2DLevel by the paper's tables (cfg.level_tables) */
    uint32_t *pending_req;                /* requests that arrived before our EXEC */
    size_t pending_req_n, pending_req_cap;
    /* Units (see vr_unit_geom_t) and the cache of received ones. */
    vr_unit_geom_t unit[VR_MAX_LEVELS];
    int unit_base[VR_MAX_LEVELS];         /* id of a level's first unit */
    int n_units;
    uint8_t *unit_nonempty;               /* per unit: may hold opacity > 0 */
    uint32_t **cache;                     /* per unit: shaded words or NULL */
    uint32_t **cache_n;                   /* GP split: N words waiting for shading */
    uint32_t *unit_stamp;                 /* resident: 1 + the last frame that used the unit */
    uint8_t *unit_tiles;                  /* this pass: bit t = tile t needs the unit */
    uint8_t *unit_state;                  /* 0 absent, 1 requested, 2 present */
    uint64_t cache_bytes, cache_budget;   /* bytes of present units; the pass's limit */
    bool cache_valid_view;                /* cache_consts are those of the cached units */
    vr_shade_consts_t cache_consts;       /* the shading the cached units were shaded with */
    int bricks_pending;                   /* reads of this pass still to arrive */
    int tiles, tile;                      /* tiles of this pass; the next to cast */
    int tile_y0[VR_MAX_TILES + 1];        /* pixel rows of each tile */
    int tile_pending[VR_MAX_TILES];       /* units each tile still waits for */
    bool blocked;                         /* waiting for a tile's units since t_blocked */
    uint64_t t_blocked;
    /* Object slabs (vr_slabs.c). */
    long zslab_lo, zslab_hi;              /* the level-0 slices this GP casts through */
    vr_texel_list_t band_need[VR_MAX_GPS];   /* each band's needed texels, as they arrive */
    bool need_in[VR_MAX_GPS], band_cast[VR_MAX_GPS];
    int needs_pending, bands_cast, bands_with_rows;
    bool slab_cast_over;
    vr_partial_t *partials[VR_MAX_GPS];   /* partials for our band, by the GP that cast them */
    size_t n_partials[VR_MAX_GPS];
    int partials_pending;
    int slab_frame;                       /* 1 + the frame whose slab state is set up */
    uint8_t *deferred;                    /* NEED/PARTIAL messages that came before our frame */
    size_t deferred_bytes;
    bool cast_done, boundary_ok;
    int levels2d, maxm;
    int y0, y1;                           /* own pixel rows */
    int ly0, ly1;                         /* pixel rows with a computed level */
    float *level;                         /* per pixel in [ly0, ly1) */
    int jlo[VR_MAX_2D_LEVELS], jhi[VR_MAX_2D_LEVELS]; /* own texel rows [jlo, jhi] */
    int tw[VR_MAX_2D_LEVELS], th[VR_MAX_2D_LEVELS];
    float *texel[VR_MAX_2D_LEVELS];       /* rows jlo..jhi+1 (+1: the next GP's first row) */
    uint8_t *need[VR_MAX_2D_LEVELS];
    uint8_t *castf[VR_MAX_2D_LEVELS];     /* the paper's flag F: texel's ray cast (kept when progressive) */
    int pass, n_passes;                   /* passes = column ranges x depth segments (memory) */
    int n_cols, n_segs;                   /* pass q: columns q / n_segs, depth segment q % n_segs */
    float seg_t0, seg_len;                /* depth (ray parameter t) covered by the segments */
    /* Per own texel: a ray resumed segment by segment (0 new, 1 started, 2 done). */
    uint8_t *ray_state[VR_MAX_2D_LEVELS];
    float *ray_a[VR_MAX_2D_LEVELS], *ray_t[VR_MAX_2D_LEVELS];
    int32_t *ray_k[VR_MAX_2D_LEVELS];
    int tables_pending;                   /* brick tables still to come from GP 0 */
    uint64_t t_pass_req;                  /* when this pass's requests were out */
    vr_shade_consts_t shade_consts;
    fw_stat_t stat[VR_STAT_COUNT];        /* handles of the published statistics */
    uint64_t t_data_done;                 /* when this pass's bricks were all in */
    bool frame_done;                      /* sections of this frame sent */
} vr_state_t;

static inline size_t vr_bits_words(int nx, int ny, int nz)
{
    return (size_t)((nx + 63) / 64) * (size_t)ny * (size_t)nz;
}

static inline bool vr_bits_get(const bits_t *b, int x, int y, int z)
{
    return (b->w[((size_t)z * b->ny + y) * b->wpr + (x >> 6)] >> (x & 63)) & 1u;
}

static inline void vr_bits_set(bits_t *b, int x, int y, int z)
{
    b->w[((size_t)z * b->ny + y) * b->wpr + (x >> 6)] |= 1ull << (x & 63);
}

static inline fw_status_t vr_send_gp(gp_t *gp, unsigned dst, uint32_t sub, uint32_t a1, uint32_t a2,
                           const void *payload, size_t bytes)
{
    uint32_t args[RING_MSG_ARGS] = {sub, a1, a2, 0, 0, 0};
    return fw_send(gp, ring_addr(RING_NODE_GP, dst), RING_MSG_GP_USER, args, payload, bytes);
}

/* Publish (fw_api statistics; common/vr_stats.h names them). */
static inline void vr_stat_add(gp_t *gp, const vr_state_t *s, int id, uint64_t n)
{
    fw_stat_add(gp, s->stat[id], n);
}

static inline void vr_stat_set(gp_t *gp, const vr_state_t *s, int id, uint64_t v)
{
    fw_stat_set(gp, s->stat[id], v);
}

/* Divisions that keep their units across frames (resident, object slabs). */
static inline bool vr_keeps_units(const vr_state_t *s)
{
    return s->cfg.division != VR_DIVISION_IMAGE_BANDS;
}

static inline bool vr_uses_exec(const vr_state_t *s)
{
    return s->cfg.lighting != VR_LIGHT_DIFFUSE && s->cfg.split == VR_SPLIT_PP;
}

/* MIP, DEMIP or MIDA on the value pyramid (one float per voxel), not
 * compositing the mip map (firmware/ARCHITECTURE.md "Blends"). */
static inline bool vr_is_blend(const vr_state_t *s)
{
    return s->cfg.blend != VR_BLEND_COMPOSITE;
}

/* vr_octree.c */
bool vr_bits_alloc(gp_t *gp, bits_t *b, int nx, int ny, int nz);
bool vr_grid_build(gp_t *gp, octgrid_t *g, const bits_t *occ, int lo, int hi, fw_ops_t *ops);

/* vr_setup.c */
fw_status_t vr_setup_start(gp_t *gp);
fw_status_t vr_setup_on_slab(gp_t *gp, vr_state_t *s, const ring_msg_t *m);
fw_status_t vr_setup_on_levelk(gp_t *gp, vr_state_t *s, const ring_msg_t *m);
fw_status_t vr_setup_on_occ(gp_t *gp, vr_state_t *s, const ring_msg_t *m);

/* vr_units.c */
fw_status_t vr_units_init(gp_t *gp, vr_state_t *s);
void vr_unit_locate(const vr_state_t *s, int id, int *level, int ijk[3]);
size_t vr_unit_bytes(const vr_state_t *s, int id);
int vr_unit_reads(const vr_state_t *s);
unsigned vr_unit_renderer(const vr_state_t *s, int id);
fw_status_t vr_unit_send_read(gp_t *gp, vr_state_t *s, int id, unsigned requester);
void vr_units_drop_all(gp_t *gp, vr_state_t *s);
fw_status_t vr_units_request(gp_t *gp, vr_state_t *s, int id);

/* vr_footprint.c */
fw_status_t vr_footprint_bricks(gp_t *gp, vr_state_t *s, uint32_t *want, size_t *n_out);
fw_status_t vr_footprint_units(gp_t *gp, vr_state_t *s, uint32_t *want, size_t *n_out,
                               uint64_t *bytes_out);

/* vr_plan.c */
fw_status_t vr_plan_frame_start(gp_t *gp, vr_state_t *s, uint32_t frame);
void vr_plan_seg_range(const vr_state_t *s, int q, float *t0, float *t1);
void vr_plan_pass_range(const vr_state_t *s, int q, float *x0, float *x1);

/* vr_fetch.c */
void vr_frame_free(gp_t *gp, vr_state_t *s, bool keep_view);
fw_status_t vr_fetch_forward(gp_t *gp, vr_state_t *s, const uint32_t *ids, size_t n,
                             unsigned requester);
fw_status_t vr_fetch_send_exec(gp_t *gp, vr_state_t *s);
fw_status_t vr_fetch_request_pass(gp_t *gp, vr_state_t *s);
fw_status_t vr_fetch_cast_ready(gp_t *gp, vr_state_t *s);
fw_status_t vr_fetch_send_requests(gp_t *gp, vr_state_t *s, const uint32_t *ids, size_t n);
fw_status_t vr_fetch_on_data(gp_t *gp, vr_state_t *s, const ring_msg_t *m);

/* vr_cast.c */
void vr_cast_texels(gp_t *gp, vr_state_t *s, int py0, int py1);
/* Object slabs: the segments of the listed texels' rays through slices
 * [zlo, zhi); their colours and opacities, where not empty, into out. */
size_t vr_cast_slab_segments(gp_t *gp, vr_state_t *s, const vr_texel_list_t *tl, long zlo,
                             long zhi, vr_partial_t *out);
fw_status_t vr_cast_send_boundary(gp_t *gp, vr_state_t *s);

/* vr_slabs.c */
fw_status_t vr_slabs_frame(gp_t *gp, vr_state_t *s);
fw_status_t vr_slabs_progress(gp_t *gp, vr_state_t *s);
fw_status_t vr_slabs_on_need(gp_t *gp, vr_state_t *s, const ring_msg_t *m);
fw_status_t vr_slabs_on_partial(gp_t *gp, vr_state_t *s, const ring_msg_t *m);
void vr_slabs_free(gp_t *gp, vr_state_t *s);
/* A NEED or PARTIAL for a frame we have not started yet: kept until we do. */
fw_status_t vr_slabs_defer(gp_t *gp, vr_state_t *s, const ring_msg_t *m);
static inline bool vr_slabs_early(const vr_state_t *s, const ring_msg_t *m)
{
    return (int)m->args[2] + 1 != s->slab_frame;
}

/* vr_resample.c */
fw_status_t vr_resample_if_ready(gp_t *gp, vr_state_t *s);
fw_status_t vr_resample_on_boundary(gp_t *gp, vr_state_t *s, const ring_msg_t *m);

#endif
