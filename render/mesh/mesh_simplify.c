/* mesh_simplify.c: the shared entry point of the three simplifiers: options,
 * input checks, timing, the mesh at the target and the collapse record. */
#include "simplify_work.h"

#include <stdio.h>
#include <string.h>
#include <time.h>

void mesh_simplify_defaults(mesh_simplify_opts_t *o, mesh_method_t method)
{
    memset(o, 0, sizeof *o);
    o->method = method;
    o->fold_cos_min = 0.0;
    /* GH97's unit planes with CGAL's default discontinuity multiplier (100):
     * ARCHITECTURE.md has the weights tried on the bunny */
    o->qem_boundary_weight = 100.0;
    o->qem_area_weighted = false;
    o->s001_cost = SEED001_COST_EQ8;
    /* seed 003: the paper gives no values (§2.1, §2.3); ARCHITECTURE.md says
     * why these, and `pp5 reproduce meshes` sweeps them. */
    o->s003_crease_deg = 45.0;
    o->s003_corner_deg = 45.0;
    o->s003_cd[0] = 1.0, o->s003_cs[0] = 0.05, o->s003_cl[0] = 0.05;
    o->s003_cd[1] = 0.2, o->s003_cs[1] = 0.2, o->s003_cl[1] = 1.0;
    o->s003_switch_fraction = 0.25;
    o->s003_independent_sets = true;
    o->s003_pin_corners = true;
    o->s003_lazy = true;
    o->s003_point = SEED003_POINT_STENCIL;
}

const char *mesh_method_name(mesh_method_t m)
{
    return m == MESH_QEM ? "qem" : m == MESH_SEED001 ? "seed001" : "seed003";
}

pp5_status_t mesh_method_parse(const char *name, mesh_method_t *m)
{
    if (strcmp(name, "qem") == 0)
        *m = MESH_QEM;
    else if (strcmp(name, "seed001") == 0)
        *m = MESH_SEED001;
    else if (strcmp(name, "seed003") == 0)
        *m = MESH_SEED003;
    else
        return pp5_fail(PP5_E_CONFIG, "--method: '%s' is not seed001, seed003 or qem", name);
    return PP5_OK;
}

pp5_status_t mesh_simplify(const mesh_t *in, const mesh_simplify_opts_t *o, mesh_t *out,
                           mesh_record_t *rec, mesh_simplify_stats_t *stats)
{
    mesh_simplify_stats_t local;
    if (!stats)
        stats = &local;
    memset(stats, 0, sizeof *stats);
    stats->phase_switch_merge = -1;
    stats->input_faces = in->n_faces;
    if (o->target_faces < 0)
        return pp5_fail(PP5_E_CONFIG, "simplify: target of %d faces", o->target_faces);
    pp5_status_t st = mesh_validate(in, in->source);
    if (st != PP5_OK)
        return st;
    struct timespec t0, t1, c0, c1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &c0);
    sw_t w;
    /* edge methods queue edges under a corner id, seed 001 queues faces */
    st = sw_init(&w, in, rec != NULL, o->method == MESH_SEED001 ? in->n_faces : 3 * in->n_faces,
                 stats);
    if (st != PP5_OK)
        return st;
    w.fold_cos_min = o->fold_cos_min;
    st = sw_check_edge_manifold(&w, in->source);
    if (st == PP5_OK) {
        if (o->method == MESH_QEM)
            st = simplify_qem_run(&w, o);
        else if (o->method == MESH_SEED001)
            st = simplify_seed001_run(&w, o);
        else
            st = simplify_seed003_run(&w, o);
    }
    clock_gettime(CLOCK_MONOTONIC, &t1);
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &c1);
    stats->ms = (double)(t1.tv_sec - t0.tv_sec) * 1e3 + (double)(t1.tv_nsec - t0.tv_nsec) / 1e6;
    stats->cpu_ms =
        (double)(c1.tv_sec - c0.tv_sec) * 1e3 + (double)(c1.tv_nsec - c0.tv_nsec) / 1e6;
    stats->output_faces = w.faces_alive;
    stats->output_vertices = w.verts_alive;
    if (st == PP5_OK && out)
        st = sw_to_mesh(&w, out);
    if (st == PP5_OK && out)
        snprintf(out->source, sizeof out->source, "%.200s, %s to %d faces", in->source,
                 mesh_method_name(o->method), out->n_faces);
    if (st == PP5_OK && rec) {
        st = sw_take_record(&w, in, rec);
        if (st != PP5_OK && out)
            mesh_free(out);
    }
    sw_free(&w);
    return st;
}
