/* test_phantom.c: the procedural phantoms against values worked out by hand
 * from their published definitions (not from phantom.c's output). */
#include <math.h>
#include <string.h>

#include "harness.h"
#include "render/volume.h"

/* On an n = 200 grid, voxel centres are at -1 + (2i+1)/200 = -0.995 + 0.01 i
 * along x and z, and y = +0.995 - 0.01 j (row 0 at the top, +y). */
static int ix(double x) { return (int)lround((x + 0.995) / 0.01); }
static int jy(double y) { return (int)lround((0.995 - y) / 0.01); }

TEST(phantom_shepp_logan_known_points)
{
    volume_t v;
    REQUIRE_MSG(phantom_make("shepp-logan", 200, 200, 200, &v) == PP5_OK, "%s",
                pp5_error_text());
    /* Sums of the Kak-Slaney ellipsoids containing each whole voxel, with the
     * Yu-Ye-Wang intensities (1, -0.8, -0.2, -0.2, 0.2, 0.2, 0.1, 0.1, 0.2,
     * -0.2) times the documented scale 200.  Each point was checked by hand to
     * lie, with all 8 voxel corners, strictly inside or outside every
     * ellipsoid (see the notes). */
    struct { double x, y, z, want; const char *why; } pts[] = {
        /* centre: in a (skull) and b (brain) only */
        {0.005, 0.005, 0.005, 200 * (1.0 - 0.8), "brain"},
        /* centre of ventricle c (-0.22, 0, -0.25): a + b + c */
        {-0.225, 0.005, -0.245, 200 * (1.0 - 0.8 - 0.2), "ventricle c"},
        /* centre of e (0, 0.35, -0.25): a + b + e; f is 0.255 away */
        {0.005, 0.355, -0.245, 200 * (1.0 - 0.8 + 0.2), "ellipsoid e"},
        /* in f (0, 0.1, -0.25) r = 0.046 and in e (its y extent 0.1..0.6) */
        {0.005, 0.125, -0.245, 200 * (1.0 - 0.8 + 0.2 + 0.2), "f inside e"},
        /* centre of j (0, 0.1, 0.625): a + b + j */
        {0.005, 0.105, 0.625, 200 * (1.0 - 0.8 - 0.2), "ellipsoid j"},
        /* skull shell: y = 0.895 is inside a (0.92) and outside b (0.874) */
        {0.005, 0.895, 0.005, 200 * 1.0, "skull"},
        /* corner of the box: air */
        {0.995, 0.995, 0.995, 0.0, "air"},
    };
    for (size_t i = 0; i < sizeof pts / sizeof pts[0]; i++) {
        int xi = ix(pts[i].x), yj = jy(pts[i].y), zk = ix(pts[i].z);
        REQUIRE(xi >= 0 && xi < 200 && yj >= 0 && yj < 200 && zk >= 0 && zk < 200);
        CHECK_MSG(fabs(volume_at(&v, xi, yj, zk) - pts[i].want) < 1e-4,
                  "%s at (%g,%g,%g): %g, want %g", pts[i].why, pts[i].x, pts[i].y, pts[i].z,
                  volume_at(&v, xi, yj, zk), pts[i].want);
    }
    /* The documented value range: 0 (air, ventricles) .. 200 (skull). */
    CHECK_NEAR(v.min_value, 0, 1e-4);
    CHECK_NEAR(v.max_value, 200, 1e-4);
    /* Slice z = 0.305 meets only a and b (c, d, e end below z = 0.25; i and j
     * start at z = 0.525), both centred on the axis: the slice must be mirror
     * symmetric in x and in y. */
    int k = ix(0.305);
    double worst = 0;
    for (int j = 0; j < 200; j++)
        for (int i = 0; i < 200; i++) {
            worst = fmax(worst, fabs(volume_at(&v, i, j, k) - volume_at(&v, 199 - i, j, k)));
            worst = fmax(worst, fabs(volume_at(&v, i, j, k) - volume_at(&v, i, 199 - j, k)));
        }
    CHECK_MSG(worst < 1e-3, "asymmetry %g", worst);
    /* ... whereas the full phantom is not symmetric in x: 0.35 along c's long
     * axis (0.41, direction 108 degrees) from its centre is (-0.328, 0.333),
     * inside c; the mirror point is 0.35 along d's axis, but d's semi-axis is
     * only 0.31, so it is plain brain. */
    int kc = ix(-0.245);
    CHECK_NEAR(volume_at(&v, ix(-0.325), jy(0.335), kc), 0, 1e-4);
    CHECK_NEAR(volume_at(&v, ix(0.325), jy(0.335), kc), 40, 1e-4);
    volume_free(&v);
}

TEST(phantom_shepp_logan_default_size_and_spacing)
{
    volume_t v;
    REQUIRE_MSG(phantom_make("shepp-logan", 0, 0, 0, &v) == PP5_OK, "%s", pp5_error_text());
    /* The paper's MR scan size (Levoy & Whitaker 1990, section 6). */
    CHECK_EQ(v.nx, 256);
    CHECK_EQ(v.ny, 256);
    CHECK_EQ(v.nz, 109);
    /* The phantom fills [-1,1] on every axis: spacing 1 : nx/ny : nx/nz. */
    CHECK_NEAR(v.spacing[0], 1.0, 1e-12);
    CHECK_NEAR(v.spacing[1], 1.0, 1e-12);
    CHECK_NEAR(v.spacing[2], 256.0 / 109.0, 1e-12);
    CHECK(strstr(v.source, "shepp-logan 256x256x109") != NULL);
    /* Partial-volume voxels exist on boundaries (values strictly between 40 and 200). */
    int partial = 0;
    for (int i = 0; i < 256; i++) {
        float f = volume_at(&v, i, 128, 54);
        partial += f > 41 && f < 199;
    }
    CHECK(partial > 0);
    volume_free(&v);
}

/* Marschner & Lobb (1994): rho(x,y,z) = (1 - sin(pi z / 2) + alpha (1 + rho_r(r)))
 * / (2 (1 + alpha)), rho_r(r) = cos(2 pi f_M cos(pi r / 2)), r = sqrt(x^2+y^2),
 * f_M = 6, alpha = 0.25; written out again here, independently of phantom.c. */
static double ml_reference(double x, double y, double z)
{
    const double pi = 3.14159265358979323846;
    double r = sqrt(x * x + y * y);
    double rr = cos(2 * pi * 6.0 * cos(pi * r / 2));
    return (1 - sin(pi * z / 2) + 0.25 * (1 + rr)) / 2.5;
}

TEST(phantom_marschner_lobb_against_formula)
{
    volume_t v;
    REQUIRE(phantom_make("marschner-lobb", 0, 0, 0, &v) == PP5_OK);
    CHECK_EQ(v.nx, 41);
    CHECK_EQ(v.ny, 41);
    CHECK_EQ(v.nz, 41);
    /* Grid: x_i = -1 + i/20.  Hand values:
     *  (0,0,0):  r = 0, rho_r = cos(12 pi) = 1 -> (1 + 0.5)/2.5 = 0.6
     *  (0,0,1):  (1 - 1 + 0.5)/2.5 = 0.2
     *  (0,0,-1): (1 + 1 + 0.5)/2.5 = 1.0
     *  (1,0,0):  r = 1, cos(pi/2) = 0, rho_r = 1 -> 0.6
     *  (0.5,0,0): cos(pi/4) = 0.70711, 12 pi * 0.70711 = 26.657 rad,
     *             cos(26.657) = 0.0464 -> (1 + 0.25 * 1.0464)/2.5 = 0.50464 */
    CHECK_NEAR(volume_at(&v, 20, 20, 20), 0.6, 1e-6);
    CHECK_NEAR(volume_at(&v, 20, 20, 40), 0.2, 1e-6);
    CHECK_NEAR(volume_at(&v, 20, 20, 0), 1.0, 1e-6);
    CHECK_NEAR(volume_at(&v, 40, 20, 20), 0.6, 1e-6);
    CHECK_NEAR(volume_at(&v, 30, 20, 20), 0.50464, 2e-4);
    double worst = 0;
    for (int k = 0; k < 41; k += 4)
        for (int j = 0; j < 41; j += 3)
            for (int i = 0; i < 41; i += 5)
                worst = fmax(worst, fabs(volume_at(&v, i, j, k) -
                                         ml_reference(-1 + i / 20.0, -1 + j / 20.0,
                                                      -1 + k / 20.0)));
    CHECK_MSG(worst < 1e-6, "worst difference %g", worst);
    /* Symmetric under x -> -x and x <-> y. */
    CHECK_NEAR(volume_at(&v, 7, 13, 9), volume_at(&v, 33, 13, 9), 1e-7);
    CHECK_NEAR(volume_at(&v, 7, 13, 9), volume_at(&v, 13, 7, 9), 1e-7);
    CHECK(v.min_value >= 0 && v.max_value <= 1.0f);
    volume_free(&v);
}

TEST(phantom_sphere_shell_shape)
{
    volume_t v;
    REQUIRE(phantom_make("sphere-shell", 0, 0, 0, &v) == PP5_OK);
    CHECK_EQ(v.nx, 64);
    CHECK_EQ(v.nz, 64);
    /* Voxel centres at -1 + (2i+1)/64; i = 31 is x = -1/64. */
    CHECK_NEAR(volume_at(&v, 31, 31, 31), 0, 0);            /* centre: hollow */
    CHECK_NEAR(volume_at(&v, 0, 0, 0), 0, 0);               /* corner: outside */
    /* x = -1 + 53/64 = -0.172..., i = 10 -> x = -0.672 (between 0.55 and 0.80). */
    CHECK_NEAR(volume_at(&v, 10, 31, 31), 200, 0);
    CHECK_NEAR(volume_at(&v, 31, 53, 31), 200, 0);          /* y = 0.672 */
    double worst = 0;
    for (int k = 0; k < 64; k += 3)
        for (int j = 0; j < 64; j += 2)
            for (int i = 0; i < 64; i++) {
                float a = volume_at(&v, i, j, k);
                worst = fmax(worst, fabs(a - volume_at(&v, 63 - i, j, k)));
                worst = fmax(worst, fabs(a - volume_at(&v, j, i, k)));
                worst = fmax(worst, fabs(a - volume_at(&v, i, k, j)));
            }
    CHECK_MSG(worst < 1e-3, "asymmetry %g", worst);
    CHECK_NEAR(v.max_value, 200, 0);
    volume_free(&v);
}

TEST(phantom_rejects_bad_requests)
{
    volume_t v;
    memset(&v, 0, sizeof v);
    CHECK_EQ(phantom_make("shepp-logn", 0, 0, 0, &v), PP5_E_CONFIG);
    CHECK_MSG(strstr(pp5_error_text(), "shepp-logan") != NULL, "lists names: %s",
              pp5_error_text());
    CHECK_EQ(phantom_make(NULL, 0, 0, 0, &v), PP5_E_CONFIG);
    CHECK_EQ(phantom_make("sphere-shell", 8, 0, 8, &v), PP5_E_RANGE);
    CHECK_EQ(phantom_make("sphere-shell", 8, -8, 8, &v), PP5_E_RANGE);
    CHECK_EQ(phantom_make("sphere-shell", 8, 8, VOLUME_MAX_SIDE + 1, &v), PP5_E_RANGE);
    CHECK(v.data == NULL);
    /* Deterministic: the same request gives the same voxels. */
    volume_t a, b;
    REQUIRE(phantom_make("shepp-logan", 24, 20, 16, &a) == PP5_OK);
    REQUIRE(phantom_make("shepp-logan", 24, 20, 16, &b) == PP5_OK);
    CHECK(a.hash == b.hash);
    CHECK(memcmp(a.data, b.data, 24 * 20 * 16 * sizeof(float)) == 0);
    volume_free(&a);
    volume_free(&b);
}
