/* test_mesh_tri.c: the triangle core of the polygon renderer (mesh_tri.h):
 * a fan's pixels covered exactly once with no gaps, on any sample grid, and
 * perspective-correct interpolation against values worked out by hand. */
#include <math.h>
#include <string.h>

#include "harness.h"
#include "render/mesh/mesh_tri.h"

static tri_vertex_t tv(double x, double y)
{
    tri_vertex_t v;
    memset(&v, 0, sizeof v);
    v.x = x, v.y = y, v.inv_w = 1;
    return v;
}

/* Is p strictly inside the convex polygon (counter-clockwise in these
 * coordinates), or on its boundary (*on)? */
static bool in_convex(const double (*poly)[2], int n, double px, double py, bool *on)
{
    bool inside = true;
    *on = false;
    for (int i = 0; i < n; i++) {
        const double *a = poly[i], *b = poly[(i + 1) % n];
        double c = (b[0] - a[0]) * (py - a[1]) - (b[1] - a[1]) * (px - a[0]);
        if (c < 0)
            return false;
        if (c == 0)
            *on = true, inside = false;
    }
    return inside;
}

TEST(mesh_tri_a_fan_covers_every_sample_exactly_once)
{
    /* a 12-gon around a centre off the grid, cut into a fan of 12 triangles
     * (alternating orientation, so both signs of area are tested), plus
     * vertices on exact pixel centres; sampled on three grids */
    enum { N = 12 };
    double poly[N][2], cx = 20.25, cy = 19.5;
    for (int i = 0; i < N; i++) {
        double a = 2 * 3.14159265358979323846 * i / N;
        poly[i][0] = cx + 15 * cos(a), poly[i][1] = cy + 15 * sin(a);
    }
    poly[0][0] = 35.5, poly[0][1] = 19.5;    /* a vertex on a pixel centre */
    tri_setup_t t[N];
    for (int i = 0; i < N; i++) {
        tri_vertex_t c = tv(cx, cy), a = tv(poly[i][0], poly[i][1]);
        tri_vertex_t b = tv(poly[(i + 1) % N][0], poly[(i + 1) % N][1]);
        REQUIRE(i % 2 ? tri_setup(&t[i], &c, &a, &b, 0) : tri_setup(&t[i], &b, &a, &c, 0));
    }
    for (int step = 1; step <= 4; step *= 2) {
        int twice = 0, gaps = 0, outside = 0, inside = 0;
        for (int j = 0; j * step < 40; j++)
            for (int i = 0; i * step < 40; i++) {
                double px = i * step + 0.5, py = j * step + 0.5, b[3];
                int hits = 0;
                for (int k = 0; k < N; k++)
                    hits += tri_cover(&t[k], px, py, b);
                bool on, in = in_convex((const double (*)[2])poly, N, px, py, &on);
                twice += hits > 1;
                gaps += in && hits == 0;
                outside += !in && !on && hits > 0;
                inside += in;
            }
        CHECK_EQ(twice, 0);
        CHECK_EQ(gaps, 0);
        CHECK_EQ(outside, 0);
        CHECK(inside > 600 / (step * step));
    }
}

TEST(mesh_tri_interpolation_is_perspective_correct)
{
    /* A segment in camera space from P0 = (-1, *, -1) to P1 = (3, *, -3),
     * attribute u = s along it (u = 0 at P0, 1 at P1).  With w = -z the
     * projected x is X = (-1 + 4 s) / (1 + 2 s), so X runs -1 .. 1 and
     * s = (1 + X) / (4 - 2 X): at the screen centre X = 0, u = 1/4 (a screen-
     * space lerp would give 1/2), at X = 1/2, u = 1/2. */
    tri_vertex_t a = tv(-1, 0), b = tv(1, 0), c = tv(-1, 1);
    a.inv_w = 1, b.inv_w = 1.0 / 3, c.inv_w = 1;
    a.attr[0] = 0, b.attr[0] = 1, c.attr[0] = 0;
    a.attr[1] = 5, b.attr[1] = 5, c.attr[1] = 5;   /* a constant stays constant */
    tri_setup_t t;
    REQUIRE(tri_setup(&t, &a, &b, &c, 2));
    double bary[3], u[2];
    REQUIRE(tri_cover(&t, 0, 0, bary));
    tri_attrs(&t, bary, u);
    CHECK_NEAR(u[0], 0.25, 1e-12);
    CHECK_NEAR(u[1], 5, 1e-12);
    REQUIRE(tri_cover(&t, 0.5, 0, bary));
    tri_attrs(&t, bary, u);
    CHECK_NEAR(u[0], 0.5, 1e-12);
    /* the edge (0, 0) lies on belongs to one side only: exactly one of the
     * two triangles sharing it reports it */
    tri_vertex_t d = tv(1, -1);
    tri_setup_t t2;
    REQUIRE(tri_setup(&t2, &a, &d, &b, 0));
    CHECK_EQ((int)tri_cover(&t, 0, 0, bary) + (int)tri_cover(&t2, 0, 0, bary), 1);
    /* zero area: nothing to draw */
    tri_vertex_t e = tv(3, 0);
    CHECK(!tri_setup(&t2, &a, &b, &e, 0));
}
