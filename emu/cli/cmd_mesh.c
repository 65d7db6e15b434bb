/* cmd_mesh.c: `pp5 mesh info|simplify|error|extract`: mesh topology, the three
 * simplifiers behind one interface (render/mesh/mesh_simplify.h), their
 * collapse records, and the Metro-style Hausdorff distance between meshes. */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cliopt.h"
#include "outfile.h"
#include "registry.h"
#include "render/mesh/mesh.h"
#include "render/mesh/mesh_gen.h"
#include "render/mesh/mesh_hausdorff.h"
#include "render/mesh/mesh_info.h"
#include "render/mesh/mesh_raster.h"
#include "render/mesh/mesh_simplify.h"

static void usage(void)
{
    printf("usage: pp5 mesh info MESH\n"
           "       pp5 mesh simplify MESH --method seed001|seed003|qem (--ratio R | --faces N)\n"
           "                         --out OUT [--levels FILE]\n"
           "       pp5 mesh extract FILE (--ratio R | --faces N) --out OUT\n"
           "       pp5 mesh error A B [--bound B] [--samples N]\n"
           "       pp5 mesh render MESH --out OUT.png [--size WxH] [--yaw D] [--pitch D]\n"
           "                       [--gouraud | --phong] [--ortho]\n\n"
           "info:     counts, boundary loops, manifoldness, orientation, genus.\n"
           "simplify: simplifies to at most N faces (or R x the input's faces) and writes\n"
           "          the result; --levels also writes the collapse record (every level).\n"
           "          Methods: seed001 (triangle collapse, Qian & Luo 2017), seed003 (edge\n"
           "          deletion with butterfly stencils, Cao et al.), qem (Garland-Heckbert).\n"
           "extract:  the level of a collapse record with at most N faces, without\n"
           "          simplifying again.\n"
           "error:    symmetric Hausdorff and mean distance between A and B as %% of A's\n"
           "          bounding-box diagonal (Metro convention); the maxima carry a guaranteed\n"
           "          error bound (--bound, x the diagonal, default 1e-5); the means use\n"
           "          --samples area-uniform samples per direction (default 200000).\n"
           "render:   the mesh shaded (flat, --gouraud or --phong) under one light\n"
           "          through the z-buffered rasteriser, seen from --yaw degrees about\n"
           "          the vertical (default 0: from +z) and --pitch degrees above\n"
           "          (default 20), perspective or --ortho; --size in pixels (512x512).\n"
           "MESH: .obj, .off, .ply (ASCII or binary), each optionally .gz, or a generated\n"
           "mesh: gen:sphere (20x20 UV sphere, 760 faces), gen:torus, gen:grid, gen:cube.\n"
           "OUT: .obj, .off or .ply (binary).\n\n"
           "examples:\n"
           "  pp5 mesh info ../shared/data/meshes/bun_zipper.ply.gz\n"
           "  pp5 mesh simplify ../shared/data/meshes/cow_tri.obj --method seed001 --ratio 0.5 \\\n"
           "      --out cow50.obj --levels cow.pmr\n"
           "  pp5 mesh extract cow.pmr --faces 1000 --out cow1000.off\n"
           "  pp5 mesh error ../shared/data/meshes/cow_tri.obj cow50.obj\n"
           "  pp5 mesh simplify gen:sphere --method seed003 --faces 188 --out s188.obj\n"
           "  pp5 mesh render cow1000.off --out cow1000.png --yaw 60 --size 640x480\n");
}

/* Loads FILE or a generated mesh named gen:NAME. */
static pp5_status_t mesh_cli_load(const char *what, mesh_t *m)
{
    return strncmp(what, "gen:", 4) == 0 ? mesh_gen_by_name(what, m) : mesh_load(what, m);
}

static int cmd_info(int argc, char **argv)
{
    if (argc != 2)
        return usage(), 2;
    mesh_t m;
    pp5_status_t st = mesh_cli_load(argv[1], &m);
    if (st != PP5_OK)
        return cliopt_report("mesh info", st);
    mesh_info_t in;
    st = mesh_info(&m, &in);
    if (st != PP5_OK) {
        mesh_free(&m);
        return cliopt_report("mesh info", st);
    }
    double lo[3], hi[3];
    mesh_bounds(&m, lo, hi);
    printf("source:      %s\n", m.source);
    printf("vertices:    %d (%d used by faces)\n", in.n_vertices, in.n_used_vertices);
    printf("faces:       %d triangles\n", in.n_faces);
    printf("edges:       %d (%d on the boundary, %d with more than two faces)\n", in.n_edges,
           in.n_boundary_edges, in.n_nonmanifold_edges);
    printf("boundary:    %d loop%s", in.n_boundary_loops, in.n_boundary_loops == 1 ? "" : "s");
    if (in.n_boundary_loops)
        printf(" (%d to %d edges)", in.shortest_loop, in.longest_loop);
    printf("\nmanifold:    %s (%d non-manifold edges, %d non-manifold vertices)\n",
           in.manifold ? "yes" : "no", in.n_nonmanifold_edges, in.n_nonmanifold_vertices);
    printf("orientable:  %s (%d edges traversed the same way by both faces)\n",
           in.orientable ? "yes" : "no", in.n_misoriented_edges);
    printf("components:  %d\n", in.n_components);
    printf("euler:       %d (V - E + F)\n", in.euler);
    if (in.genus >= 0)
        printf("genus:       %d\n", in.genus);
    else
        printf("genus:       undefined (not an orientable manifold)\n");
    printf("bounds:      [%g %g %g] .. [%g %g %g], diagonal %g\n", lo[0], lo[1], lo[2], hi[0],
           hi[1], hi[2], mesh_diagonal(&m));
    printf("area:        %g\n", mesh_area(&m));
    double vol = mesh_signed_volume(&m);
    printf("volume:      %g (signed; faces %s)\n", vol,
           vol < 0 ? "point inward: clockwise seen from outside" : "counter-clockwise outside");
    mesh_free(&m);
    return 0;
}

typedef struct {
    const char *method, *out, *levels;
    double ratio;
    long faces;
    double bound;
    long samples;
    int width, height;           /* render */
    double yaw, pitch;
    bool gouraud, phong, ortho, help;
} mesh_cli_opts_t;

static pp5_status_t parse_opts(int argc, char **argv, mesh_cli_opts_t *o)
{
    static const struct option longopts[] = {
        {"method", required_argument, NULL, 'm'}, {"ratio", required_argument, NULL, 'r'},
        {"faces", required_argument, NULL, 'f'},  {"out", required_argument, NULL, 'o'},
        {"levels", required_argument, NULL, 'l'}, {"bound", required_argument, NULL, 'b'},
        {"samples", required_argument, NULL, 's'}, {"size", required_argument, NULL, 'z'},
        {"yaw", required_argument, NULL, 'y'},    {"pitch", required_argument, NULL, 'p'},
        {"gouraud", no_argument, NULL, 'g'},      {"ortho", no_argument, NULL, 't'},
        {"phong", no_argument, NULL, 'P'},
        {"help", no_argument, NULL, 'h'},         {NULL, 0, NULL, 0},
    };
    memset(o, 0, sizeof *o);
    o->ratio = -1, o->faces = -1, o->bound = 1e-5, o->samples = 200000;
    o->width = o->height = 512, o->pitch = 20;
    int c;
    optind = 1;
    pp5_status_t st = PP5_OK;
    while (st == PP5_OK && (c = getopt_long(argc, argv, "", longopts, NULL)) != -1) {
        switch (c) {
        case 'm': o->method = optarg; break;
        case 'r': st = cliopt_double("--ratio", optarg, 0.0, 1.0, &o->ratio); break;
        case 'f': st = cliopt_long("--faces", optarg, 0, MESH_MAX_FACES, &o->faces); break;
        case 'o': o->out = optarg; break;
        case 'l': o->levels = optarg; break;
        case 'b': st = cliopt_double("--bound", optarg, 1e-9, 1.0, &o->bound); break;
        case 's': st = cliopt_long("--samples", optarg, 0, 100000000, &o->samples); break;
        case 'z': st = cliopt_size2("--size", optarg, 16, 8192, &o->width, &o->height); break;
        case 'y': st = cliopt_double("--yaw", optarg, -3600, 3600, &o->yaw); break;
        case 'p': st = cliopt_double("--pitch", optarg, -90, 90, &o->pitch); break;
        case 'g': o->gouraud = true; break;
        case 'P': o->phong = true; break;
        case 't': o->ortho = true; break;
        case 'h': o->help = true; break;
        default: st = pp5_fail(PP5_E_CONFIG, "unknown option (see pp5 mesh --help)");
        }
    }
    if (st == PP5_OK && o->ratio >= 0 && o->faces >= 0)
        st = pp5_fail(PP5_E_CONFIG, "give --ratio or --faces, not both");
    return st;
}

static long target_faces(const mesh_cli_opts_t *o, int input_faces)
{
    return o->faces >= 0 ? o->faces : (long)(o->ratio * input_faces + 0.5);
}

static int cmd_simplify(int argc, char **argv)
{
    mesh_cli_opts_t o;
    pp5_status_t st = parse_opts(argc, argv, &o);
    if (st == PP5_OK && (optind != argc - 1 || !o.method || !o.out))
        st = pp5_fail(PP5_E_CONFIG, "usage: pp5 mesh simplify MESH --method M --ratio R|--faces "
                      "N --out OUT");
    if (st == PP5_OK && o.ratio < 0 && o.faces < 0)
        st = pp5_fail(PP5_E_CONFIG, "give --ratio or --faces");
    mesh_simplify_opts_t so;
    mesh_method_t method = MESH_QEM;
    if (st == PP5_OK)
        st = mesh_method_parse(o.method, &method);
    if (st == PP5_OK)
        st = outpath_check_all("--out", o.out, "--levels", o.levels, NULL);
    if (st != PP5_OK)
        return cliopt_report("mesh simplify", st);
    mesh_t in, out;
    st = mesh_cli_load(argv[optind], &in);
    if (st != PP5_OK)
        return cliopt_report("mesh simplify", st);
    mesh_simplify_defaults(&so, method);
    so.target_faces = (int)target_faces(&o, in.n_faces);
    mesh_record_t rec;
    mesh_simplify_stats_t stats;
    /* With --levels the record goes down to the topology floor, and the
     * output is its level at the target (the same mesh: tests/test_mesh_simplify.c). */
    int want = so.target_faces;
    if (o.levels)
        so.target_faces = 0;
    st = mesh_simplify(&in, &so, o.levels ? NULL : &out, o.levels ? &rec : NULL, &stats);
    so.target_faces = want;
    if (st == PP5_OK && o.levels) {
        st = mesh_record_extract(&rec, mesh_record_level_for_faces(&rec, want), &out);
        if (st != PP5_OK)
            mesh_record_free(&rec);
    }
    if (st == PP5_OK) {
        st = mesh_save(o.out, &out);
        if (st == PP5_OK && o.levels)
            st = mesh_record_save(o.levels, &rec);
        printf("%s: %d faces, %d vertices -> %d faces, %d vertices with %s in %.1f ms "
               "(CPU %.1f ms; %d merges%s; refused: %ld topology, %ld fold-over)\n", in.source,
               in.n_faces, in.n_vertices, out.n_faces, out.n_vertices, mesh_method_name(method),
               stats.ms, stats.cpu_ms, stats.merges, o.levels ? " to the floor" : "",
               stats.refused_topology, stats.refused_fold);
        if (out.n_faces > so.target_faces)
            printf("  stopped at the topology floor: no allowed merge left above %d faces\n",
                   so.target_faces);
        if (o.levels && st == PP5_OK)
            printf("  collapse record: %d levels, %d to %d faces, in %s\n", rec.n_levels,
                   rec.level_faces[0], rec.level_faces[rec.n_levels - 1], o.levels);
        mesh_free(&out);
        if (o.levels)
            mesh_record_free(&rec);
    }
    mesh_free(&in);
    return st == PP5_OK ? 0 : cliopt_report("mesh simplify", st);
}

static int cmd_extract(int argc, char **argv)
{
    mesh_cli_opts_t o;
    pp5_status_t st = parse_opts(argc, argv, &o);
    if (st == PP5_OK && (optind != argc - 1 || !o.out || (o.ratio < 0 && o.faces < 0)))
        st = pp5_fail(PP5_E_CONFIG, "usage: pp5 mesh extract FILE --ratio R|--faces N --out "
                      "OUT");
    mesh_record_t rec;
    if (st == PP5_OK)
        st = outpath_check("--out", o.out);
    if (st == PP5_OK)
        st = mesh_record_load(argv[optind], &rec);
    if (st != PP5_OK)
        return cliopt_report("mesh extract", st);
    mesh_t out;
    int level = mesh_record_level_for_faces(&rec, (int)target_faces(&o, rec.level_faces[0]));
    st = mesh_record_extract(&rec, level, &out);
    if (st == PP5_OK) {
        st = mesh_save(o.out, &out);
        printf("level %d of %d: %d faces, %d vertices\n", level, rec.n_levels - 1, out.n_faces,
               out.n_vertices);
        mesh_free(&out);
    }
    mesh_record_free(&rec);
    return st == PP5_OK ? 0 : cliopt_report("mesh extract", st);
}

static int cmd_error(int argc, char **argv)
{
    mesh_cli_opts_t o;
    pp5_status_t st = parse_opts(argc, argv, &o);
    if (st == PP5_OK && optind != argc - 2)
        st = pp5_fail(PP5_E_CONFIG, "usage: pp5 mesh error A B");
    if (st != PP5_OK)
        return cliopt_report("mesh error", st);
    mesh_t a, b;
    st = mesh_cli_load(argv[optind], &a);
    if (st != PP5_OK)
        return cliopt_report("mesh error", st);
    st = mesh_cli_load(argv[optind + 1], &b);
    if (st != PP5_OK) {
        mesh_free(&a);
        return cliopt_report("mesh error", st);
    }
    mesh_distance_opts_t dopt;
    mesh_distance_defaults(&dopt);
    dopt.bound_rel = o.bound;
    dopt.mean_samples = o.samples;
    mesh_distance_t d;
    st = mesh_distance(&a, &b, &dopt, &d);
    if (st == PP5_OK) {
        double pc = 100.0 / d.diagonal;
        printf("A: %s (%d faces), B: %s (%d faces); diagonal of A %.9g\n", a.source, a.n_faces,
               b.source, b.n_faces, d.diagonal);
        printf("hausdorff: %.6f %% of the diagonal (%.9g), within +%.6f %%\n", d.hausdorff * pc,
               d.hausdorff, fmax(d.bound_ab, d.bound_ba) * pc);
        printf("  A->B max %.6f %%  mean %.6f %%   B->A max %.6f %%  mean %.6f %%\n",
               d.h_ab * pc, d.mean_ab * pc, d.h_ba * pc, d.mean_ba * pc);
        printf("mean: %.6f %% (the larger one-sided mean)\n", fmax(d.mean_ab, d.mean_ba) * pc);
        printf("refinement: %ld + %ld triangles examined\n", d.cells_ab, d.cells_ba);
    }
    mesh_free(&a);
    mesh_free(&b);
    return st == PP5_OK ? 0 : cliopt_report("mesh error", st);
}

static int cmd_render(int argc, char **argv)
{
    mesh_cli_opts_t o;
    pp5_status_t st = parse_opts(argc, argv, &o);
    if (st == PP5_OK && (optind != argc - 1 || !o.out))
        st = pp5_fail(PP5_E_CONFIG, "usage: pp5 mesh render MESH --out OUT.png");
    if (st == PP5_OK)
        st = outpath_check("--out", o.out);
    if (st != PP5_OK)
        return cliopt_report("mesh render", st);
    mesh_t m;
    st = mesh_cli_load(argv[optind], &m);
    if (st != PP5_OK)
        return cliopt_report("mesh render", st);
    mesh_raster_t r;
    st = mesh_raster_init(&r, o.width, o.height);
    if (st == PP5_OK) {
        raster_viewport_t vp = {0, 0, o.width, o.height};
        static const uint8_t bg[3] = {255, 255, 255};
        raster_camera_t cam;
        raster_style_t style;
        raster_camera_fit(&m, o.yaw, o.pitch, (double)o.width / o.height, !o.ortho, &cam);
        raster_shading_t sh = o.phong ? RASTER_PHONG : o.gouraud ? RASTER_GOURAUD : RASTER_FLAT;
        raster_style_default(&style, sh);
        raster_style_orient(&style, &m);
        mesh_raster_clear(&r, &vp, bg);
        st = mesh_raster_draw(&r, &vp, &m, &cam, &style);
        if (st == PP5_OK)
            st = png_write(o.out, &r.image);
        if (st == PP5_OK)
            printf("%s: %d faces, %s shading, %dx%d pixels -> %s\n", m.source, m.n_faces,
                   sh == RASTER_PHONG ? "Phong" : sh == RASTER_GOURAUD ? "Gouraud" : "flat",
                   o.width, o.height, o.out);
        mesh_raster_free(&r);
    }
    mesh_free(&m);
    return st == PP5_OK ? 0 : cliopt_report("mesh render", st);
}

static int cmd_mesh(int argc, char **argv)
{
    for (int i = 2; i < argc; i++)   /* pp5 mesh SUB --help */
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            usage();
            return 0;
        }
    if (argc < 2 || strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0) {
        usage();
        return argc < 2 ? 2 : 0;
    }
    if (strcmp(argv[1], "info") == 0)
        return cmd_info(argc - 1, argv + 1);
    if (strcmp(argv[1], "simplify") == 0)
        return cmd_simplify(argc - 1, argv + 1);
    if (strcmp(argv[1], "extract") == 0)
        return cmd_extract(argc - 1, argv + 1);
    if (strcmp(argv[1], "error") == 0)
        return cmd_error(argc - 1, argv + 1);
    if (strcmp(argv[1], "render") == 0)
        return cmd_render(argc - 1, argv + 1);
    fprintf(stderr, "pp5 mesh: unknown subcommand '%s' (see pp5 mesh --help)\n", argv[1]);
    return 2;
}

PP5_COMMAND(mesh, "mesh info, simplification (seeds 001/003, QEM), Hausdorff error, rendering",
            cmd_mesh)
