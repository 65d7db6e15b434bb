/* test_fw_poly_cost.c: every row and column of firmware/common/poly_cost.h against the operations its kernel performs, on real scenes.
 *
 * The kernels are the polygon GP program's own (firmware/gp/poly_kernels.h).
 * They run here on a sphere in perspective with the triangles that exercise
 * every path (one through the near plane, one past the guard band, an
 * edge-on sliver whose depth plane needs fewer fraction bits, one of zero
 * area), for flat, Gouraud and Phong, through the whole frame's kernels:
 * transform and set-up, the sort into regions, every (triangle, region)
 * stream.  For each row and each column the operations its spans stated
 * must equal (times it ran) x (the row); every row must run; and the words
 * charged must be the words the streams hold. */
#include <stdlib.h>
#include <string.h>

#include "firmware/common/poly_phong_pp.h"
#include "firmware/gp/poly_vrz_kernels.h"
#include "firmware/host/poly_session.h"
#include "harness.h"
#include "render/gaze2d.h"
#include "render/mesh/mesh_gen.h"

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

static const char *const COLUMN[9] = {"fadd", "fmul", "fdiv", "fsqrt", "loads", "load_use",
                                      "stores", "int_ops", "branches"};

static void check_rows(const poly_spans_t *sp, const poly_count_t *cnt, const char *where)
{
    const vr_cost_entry_t *t = poly_cost_table();
    for (int i = 0; i < POLY_ROW_COUNT; i++) {
        uint64_t want[9], got[9];
        row_columns(&t[i].row, want);
        ops_columns(&cnt->row[i], got);
        for (int k = 0; k < 9; k++)
            CHECK_MSG(got[k] == want[k] * sp->n[i], "%s: row %s column %s: stated %llu over %llu runs, "
                      "the row says %llu each", where, t[i].name, COLUMN[k],
                      (unsigned long long)got[k], (unsigned long long)sp->n[i],
                      (unsigned long long)want[k]);
    }
}

/* The sphere (radius 1 at z = -4.5, camera at the origin looking down -z)
 * and the special triangles, as the session deals them. */
static poly_tri_in_t *cost_scene(size_t *n, int W)
{
    mesh_t m;
    REQUIRE(mesh_gen_uv_sphere(16, 10, 1.0, &m) == PP5_OK);
    for (int v = 0; v < m.n_vertices; v++)
        m.pos[3 * v + 2] -= 4.5;
    poly_tri_in_t *t;
    size_t ns;
    REQUIRE(poly_triangles_from_mesh(&m, &t, &ns) == PP5_OK);
    mesh_free(&m);
    t = realloc(t, sizeof *t * (ns + 4));
    REQUIRE(t != NULL);
    double f = 1 / tan(0.5 * 50.0 * 3.14159265358979 / 180);
    double half = 1.0 / (f * W);   /* x of half a pixel at depth 1 (aspect 1) */
    const float special[4][9] = {
        {-1, -1, -0.5f, 1, -1, -5, 0, 1, -5},                 /* through the near plane */
        {-100, -1, -4, 100, -1, -4, 0, 2, -4},                /* past the guard band */
        {(float)(3 * half), -0.5f, -3, (float)(3 * half), 0.5f, -3,
         (float)(8 * 1.5 * half), 0, -8},                     /* edge-on: a steep depth plane */
        {0, 0, -4, 0, 0, -4.5f, 0, 0, -5},                    /* no area on the screen */
    };
    for (int k = 0; k < 4; k++) {
        poly_tri_in_t *q = &t[ns + k];
        q->rgb = k == 0 ? POLY_RGB_OWN | 0x204080u : 0;   /* one with its own colour */
        for (int c = 0; c < 3; c++)
            for (int d = 0; d < 3; d++) {
                q->p[c][d] = special[k][3 * c + d];
                q->n[c][d] = d == 2 ? 1.0f : 0.0f;
            }
    }
    *n = ns + 4;
    return t;
}

/* The gaze-directed frame's kernels (poly_vrz_kernels.h) on the set-up
 * triangles tri[0..nt) of configuration c: the plan, the sort into level
 * tiles, every (triangle, level tile) stream, the box requests, the texel
 * rows and RenderPixel of the band, counted into the caller's sp and cnt. */
static void vrz_kernels(const poly_config_t *c, const poly_tri_t *tri, size_t nt, poly_spans_t *sp,
                        poly_count_t *cnt, pp_stream_t *st)
{
    poly_state_t *s = calloc(1, sizeof *s);
    REQUIRE(s != NULL);
    s->cfg = *c;
    s->levels = c->levels2d;
    poly_levels_setup(s);
    vr_level_tables_t *lt = &s->tables;      /* as vr_level_tables_build, in host memory */
    lt->w = c->width, lt->h = c->height;
    lt->n = vr_level_tables_entries(&s->gaze_model, lt->w, lt->h);
    lt->dist = calloc((size_t)lt->w * (size_t)lt->h, sizeof *lt->dist);
    lt->level = calloc((size_t)lt->n, sizeof *lt->level);
    REQUIRE(lt->dist && lt->level);
    vr_level_tables_fill(&s->gaze_model, lt, NULL, NULL);
    size_t n = (size_t)s->n_tiles;
    s->slot_of = calloc(n, sizeof *s->slot_of), s->reg = calloc(n, sizeof *s->reg);
    s->count = calloc(n, 4), s->start = calloc(n, 4), s->fill = calloc(n, 4);
    REQUIRE(s->slot_of && s->reg && s->count && s->start && s->fill);
    for (int l = 0; l < s->levels; l++)
        for (int ty = 0; ty < s->tiles_y[l]; ty++)
            for (int tx = 0; tx < s->tiles_x[l]; tx++)
                poly_plan_tile(s, l, tx, ty, cnt);
    s->y0 = 0, s->y1 = c->height;
    s->level = calloc((size_t)c->width * (size_t)c->height, sizeof *s->level);
    REQUIRE(s->level != NULL);
    for (int l = 0; l < s->levels; l++) {
        poly_band_texel_rows(s, s->y0, s->y1, l, &s->jlo[l], &s->jhi[l]);
        s->texel[l] = calloc((size_t)(s->jhi[l] - s->jlo[l] + 1) * (size_t)s->tw[l], 4);
        REQUIRE(s->texel[l] != NULL);
    }
    for (int k = 0; k < s->n_regions; k++)
        (void)poly_expect_region(s, k, cnt);
    for (int y = 0; y < c->height; y++)
        for (int x = 0; x < c->width; x++)
            poly_band_level(s, x, y, cnt);
    for (int pass = 0; pass < 2; pass++) {
        for (size_t i = 0; i < nt; i++) {
            poly_box_t b = poly_tri_box(&tri[i], &s->sp, cnt);
            for (int l = 0; l < s->levels; l++) {
                int t[4];
                if (poly_level_tiles(s, &b, l, t, &s->sp, cnt))
                    for (int ty = t[2]; ty <= t[3]; ty++)
                        for (int tx = t[0]; tx <= t[1]; tx++)
                            poly_sort_tile(s, l, tx, ty, (uint32_t)i, pass == 1, cnt);
            }
        }
        if (pass == 0) {
            uint32_t pairs = poly_bin_prefix(s->count, s->start, s->fill, s->n_regions, &s->sp, cnt);
            s->list = calloc(pairs + 1, sizeof *s->list);
            REQUIRE(s->list != NULL);
        }
    }
    int n_planes = c->shading == POLY_FLAT ? 1 : 4;
    for (int k = 0; k < s->n_regions; k++) {
        const poly_region_t *r = &s->reg[k];
        for (uint32_t i = 0; i < s->fill[k]; i++) {
            poly_tri_t on = tri[s->list[s->start[k] + i]];
            if (r->level > 0)
                poly_tri_on_level(&tri[s->list[s->start[k] + i]], r->level, n_planes, &on, &s->sp, cnt);
            poly_encode(c, &on, r->level, r->x, r->y, st, &s->sp, cnt);
        }
        uint32_t args[6];
        for (unsigned h = 0; h < 3; h++)
            if (poly_box_request(s, h, 3, k, 0, args, cnt))
                (void)poly_texel_row_at(s, k, s->reg[k].y + (int)(args[4] >> 16), cnt);
    }
    uint8_t px[3];
    for (int y = 0; y < c->height; y += 7)
        for (int x = 0; x < c->width; x += 3)
            poly_render_pixel(s, x, y, px, &s->sp, cnt);
    poly_section_sent(&s->sp, cnt);
    for (int i = 0; i < POLY_ROW_COUNT; i++)
        sp->n[i] += s->sp.n[i];
    for (int l = 0; l < s->levels; l++)
        free(s->texel[l]);
    free(s->level), free(s->list), free(s->slot_of), free(s->reg);
    free(lt->dist), free(lt->level);
    free(s->count), free(s->start), free(s->fill);
    free(s);
}

TEST(fw_poly_cost_rows_match_their_kernels)
{
    const int W = 256;
    size_t n;
    poly_tri_in_t *in = cost_scene(&n, W);
    bool ran[POLY_ROW_COUNT] = {false};
    for (int sh = POLY_FLAT; sh <= POLY_PHONG; sh++) {
        pp5_params_t p;
        pp5_params_default(&p);
        p.n_gp = 1;
        p.n_renderers = 1;
        raster_camera_t cam;
        raster_camera_perspective(50, 1.0, 1.0, 10.0, &cam);
        raster_style_t style;
        raster_style_default(&style, RASTER_GOURAUD);
        poly_options_t o;
        poly_options_default(&o);
        o.shading = (poly_shading_t)sh;
        gaze_display_t gd;
        gaze_display_defaults(&gd);
        REQUIRE(gaze_model_init(&o.gaze_model, &gd, W, W) == PP5_OK);
        o.gaze = true;
        o.colour_per_pixel = sh == POLY_PHONG;
        o.gaze_x = 0.3 * W, o.gaze_y = 0.6 * W;
        poly_session_t s;
        REQUIRE_MSG(poly_session_init(&s, &p, in, 1, W, W, &cam, &style, &o) == PP5_OK, "%s",
                    pp5_error_text());
        poly_config_t c = s.cfg;
        poly_session_free(&s);
        poly_spans_t sp;
        poly_count_t *cnt = calloc(1, sizeof *cnt);
        poly_tri_t *tri = calloc(n * (POLY_CLIP_MAX - 2), sizeof *tri);
        REQUIRE(cnt && tri);
        memset(&sp, 0, sizeof sp);
        size_t nt = 0;
        for (size_t i = 0; i < n; i++)
            nt += (size_t)poly_triangle(&c, &in[i], tri + nt, &sp, cnt);
        const int rx = W / 128, nr = rx * rx;
        uint32_t count[4] = {0}, start[4], fill[4];
        for (size_t i = 0; i < nt; i++)
            poly_bin_count(&tri[i], rx, count, &sp, cnt);
        uint32_t pairs = poly_bin_prefix(count, start, fill, nr, &sp, cnt);
        uint32_t *list = calloc(pairs + 1, sizeof *list);
        REQUIRE(list != NULL);
        for (size_t i = 0; i < nt; i++)
            poly_bin_fill(&tri[i], (uint32_t)i, rx, start, fill, list, &sp, cnt);
        pp_stream_t st;
        pp_stream_init(&st);
        for (int k = 0; k < nr; k++) {
            poly_region_start(&c, k % 2 == 0, &st, &sp, cnt);
            for (uint32_t i = 0; i < fill[k]; i++)
                poly_encode(&c, &tri[list[start[k] + i]], 0, (k % rx) * 128, (k / rx) * 128, &st, &sp, cnt);
        }
        for (int tables = 0; tables < 2; tables++) {   /* 2DLevel exactly, then by the tables */
            c.level_tables = tables;
            vrz_kernels(&c, tri, nt, &sp, cnt, &st);
        }
        size_t w0 = st.n_words;
        poly_phong_stream(&st, c.light, c.ambient, c.diffuse, c.front_rgb, c.back_rgb, false);
        poly_words(st.n_words - w0, &sp, cnt);
        poly_grow_moved(30, &sp, cnt);
        CHECK(pp_stream_ok(&st));
        CHECK_MSG(sp.n[POLY_ROW_ENC_WORD] == st.n_words, "words charged %llu, words in the streams %zu",
                  (unsigned long long)sp.n[POLY_ROW_ENC_WORD], st.n_words);
        check_rows(&sp, cnt, poly_shading_name((poly_shading_t)sh));
        for (int i = 0; i < POLY_ROW_COUNT; i++)
            ran[i] = ran[i] || sp.n[i] > 0;
        pp_stream_free(&st);
        free(list);
        free(tri);
        free(cnt);
    }
    const vr_cost_entry_t *t = poly_cost_table();
    for (int i = 0; i < POLY_ROW_COUNT; i++)
        CHECK_MSG(ran[i], "row %s never ran", t[i].name);
    free(in);
}
