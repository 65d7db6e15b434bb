/* test_fw_cost.c: every row and column of firmware/common/vr_cost.h against the operations its kernel performs, on the state of real GPs after a frame.
 *
 * The kernels are the GP program's own (firmware/gp/vr_*_kernels.h,
 * common/vr_kernels.h, common/vr_shade_fixed.h).  Each states, span by span,
 * the operations it performs (counting on: a vr_count_t); production counts
 * only how often each span ran (vr_spans_t) and charges rows x counts.  Here
 * both run together on what a GP of a real session holds after a frame (its
 * fetched units, octree grids, 2DLevel tables, frame), over every ray, pixel
 * and voxel of its band and slab, so every row is checked where the program
 * uses it: for each row and each of its nine columns, the operations its
 * spans stated must equal (times it ran) x (the row).  A kernel edited
 * without its row, or a span whose operations change with the data, fails
 * here; so does a row that no kernel ran. */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "firmware/gp/vr_blend_kernels.h"
#include "firmware/gp/vr_slab_kernels.h"
#include "firmware/gp/vr_image_kernels.h"
#include "firmware/gp/vr_setup_kernels.h"
#include "firmware/host/fw_session.h"
#include "harness.h"
#include "machine.h"

typedef struct {
    vr_spans_t sp;
    vr_count_t cnt;
} tally_t;

/* The columns of a row as an array (the order of vr_cost_row_t). */
static void row_columns(const vr_cost_row_t *r, uint64_t v[9])
{
    const uint64_t c[9] = {r->fadd, r->fmul, r->fdiv, r->fsqrt, r->loads, r->load_use,
                           r->stores, r->int_ops, r->branches};
    memcpy(v, c, sizeof c);
}

static void ops_columns(const fw_ops_t *o, uint64_t v[9])
{
    const uint64_t c[9] = {o->fadd, o->fmul, o->fdiv, o->fsqrt, o->loads, o->load_use,
                           o->stores, o->int_ops, o->branches};
    memcpy(v, c, sizeof c);
}

static const char *const column_names[9] = {"fadd", "fmul", "fdiv", "fsqrt", "loads",
                                            "load_use", "stores", "int_ops", "branches"};

/* Every row that ran: stated operations = runs x row, column by column. */
static void check_tally(const tally_t *t, const char *where)
{
    const vr_cost_entry_t *table = vr_cost_table();
    for (int i = 0; i < VR_ROW_COUNT; i++) {
        uint64_t want[9], got[9];
        row_columns(&table[i].row, want);
        ops_columns(&t->cnt.row[i], got);
        for (int k = 0; k < 9; k++)
            CHECK_MSG(got[k] == want[k] * t->sp.n[i],
                      "%s: row %s column %s: the kernel stated %llu over %llu runs, the row says "
                      "%llu each", where, table[i].name, column_names[k], (unsigned long long)got[k],
                      (unsigned long long)t->sp.n[i], (unsigned long long)want[k]);
    }
}

/* ---- the sessions ---- */

typedef struct {
    volume_t v;
    fw_session_t s;
    int g;                        /* the GP whose state the kernels use */
    gp_t *gp;
    vr_state_t *st;
} sess_t;

/* blend: NULL for compositing, else MIP, DEMIP or MIDA with these settings. */
static void sess_open_blend(sess_t *x, shade_case_t lighting, projection_t proj, bool level_tables,
                            int split, fw_division_t division, const blend_settings_t *blend)
{
    memset(x, 0, sizeof *x);
    REQUIRE(phantom_make("shepp-logan", 40, 40, 36, &x->v) == PP5_OK);
    classify_tf_t tf;
    REQUIRE(classify_preset("shepp-logan", &tf) == PP5_OK);
    shade_params_t sh;
    shade_defaults(&sh);
    sh.lighting = lighting;
    if (lighting != SHADE_DIFFUSE_FIXED_LIGHT)
        sh.specular = 0.5f;
    render_settings_t rs;
    render_settings_defaults(&rs);
    rs.width = rs.height = 64;
    rs.mode = RENDER_MODE_GAZE;
    rs.threads = 1;
    rs.view.rot_x_deg = 20.0f;
    rs.view.rot_y_deg = 30.0f;
    rs.view.projection = proj;
    rs.level_tables = level_tables;
    if (blend)
        rs.blend = *blend;
    pp5_params_t p;
    pp5_params_default(&p);
    p.n_gp = 4;
    p.n_renderers = 4;
    fw_options_t o;
    fw_options_default(&o);
    o.division = division;        /* resident or object slabs: the fetched units stay */
    o.level_tables = level_tables;
    o.split = split;
    render_job_t job = {.volume = &x->v, .volume_name = "phantom", .tf = tf, .shade = sh,
                        .settings = rs, .frames = 1};
    REQUIRE_MSG(fw_session_init(&x->s, &job, &p, &o) == PP5_OK, "session: %s", pp5_error_text());
    fw_frame_result_t r;
    REQUIRE_MSG(fw_session_frame(&x->s, 30.0, 28.0, NULL, &r) == PP5_OK, "frame: %s", pp5_error_text());
    x->g = 1;
    x->gp = &x->s.m.gp[x->g];
    x->st = fw_state(x->gp);
    REQUIRE(x->st != NULL);
}

static void sess_open(sess_t *x, shade_case_t lighting, projection_t proj, bool level_tables,
                      int split, fw_division_t division)
{
    sess_open_blend(x, lighting, proj, level_tables, split, division, NULL);
}

static void sess_close(sess_t *x)
{
    fw_session_free(&x->s);
    volume_free(&x->v);
}

/* Texel rows, parked-ray arrays and flag rows of every 2D level of the
 * band, in the GP's local memory (the frame freed its own at its end). */
static void band_arrays(sess_t *x, bool alloc)
{
    vr_state_t *s = x->st;
    for (int m = 0; m < s->levels2d; m++) {
        if (!alloc) {
            fw_free(x->gp, s->texel[m]);
            fw_free(x->gp, s->need[m]);
            fw_free(x->gp, s->ray_a[m]);
            fw_free(x->gp, s->ray_t[m]);
            fw_free(x->gp, s->ray_k[m]);
            s->texel[m] = s->ray_a[m] = s->ray_t[m] = NULL;
            s->need[m] = NULL;
            s->ray_k[m] = NULL;
            continue;
        }
        size_t rows = (size_t)(s->jhi[m] - s->jlo[m] + 2), n = rows * (size_t)s->tw[m];
        s->texel[m] = fw_alloc(x->gp, n * 3 * sizeof(float));
        s->need[m] = fw_alloc(x->gp, n);
        s->ray_a[m] = fw_alloc(x->gp, n * sizeof(float));
        s->ray_t[m] = fw_alloc(x->gp, n * sizeof(float));
        s->ray_k[m] = fw_alloc(x->gp, n * sizeof(int32_t));
        REQUIRE(s->texel[m] && s->need[m] && s->ray_a[m] && s->ray_t[m] && s->ray_k[m]);
    }
}

/* ---- the kernels on the session's data ---- */

/* Every texel ray of the band, whole and in two depth segments (parked,
 * then resumed), and rays past the image (they miss the volume). */
static void run_rays(sess_t *x, tally_t *t)
{
    vr_state_t *s = x->st;
    fw_ops_t mops = {0};
    const vr_mem_t mem = {x->gp, &mops};
    uint64_t skipped = 0;
    int rays = 0, parked = 0, same = 0;
    for (int m = 0; m < s->levels2d; m++) {
        vr_ray_consts_t rc;
        vr_ray_consts(s, m, &rc);
        float mid = s->fr.projection ? s->fr.eye_distance : s->fr.radius + 1.0f;   /* mid-ray */
        for (int j = s->jlo[m]; j <= s->jhi[m]; j++)
            for (int i = 0; i < s->tw[m]; i++) {
                vr_ray_slot_t slot = {m, (size_t)(j - s->jlo[m]) * s->tw[m] + (size_t)i};
                float px = (float)(i << m) + 0.5f, py = (float)(j << m) + 0.5f;
                vr_trace(s, &rc, px, py, slot, false, INFINITY, &mem, &t->sp, &t->cnt, &skipped);
                float whole[3];
                memcpy(whole, s->texel[m] + slot.idx * 3, sizeof whole);
                if (!vr_trace(s, &rc, px, py, slot, false, mid, &mem, &t->sp, &t->cnt, &skipped)) {
                    vr_trace(s, &rc, px, py, slot, true, INFINITY, &mem, &t->sp, &t->cnt, &skipped);
                    parked++;
                }
                /* in two segments exactly as in one */
                same += memcmp(whole, s->texel[m] + slot.idx * 3, sizeof whole) == 0;
                rays++;
            }
        vr_ray_slot_t slot = {m, 0};
        vr_trace(s, &rc, -500.0f, -500.0f, slot, false, INFINITY, &mem, &t->sp, &t->cnt, &skipped);
    }
    CHECK(rays > 100);
    CHECK(parked > 10);
    CHECK_EQ(same, rays);
    CHECK(mops.dcache_hits + mops.dcache_misses > 0);   /* the accesses were declared */
}

/* Rays parallel to two axes (the frame's basis turned to the axes). */
static void run_axis_rays(sess_t *x, tally_t *t)
{
    vr_state_t *s = x->st;
    vr_frame_t keep = s->fr;
    const float right[3] = {1, 0, 0}, down[3] = {0, 1, 0}, fwd[3] = {0, 0, 1};
    memcpy(s->fr.right, right, sizeof right);
    memcpy(s->fr.down, down, sizeof down);
    memcpy(s->fr.forward, fwd, sizeof fwd);
    vr_ray_consts_t rc;
    vr_ray_consts(s, 0, &rc);
    uint64_t skipped = 0;
    for (int i = 0; i < s->tw[0]; i += 3) {
        vr_ray_slot_t slot = {0, (size_t)i};
        vr_trace(s, &rc, (float)i + 0.5f, (float)s->jlo[0] + 0.5f, slot, false, INFINITY, NULL, &t->sp,
                 &t->cnt, &skipped);
    }
    s->fr = keep;
}

/* The octree's steps to the top: a level whose grids are all empty. */
static void run_empty_octree(sess_t *x, tally_t *t)
{
    vr_state_t *s = x->st;
    octgrid_t keep = s->exact[0];
    octgrid_t *g = &s->exact[0];
    uint64_t *words[VR_MAX_LEVELS] = {0};
    for (int h = 0; h < g->heights; h++) {
        size_t n = vr_bits_words(g->occ[h].nx, g->occ[h].ny, g->occ[h].nz);
        words[h] = fw_alloc(x->gp, n * 8);           /* zeroed: empty */
        REQUIRE(words[h] != NULL);
        g->occ[h].w = words[h];
    }
    float p[3] = {10.0f, 12.0f, 9.0f}, lo[3], hi[3];
    VR_SPAN(&t->sp, &t->cnt, OCT_LEAF, .int_ops = 2 + 1, .fadd = 1, .branches = 1);   /* the caller's part */
    CHECK_EQ(vr_oct_empty_node(s, 0, true, p, lo, hi, NULL, &t->sp, &t->cnt), g->heights - 1);
    *g = keep;
    for (int h = 0; h < VR_MAX_LEVELS; h++)
        fw_free(x->gp, words[h]);
}

/* 2DLevel, marks and RenderPixel of every pixel of the band, with the
 * gaze inside the image, outside it (offsets past the distance table) and
 * a scaled distance (progressive growth). */
static void run_pixels(sess_t *x, tally_t *t)
{
    vr_state_t *s = x->st;
    const vr_config_t *c = &s->cfg;
    int W = c->width;
    size_t nlev = (size_t)(s->ly1 - s->ly0) * W;
    float *level = fw_alloc(x->gp, nlev * sizeof(float));
    REQUIRE(level != NULL);
    s->level = level;
    bool tables = c->level_tables != 0;
    double scale = s->fr.gaze_scale;
    const int gazes[3][2] = {{30, 28}, {-300, 10}, {30, 28}};
    for (int k = 0; k < 3; k++) {
        s->fr.gaze_scale = k == 2 ? 2.0 : scale;
        for (size_t i = 0; i < nlev; i++)
            level[i] = INFINITY;
        for (int y = s->ly0; y < s->ly1; y++)
            for (int px = 0; px < W; px++)
                vr_pixel_level(s, px, y, true, tables, gazes[k][0], gazes[k][1],
                               &level[(size_t)(y - s->ly0) * W + px], &t->sp, &t->cnt);
    }
    s->fr.gaze_scale = scale;
    for (int y = s->ly0; y < s->ly1; y++)
        for (int px = 0; px < W; px++) {
            float lv = level[(size_t)(y - s->ly0) * W + px];
            vr_mark_pixel(s, px, y, lv > (float)(s->levels2d - 1) ? (float)(s->levels2d - 1) : lv,
                          &t->sp, &t->cnt);
        }
    /* RenderPixel reads the texels the rays left (run_rays ran first). */
    int rows = s->y1 - s->y0;
    uint8_t *section = fw_alloc(x->gp, (size_t)W * rows * 3);
    REQUIRE(section != NULL);
    fw_ops_t mops = {0};
    const vr_mem_t mem = {x->gp, &mops};
    for (int i = 0; i < (int)nlev; i++)
        if (level[i] > (float)(s->levels2d - 1))
            level[i] = (float)(s->levels2d - 1);
    for (int y = s->y0; y < s->y1; y++)
        for (int px = 0; px < W; px++)
            vr_render_pixel(s, px, y, section, ((size_t)(y - s->y0) * W + px) * 3, &mem, &t->sp, &t->cnt);
    CHECK(mops.dcache_misses > 0);
    fw_free(x->gp, section);
    fw_free(x->gp, level);
    s->level = NULL;
}

/* The mip-map build's kernels on the GP's slab of the phantom: every voxel
 * (borders included), quantised; the box filter over it (an odd level
 * included, whose edge children are missing); the GP split's shading of the
 * quantised words; the tables. */
static void run_setup(sess_t *x, tally_t *t)
{
    vr_state_t *s = x->st;
    const vr_config_t *c = &s->cfg;
    size_t plane = (size_t)c->nx * c->ny, slices = (size_t)(c->data_z1 - c->data_z0);
    float *slab = fw_alloc(x->gp, plane * slices * sizeof(float));
    REQUIRE(slab != NULL);
    memcpy(slab, x->v.data + plane * (size_t)c->data_z0, plane * slices * sizeof(float));
    s->slab = slab;
    int z0 = c->data_z0 > 0 ? c->data_z0 + 1 : 0, z1 = c->data_z1 < c->nz ? c->data_z1 - 1 : c->nz;
    REQUIRE(z1 - z0 >= 2);
    size_t vox = plane * (size_t)(z1 - z0);
    float *o = fw_alloc(x->gp, vox * (size_t)s->stride * sizeof(float));
    uint32_t *qa = fw_alloc(x->gp, vox * 4), *qn = fw_alloc(x->gp, vox * 4);
    REQUIRE(o && qa && qn);
    fw_ops_t mops = {0};
    const vr_mem_t mem = {x->gp, &mops};
    for (int z = z0; z < z1; z++)
        for (int y = 0; y < c->ny; y++)
            for (int vx = 0; vx < c->nx; vx++) {
                size_t i = ((size_t)(z - z0) * c->ny + y) * c->nx + vx;
                vr_base_voxel(s, vx, y, z, o + i * s->stride, &mem, &t->sp, &t->cnt);
                vr_quantise(o + i * s->stride, s->stride, &qa[i], &qn[i], &t->sp, &t->cnt);
            }
    CHECK(mops.dcache_misses > 0);
    /* The filter: the built slices as a level (even dims), and a 5x5x3
     * corner of it as an odd level. */
    float out[8];
    for (int z = 0; z < (z1 - z0) / 2; z++)
        for (int y = 0; y < c->ny / 2; y++)
            for (int vx = 0; vx < c->nx / 2; vx++)
                vr_filter_voxel(o, c->nx, c->ny, z1 - z0, 0, 0, c->ny, vx, y, z, s->stride, out, &t->sp,
                                &t->cnt);
    for (int z = 0; z < 2; z++)
        for (int y = 0; y < 3; y++)
            for (int vx = 0; vx < 3; vx++)
                vr_filter_voxel(o, 5, 5, 3, 0, 0, c->ny, vx, y, z, s->stride, out, &t->sp, &t->cnt);
    /* GP split shading, the specular consts of the frame and a moving
     * object's diffuse term. */
    vr_shade_consts_t sc = s->shade_consts;
    if (sc.exponent < 1) {
        const float half[3] = {0.0f, 0.0f, 1.0f};
        vr_shade_consts(&sc, half, 0.5f, 20, 0);
    }
    vr_shade_words(&sc, qa, qn, vox, &mem, &t->sp, &t->cnt);
    const float light[3] = {0.6f, 0.0f, 0.8f};
    vr_shade_consts_diffuse(&sc, light, 0.2f, 0.8f);
    vr_shade_words(&sc, qa, qn, vox / 4, NULL, &t->sp, &t->cnt);
    /* A zero normal at an opaque voxel (render/'s "no surface"). */
    const float zero[3] = {0, 0, 0};
    vr_diffuse(c, zero, c->light_dir, &t->sp, &t->cnt);
    /* The tables of the sequence. */
    vr_alpha_lut_fill(s, &t->sp, &t->cnt);
    vr_level_tables_t lt = {.w = 24, .h = 16};
    lt.n = vr_level_tables_entries(c, lt.w, lt.h);
    lt.dist = fw_alloc(x->gp, (size_t)lt.w * lt.h * sizeof *lt.dist);
    lt.level = fw_alloc(x->gp, (size_t)lt.n * sizeof *lt.level);
    REQUIRE(lt.dist && lt.level);
    vr_level_tables_fill(c, &lt, &t->sp, &t->cnt);
    fw_free(x->gp, lt.dist);
    fw_free(x->gp, lt.level);
    fw_free(x->gp, o);
    fw_free(x->gp, qa);
    fw_free(x->gp, qn);
    fw_free(x->gp, slab);
    s->slab = NULL;
}

/* Object slabs on a GP of an object-slabs session: its band's need set
 * packed from flags, counted and unpacked; every needed texel's segment
 * through the GP's slab and through the whole volume (which must equal the
 * whole ray); the partials merged front to back, and a partial naming a
 * texel past the band refused. */
static void run_slabs(sess_t *x, tally_t *t)
{
    vr_state_t *s = x->st;
    vr_band_geom_t bg;
    memset(&bg, 0, sizeof bg);
    size_t flagged = 0;
    for (int m = 0; m < s->levels2d; m++) {
        bg.jlo[m] = s->jlo[m];
        bg.jhi[m] = s->jhi[m];
        bg.tw[m] = s->tw[m];
        int rows = s->jhi[m] - s->jlo[m] + 1;
        bg.base[m + 1] = bg.base[m] + (uint32_t)rows * (uint32_t)s->tw[m];
        for (size_t i = 0; i < (size_t)rows * s->tw[m]; i++) {
            s->need[m][i] = (uint8_t)(i % 3 == 0);
            flagged += i % 3 == 0;
        }
    }
    uint32_t total = bg.base[s->levels2d];
    uint8_t *bits = fw_alloc(x->gp, (total + 7) / 8);
    vr_texel_ref_t *refs = fw_alloc(x->gp, (flagged ? flagged : 1) * sizeof *refs);
    vr_partial_t *parts = fw_alloc(x->gp, (flagged ? flagged : 1) * sizeof *parts);
    float *acc = fw_alloc(x->gp, (size_t)total * 4 * sizeof *acc);
    REQUIRE(bits && refs && parts && acc);
    vr_need_pack(s->need, s->jlo, s->tw, &bg, s->levels2d, bits, &t->sp, &t->cnt);
    CHECK_EQ(vr_need_count(bits, total, &t->sp, &t->cnt), flagged);
    CHECK_EQ(vr_need_unpack(bits, &bg, s->levels2d, refs, &t->sp, &t->cnt), flagged);
    fw_ops_t mops = {0};
    const vr_mem_t mem = {x->gp, &mops};
    uint64_t skipped = 0;
    size_t kept = 0, same = 0, cast = 0;
    for (size_t i = 0; i < flagged; i++) {
        const vr_texel_ref_t *r = &refs[i];
        vr_ray_consts_t rc;
        vr_ray_consts(s, r->m, &rc);
        if (vr_slab_segment(s, &rc, r, s->zslab_lo, s->zslab_hi, &parts[kept], &mem, &t->sp,
                            &t->cnt, &skipped))
            kept++;
        /* The whole volume as one slab is the whole ray (before its texel
         * store): same samples, same arithmetic. */
        vr_partial_t whole;
        bool any = vr_slab_segment(s, &rc, r, LONG_MIN / 4, LONG_MAX / 4, &whole, &mem, &t->sp,
                                   &t->cnt, &skipped);
        vr_ray_slot_t slot = {r->m, (size_t)(r->j - s->jlo[r->m]) * s->tw[r->m] + r->i};
        float px = (float)(r->i << r->m) + 0.5f, py = (float)(r->j << r->m) + 0.5f;
        vr_trace(s, &rc, px, py, slot, false, INFINITY, NULL, NULL, NULL, &skipped);
        const float *tx = s->texel[r->m] + slot.idx * 3;
        bool black = tx[0] == 0.0f && tx[1] == 0.0f && tx[2] == 0.0f;
        same += any ? memcmp(whole.rgba, tx, 3 * sizeof *tx) == 0 : black;
        cast++;
    }
    CHECK(kept > 10 && kept < flagged);   /* segments kept and segments with nothing */
    CHECK_EQ(same, cast);
    for (size_t r = 0; r < kept; r++)
        CHECK(vr_merge_partial(acc, total, parts, r, &mem, &t->sp, &t->cnt));
    parts[0].code = total;
    CHECK(!vr_merge_partial(acc, total, parts, 0, &mem, &t->sp, &t->cnt));
    fw_free(x->gp, acc);
    fw_free(x->gp, parts);
    fw_free(x->gp, refs);
    fw_free(x->gp, bits);
}

/* ---- blends ---- */

/* Every texel ray of the band under the session's blend, then under the
 * variants that only the ray's last part reads (the state's settings
 * turned for the run): the other reading, depth and sphere weight, and
 * DEMIP on a MIP or MIDA session's units. */
static void run_blend_rays(sess_t *x, tally_t *t)
{
    vr_state_t *s = x->st;
    vr_config_t keep = s->cfg;
    fw_ops_t mops = {0};
    const vr_mem_t mem = {x->gp, &mops};
    uint64_t skipped = 0;
    vr_blend_tally_t bt = {0};
    int rays = 0;
    /* blend, reading, depth, sphere on, a window four times narrower (the
     * skull saturates: ray 1 and MIDA stop early) */
    const int variants[6][5] = {
        {-1, -1, -1, -1, 0},
        {VR_BLEND_DEMIP, VR_READING_B, VR_DEPTH_EXACT, 0, 0},
        {VR_BLEND_DEMIP, VR_READING_A, VR_DEPTH_ENTRY_PLUS_LENGTH, 1, 0},
        {VR_BLEND_MIDA, -1, -1, -1, 0},
        {VR_BLEND_DEMIP, VR_READING_B, VR_DEPTH_EXACT, 1, 1},
        {VR_BLEND_MIDA, -1, -1, -1, 1},
    };
    for (int v = 0; v < 6; v++) {
        const int *w = variants[v];
        if (w[4])
            s->cfg.window_inv_width *= 4.0f;
        if (w[0] >= 0)
            s->cfg.blend = w[0];
        if (w[1] >= 0)
            s->cfg.reading = w[1];
        if (w[2] >= 0)
            s->cfg.depth = w[2];
        if (w[3] >= 0)
            s->cfg.sw = w[3] ? 0.3f : 0.0f;
        for (int m = 0; m < s->levels2d; m++) {
            vr_ray_consts_t rc;
            vr_ray_consts(s, m, &rc);
            for (int j = s->jlo[m]; j <= s->jhi[m]; j++)
                for (int i = 0; i < s->tw[m]; i++) {
                    vr_ray_slot_t slot = {m, (size_t)(j - s->jlo[m]) * s->tw[m] + (size_t)i};
                    vr_blend_trace(s, &rc, (float)(i << m) + 0.5f, (float)(j << m) + 0.5f, slot,
                                   &mem, &t->sp, &t->cnt, &skipped, &bt);
                    rays++;
                }
            vr_ray_slot_t slot = {m, 0};
            vr_blend_trace(s, &rc, -500.0f, -500.0f, slot, &mem, &t->sp, &t->cnt, &skipped, &bt);
        }
        s->cfg = keep;
    }
    CHECK(rays > 400);
    CHECK(bt.ray2_samples > 0);
    CHECK(bt.occluded > 0);
    CHECK(bt.saturated > 0);
    CHECK(bt.terminated > 0);
    CHECK(mops.dcache_hits + mops.dcache_misses > 0);
}

/* The value pyramid's build kernels on the GP's slab: every level-0 value
 * and its word, the max reduction over them (an odd level included). */
static void run_blend_setup(sess_t *x, tally_t *t)
{
    vr_state_t *s = x->st;
    const vr_config_t *c = &s->cfg;
    size_t plane = (size_t)c->nx * c->ny, slices = (size_t)(c->data_z1 - c->data_z0);
    float *slab = fw_alloc(x->gp, plane * slices * sizeof(float));
    REQUIRE(slab != NULL);
    memcpy(slab, x->v.data + plane * (size_t)c->data_z0, plane * slices * sizeof(float));
    s->slab = slab;
    int z0 = c->data_z0, z1 = c->data_z1;
    size_t vox = plane * (size_t)(z1 - z0);
    float *o = fw_alloc(x->gp, vox * sizeof(float));
    uint32_t *qa = fw_alloc(x->gp, vox * 4);
    REQUIRE(o && qa);
    fw_ops_t mops = {0};
    const vr_mem_t mem = {x->gp, &mops};
    size_t warm = 0;
    for (int z = z0; z < z1; z++)
        for (int y = 0; y < c->ny; y++)
            for (int vx = 0; vx < c->nx; vx++) {
                size_t i = ((size_t)(z - z0) * c->ny + y) * c->nx + vx;
                vr_value_voxel(s, vx, y, z, o + i, &mem, &t->sp, &t->cnt);
                warm += vr_value_word(s, o + i, &qa[i], &t->sp, &t->cnt);
                CHECK(memcmp(&qa[i], o + i, 4) == 0);
            }
    CHECK(warm > 0);
    /* cold voxels too, where the session skips (parallel projection) */
    CHECK(isinf(c->cold_below) || warm < vox);
    CHECK(mops.dcache_misses > 0);
    float out;
    for (int z = 0; z < (z1 - z0) / 2; z++)
        for (int y = 0; y < c->ny / 2; y++)
            for (int vx = 0; vx < c->nx / 2; vx++)
                vr_max_voxel(o, c->nx, c->ny, z1 - z0, 0, 0, c->ny, vx, y, z, &out, &t->sp, &t->cnt);
    for (int z = 0; z < 2; z++)
        for (int y = 0; y < 3; y++)
            for (int vx = 0; vx < 3; vx++)
                vr_max_voxel(o, 5, 5, 3, 0, 0, c->ny, vx, y, z, &out, &t->sp, &t->cnt);
    fw_free(x->gp, o);
    fw_free(x->gp, qa);
    fw_free(x->gp, slab);
    s->slab = NULL;
}

static void run_blend_session(blend_mode_t mode, projection_t proj, const char *where,
                              tally_t *all)
{
    blend_settings_t b;
    blend_settings_defaults(&b);
    b.mode = mode;
    /* The phantom is 0..200: brain 40 and below cold (skipped), the skull
     * (200) saturating where a sample is near its voxels, partial volumes
     * below: reading B meets the front skull as an occluder of the back. */
    b.window_centre = 115.0f;
    b.window_width = 150.0f;
    b.tolerance = 0.1f;
    b.reading = DEMIP_READING_B;
    sess_t x;
    sess_open_blend(&x, SHADE_DIFFUSE_FIXED_LIGHT, proj, true, VR_SPLIT_PP, FW_DIVISION_RESIDENT,
                    &b);
    tally_t *t = calloc(1, sizeof *t);
    REQUIRE(t != NULL);
    band_arrays(&x, true);
    run_blend_rays(&x, t);
    band_arrays(&x, false);
    run_blend_setup(&x, t);
    CHECK_MSG(!x.gp->fw_error, "%s: %s", where, x.gp->error);
    check_tally(t, where);
    for (int i = 0; i < VR_ROW_COUNT; i++)
        all->sp.n[i] += t->sp.n[i];
    free(t);
    sess_close(&x);
}

static void run_slab_session(tally_t *all)
{
    sess_t x;
    sess_open(&x, SHADE_DIFFUSE_FIXED_LIGHT, PROJECTION_PARALLEL, true, VR_SPLIT_PP,
              FW_DIVISION_OBJECT_SLABS);
    tally_t *t = calloc(1, sizeof *t);
    REQUIRE(t != NULL);
    band_arrays(&x, true);
    run_slabs(&x, t);
    band_arrays(&x, false);
    CHECK_MSG(!x.gp->fw_error, "object slabs: %s", x.gp->error);
    check_tally(t, "object slabs, diffuse, parallel");
    for (int i = 0; i < VR_ROW_COUNT; i++)
        all->sp.n[i] += t->sp.n[i];
    free(t);
    sess_close(&x);
}

static void run_session(shade_case_t lighting, projection_t proj, bool level_tables, int split,
                        const char *where, tally_t *all)
{
    sess_t x;
    sess_open(&x, lighting, proj, level_tables, split, FW_DIVISION_RESIDENT);
    tally_t *t = calloc(1, sizeof *t);
    REQUIRE(t != NULL);
    band_arrays(&x, true);
    run_rays(&x, t);
    run_axis_rays(&x, t);
    run_empty_octree(&x, t);
    run_pixels(&x, t);
    band_arrays(&x, false);
    run_setup(&x, t);
    CHECK_MSG(!x.gp->fw_error, "%s: %s", where, x.gp->error);
    check_tally(t, where);
    for (int i = 0; i < VR_ROW_COUNT; i++)
        all->sp.n[i] += t->sp.n[i];
    free(t);
    sess_close(&x);
}

TEST(fw_cost_every_row_equals_its_kernel_on_real_data)
{
    tally_t all;
    memset(&all, 0, sizeof all);
    /* Specular with the paper's 2DLevel tables, parallel projection; then
     * diffuse, perspective, exact 2DLevel. */
    run_session(SHADE_SPECULAR_FIXED_LIGHT, PROJECTION_PARALLEL, true, VR_SPLIT_GP,
                "specular, parallel, 2DLevel by tables", &all);
    run_session(SHADE_DIFFUSE_FIXED_LIGHT, PROJECTION_PERSPECTIVE, false, VR_SPLIT_PP,
                "diffuse, perspective, 2DLevel exact", &all);
    run_slab_session(&all);
    /* Blends: DEMIP parallel (cold cells skipped), MIDA perspective (two 3D
     * levels per sample, no skipping). */
    run_blend_session(BLEND_DEMIP, PROJECTION_PARALLEL, "DEMIP, parallel", &all);
    run_blend_session(BLEND_MIDA, PROJECTION_PERSPECTIVE, "MIDA, perspective", &all);
    /* Every row was checked somewhere (a row no kernel runs is dead). */
    const vr_cost_entry_t *table = vr_cost_table();
    for (int i = 0; i < VR_ROW_COUNT; i++)
        CHECK_MSG(all.sp.n[i] > 0, "row %s (%s) never ran: no kernel checks it", table[i].name,
                  table[i].what);
}

/* The production charge is the rows times the span counts: the same spans
 * counted with and without the statements give the same operations. */
TEST(fw_cost_production_charge_is_rows_times_spans)
{
    sess_t x;
    sess_open(&x, SHADE_SPECULAR_FIXED_LIGHT, PROJECTION_PARALLEL, true, VR_SPLIT_PP,
              FW_DIVISION_RESIDENT);
    band_arrays(&x, true);
    vr_state_t *s = x.st;
    vr_spans_t sp;
    memset(&sp, 0, sizeof sp);
    vr_count_t *cnt = calloc(1, sizeof *cnt);
    REQUIRE(cnt != NULL);
    vr_ray_consts_t rc;
    vr_ray_consts(s, 0, &rc);
    uint64_t skipped = 0;
    for (int i = 0; i < s->tw[0]; i++) {
        vr_ray_slot_t slot = {0, (size_t)i};
        vr_trace(s, &rc, (float)i + 0.5f, (float)s->jlo[0] + 0.5f, slot, false, INFINITY, NULL, &sp, cnt,
                 &skipped);
    }
    fw_ops_t charged = {0}, stated = {0};
    vr_spans_charge(&charged, &sp);
    for (int i = 0; i < VR_ROW_COUNT; i++)
        gp_cost_add(&stated, &cnt->row[i]);
    uint64_t a[9], b[9];
    ops_columns(&charged, a);
    ops_columns(&stated, b);
    for (int k = 0; k < 9; k++)
        CHECK_MSG(a[k] == b[k], "column %s: charged %llu, stated %llu", column_names[k],
                  (unsigned long long)a[k], (unsigned long long)b[k]);
    CHECK(sp.n[VR_ROW_TRILERP] > 0);
    free(cnt);
    band_arrays(&x, false);
    sess_close(&x);
}
