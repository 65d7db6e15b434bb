/* simplify_seed001.c: triangle collapse of Qian & Luo 2017
 * (../shared/seeds/001_2cfb54a79f74d617.txt, §1.2-§2.3).
 *
 * A triangle T0 collapses to one point v0: T0 and its edge-neighbours go (4
 * faces and 2 vertices for an interior triangle), its vertex-neighbours
 * follow v0.  For each vertex v_j of T0 the weight is eqs. (1)-(3)
 * generalised to any valence:
 *   lambda_j = (sum of w over the vertex-neighbours at v_j
 *              + 1/2 sum of w over the edge-neighbours through v_j) / sum of w,
 *   w = <n0, ni> = 1 - |n0 . ni|  (the text's normalised form),
 * v0 = sum lambda_j v_j (eq. 4).  The cost is eq. (8) = eq. (5) x LAR (6) x
 * LRI (7), eq. (5) being the largest squared distance from v0 to the planes
 * of the neighbourhood.  What the paper leaves open (ARCHITECTURE.md):
 * flat neighbourhoods (sum of w = 0) use the centroid; a triangle with one
 * boundary vertex collapses onto it and one with two or more is kept, so
 * boundaries stay exactly; ties go to the lower face index; collapses that
 * break the manifold or flip a face are refused (simplify_work.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "simplify_work.h"

typedef struct {
    sw_t *w;
    seed001_cost_t cost;
    uint8_t *on_boundary;   /* per vertex, kept current */
    uint32_t *mark, epoch;  /* per face, for de-duplicating neighbourhoods */
} s001_t;

static void unit_normal(const sw_t *w, int f, double n[3], double *area)
{
    sw_face_normal(w, f, n);
    double len = sqrt(sw_dot(n, n));
    *area = 0.5 * len;
    if (len > 0)
        for (int k = 0; k < 3; k++)
            n[k] /= len;
}

/* The collapse point and cost of face f; false if f may not collapse. */
static bool s001_evaluate(s001_t *s, int f, double v0[3], double *cost)
{
    const sw_t *w = s->w;
    const int32_t *t = w->tri + 3 * f;
    int n_boundary = 0, pinned = -1;
    for (int j = 0; j < 3; j++)
        if (s->on_boundary[t[j]])
            n_boundary++, pinned = j;
    if (n_boundary >= 2)
        return false;
    double n0[3], a0, sum_w = 0, max_w = 0, area_sum = a0 = 0, lam[3] = {0, 0, 0};
    unit_normal(w, f, n0, &a0);
    area_sum = a0;
    double planes[3 * SW_MAX_FAN][4];
    int k = 0;
    if (++s->epoch == 0)
        memset(s->mark, 0, sizeof *s->mark * (size_t)w->nf), s->epoch = 1;
    s->mark[f] = s->epoch;
    for (int j = 0; j < 3; j++) {
        const int32_t *fan = w->pool + w->fan_off[t[j]];
        for (int i = 0; i < w->fan_n[t[j]]; i++) {
            int g = fan[i];
            if (s->mark[g] == s->epoch || k == 3 * SW_MAX_FAN)
                continue;
            s->mark[g] = s->epoch;
            double ng[3], ag;
            unit_normal(w, g, ng, &ag);
            double wt = 1.0 - fabs(sw_dot(n0, ng));
            /* shared vertices of g with T0: one (vertex-neighbour) or two (edge) */
            int shared[3], ns = 0;
            for (int q = 0; q < 3; q++)
                for (int c = 0; c < 3; c++)
                    if (w->tri[3 * g + c] == t[q])
                        shared[ns++] = q;
            for (int q = 0; q < ns; q++)
                lam[shared[q]] += ns == 1 ? wt : 0.5 * wt;
            sum_w += wt;
            max_w = fmax(max_w, wt);
            area_sum += ag;
            const double *pg = w->pos + 3 * w->tri[3 * g];
            memcpy(planes[k], ng, sizeof ng);
            planes[k][3] = -sw_dot(ng, pg);
            k++;
        }
    }
    if (pinned >= 0) {
        lam[0] = lam[1] = lam[2] = 0;
        lam[pinned] = 1;
    } else if (sum_w > 1e-12) {
        for (int j = 0; j < 3; j++)
            lam[j] /= sum_w;
    } else {
        lam[0] = lam[1] = lam[2] = 1.0 / 3.0;   /* flat: eqs. (1)-(3) are 0/0 */
    }
    for (int c = 0; c < 3; c++)
        v0[c] = lam[0] * w->pos[3 * t[0] + c] + lam[1] * w->pos[3 * t[1] + c] +
                lam[2] * w->pos[3 * t[2] + c];
    double delta = 0;   /* eq. (5): the largest, not the summed, plane error */
    for (int i = 0; i < k; i++) {
        double e = sw_dot(planes[i], v0) + planes[i][3];
        delta = fmax(delta, e * e);
    }
    double lar = area_sum > 0 ? a0 / area_sum : 0;             /* eq. (6) */
    double lri = k > 0 ? sum_w / k + max_w : 0;                 /* eq. (7) */
    *cost = s->cost == SEED001_COST_EQ5 ? delta
          : s->cost == SEED001_COST_EQ5_LRI ? delta * lri : delta * lar * lri; /* eq. (8) */
    return true;
}

static pp5_status_t s001_push(s001_t *s, int f)
{
    double v0[3], cost;
    if (!s001_evaluate(s, f, v0, &cost))
        return PP5_OK;
    sw_entry_t e = {cost, f, -1, s->w->fstamp[f], 0};
    return sw_heap_push(&s->w->heap, e);
}

/* After a collapse at v: every face touching v or its ring has a new
 * neighbourhood; their boundary flags and costs are renewed. */
static pp5_status_t s001_refresh(s001_t *s, int v, const sw_merge_t *m)
{
    sw_t *w = s->w;
    int32_t verts[SW_MAX_FAN + 1];
    int nv = 0;
    verts[nv++] = v;
    for (int i = 0; i < m->n_ring; i++)
        verts[nv++] = m->ring[i];
    for (int i = 0; i < nv; i++)
        s->on_boundary[verts[i]] = sw_vertex_on_boundary(w, verts[i]);
    if (++s->epoch == 0)
        memset(s->mark, 0, sizeof *s->mark * (size_t)w->nf), s->epoch = 1;
    uint32_t ep = s->epoch;
    int32_t faces[4 * SW_MAX_FAN];
    int nf = 0;
    for (int i = 0; i < nv; i++) {
        const int32_t *fan = w->pool + w->fan_off[verts[i]];
        for (int j = 0; j < w->fan_n[verts[i]] && nf < 4 * SW_MAX_FAN; j++)
            if (s->mark[fan[j]] != ep) {
                s->mark[fan[j]] = ep;
                faces[nf++] = fan[j];
            }
    }
    pp5_status_t st = PP5_OK;
    for (int i = 0; i < nf && st == PP5_OK; i++) {
        w->fstamp[faces[i]]++;
        st = s001_push(s, faces[i]);
    }
    return st;
}

pp5_status_t simplify_seed001_run(sw_t *w, const mesh_simplify_opts_t *o)
{
    s001_t s = {w, o->s001_cost, calloc((size_t)w->nv + 1, 1),
                calloc((size_t)w->nf + 1, sizeof(uint32_t)), 0};
    if (!s.on_boundary || !s.mark) {
        free(s.on_boundary), free(s.mark);
        return pp5_fail(PP5_E_NOMEM, "seed001: out of memory");
    }
    for (int v = 0; v < w->nv; v++)
        s.on_boundary[v] = w->vert_alive[v] && sw_vertex_on_boundary(w, v);
    pp5_status_t st = PP5_OK;
    for (int f = 0; f < w->nf && st == PP5_OK; f++)
        st = s001_push(&s, f);
    sw_entry_t e;
    sw_merge_t m;
    while (st == PP5_OK && w->faces_alive > o->target_faces && sw_heap_pop(&w->heap, &e)) {
        if (!sw_entry_current(w, &e))
            continue;
        double v0[3], cost;
        if (!s001_evaluate(&s, e.a, v0, &cost))
            continue;
        int32_t S[3] = {w->tri[3 * e.a], w->tri[3 * e.a + 1], w->tri[3 * e.a + 2]};
        sw_verdict_t v = sw_test_merge(w, S, 3, v0, &m);
        if (v != SW_OK) {
            if (v == SW_FOLD)
                w->stats->refused_fold++;
            else
                w->stats->refused_topology++;
            continue;
        }
        st = sw_apply_merge(w, S, 3, v0, &m);
        if (st == PP5_OK)
            st = s001_refresh(&s, S[0], &m);
    }
    free(s.on_boundary);
    free(s.mark);
    return st;
}
