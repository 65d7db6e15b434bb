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
    double *plane;          /* per face: unit normal, offset, area (kept current) */
} s001_t;

/* The face's unit normal n, its plane offset -n.p0 and its area. */
static void s001_face_plane(s001_t *s, int f)
{
    const sw_t *w = s->w;
    double *pl = s->plane + 5 * f;
    sw_face_normal(w, f, pl);
    double len = sqrt(sw_dot(pl, pl));
    pl[4] = 0.5 * len;
    if (len > 0)
        for (int k = 0; k < 3; k++)
            pl[k] /= len;
    pl[3] = -sw_dot(pl, w->pos + 3 * w->tri[3 * f]);
}

static uint32_t s001_next_epoch(s001_t *s)
{
    if (++s->epoch == 0) {
        memset(s->mark, 0, sizeof *s->mark * (size_t)s->w->nf);
        s->epoch = 1;
    }
    return s->epoch;
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
    const double *n0 = s->plane + 5 * f;
    double a0 = n0[4], sum_w = 0, max_w = 0, area_sum = a0, lam[3] = {0, 0, 0};
    int32_t nb[3 * SW_MAX_FAN];
    int k = 0;
    for (int j = 0; j < 3; j++) {
        const int32_t *fan = sw_fan(w, t[j]);
        int n = w->fan_n[t[j]], lo = j == 0 ? 1 : 0, hi = j == 2 ? 1 : 2;
        int t_lo = t[lo], t_hi = t[hi];
        for (int i = 0; i < n && k < 3 * SW_MAX_FAN; i++) {
            int c = fan[i], g = c / 3;
            if (g == f)
                continue;
            /* vertex-neighbour (one shared vertex, t[j]) or edge-neighbour (two):
             * the face's other corners name the second one, if any; an
             * edge-neighbour is in two of the fans and counts from the first */
            int y = w->nextv[c], z = w->prevv[c];
            int second = t_hi == y || t_hi == z ? hi : t_lo == y || t_lo == z ? lo : -1;
            if (second >= 0 && second < j)
                continue;
            const double *ng = s->plane + 5 * g;
            double wt = 1.0 - fabs(sw_dot(n0, ng));
            if (second < 0)
                lam[j] += wt;
            else
                lam[j] += 0.5 * wt, lam[second] += 0.5 * wt;
            sum_w += wt;
            max_w = sw_max(max_w, wt);
            area_sum += ng[4];
            nb[k++] = g;
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
        const double *pl = s->plane + 5 * nb[i];
        double e = sw_dot(pl, v0) + pl[3];
        delta = sw_max(delta, e * e);
    }
    double lar = area_sum > 0 ? a0 / area_sum : 0;             /* eq. (6) */
    double lri = k > 0 ? sum_w / k + max_w : 0;                 /* eq. (7) */
    *cost = s->cost == SEED001_COST_EQ5 ? delta
          : s->cost == SEED001_COST_EQ5_LRI ? delta * lri : delta * lar * lri; /* eq. (8) */
    return true;
}

static void s001_queue(s001_t *s, int f)
{
    double v0[3], cost;
    if (s001_evaluate(s, f, v0, &cost))
        sw_queue_set(&s->w->queue, f, cost, (uint64_t)f);
    else
        sw_queue_remove(&s->w->queue, f);
}

/* After a collapse at v: v's faces moved; every face touching v or its ring
 * has a new neighbourhood, so their boundary flags and costs are renewed. */
static void s001_refresh(s001_t *s, int v, const sw_merge_t *m)
{
    sw_t *w = s->w;
    int32_t verts[SW_MAX_FAN + 2];
    int nv = 0;
    verts[nv++] = v;
    for (int i = 0; i < m->n_ring; i++)
        verts[nv++] = m->ring[i];
    for (int i = 0; i < nv; i++)
        s->on_boundary[verts[i]] = sw_vertex_on_boundary(w, verts[i]);
    const int32_t *vfan = sw_fan(w, v);
    for (int i = 0; i < w->fan_n[v]; i++)
        s001_face_plane(s, vfan[i] / 3);
    uint32_t ep = s001_next_epoch(s);
    int32_t faces[4 * SW_MAX_FAN];
    int nf = 0;
    for (int i = 0; i < nv; i++) {
        const int32_t *fan = sw_fan(w, verts[i]);
        for (int j = 0; j < w->fan_n[verts[i]] && nf < 4 * SW_MAX_FAN; j++)
            if (s->mark[fan[j] / 3] != ep) {
                s->mark[fan[j] / 3] = ep;
                faces[nf++] = fan[j] / 3;
            }
    }
    for (int i = 0; i < nf; i++)
        s001_queue(s, faces[i]);
}

pp5_status_t simplify_seed001_run(sw_t *w, const mesh_simplify_opts_t *o)
{
    s001_t s = {w, o->s001_cost, calloc((size_t)w->nv + 1, 1),
                calloc((size_t)w->nf + 1, sizeof(uint32_t)), 0,
                malloc(sizeof(double) * 5 * ((size_t)w->nf + 1))};
    if (!s.on_boundary || !s.mark || !s.plane) {
        free(s.on_boundary), free(s.mark), free(s.plane);
        return pp5_fail(PP5_E_NOMEM, "seed001: out of memory");
    }
    for (int v = 0; v < w->nv; v++)
        s.on_boundary[v] = w->vert_alive[v] && sw_vertex_on_boundary(w, v);
    for (int f = 0; f < w->nf; f++)
        s001_face_plane(&s, f);
    for (int f = 0; f < w->nf; f++)
        s001_queue(&s, f);
    pp5_status_t st = PP5_OK;
    sw_qentry_t e;
    sw_merge_t m;
    while (st == PP5_OK && w->faces_alive > o->target_faces && sw_queue_pop(&w->queue, &e)) {
        double v0[3], cost;
        if (!s001_evaluate(&s, e.id, v0, &cost))
            continue;
        int32_t S[3] = {w->tri[3 * e.id], w->tri[3 * e.id + 1], w->tri[3 * e.id + 2]};
        if (!sw_merge_allowed(w, S, 3, v0, &m))
            continue;
        st = sw_apply_merge(w, S, 3, v0, &m);
        if (st == PP5_OK)
            s001_refresh(&s, S[0], &m);
    }
    free(s.on_boundary);
    free(s.mark);
    free(s.plane);
    return st;
}
