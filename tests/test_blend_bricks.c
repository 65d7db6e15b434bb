/* test_blend_bricks.c: MIP and DEMIP in brick order (render/blend_bricks.h)
 * against the reference tracer (every sample position), ray by ray and bit
 * for bit, with the counts' identity; and the pyramid's brick order.
 * Expectations are never stored: both paths run here. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "render/blend_bricks.h"
#include "render/renderer_native.h"
#include "render/scene.h"

typedef struct {
    const char *name;
    blend_mode_t mode;
    demip_reading_t reading;
    float eps, zoom;
    float rot_x, rot_y, rot_z;
    int levels, side;
} brick_case_t;

typedef struct {
    uint64_t rays, diff, lit, windows;
    raycast_counts_t tile, ref;
} brick_result_t;

typedef struct {
    scalar_pyramid_t scalar;
    mip3d_t mip;                  /* the header camera_setup reads */
} pyramid_t;

static void pyramid_build(const volume_t *v, pyramid_t *p)
{
    memset(p, 0, sizeof *p);
    REQUIRE(scalar_pyramid_build(&p->scalar, v, SCALAR_PYRAMID_MAX, 2) == PP5_OK);
    p->mip.levels = 1;
    p->mip.level[0].nx = v->nx;
    p->mip.level[0].ny = v->ny;
    p->mip.level[0].nz = v->nz;
    mip3d_voxel_spacing(v, p->mip.spacing, p->mip.inv_spacing);
}

/* Every texel of one tile, brick order against the reference. */
static void trace_tile(const blend_ctx_t *c, const blend_bins_t *b, int tile, brick_result_t *res)
{
    int ti[BLEND_TILE * BLEND_TILE] = {0}, tj[BLEND_TILE * BLEND_TILE] = {0}, n = 0;
    int x0 = tile % b->tiles_x * BLEND_TILE, y0 = tile / b->tiles_x * BLEND_TILE;
    for (int j = y0; j < y0 + BLEND_TILE && j < b->tex_h; j++)
        for (int i = x0; i < x0 + BLEND_TILE && i < b->tex_w; i++) {
            ti[n] = i;
            tj[n++] = j;
        }
    static float rgb[BLEND_TILE * BLEND_TILE][3];
    REQUIRE(blend_trace_tile(c, b, tile, n, ti, tj, rgb, &res->tile) == PP5_OK);
    for (int k = 0; k < n; k++) {
        float px, py;
        mip2d_texel_point(b->level2d, ti[k], tj[k], &px, &py);
        blend_ray_info_t info;
        blend_trace_reference_info(c, px, py, b->level2d, &info);
        res->ref.rays++;
        res->ref.samples += info.samples;
        res->rays++;
        res->diff += memcmp(rgb[k], info.rgb, sizeof info.rgb) != 0;
        res->lit += info.rgb[0] + info.rgb[1] + info.rgb[2] > 0.0f;
        /* What brick order accounts for (blend_bricks.h): the window, and
         * for DEMIP ray 2's positions up to its stop. */
        if (info.hit_box && info.geom.positions > 0) {
            res->windows += (uint64_t)info.geom.positions;
            if (c->frame.mode == BLEND_DEMIP && info.k_max >= 0)
                res->windows += (uint64_t)info.k_stop + 1;
        }
    }
}

static void trace_case(const pyramid_t *p, const brick_case_t *bc, const float *window,
                       brick_result_t *res)
{
    memset(res, 0, sizeof *res);
    view_params_t vp;
    view_defaults(&vp);
    vp.rot_x_deg = bc->rot_x;
    vp.rot_y_deg = bc->rot_y;
    vp.rot_z_deg = bc->rot_z;
    vp.zoom = bc->zoom;
    blend_settings_t b;
    blend_settings_defaults(&b);
    b.mode = bc->mode;
    b.reading = bc->reading;
    b.tolerance = bc->eps;
    b.sphere_weight = 0.3f;
    if (window) {
        b.window_centre = window[0];
        b.window_width = window[1];
    }
    camera_t cam;
    camera_setup(&cam, &vp, &p->mip, bc->side, bc->side);
    blend_ctx_t c;
    blend_ctx_init(&c, &p->scalar, &cam, &vp, &b);
    REQUIRE(blend_bricks_apply(&c));
    blend_bins_t bins;
    memset(&bins, 0, sizeof bins);
    for (int l = 0; l < bc->levels; l++) {
        int n = (bc->side >> l) + 1;
        /* The bins of the level before are reused: stale memory must not
         * leak into this level's.  Two threads: the bricks are described
         * in chunks on both. */
        REQUIRE(blend_bins_build(&bins, &c, l, n, n, NULL, 2) == PP5_OK);
        for (int t = 0; t < bins.tiles_x * bins.tiles_y; t++)
            trace_tile(&c, &bins, t, res);
    }
    /* Level 0 with one tile active, as a gaze-directed frame's sweet spot:
     * the bricks are culled against that tile alone. */
    int n = bc->side + 1, tiles_x = (n + BLEND_TILE - 1) / BLEND_TILE;
    uint8_t active[64 * 64] = {0};
    REQUIRE(tiles_x <= 64);
    int centre = (tiles_x / 2) * tiles_x + tiles_x / 2;
    active[centre] = 1;
    REQUIRE(blend_bins_build(&bins, &c, 0, n, n, active, 2) == PP5_OK);
    trace_tile(&c, &bins, centre, res);
    blend_bins_free(&bins);
}

static void check_cases(const pyramid_t *p, const brick_case_t *cases, int n, const float *window)
{
    for (int i = 0; i < n; i++) {
        brick_result_t res;
        trace_case(p, &cases[i], window, &res);
        const raycast_counts_t *f = &res.tile;
        CHECK_MSG(res.diff == 0, "%s: %llu of %llu rays differ from the reference",
                  cases[i].name, (unsigned long long)res.diff, (unsigned long long)res.rays);
        CHECK_MSG(f->rays == res.rays, "%s: %llu rays counted for %llu", cases[i].name,
                  (unsigned long long)f->rays, (unsigned long long)res.rays);
        if (cases[i].reading == DEMIP_READING_A)
            CHECK_MSG(f->samples + f->samples_skipped == res.windows,
                      "%s: drawn %llu + skipped %llu != positions %llu", cases[i].name,
                      (unsigned long long)f->samples, (unsigned long long)f->samples_skipped,
                      (unsigned long long)res.windows);
        CHECK_MSG(f->samples < res.ref.samples, "%s: brick order drew %llu, the reference %llu",
                  cases[i].name, (unsigned long long)f->samples,
                  (unsigned long long)res.ref.samples);
        CHECK_EQ(f->samples_retraced, 0);
        CHECK_MSG(res.lit > res.rays / 20, "%s: only %llu of %llu rays lit", cases[i].name,
                  (unsigned long long)res.lit, (unsigned long long)res.rays);
    }
}

static const brick_case_t phantom_cases[] = {
    {"mip front", BLEND_MIP, DEMIP_READING_A, 0.1f, 1.0f, 0, 0, 0, 3, 64},
    {"mip oblique", BLEND_MIP, DEMIP_READING_A, 0.1f, 1.0f, 23, 37, 11, 3, 64},
    {"mip zoomed", BLEND_MIP, DEMIP_READING_A, 0.1f, 2.7f, -17, 61, 4, 2, 96},
    {"mip axis-aligned side", BLEND_MIP, DEMIP_READING_A, 0.1f, 1.0f, 0, 90, 0, 3, 64},
    {"demip A oblique", BLEND_DEMIP, DEMIP_READING_A, 0.1f, 1.0f, -31, 142, 5, 3, 64},
    {"demip A eps 0.4", BLEND_DEMIP, DEMIP_READING_A, 0.4f, 1.3f, 90, 0, 0, 3, 64},
    {"demip B eps 0", BLEND_DEMIP, DEMIP_READING_B, 0.0f, 1.0f, 71, -12, 40, 3, 64},
};

TEST(blend_bricks_match_reference_shepp_logan)
{
    volume_t v;
    pyramid_t p;
    REQUIRE(phantom_make("shepp-logan", 61, 54, 37, &v) == PP5_OK);
    pyramid_build(&v, &p);
    check_cases(&p, phantom_cases, (int)(sizeof phantom_cases / sizeof phantom_cases[0]), NULL);
    /* A window that saturates the skull: many rays reach m = 1, so ties
     * at the maximum decide k_max (and DEMIP's depth). */
    const float window[2] = {120.0f, 120.0f};
    check_cases(&p, phantom_cases, (int)(sizeof phantom_cases / sizeof phantom_cases[0]), window);
    scalar_pyramid_free(&p.scalar);
    volume_free(&v);
}

TEST(blend_bricks_match_reference_sphere_shell)
{
    volume_t v;
    pyramid_t p;
    REQUIRE(phantom_make("sphere-shell", 40, 33, 47, &v) == PP5_OK);
    pyramid_build(&v, &p);
    check_cases(&p, phantom_cases, (int)(sizeof phantom_cases / sizeof phantom_cases[0]), NULL);
    scalar_pyramid_free(&p.scalar);
    volume_free(&v);
}

TEST(blend_bricks_match_reference_cthead)
{
    scene_t sc;
    if (!pp5_test_shared_data("volumes/cthead/cthead_256x256x113_u16be.raw.gz"))
        SKIP("volumes/cthead/cthead_256x256x113_u16be.raw.gz absent (see shared/data/README)");
    REQUIRE(scene_load("cthead", false, &sc) == PP5_OK);
    volume_t half;
    REQUIRE(volume_resample(&sc.volume, 128, 128, 57, &half) == PP5_OK);
    memcpy(half.spacing, sc.volume.spacing, sizeof half.spacing);
    pyramid_t p;
    pyramid_build(&half, &p);
    const brick_case_t cases[] = {
        {"cthead mip face", BLEND_MIP, DEMIP_READING_A, 0.1f, 1.0f, 90, 0, 180, 3, 192},
        {"cthead demip oblique", BLEND_DEMIP, DEMIP_READING_A, 0.1f, 1.0f, 70, 30, 160, 2, 160},
        {"cthead demip B", BLEND_DEMIP, DEMIP_READING_B, 0.05f, 1.0f, 90, 45, 180, 2, 128},
    };
    const float window[2] = {sc.window_centre, sc.window_width};
    check_cases(&p, cases, 3, window);
    scalar_pyramid_free(&p.scalar);
    volume_free(&half);
    scene_free(&sc);
}

/* The order the tiles rely on: bounds never rise along it, ties go by
 * index, every brick appears once, and the stored node coordinates are the
 * index's. */
TEST(blend_brick_order_is_by_decreasing_bound)
{
    volume_t v;
    pyramid_t p;
    REQUIRE(phantom_make("shepp-logan", 45, 38, 29, &v) == PP5_OK);
    pyramid_build(&v, &p);
    for (int n = 0; n < p.scalar.levels; n++) {
        const scalar_level_t *L = &p.scalar.level[n];
        int h = L->brick_height;
        size_t count = (size_t)L->hx[h] * L->hy[h] * L->hz[h];
        REQUIRE(L->brick_count == count);
        unsigned char *seen = calloc(count, 1);
        REQUIRE(seen);
        size_t bad_order = 0, bad_coord = 0, repeats = 0;
        for (size_t i = 0; i < count; i++) {
            uint32_t x = L->brick_order[i];
            REQUIRE(x < count);
            repeats += seen[x]++;
            if (i > 0) {
                float a = L->node_max[h][L->brick_order[i - 1]], b = L->node_max[h][x];
                bad_order += a < b || (a == b && L->brick_order[i - 1] > x);
            }
            uint32_t cx = x % (uint32_t)L->hx[h], cy = x / (uint32_t)L->hx[h] % (uint32_t)L->hy[h];
            uint32_t cz = x / ((uint32_t)L->hx[h] * (uint32_t)L->hy[h]);
            bad_coord += L->brick_coord[i][0] != cx || L->brick_coord[i][1] != cy ||
                         L->brick_coord[i][2] != cz;
        }
        CHECK_EQ(bad_order, 0);
        CHECK_EQ(bad_coord, 0);
        CHECK_EQ(repeats, 0);
        free(seen);
    }
    scalar_pyramid_free(&p.scalar);
    volume_free(&v);
}

/* Field by field: the struct's padding is never written. */
static bool brick_same(const blend_brick_t *x, const blend_brick_t *y)
{
    bool same = x->material == y->material;
    for (int a = 0; a < 4; a++)
        same = same && x->lo[a] == y->lo[a] && x->hi[a] == y->hi[a] && x->c0[a] == y->c0[a] &&
               x->c1[a] == y->c1[a] && x->rect[a] == y->rect[a];
    return same;
}

/* The bins do not depend on the thread count: each tile lists the same
 * bricks, described alike, in the same order; and along each tile's list
 * the material never rises (the tile's early stop relies on it), across the
 * chunks the bricks were described in. */
TEST(blend_bins_are_the_same_for_any_thread_count)
{
    volume_t v;
    pyramid_t p;
    REQUIRE(phantom_make("shepp-logan", 61, 54, 37, &v) == PP5_OK);
    pyramid_build(&v, &p);
    REQUIRE(p.scalar.level[0].brick_count > 2 * BINS_CHUNK);
    view_params_t vp;
    view_defaults(&vp);
    vp.rot_x_deg = 23, vp.rot_y_deg = 37, vp.rot_z_deg = 11;
    blend_settings_t b;
    blend_settings_defaults(&b);
    b.mode = BLEND_MIP;
    camera_t cam;
    camera_setup(&cam, &vp, &p.mip, 65, 65);
    blend_ctx_t c;
    blend_ctx_init(&c, &p.scalar, &cam, &vp, &b);
    blend_bins_t one, three;
    memset(&one, 0, sizeof one);
    memset(&three, 0, sizeof three);
    REQUIRE(blend_bins_build(&one, &c, 0, 65, 65, NULL, 1) == PP5_OK);
    REQUIRE(blend_bins_build(&three, &c, 0, 65, 65, NULL, 3) == PP5_OK);
    REQUIRE(one.chunks > 2);
    CHECK_EQ(one.bricks, three.bricks);
    int tiles = one.tiles_x * one.tiles_y, differ = 0, rises = 0, chunk_crossings = 0;
    REQUIRE(tiles == three.tiles_x * three.tiles_y);
    CHECK(memcmp(one.start, three.start, sizeof *one.start * (size_t)(tiles + 1)) == 0);
    for (int t = 0; t < tiles; t++)
        for (uint32_t e = one.start[t]; e < one.start[t + 1]; e++) {
            const blend_brick_t *x = &one.brick[one.entry[e]], *y = &three.brick[three.entry[e]];
            differ += !brick_same(x, y);
            if (e > one.start[t]) {
                const blend_brick_t *before = &one.brick[one.entry[e - 1]];
                rises += x->material > before->material;
                chunk_crossings += one.entry[e] / BINS_CHUNK != one.entry[e - 1] / BINS_CHUNK;
            }
        }
    CHECK_EQ(differ, 0);
    CHECK_EQ(rises, 0);
    CHECK(chunk_crossings > 0);   /* the lists do run across chunks */
    CHECK(one.start[tiles] > 0);
    blend_bins_free(&one);
    blend_bins_free(&three);
    scalar_pyramid_free(&p.scalar);
    volume_free(&v);
}
