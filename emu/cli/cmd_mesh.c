/* cmd_mesh.c: `pp5 mesh info|simplify|error|extract`: mesh topology, the three
 * simplifiers behind one interface (render/mesh/mesh_simplify.h), their
 * collapse records, and the Metro-style Hausdorff distance between meshes. */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cliopt.h"
#include "registry.h"
#include "render/mesh/mesh.h"
#include "render/mesh/mesh_gen.h"
#include "render/mesh/mesh_info.h"

static void usage(void)
{
    printf("usage: pp5 mesh info FILE|gen:NAME\n"
           "Meshes: .obj, .off, .ply (ASCII or binary), each optionally .gz; or a\n"
           "generated one: gen:sphere (20x20 UV sphere, 760 faces), gen:torus, gen:grid,\n"
           "gen:cube.\n"
           "examples:\n"
           "  pp5 mesh info ../shared/data/meshes/bun_zipper.ply.gz\n"
           "  pp5 mesh info gen:sphere\n");
}

/* Loads FILE or a generated mesh named gen:NAME. */
static pp5_status_t mesh_cli_load(const char *what, mesh_t *m)
{
    if (strncmp(what, "gen:", 4) != 0)
        return mesh_load(what, m);
    const char *g = what + 4;
    if (strcmp(g, "sphere") == 0)
        return mesh_gen_uv_sphere(20, 20, 1.0, m);
    if (strcmp(g, "torus") == 0)
        return mesh_gen_torus(48, 24, 1.0, 0.35, m);
    if (strcmp(g, "grid") == 0)
        return mesh_gen_grid(32, 32, 1.0, 1.0, m);
    if (strcmp(g, "cube") == 0)
        return mesh_gen_cube(8, m);
    return pp5_fail(PP5_E_CONFIG, "%s: unknown generated mesh (sphere, torus, grid, cube)",
                    what);
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
    mesh_free(&m);
    return 0;
}

static int cmd_mesh(int argc, char **argv)
{
    if (argc < 2 || strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0) {
        usage();
        return argc < 2 ? 2 : 0;
    }
    if (strcmp(argv[1], "info") == 0)
        return cmd_info(argc - 1, argv + 1);
    fprintf(stderr, "pp5 mesh: unknown subcommand '%s' (see pp5 mesh --help)\n", argv[1]);
    return 2;
}

PP5_COMMAND(mesh, "mesh info, simplification (seeds 001/003, QEM) and Hausdorff error",
            cmd_mesh)
