/* mesh_tri.c: triangle setup, the top-left coverage test, depth and
 * perspective-correct attributes (mesh_tri.h). */
#include "mesh_tri.h"

#include <math.h>
#include <string.h>

/* The same expression as mesh_raster.c's edge_fn: twice the signed area of
 * (a, b, p), positive when p is to the left of a -> b with y up. */
static double edge_fn(const tri_vertex_t *a, const tri_vertex_t *b, double px, double py)
{
    return (b->x - a->x) * (py - a->y) - (b->y - a->y) * (px - a->x);
}

/* The edge a -> b owns the points on it when its inward normal points right,
 * or straight down the screen's y (the top-left rule, with y down: a point
 * on a shared edge belongs to exactly one of the two triangles). */
static bool owns_edge(const tri_vertex_t *a, const tri_vertex_t *b, double s)
{
    double nx = -(b->y - a->y) * s, ny = (b->x - a->x) * s;
    return nx > 0 || (nx == 0 && ny > 0);
}

bool tri_setup(tri_setup_t *t, const tri_vertex_t *a, const tri_vertex_t *b,
               const tri_vertex_t *c, int n_attrs)
{
    double area = edge_fn(a, b, c->x, c->y);
    if (area == 0 || !isfinite(area))
        return false;
    t->v[0] = *a, t->v[1] = *b, t->v[2] = *c;
    t->n_attrs = n_attrs < 0 ? 0 : n_attrs > TRI_MAX_ATTRS ? TRI_MAX_ATTRS : n_attrs;
    t->sign = area > 0 ? 1 : -1;
    t->inv_area = 1 / fabs(area);
    t->front = area < 0;   /* y down on the screen: negative area is counter-clockwise with y up */
    for (int k = 0; k < 3; k++)
        t->own[k] = owns_edge(&t->v[(k + 1) % 3], &t->v[(k + 2) % 3], t->sign);
    t->xmin = fmin(a->x, fmin(b->x, c->x)), t->xmax = fmax(a->x, fmax(b->x, c->x));
    t->ymin = fmin(a->y, fmin(b->y, c->y)), t->ymax = fmax(a->y, fmax(b->y, c->y));
    return true;
}

bool tri_cover(const tri_setup_t *t, double px, double py, double b[3])
{
    for (int k = 0; k < 3; k++) {
        /* b[k]: the edge opposite vertex k, positive inside */
        double e = t->sign * edge_fn(&t->v[(k + 1) % 3], &t->v[(k + 2) % 3], px, py);
        if (!(e > 0 || (e == 0 && t->own[k])))
            return false;
        b[k] = e * t->inv_area;
    }
    return true;
}

double tri_depth(const tri_setup_t *t, const double b[3])
{
    return b[0] * t->v[0].z + b[1] * t->v[1].z + b[2] * t->v[2].z;
}

void tri_interp_perspective(const double b[3], const double inv_w[3], const double *const attr[3],
                            int n, double *out)
{
    double w0 = b[0] * inv_w[0], w1 = b[1] * inv_w[1], w2 = b[2] * inv_w[2];
    double iw = w0 + w1 + w2;
    for (int i = 0; i < n; i++)
        out[i] = (w0 * attr[0][i] + w1 * attr[1][i] + w2 * attr[2][i]) / iw;
}

void tri_attrs(const tri_setup_t *t, const double b[3], double *out)
{
    const double inv_w[3] = {t->v[0].inv_w, t->v[1].inv_w, t->v[2].inv_w};
    const double *const attr[3] = {t->v[0].attr, t->v[1].attr, t->v[2].attr};
    tri_interp_perspective(b, inv_w, attr, t->n_attrs, out);
}
