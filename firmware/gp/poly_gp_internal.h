/* poly_gp_internal.h: the polygon GP program's state, shared by its files: poly_gp.c (configuration, transform and sort, the region token) and poly_vrz.c (gaze-directed frames: the variable-resolution Z-buffer).
 *
 * A region is a 128x128 tile of one level of the screen: level 0 is the
 * image; level l (gaze-directed frames only) the level-l Z-buffer of the
 * gaze paper's §7 (seed 004), one texel per 2^l x 2^l pixels, rasterised by
 * a renderer as a smaller screen.  Full-resolution frames use the level-0
 * tiles only, all of them, row-major. */
#ifndef PP5_POLY_GP_INTERNAL_H
#define PP5_POLY_GP_INTERNAL_H

#include "common/poly_stats.h"
#include "common/vr_config.h"
#include "poly_kernels.h"

typedef struct {
    int32_t level, x, y;             /* the level and the tile's top-left texel */
} poly_region_t;

typedef struct {
    poly_config_t cfg;
    poly_tri_in_t *in;
    uint32_t n_in;
    poly_tri_t *tri;                 /* this frame's screen triangles */
    uint32_t n_tri, cap_tri;
    uint32_t *count, *start, *fill;  /* per region */
    uint32_t *list;                  /* triangle indices, region by region */
    uint32_t list_cap;
    uint32_t *phong;                 /* the Phong stream (last GP) */
    size_t phong_words;
    int regions_x, regions_y, n_regions;
    poly_region_t *reg;              /* this frame's regions, in the renderers' order */
    uint32_t frame;
    poly_spans_t sp;
    fw_stat_t stat[POLY_STAT_COUNT];
    /* Gaze-directed frames (poly_vrz.c).  Per level: texels across and down
     * (render/gaze2d.h mip2d_init's), tiles across and down, the first
     * tile's dense index; slot_of maps a dense tile to its region (-1: not
     * populated this frame). */
    int levels;
    int tw[POLY_MAX_LEVELS], th[POLY_MAX_LEVELS];
    int tiles_x[POLY_MAX_LEVELS], tiles_y[POLY_MAX_LEVELS], tile_base[POLY_MAX_LEVELS];
    int n_tiles;
    int32_t *slot_of;
    /* Resampling: this GP's image rows [y0, y1), their 2DLevels, and per
     * level the texel rows jlo..jhi it reads, as the renderers sent them
     * (R | G << 8 | B << 16 in the low 24 bits of a word). */
    int y0, y1;
    float *level;
    int jlo[POLY_MAX_LEVELS], jhi[POLY_MAX_LEVELS];
    uint32_t *texel[POLY_MAX_LEVELS];
    uint32_t expected, arrived;      /* texel boxes this frame */
    vr_config_t gaze_model;          /* only its g_* constants: vr_gaze_level's input */
    vr_level_tables_t tables;        /* level_tables: built with the band (poly_vrz_start) */
    vr_spans_t vsp;                  /* vr_kernels.h spans (2DLevel) */
} poly_state_t;

/* Charges the spans counted so far and adds their cycles to statistic id. */
void poly_charge(gp_t *gp, poly_state_t *s, int id);

/* Room in s->list for `pairs` (triangle, region) entries (a new, larger
 * list; the old entries are not kept: the sort fills it afterwards). */
fw_status_t poly_reserve_list(gp_t *gp, poly_state_t *s, uint32_t pairs);

/* poly_vrz.c */
fw_status_t poly_vrz_start(gp_t *gp, poly_state_t *s);
fw_status_t poly_vrz_plan(gp_t *gp, poly_state_t *s);
fw_status_t poly_vrz_sort(gp_t *gp, poly_state_t *s);
fw_status_t poly_vrz_store_region(gp_t *gp, poly_state_t *s, unsigned renderer, unsigned round, int k);
fw_status_t poly_vrz_take_texels(gp_t *gp, poly_state_t *s, const ring_msg_t *msg);

#endif
