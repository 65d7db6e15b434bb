/* test_mesh_io.c: mesh readers on good and malformed files (every truncated
 * prefix of a binary PLY, absurd header counts), topology info, generated
 * meshes, hole filling, and the bounded Hausdorff distance on analytic cases. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "emu/util/status.h"
#include "harness.h"
#include "render/mesh/mesh.h"
#include "render/mesh/mesh_gen.h"
#include "render/mesh/mesh_hausdorff.h"
#include "render/mesh/mesh_info.h"

/* A unit square as two triangles, then a third vertex-sharing triangle. */
static const double SQ_POS[5][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}};

static void put_u32(uint8_t *p, uint32_t v, int be)
{
    for (int i = 0; i < 4; i++)
        p[be ? 3 - i : i] = (uint8_t)(v >> (8 * i));
}

/* A binary PLY of SQ_POS with one quad and one triangle (and an extra
 * vertex property and element to skip); returns its length. */
static size_t make_binary_ply(uint8_t *buf, int be)
{
    int n = sprintf((char *)buf, "ply\nformat %s 1.0\ncomment test\nelement vertex 5\n"
                    "property float x\nproperty float y\nproperty float z\nproperty uchar "
                    "flags\nelement face 2\nproperty list uchar int vertex_indices\n"
                    "element extra 1\nproperty short s\nend_header\n",
                    be ? "binary_big_endian" : "binary_little_endian");
    uint8_t *p = buf + n;
    for (int v = 0; v < 5; v++) {
        for (int k = 0; k < 3; k++) {
            float f = (float)SQ_POS[v][k];
            uint32_t bits;
            memcpy(&bits, &f, 4);
            put_u32(p, bits, be);
            p += 4;
        }
        *p++ = 7;
    }
    *p++ = 4;
    for (int i = 0; i < 4; i++, p += 4)
        put_u32(p, (uint32_t)i, be);
    *p++ = 3;
    uint32_t tri[3] = {1, 4, 2};
    for (int i = 0; i < 3; i++, p += 4)
        put_u32(p, tri[i], be);
    *p++ = 0, *p++ = 1;   /* the extra element's short */
    return (size_t)(p - buf);
}

static void check_square(const mesh_t *m)
{
    REQUIRE(m->n_vertices == 5 && m->n_faces == 3);
    for (int v = 0; v < 5; v++)
        for (int k = 0; k < 3; k++)
            CHECK_NEAR(m->pos[3 * v + k], SQ_POS[v][k], 0);
    /* the quad 0 1 2 3 fanned from 0, then 1 4 2 */
    static const int32_t want[9] = {0, 1, 2, 0, 2, 3, 1, 4, 2};
    for (int i = 0; i < 9; i++)
        CHECK_EQ(m->tri[i], want[i]);
}

TEST(mesh_ply_binary_both_byte_orders_and_every_truncated_prefix)
{
    uint8_t buf[1024];
    for (int be = 0; be < 2; be++) {
        size_t n = make_binary_ply(buf, be);
        mesh_t m;
        REQUIRE(mesh_load_ply("t.ply", buf, n, &m) == PP5_OK);
        check_square(&m);
        mesh_free(&m);
        for (size_t len = 0; len < n; len++) {
            pp5_status_t st = mesh_load_ply("cut.ply", buf, len, &m);
            CHECK_MSG(st == PP5_E_FORMAT, "prefix of %zu bytes: status %d", len, st);
            CHECK(strstr(pp5_error_text(), "cut.ply") != NULL);
        }
    }
}

TEST(mesh_ply_ascii_reads_like_binary_and_rejects_absurd_counts)
{
    const char *ply = "ply\nformat ascii 1.0\nelement vertex 5\nproperty double x\n"
                      "property double y\nproperty double z\nelement face 2\n"
                      "property list uchar uint vertex_index\nend_header\n"
                      "0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0 0\n4 0 1 2 3\n3 1 4 2\n";
    mesh_t m;
    REQUIRE(mesh_load_ply("a.ply", (const uint8_t *)ply, strlen(ply), &m) == PP5_OK);
    check_square(&m);
    mesh_free(&m);
    const char *absurd = "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n"
                         "property float x\nproperty float y\nproperty float z\nend_header\n";
    CHECK_EQ(mesh_load_ply("big.ply", (const uint8_t *)absurd, strlen(absurd), &m), PP5_E_RANGE);
    CHECK(strstr(pp5_error_text(), "at most 50000000") != NULL);
    /* a plausible count that the body cannot hold fails before allocating */
    const char *short_body = "ply\nformat binary_little_endian 1.0\nelement vertex 40000000\n"
                             "property float x\nproperty float y\nproperty float z\n"
                             "element face 1\nproperty list uchar int vertex_indices\n"
                             "end_header\nxyz";
    CHECK_EQ(mesh_load_ply("s.ply", (const uint8_t *)short_body, strlen(short_body), &m),
             PP5_E_FORMAT);
    CHECK(strstr(pp5_error_text(), "truncated") != NULL);
    const char *bad_index = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                            "property float y\nproperty float z\nelement face 1\n"
                            "property list uchar int vertex_indices\nend_header\n"
                            "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n";
    CHECK_EQ(mesh_load_ply("i.ply", (const uint8_t *)bad_index, strlen(bad_index), &m),
             PP5_E_FORMAT);
    CHECK(strstr(pp5_error_text(), "vertex 3 of 3") != NULL);
}

TEST(mesh_obj_and_off_read_the_same_mesh_and_name_bad_lines)
{
    const char *obj = "# square\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nvn 0 0 1\n"
                      "g a\nf 1//1 2//1 3//1 4//1\nf -4 -1 -3\n";
    mesh_t m;
    REQUIRE(mesh_load_obj("s.obj", obj, strlen(obj), &m) == PP5_OK);
    check_square(&m);
    mesh_free(&m);
    const char *off = "OFF\n# c\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0 0\n4 0 1 2 3\n"
                      "3 1 4 2 255 0 0\n";
    REQUIRE(mesh_load_off("s.off", off, strlen(off), &m) == PP5_OK);
    check_square(&m);
    mesh_free(&m);
    const char *bad = "v 0 0 0\nv 1 0 0\nf 1 2 9\n";
    CHECK_EQ(mesh_load_obj("b.obj", bad, strlen(bad), &m), PP5_E_FORMAT);
    CHECK(strstr(pp5_error_text(), "b.obj:3:") != NULL);
    const char *weird = "v 0 0 0\n$ hello\n";
    CHECK_EQ(mesh_load_obj("w.obj", weird, strlen(weird), &m), PP5_E_FORMAT);
    CHECK(strstr(pp5_error_text(), "w.obj:2: unsupported statement '$'") != NULL);
    const char *nan = "v 0 nan 0\n";
    CHECK_EQ(mesh_load_obj("n.obj", nan, strlen(nan), &m), PP5_E_FORMAT);
    const char *huge = "OFF\n999999999 1 0\n";
    CHECK_EQ(mesh_load_off("h.off", huge, strlen(huge), &m), PP5_E_RANGE);
    CHECK(strstr(pp5_error_text(), "h.off:2: 999999999 vertices (at most 50000000)") != NULL);
    const char *cut = "OFF\n5 2 0\n0 0 0\n1 0 0\n";
    CHECK_EQ(mesh_load_off("c.off", cut, strlen(cut), &m), PP5_E_FORMAT);
    CHECK(strstr(pp5_error_text(), "truncated: 2 of 5 vertices") != NULL);
}

TEST(mesh_files_round_trip_through_every_writer)
{
    mesh_t t, back;
    REQUIRE(mesh_gen_torus(12, 8, 1.0, 0.3, &t) == PP5_OK);
    const char *exts[3] = {"obj", "off", "ply"};
    for (int e = 0; e < 3; e++) {
        char path[1200];
        snprintf(path, sizeof path, "%s/t.%s", pp5_test_outdir(), exts[e]);
        REQUIRE(mesh_save(path, &t) == PP5_OK);
        REQUIRE(mesh_load(path, &back) == PP5_OK);
        CHECK_EQ(back.n_vertices, t.n_vertices);
        CHECK_EQ(back.n_faces, t.n_faces);
        double worst = 0;
        for (int i = 0; i < 3 * t.n_vertices; i++)
            worst = fmax(worst, fabs(back.pos[i] - t.pos[i]));
        CHECK(worst < 1e-6);   /* float32 in PLY, 9 digits in OBJ */
        CHECK(memcmp(back.tri, t.tri, sizeof *t.tri * 3 * (size_t)t.n_faces) == 0);
        mesh_free(&back);
    }
    mesh_free(&t);
}

TEST(mesh_info_counts_genus_and_boundary_loops_of_generated_meshes)
{
    mesh_t m;
    mesh_info_t in;
    REQUIRE(mesh_gen_uv_sphere(20, 20, 1.0, &m) == PP5_OK);
    REQUIRE(mesh_info(&m, &in) == PP5_OK);
    /* seed 003 Table 2: 760 faces, 382 vertices; a closed sphere: genus 0 */
    CHECK_EQ(in.n_faces, 760);
    CHECK_EQ(in.n_vertices, 382);
    CHECK_EQ(in.genus, 0);
    CHECK_EQ(in.n_boundary_loops, 0);
    mesh_free(&m);
    REQUIRE(mesh_gen_torus(16, 8, 1.0, 0.3, &m) == PP5_OK);
    REQUIRE(mesh_info(&m, &in) == PP5_OK);
    CHECK_EQ(in.genus, 1);
    CHECK_EQ(in.euler, 0);
    mesh_free(&m);
    REQUIRE(mesh_gen_grid(5, 3, 1.0, 1.0, &m) == PP5_OK);
    REQUIRE(mesh_info(&m, &in) == PP5_OK);
    CHECK_EQ(in.n_boundary_loops, 1);
    CHECK_EQ(in.longest_loop, 2 * (5 + 3));
    CHECK(in.manifold && in.orientable);
    mesh_free(&m);
    REQUIRE(mesh_gen_cube(3, &m) == PP5_OK);
    REQUIRE(mesh_info(&m, &in) == PP5_OK);
    CHECK_EQ(in.n_vertices, 6 * 9 + 2);
    CHECK_EQ(in.genus, 0);
    CHECK(in.orientable);
    /* outward normals: positive enclosed volume (8 for the cube [-1,1]^3) */
    double vol = 0;
    for (int f = 0; f < m.n_faces; f++) {
        const double *a = m.pos + 3 * m.tri[3 * f], *b = m.pos + 3 * m.tri[3 * f + 1],
                     *c = m.pos + 3 * m.tri[3 * f + 2];
        vol += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                a[2] * (b[0] * c[1] - b[1] * c[0])) / 6.0;
    }
    CHECK_NEAR(vol, 8.0, 1e-12);
    mesh_free(&m);
}

TEST(mesh_bunny_loads_and_its_hole_fills_to_seed003_counts)
{
    const char *path = pp5_test_shared_data("meshes/bun_zipper.ply.gz");
    if (!path)
        SKIP("meshes/bun_zipper.ply.gz absent (see shared/data/README)");
    mesh_t m;
    REQUIRE(mesh_load(path, &m) == PP5_OK);
    CHECK_EQ(m.n_faces, 69451);   /* PROVENANCE.md */
    CHECK_EQ(m.n_vertices, 35947);
    REQUIRE(mesh_gen_fill_hole(&m, 22) == PP5_OK);
    /* seed 003 Table 3: 69,473 faces, 34,835 vertices */
    CHECK_EQ(m.n_faces, 69473);
    CHECK_EQ(m.n_vertices, 34835);
    mesh_info_t in;
    REQUIRE(mesh_info(&m, &in) == PP5_OK);
    CHECK_EQ(in.n_boundary_loops, 4);
    CHECK(in.manifold && in.orientable);
    mesh_free(&m);
}

TEST(mesh_cow_loads_with_5804_triangles)
{
    const char *path = pp5_test_shared_data("meshes/cow_tri.obj");
    if (!path)
        SKIP("meshes/cow_tri.obj absent (see shared/data/README)");
    mesh_t m;
    REQUIRE(mesh_load(path, &m) == PP5_OK);
    CHECK_EQ(m.n_faces, 5804);
    CHECK_EQ(m.n_vertices, 2903);
    mesh_free(&m);
}

static void scale_mesh(mesh_t *m, double s, double dx, double dz)
{
    for (int v = 0; v < m->n_vertices; v++) {
        m->pos[3 * v] = m->pos[3 * v] * s + dx;
        m->pos[3 * v + 1] *= s;
        m->pos[3 * v + 2] = m->pos[3 * v + 2] * s + dz;
    }
}

TEST(mesh_hausdorff_sphere_against_a_scaled_sphere)
{
    /* Every vertex lies on its sphere and each point of A scaled by s lies
     * on B, so h(B, A) = (s - 1) r exactly (at B's vertices, whose radial
     * direction is in A's normal cone there), and h(A, B) <= (s - 1) r. */
    mesh_t a, b;
    REQUIRE(mesh_gen_uv_sphere(16, 12, 1.0, &a) == PP5_OK);
    REQUIRE(mesh_copy(&a, &b) == PP5_OK);
    scale_mesh(&b, 1.1, 0, 0);
    mesh_distance_opts_t o;
    mesh_distance_defaults(&o);
    o.mean_samples = 20000;
    mesh_distance_t d;
    REQUIRE(mesh_distance(&a, &b, &o, &d) == PP5_OK);
    CHECK_NEAR(d.h_ba, 0.1, 1e-12);
    CHECK(d.h_ab <= 0.1 + 1e-12 && d.h_ab > 0.05);
    CHECK_NEAR(d.hausdorff, 0.1, 1e-12);
    CHECK(d.mean_ab > 0 && d.mean_ab < 0.1);
    mesh_free(&a);
    mesh_free(&b);
}

TEST(mesh_hausdorff_plane_against_an_offset_plane)
{
    mesh_t a, b;
    REQUIRE(mesh_gen_grid(6, 6, 1.0, 1.0, &a) == PP5_OK);
    REQUIRE(mesh_copy(&a, &b) == PP5_OK);
    scale_mesh(&b, 1.0, 0, 0.05);
    mesh_distance_opts_t o;
    mesh_distance_defaults(&o);
    o.mean_samples = 5000;
    mesh_distance_t d;
    REQUIRE(mesh_distance(&a, &b, &o, &d) == PP5_OK);
    CHECK_NEAR(d.hausdorff, 0.05, 1e-12);
    CHECK_NEAR(d.mean_ab, 0.05, 1e-12);   /* every point is 0.05 above */
    CHECK_NEAR(d.mean_ba, 0.05, 1e-12);
    /* shifted sideways as well: the far edge is sqrt(0.1^2 + 0.05^2) away */
    scale_mesh(&b, 1.0, 0.1, 0);
    REQUIRE(mesh_distance(&a, &b, &o, &d) == PP5_OK);
    CHECK(d.hausdorff <= sqrt(0.0125) + 1e-12);
    CHECK(d.hausdorff + d.bound_ab + 1e-12 >= sqrt(0.0125));
    CHECK_NEAR(d.hausdorff, sqrt(0.0125), 1e-9);   /* reached at a corner vertex */
    mesh_free(&a);
    mesh_free(&b);
}

TEST(mesh_cli_info_and_error_run_and_fail_cleanly)
{
    char out[1200], err[1200], path[1200];
    snprintf(out, sizeof out, "%s/out.txt", pp5_test_outdir());
    snprintf(err, sizeof err, "%s/err.txt", pp5_test_outdir());
    CHECK_EQ(pp5_test_run_cli("mesh info gen:torus", out, err), 0);
    char *text = pp5_test_read_file(out);
    REQUIRE(text);
    CHECK(strstr(text, "genus:       1") != NULL);
    free(text);
    snprintf(path, sizeof path, "%s/bad.off", pp5_test_outdir());
    FILE *f = fopen(path, "w");
    REQUIRE(f);
    fputs("OFF\n3 1 0\n0 0 0\n1 0 0\n", f);
    fclose(f);
    char args[1400];
    snprintf(args, sizeof args, "mesh info %s", path);
    CHECK_EQ(pp5_test_run_cli(args, out, err), PP5_EXIT_INPUT);   /* a truncated file is bad input */
    text = pp5_test_read_file(err);
    REQUIRE(text);
    CHECK(strstr(text, "bad.off: truncated: 2 of 3 vertices") != NULL);
    CHECK(strchr(text, '\n') == text + strlen(text) - 1);   /* one line */
    free(text);
}
