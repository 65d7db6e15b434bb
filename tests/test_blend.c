/* test_blend.c: the per-ray maths of MIP, DEMIP and MIDA against values
 * worked out by hand, the max pyramid, the colour sphere, the depths, and
 * the blend options. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "render/blend_ray.h"
#include "render/colour_sphere.h"
#include "render/scalar_pyramid.h"

TEST(blend_material_is_the_window_ramp)
{
    /* --window 1500,2000: material 0 at 500, 1 at 2500. */
    blend_window_t w = {500.0f, 1.0f / 2000.0f};
    CHECK_NEAR(blend_material(&w, 400.0f), 0.0, 0.0);
    CHECK_NEAR(blend_material(&w, 500.0f), 0.0, 0.0);
    CHECK_NEAR(blend_material(&w, 1000.0f), 0.25, 1e-7);
    CHECK_NEAR(blend_material(&w, 2000.0f), 0.75, 1e-7);
    CHECK_NEAR(blend_material(&w, 3000.0f), 1.0, 0.0);
    CHECK_NEAR(blend_material(&w, NAN), 0.0, 0.0);
}

TEST(blend_eq1_and_eq2_by_hand)
{
    /* 0.5 * 0.85 + 2 * 0.15 * 0.75 = 0.425 + 0.225 */
    CHECK_NEAR(demip_eq1(0.5f, 0.25f, 0.15f), 0.65, 1e-6);
    /* dw = 0 is MIP exactly; bright and near exceeds 1 and is clamped. */
    CHECK(demip_eq1(0.37f, 0.8f, 0.0f) == 0.37f);
    CHECK(demip_eq1(1.0f, 0.0f, 0.5f) == 1.0f);
    /* far and dark: 0.1 * 0.7 + 0.6 * 0 */
    CHECK_NEAR(demip_eq1(0.1f, 1.0f, 0.3f), 0.07, 1e-7);
    float sph[3] = {1.0f, 0.0f, 0.0f}, rgb[3];
    demip_eq2(0.6f, sph, 0.25f, rgb);
    CHECK_NEAR(rgb[0], 0.6 * 0.75 + 0.25, 1e-6);
    CHECK_NEAR(rgb[1], 0.45, 1e-6);
    CHECK_NEAR(rgb[2], 0.45, 1e-6);
}

TEST(blend_mip_rays_first_maximum_and_ray2_stop)
{
    /* Samples 0.2 0.7 0.4 0.7 0.9 0.9: m_max 0.9 first at 4; with eps 0.25
     * ray 2 stops at the first m >= 0.65, index 1. */
    const float m[6] = {0.2f, 0.7f, 0.4f, 0.7f, 0.9f, 0.9f};
    mip_ray_t r;
    mip_ray_init(&r);
    for (long k = 0; k < 6; k++)
        mip_ray_sample(&r, k, m[k]);
    CHECK(r.m_max == 0.9f);
    CHECK_EQ(r.k_max, 4);
    float thr = demip_ray2_threshold(r.m_max, 0.25f);
    long stop = 0;
    while (!demip_ray2_stops(m[stop], thr))
        stop++;
    CHECK_EQ(stop, 1);
    /* Material 0 is never "the same material", whatever eps. */
    CHECK(!demip_ray2_stops(0.0f, -0.5f));
    CHECK(mip_ray_can_skip(&r, 0.9f) && !mip_ray_can_skip(&r, 0.95f));
}

TEST(blend_mida_by_hand)
{
    /* Materials 0.5, 0.5, 1.0 with opacity = material:
     *   1: delta 0.5, beta 0.5: C = 0 + 1 * 0.5 * 0.5 = 0.25, A = 0.5
     *   2: delta 0,   beta 1:   w = 0.5 * 0.5 = 0.25, C = 0.375, A = 0.75
     *   3: delta 0.5, beta 0.5: w = (1 - 0.375) * 1 = 0.625,
     *      C = 0.1875 + 0.625 = 0.8125, A = 0.375 + 0.625 = 1 */
    mida_ray_t s;
    mida_ray_init(&s);
    mida_ray_sample(&s, 0.5f, 0.5f, 0.95f);
    CHECK_NEAR(s.colour, 0.25, 1e-7);
    CHECK_NEAR(s.alpha, 0.5, 1e-7);
    mida_ray_sample(&s, 0.5f, 0.5f, 0.95f);
    CHECK_NEAR(s.colour, 0.375, 1e-7);
    CHECK_NEAR(s.alpha, 0.75, 1e-7);
    CHECK(mida_ray_sample(&s, 1.0f, 1.0f, 0.95f));   /* alpha 1, f_max 1: may stop */
    CHECK_NEAR(s.colour, 0.8125, 1e-6);
    CHECK_NEAR(s.alpha, 1.0, 1e-6);
    /* Without a new maximum MIDA is front-to-back compositing. */
    mida_ray_t t;
    mida_ray_init(&t);
    float acc[3] = {0, 0, 0}, acc_a = 0.0f;
    for (int i = 0; i < 5; i++) {
        mida_ray_sample(&t, 0.3f, 0.2f, 0.95f);
        const float c[3] = {0.3f * 0.2f, 0.3f * 0.2f, 0.3f * 0.2f};
        raycast_composite(acc, &acc_a, c, 0.2f);
    }
    CHECK_NEAR(t.colour, acc[0], 1e-6);
    CHECK_NEAR(t.alpha, acc_a, 1e-6);
    /* Opacity for a sample standing for 2 units: 1 - (1 - 0.5)^2. */
    CHECK_NEAR(mida_opacity(0.5f, 2.0f), 0.75, 1e-6);
    CHECK(mida_opacity(0.3f, 1.0f) == 0.3f);
}

/* A deterministic pseudo-random volume with odd sides (partial children). */
static void random_volume(volume_t *v, int nx, int ny, int nz)
{
    REQUIRE(volume_alloc(v, nx, ny, nz) == PP5_OK);
    uint32_t x = 12345u;
    for (size_t i = 0; i < (size_t)nx * ny * nz; i++) {
        x = x * 1664525u + 1013904223u;
        v->data[i] = (float)(x >> 8) / (float)(1u << 24) * 1000.0f - 100.0f;
    }
    volume_update_stats(v);
}

/* Largest level-0 value covered by voxel (x, y, z) of level n. */
static float covered_max(const volume_t *v, int n, int x, int y, int z)
{
    float m = -INFINITY;
    int s = 1 << n;
    for (int k = z * s; k < (z + 1) * s && k < v->nz; k++)
        for (int j = y * s; j < (y + 1) * s && j < v->ny; j++)
            for (int i = x * s; i < (x + 1) * s && i < v->nx; i++)
                m = fmaxf(m, volume_at(v, i, j, k));
    return m;
}

static long count_lost_maxima(const scalar_pyramid_t *p, const volume_t *v)
{
    long lost = 0;
    for (int n = 1; n < p->levels; n++) {
        const scalar_level_t *L = &p->level[n];
        for (int z = 0; z < L->nz; z++)
            for (int y = 0; y < L->ny; y++)
                for (int x = 0; x < L->nx; x++)
                    lost += scalar_at(L, x, y, z) < covered_max(v, n, x, y, z);
    }
    return lost;
}

TEST(blend_max_pyramid_never_loses_a_maximum)
{
    volume_t v;
    random_volume(&v, 23, 18, 11);
    scalar_pyramid_t pmax, pbox;
    REQUIRE(scalar_pyramid_build(&pmax, &v, SCALAR_PYRAMID_MAX, 2) == PP5_OK);
    REQUIRE(scalar_pyramid_build(&pbox, &v, SCALAR_PYRAMID_BOX, 1) == PP5_OK);
    CHECK_EQ(pmax.levels, 6);     /* 23 -> 12 -> 6 -> 3 -> 2 -> 1 */
    CHECK_EQ(count_lost_maxima(&pmax, &v), 0);
    /* The check can fail: the box filter lowers maxima almost everywhere. */
    CHECK(count_lost_maxima(&pbox, &v) > 100);
    CHECK(scalar_at(&pmax.level[pmax.levels - 1], 0, 0, 0) == v.max_value);
    scalar_pyramid_free(&pmax);
    scalar_pyramid_free(&pbox);
    volume_free(&v);
}

TEST(blend_node_bounds_bound_every_sample)
{
    volume_t v;
    random_volume(&v, 17, 13, 9);
    scalar_pyramid_t p;
    REQUIRE(scalar_pyramid_build(&p, &v, SCALAR_PYRAMID_MAX, 1) == PP5_OK);
    uint32_t x = 99u;
    long above = 0;
    for (int n = 0; n < 3; n++) {
        const scalar_level_t *L = &p.level[n];
        for (int i = 0; i < 20000; i++) {
            float pos[3], q[3];
            int fl[3], c[3];
            for (int a = 0; a < 3; a++) {
                x = x * 1664525u + 1013904223u;
                /* Positions from a voxel outside the volume to one beyond. */
                pos[a] = ((float)(x >> 8) / (float)(1u << 24)) * ((float)v.nx + 2.0f) - 1.0f;
            }
            scalar_level_coords(pos, n, q, fl);
            int dims[3] = {L->nx, L->ny, L->nz};
            for (int a = 0; a < 3; a++)
                c[a] = fl[a] < 0 ? 0 : (fl[a] >= dims[a] ? dims[a] - 1 : fl[a]);
            float s = scalar_trilerp(L, q, fl);
            for (int h = 0; h < L->heights; h++)
                above += s > scalar_node_max(L, h, c[0], c[1], c[2]);
        }
    }
    CHECK_EQ(above, 0);
    scalar_pyramid_free(&p);
    volume_free(&v);
}

TEST(blend_brick_distance_maps_are_chessboard_distances)
{
    volume_t v;
    REQUIRE(volume_alloc(&v, 70, 45, 38) == PP5_OK);
    /* A few bright voxels in an empty volume. */
    const int spots[4][3] = {{3, 4, 5}, {60, 40, 30}, {35, 20, 2}, {36, 21, 3}};
    for (int i = 0; i < 4; i++)
        v.data[((size_t)spots[i][2] * v.ny + spots[i][1]) * v.nx + spots[i][0]] = 100.0f;
    volume_update_stats(&v);
    scalar_pyramid_t p;
    REQUIRE(scalar_pyramid_build(&p, &v, SCALAR_PYRAMID_MAX, 2) == PP5_OK);
    const scalar_level_t *L = &p.level[0];
    const int s = SCALAR_BRICK_SHIFT;
    long wrong = 0, zeros = 0;
    for (int j = 0; j < SCALAR_THRESHOLDS; j += 5)
        for (int bz = 0; bz < L->hz[s]; bz++)
            for (int by = 0; by < L->hy[s]; by++)
                for (int bx = 0; bx < L->hx[s]; bx++) {
                    /* Brute force over all bricks. */
                    int best = 255;
                    for (int z = 0; z < L->hz[s]; z++)
                        for (int y = 0; y < L->hy[s]; y++)
                            for (int x = 0; x < L->hx[s]; x++) {
                                size_t i = ((size_t)z * L->hy[s] + y) * L->hx[s] + x;
                                if (!(L->node_max[s][i] > p.threshold[j]))
                                    continue;
                                int d = abs(x - bx);
                                d = abs(y - by) > d ? abs(y - by) : d;
                                d = abs(z - bz) > d ? abs(z - bz) : d;
                                best = d < best ? d : best;
                            }
                    int got = scalar_brick_dist(L, j, bx << s, by << s, bz << s);
                    wrong += got != best;
                    zeros += got == 0;
                }
    CHECK_EQ(wrong, 0);
    CHECK(zeros >= 4);
    scalar_pyramid_free(&p);
    volume_free(&v);
}

TEST(blend_colour_sphere_maps_front_and_back_to_end_colours)
{
    for (int m = 0; m < SPHERE_MAP_COUNT; m++) {
        const sphere_map_info_t *info = colour_sphere_map_info((sphere_map_t)m);
        colour_sphere_t s;
        const float rot0[3] = {0, 0, 0};
        colour_sphere_init(&s, (sphere_map_t)m, rot0);
        /* Angles 0: the front pole faces a camera looking along +z, i.e. -z. */
        const float front[3] = {0, 0, -3}, back[3] = {0, 0, 5}, side[3] = {2, 0, 0};
        float rgb[3];
        colour_sphere_colour(&s, front, rgb);
        for (int k = 0; k < 3; k++)
            CHECK_NEAR(rgb[k], info->front[k], 1e-6);
        colour_sphere_colour(&s, back, rgb);
        for (int k = 0; k < 3; k++)
            CHECK_NEAR(rgb[k], info->back[k], 1e-6);
        colour_sphere_colour(&s, side, rgb);
        for (int k = 0; k < 3; k++)
            CHECK_NEAR(rgb[k], 0.5 * (info->front[k] + info->back[k]), 1e-6);
    }
    /* Rotated 90 degrees about y (the camera convention: forward = +x), the
     * front pole is -x. */
    colour_sphere_t s;
    const float rot[3] = {0, 90, 0};
    colour_sphere_init(&s, SPHERE_RED_BLUE, rot);
    CHECK_NEAR(s.pole[0], -1.0, 1e-6);
    float rgb[3];
    colour_sphere_colour(&s, (const float[3]){-1, 0, 0}, rgb);
    CHECK_NEAR(rgb[0], 1.0, 1e-6);
    CHECK_NEAR(rgb[2], 0.0, 1e-6);
    sphere_map_t map;
    CHECK(colour_sphere_map_parse("orange-blue", &map) == PP5_OK && map == SPHERE_ORANGE_BLUE);
    CHECK(colour_sphere_map_parse("purple", &map) == PP5_E_CONFIG);
    CHECK(strstr(pp5_error_text(), "--sphere-map") != NULL);
}

/* A camera over a box of 30 x 20 x 40 voxels, spacing 1:1:2. */
static void depth_frame(float rx, float ry, float rz, projection_t proj, camera_t *cam,
                        blend_frame_t *f)
{
    mip3d_t m;
    memset(&m, 0, sizeof m);
    m.levels = 1;
    m.level[0].nx = 30, m.level[0].ny = 20, m.level[0].nz = 40;
    m.spacing[0] = m.spacing[1] = 1.0f;
    m.spacing[2] = 2.0f;
    view_params_t v;
    view_defaults(&v);
    v.rot_x_deg = rx, v.rot_y_deg = ry, v.rot_z_deg = rz;
    v.projection = proj;
    v.eye_distance = 2.5f;
    camera_setup(cam, &v, &m, 64, 64);
    blend_settings_t b;
    blend_settings_defaults(&b);
    blend_frame_init(f, &b, cam, 0.0f, 1.0f, 0.95f);
}

TEST(blend_exact_depth_is_0_at_nearest_corner_and_1_at_farthest)
{
    const float views[4][3] = {{0, 0, 0}, {30, 45, 10}, {-70, 200, 33}, {90, 0, 180}};
    for (int p = 0; p < 2; p++)
        for (int i = 0; i < 4; i++) {
            camera_t cam;
            blend_frame_t f;
            projection_t proj = p ? PROJECTION_PERSPECTIVE : PROJECTION_PARALLEL;
            depth_frame(views[i][0], views[i][1], views[i][2], proj, &cam, &f);
            /* The corners in double: box [0, 29] x [0, 19] x [0, 78]. */
            double dmin = INFINITY, dmax = -INFINITY;
            float cmin[3] = {0}, cmax[3] = {0};
            for (int c = 0; c < 8; c++) {
                double q[3] = {c & 1 ? 29.0 : 0.0, c & 2 ? 19.0 : 0.0, c & 4 ? 78.0 : 0.0}, d = 0;
                if (proj == PROJECTION_PARALLEL) {
                    for (int a = 0; a < 3; a++)
                        d += q[a] * cam.forward[a];
                } else {
                    for (int a = 0; a < 3; a++)
                        d += (q[a] - cam.eye[a]) * (q[a] - cam.eye[a]);
                    d = sqrt(d);
                }
                float qf[3] = {(float)q[0], (float)q[1], (float)q[2]};
                if (d < dmin) {
                    dmin = d;
                    memcpy(cmin, qf, sizeof qf);
                }
                if (d > dmax) {
                    dmax = d;
                    memcpy(cmax, qf, sizeof qf);
                }
            }
            CHECK_NEAR(demip_depth_exact(&f, cmin), 0.0, 1e-6);
            CHECK_NEAR(demip_depth_exact(&f, cmax), 1.0, 1e-6);
            float centre = demip_depth_exact(&f, cam.centre);
            CHECK(centre > 0.05f && centre < 0.95f);
        }
}

TEST(blend_entry_plus_length_equals_exact_depth_under_parallel_projection)
{
    camera_t cam;
    blend_frame_t f;
    depth_frame(30, 45, 10, PROJECTION_PARALLEL, &cam, &f);
    double worst = 0;
    for (int i = 0; i < 50; i++) {
        float o[3], d[3];
        camera_ray(&cam, 10.0f + (float)i, 5.0f + 1.1f * (float)i, o, d);
        float t_entry = 5.0f + 0.7f * (float)i, t_hit = t_entry + 0.9f * (float)i, e[3], p[3];
        for (int a = 0; a < 3; a++) {
            e[a] = o[a] + t_entry * d[a];
            p[a] = o[a] + t_hit * d[a];
        }
        double diff = fabs(demip_depth_exact(&f, p) -
                           demip_depth_entry_plus_length(&f, e, t_hit - t_entry));
        worst = diff > worst ? diff : worst;
    }
    CHECK(worst < 2e-5);
    /* Under perspective they differ off the axis (the paper's approximation). */
    depth_frame(30, 45, 10, PROJECTION_PERSPECTIVE, &cam, &f);
    float o[3], d[3];
    camera_ray(&cam, 2.0f, 3.0f, o, d);
    float e[3], p[3];
    for (int a = 0; a < 3; a++) {
        e[a] = o[a] + 60.0f * d[a];
        p[a] = o[a] + 90.0f * d[a];
    }
    CHECK(fabs(demip_depth_exact(&f, p) - demip_depth_entry_plus_length(&f, e, 30.0f)) > 1e-3);
}

TEST(blend_options_parse_and_reject_bad_values)
{
    blend_settings_t b;
    blend_settings_defaults(&b);
    CHECK(b.mode == BLEND_COMPOSITE && b.depth_weight == 0.15f && b.sphere_weight == 0.3f);
    CHECK(blend_option("blend", "demip", &b) == PP5_OK && b.mode == BLEND_DEMIP);
    CHECK(blend_option("window", "1500,2000", &b) == PP5_OK && b.window_centre == 1500.0f &&
          b.window_width == 2000.0f);
    CHECK(blend_option("tolerance", "0.05", &b) == PP5_OK && b.tolerance == 0.05f);
    CHECK(blend_option("depth", "entry-plus-length", &b) == PP5_OK &&
          b.depth == DEMIP_DEPTH_ENTRY_PLUS_LENGTH);
    CHECK(blend_option("demip-reading", "B", &b) == PP5_OK && b.reading == DEMIP_READING_B);
    CHECK(blend_option("sphere-rotate", "10,-20,30.5", &b) == PP5_OK && b.sphere_rot_given &&
          b.sphere_rot_deg[2] == 30.5f);
    CHECK(blend_option("mip-pyramid", "box", &b) == PP5_OK && b.pyramid == SCALAR_PYRAMID_BOX);
    CHECK(blend_settings_check(&b) == PP5_OK);
    const char *bad[][2] = {{"blend", "maximum"},   {"window", "5,0"},
                            {"window", "5"},        {"tolerance", "nan"},
                            {"tolerance", "1.5"},   {"depth-weight", "-0.1"},
                            {"sphere-weight", "x"}, {"sphere-rotate", "1,2"},
                            {"sphere-rotate", "1,2,inf"}, {"depth", "opengl"},
                            {"demip-reading", "C"}, {"mip-pyramid", "min"},
                            {"no-such", "1"}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        blend_settings_t c = b;
        CHECK_MSG(blend_option(bad[i][0], bad[i][1], &c) == PP5_E_CONFIG, "--%s %s accepted",
                  bad[i][0], bad[i][1]);
        char opt[64];
        snprintf(opt, sizeof opt, "--%s", bad[i][0]);
        CHECK_MSG(strstr(pp5_error_text(), opt) != NULL, "message '%s' does not name %s",
                  pp5_error_text(), opt);
    }
    b.depth_weight = NAN;
    CHECK(blend_settings_check(&b) == PP5_E_RANGE);
}
