/* test_mip.c: the 3D mip map pyramid (sizes, 2x2x2 box filter with zero
 * padding, blending between levels) and the octree's conservativeness. */
#include <math.h>
#include <string.h>

#include "harness.h"
#include "render/mip3d.h"
#include "render/octree.h"

/* Opacity 0.5 wherever the value is 10 (a contour with zero gradient), so
 * the stored alpha is a 0/0.5 indicator of the test's own pattern. */
static void build_pattern(mip3d_t *m, int nx, int ny, int nz, int (*on)(int, int, int))
{
    volume_t v;
    REQUIRE(volume_alloc(&v, nx, ny, nz) == PP5_OK);
    for (int z = 0; z < nz; z++)
        for (int y = 0; y < ny; y++)
            for (int x = 0; x < nx; x++)
                v.data[((size_t)z * ny + y) * nx + x] = on(x, y, z) ? 10.0f : 0.0f;
    v.spacing[0] = v.spacing[1] = v.spacing[2] = 1.0;
    /* Width 1e-6: only exact 10s are opaque (neighbours have |g| >= 5). */
    classify_tf_t tf = {.count = 1, .contour = {{10.0f, 0.5f, 1e-6f, {1.0f, 1.0f, 1.0f}, 0.0f}}};
    shade_params_t sh;
    shade_defaults(&sh);
    REQUIRE(mip3d_build(m, &v, &tf, &sh, 2) == PP5_OK);
    volume_free(&v);
}

static int all_on(int x, int y, int z) { (void)x; (void)y; (void)z; return 1; }
static int few_on(int x, int y, int z)
{
    return (x == 3 && y == 4 && z == 2) || (x == 17 && y == 9 && z == 11);
}

TEST(mip_pyramid_sizes)
{
    mip3d_t m;
    build_pattern(&m, 5, 4, 3, all_on);
    /* ceil halving: 5x4x3, 3x2x2, 2x1x1, 1x1x1. */
    CHECK_EQ(m.levels, 4);
    int want[4][3] = {{5, 4, 3}, {3, 2, 2}, {2, 1, 1}, {1, 1, 1}};
    for (int l = 0; l < 4; l++) {
        CHECK_EQ(m.level[l].nx, want[l][0]);
        CHECK_EQ(m.level[l].ny, want[l][1]);
        CHECK_EQ(m.level[l].nz, want[l][2]);
    }
    CHECK_EQ(m.stride, 4);
    mip3d_free(&m);
}

TEST(mip_box_filter_with_zero_padding_by_hand)
{
    mip3d_t m;
    build_pattern(&m, 3, 3, 3, all_on);
    /* Level 0: alpha 0.5 everywhere.  Level 1 is 2x2x2: voxel (0,0,0) averages
     * 8 present children (0.5); (1,0,0) has 4 present (x = 2 only): 0.25;
     * (1,1,0) has 2: 0.125; (1,1,1) has 1: 0.0625. */
    const mip3d_level_t *L = &m.level[1];
    REQUIRE(L->nx == 2 && L->ny == 2 && L->nz == 2);
    CHECK_NEAR(L->data[(0) * 4 + MIP3D_A], 0.5, 1e-7);
    CHECK_NEAR(L->data[(1) * 4 + MIP3D_A], 0.25, 1e-7);
    CHECK_NEAR(L->data[(1 + 2) * 4 + MIP3D_A], 0.125, 1e-7);
    CHECK_NEAR(L->data[(1 + 2 + 4) * 4 + MIP3D_A], 0.0625, 1e-7);
    /* Level 2 (1x1x1) is the mean of those 8 level-1 values:
     * (0.5 + 3*0.25 + 3*0.125 + 0.0625) / 8 = 27 * 0.5 / 64. */
    CHECK_NEAR(m.level[2].data[MIP3D_A], 27.0 * 0.5 / 64.0, 1e-7);
    mip3d_free(&m);
}

TEST(mip_every_level_is_the_mean_of_its_children)
{
    mip3d_t m;
    volume_t v;
    REQUIRE(phantom_make("shepp-logan", 21, 18, 11, &v) == PP5_OK);
    classify_tf_t tf;
    REQUIRE(classify_preset("shepp-logan", &tf) == PP5_OK);
    shade_params_t sh;
    shade_defaults(&sh);
    sh.lighting = SHADE_SPECULAR_FIXED_LIGHT;   /* 8 components */
    REQUIRE(mip3d_build(&m, &v, &tf, &sh, 3) == PP5_OK);
    CHECK_EQ(m.stride, 8);
    double worst = 0.0;
    for (int l = 1; l < m.levels; l++) {
        const mip3d_level_t *S = &m.level[l - 1], *D = &m.level[l];
        for (int z = 0; z < D->nz; z++)
            for (int y = 0; y < D->ny; y++)
                for (int x = 0; x < D->nx; x++)
                    for (int k = 0; k < 8; k++) {
                        double sum = 0.0;
                        for (int c = 0; c < 8; c++) {
                            int cx = 2 * x + (c & 1), cy = 2 * y + ((c >> 1) & 1),
                                cz = 2 * z + (c >> 2);
                            if (cx < S->nx && cy < S->ny && cz < S->nz)
                                sum += S->data[(((size_t)cz * S->ny + cy) * S->nx + cx) * 8 + k];
                        }
                        double got = D->data[(((size_t)z * D->ny + y) * D->nx + x) * 8 + k];
                        if (fabs(got - sum / 8.0) > worst)
                            worst = fabs(got - sum / 8.0);
                    }
    }
    CHECK(worst < 1e-5);
    mip3d_free(&m);
    volume_free(&v);
}

TEST(mip_sample_blends_two_levels_linearly)
{
    mip3d_t m;
    build_pattern(&m, 8, 8, 8, few_on);
    float p[3] = {3.3f, 4.1f, 2.6f}, lo[4], hi[4], mid[4];
    mip3d_trilerp(&m, 0, p[0], p[1], p[2], lo);
    mip3d_trilerp(&m, 1, mip3d_level_coord(p[0], 1), mip3d_level_coord(p[1], 1),
                  mip3d_level_coord(p[2], 1), hi);
    mip3d_sample(&m, 0.25f, p, mid);
    CHECK(lo[MIP3D_A] > 0.0f);
    CHECK_NEAR(mid[MIP3D_A], 0.75 * lo[MIP3D_A] + 0.25 * hi[MIP3D_A], 1e-6);
    /* Level coordinate: voxel j of level n sits at (j + 0.5) 2^n - 0.5. */
    CHECK_NEAR(mip3d_level_coord(1.5f, 1), 0.5, 1e-7);
    CHECK_NEAR(mip3d_level_coord(3.5f, 2), 0.5, 1e-7);
    mip3d_free(&m);
}

TEST(mip_octree_empty_means_zero_sample)
{
    /* Exhaustive check on a sparse volume: wherever the octree reports an
     * empty node, every sample whose floor level is n (or, for the exact grid,
     * whose level is exactly n) is exactly zero, and the reported node
     * contains the sample. */
    mip3d_t m;
    build_pattern(&m, 24, 13, 14, few_on);
    octree_t o;
    REQUIRE(octree_build(&o, &m, 1) == PP5_OK);
    long empty = 0, occupied = 0, bad = 0, outside = 0, empty_exact = 0, occupied_exact = 0;
    float first_bad[4] = {0};      /* level, x, y, z of the first non-zero sample */
    for (int n = 0; n < m.levels; n++) {
        for (float z = -0.4f; z < 13.4f; z += 0.37f)
            for (float y = -0.4f; y < 12.4f; y += 0.41f)
                for (float x = -0.4f; x < 23.4f; x += 0.43f) {
                    float p[3] = {x, y, z}, lo[3], hi[3], s[4];
                    /* Blended samples (levels n .. n+1). */
                    if (octree_empty_node(&o, n, false, p, lo, hi) < 0) {
                        occupied++;
                    } else {
                        empty++;
                        for (int a = 0; a < 3; a++)
                            if (!(p[a] >= lo[a] && p[a] < hi[a]))
                                outside++;
                        for (float f = 0.0f; f < 1.0f; f += 0.125f) {
                            mip3d_sample(&m, (float)n + f, p, s);
                            if ((s[MIP3D_A] != 0.0f || s[MIP3D_R] != 0.0f) && bad++ == 0)
                                memcpy(first_bad, (float[4]){(float)n + f, x, y, z}, sizeof first_bad);
                        }
                    }
                    /* Samples at exactly level n. */
                    if (octree_empty_node(&o, n, true, p, lo, hi) < 0) {
                        occupied_exact++;
                    } else {
                        empty_exact++;
                        for (int a = 0; a < 3; a++)
                            if (!(p[a] >= lo[a] && p[a] < hi[a]))
                                outside++;
                        mip3d_sample(&m, (float)n, p, s);
                        if ((s[MIP3D_A] != 0.0f || s[MIP3D_R] != 0.0f) && bad++ == 0)
                            memcpy(first_bad, (float[4]){(float)n, x, y, z}, sizeof first_bad);
                    }
                }
    }
    CHECK(empty > 0);
    CHECK(occupied > 0);
    CHECK(occupied_exact > 0);
    CHECK(empty_exact > empty);          /* the exact grid is tighter */
    CHECK_MSG(bad == 0, "%ld samples in empty nodes are not zero; first: level %g at (%g, %g, %g)",
              bad, first_bad[0], first_bad[1], first_bad[2], first_bad[3]);
    CHECK_EQ(outside, 0);
    octree_free(&o);
    mip3d_free(&m);
}

TEST(mip_classification_by_hand)
{
    float rgb[3];
    /* Levoy 1988 contour: 1 - |v - f| / (r |g|): value 500, r = 2, |g| = 10. */
    classify_tf_t iso = {.count = 1, .contour = {{500.0f, 1.0f, 2.0f, {1.0f, 0.5f, 0.0f}, 0.0f}}};
    CHECK_NEAR(classify_voxel(&iso, 510.0f, 10.0f, rgb), 0.5, 1e-6);
    CHECK_NEAR(rgb[1], 0.5, 1e-6);
    CHECK_NEAR(classify_voxel(&iso, 520.0f, 10.0f, rgb), 0.0, 1e-7);
    CHECK_NEAR(classify_voxel(&iso, 500.0f, 0.0f, rgb), 1.0, 1e-7);   /* flat, on the value */
    CHECK_NEAR(classify_voxel(&iso, 501.0f, 0.0f, rgb), 0.0, 1e-7);   /* flat, off it */
    /* Two contours combine as layers: the second (520, opacity 0.5) gives
     * 0.5 * (1 - 10 / 20) = 0.25, so 1 - (1 - 0.5)(1 - 0.25). */
    classify_tf_t two = {.count = 2, .contour = {{500.0f, 1.0f, 2.0f, {1, 1, 1}, 0.0f},
                                                 {520.0f, 0.5f, 2.0f, {1, 1, 1}, 0.0f}}};
    CHECK_NEAR(classify_voxel(&two, 510.0f, 10.0f, rgb), 1.0 - 0.5 * 0.75, 1e-6);
    /* Value ramp (ct-skin-ramp): 0 at 350, 0.4 at 495, 0.8 from 640 on. */
    classify_tf_t ramp;
    REQUIRE(classify_preset("ct-skin-ramp", &ramp) == PP5_OK);
    CHECK_NEAR(classify_voxel(&ramp, 350.0f, 5.0f, rgb), 0.0, 1e-6);
    CHECK_NEAR(classify_voxel(&ramp, 495.0f, 5.0f, rgb), 0.4, 1e-6);
    CHECK_NEAR(classify_voxel(&ramp, 640.0f, 0.0f, rgb), 0.8, 1e-6);
    CHECK_NEAR(classify_voxel(&ramp, 3000.0f, 99.0f, rgb), 0.8, 1e-6);
    /* Below the preset's 5% floor: transparent (0.8 * 0.05 / 0.8 of the way). */
    CHECK_NEAR(classify_voxel(&ramp, 360.0f, 0.0f, rgb), 0.0, 1e-7);
}
