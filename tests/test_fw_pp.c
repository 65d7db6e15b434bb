/* test_fw_pp.c: the PP shading stream on an emulated renderer equals the integer definition (vr_shade_fixed.h) bit for bit (the kernels' operation counts are checked in test_fw_cost.c). */
#include <math.h>
#include <string.h>

#include "firmware/common/vr_shade_fixed.h"
#include "firmware/common/vr_shade_pp.h"
#include "fw_api.h"
#include "harness.h"
#include "renderer.h"

/* Deterministic pseudo-random words (xorshift) for the voxel blocks. */
static uint32_t next(uint32_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 17;
    *s ^= *s << 5;
    return *s;
}

static void run_case_l(const float half[3], const float *light, float ks, int exponent,
                       int two_sided, uint32_t seed)
{
    pp_params_t pp;
    pp_params_default(&pp);
    renderer_t r;
    REQUIRE(renderer_init(&r, 0, &pp) == PP5_OK);
    enum { N = 16384, SLOTS = 2 };
    static uint32_t a[SLOTS][N], n[SLOTS][N], out[N];
    for (int s = 0; s < SLOTS; s++) {
        for (int i = 0; i < N; i++) {
            a[s][i] = next(&seed);
            /* unit-length normals (the GP renormalises) plus some zero ones */
            float v[3] = {(float)((int)(next(&seed) % 2001) - 1000), (float)((int)(next(&seed) % 2001) - 1000),
                          (float)((int)(next(&seed) % 2001) - 1000)};
            float len = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
            if (i % 97 == 0 || len == 0.0f) {
                v[0] = v[1] = v[2] = 0.0f;
            } else {
                for (int k = 0; k < 3; k++)
                    v[k] /= len;
            }
            n[s][i] = vr_pack_normal(v);
        }
        REQUIRE(renderer_bs_write(&r, (unsigned)s * 3, a[s]) == PP5_OK);
        REQUIRE(renderer_bs_write(&r, (unsigned)s * 3 + 1, n[s]) == PP5_OK);
    }
    vr_shade_consts_t c;
    vr_shade_consts(&c, half, ks, exponent, two_sided);
    if (light)
        vr_shade_consts_diffuse(&c, light, 0.15f, 0.85f);
    pp_stream_t st;
    pp_stream_init(&st);
    uint32_t slots[SLOTS] = {0, 1};
    vr_pp_shade_stream(&st, &c, slots, SLOTS);
    REQUIRE_MSG(pp_stream_ok(&st), "%s", pp_stream_error(&st));
    renderer_exec_result_t res;
    pp5_status_t e = renderer_execute(&r, st.words, st.n_words, &res);
    REQUIRE_MSG(e == PP5_OK, "%s", pp5_error_text());
    CHECK(res.total_cycles > 0);
    for (int s = 0; s < SLOTS; s++) {
        REQUIRE(renderer_bs_read(&r, (unsigned)s * 3 + 2, out) == PP5_OK);
        int bad = 0, first = 0;
        for (int i = 0; i < N; i++)
            if (out[i] != vr_shade_voxel(&c, a[s][i], n[s][i]) && bad++ == 0)
                first = i;
        CHECK_MSG(bad == 0, "slot %d: %d of %d voxels differ (exponent %d, ks %g); first: PP %d "
                  "gave %u, want %u", s, bad, N, exponent, ks, first, (unsigned)out[first],
                  (unsigned)vr_shade_voxel(&c, a[s][first], n[s][first]));
    }
    pp_stream_free(&st);
    renderer_free(&r);
}

static void run_case(const float half[3], float ks, int exponent, int two_sided, uint32_t seed)
{
    run_case_l(half, NULL, ks, exponent, two_sided, seed);
}

TEST(fw_pp_moving_object_stream_matches_integer_definition)
{
    float h[3] = {0.2f, -0.3f, -0.932738f}, l[3] = {-0.35f, -0.45f, -0.821854f};
    run_case_l(h, l, 0.3f, 20, 1, 31337u);
    run_case_l(h, l, 0.0f, 8, 0, 5150u);
}

TEST(fw_pp_shading_stream_matches_integer_definition)
{
    float h1[3] = {0.2f, -0.3f, -0.932738f};
    run_case(h1, 0.5f, 20, 1, 12345u);
    float h2[3] = {0.0f, 0.0f, -1.0f};
    run_case(h2, 1.5f, 1, 0, 777u);
    float h3[3] = {0.577350f, 0.577350f, 0.577350f};
    run_case(h3, 0.25f, 255, 1, 4242u);
}

/* The integer definition against float shading: the Q15 power stays within
 * a few units of 1/255 of a*ks*|N.H|^e for unit vectors. */
TEST(fw_fixed_point_shading_error_is_bounded)
{
    float h[3] = {0.3f, -0.4f, -0.866025f};
    vr_shade_consts_t c;
    vr_shade_consts(&c, h, 0.5f, 20, 1);
    uint32_t seed = 99u;
    double worst = 0;
    for (int i = 0; i < 20000; i++) {
        float v[3] = {(float)((int)(next(&seed) % 2001) - 1000), (float)((int)(next(&seed) % 2001) - 1000),
                      (float)((int)(next(&seed) % 2001) - 1000)};
        float len = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        if (len == 0.0f)
            continue;
        for (int k = 0; k < 3; k++)
            v[k] /= len;
        uint32_t a8 = 255u, blk = a8 << 24;   /* black, opaque: output = specular */
        uint32_t o = vr_shade_voxel(&c, blk, vr_pack_normal(v));
        double d = fabs((double)(v[0] * h[0] + v[1] * h[1] + v[2] * h[2]));
        double want = 0.5 * pow(d, 20.0) * 255.0;
        if (want > 255.0)
            want = 255.0;
        double err = fabs((double)(o & 255u) - want);
        worst = err > worst ? err : worst;
    }
    /* normals quantised to 1/511 move N.H by up to ~0.003, times e = 20 */
    CHECK_MSG(worst <= 4.0, "worst specular error %.2f / 255", worst);
}
