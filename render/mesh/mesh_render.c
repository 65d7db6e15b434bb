/* mesh_render.c: the native polygon renderer's pipeline (transform, near
 * clip, cull, light, set-up), deferred shading, and the full-resolution
 * Z-buffer (mesh_render.h).  The variable-resolution Z-buffer is
 * mesh_render_vrz.c. */
#include "mesh_render.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "mesh_tri.h"

double mesh_render_now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec / 1e6;
}

double mesh_render_cpu_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec / 1e6;
}

static void normalise(double v[3])
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (l > 0)
        v[0] /= l, v[1] /= l, v[2] /= l;
}

void mesh_render_opts_from_scene(const mesh_scene_t *s, const raster_camera_t *cam,
                                 raster_shading_t shading, mesh_render_opts_t *o)
{
    memset(o, 0, sizeof *o);
    o->shading = shading;
    for (int i = 0; i < 3; i++)
        o->light_dir[i] = cam->view[4 * i] * s->light_dir[0] +
                          cam->view[4 * i + 1] * s->light_dir[1] +
                          cam->view[4 * i + 2] * s->light_dir[2];
    normalise(o->light_dir);
    o->ambient = s->ambient, o->diffuse = s->diffuse;
    o->specular = s->specular, o->shininess = s->shininess;
    for (int k = 0; k < 3; k++) {
        double c = 255 * s->background[k];
        o->background[k] = (uint8_t)(c >= 255 ? 255 : c + 0.5);
    }
    o->cull_back = s->cull_back;
}

/* The lit colour (0..1 scale, may exceed 1) of colour rgb with unit normal n. */
static void light(const mesh_render_opts_t *o, const double n[3], const double rgb[3], double out[3])
{
    const double *l = o->light_dir;
    double d = n[0] * l[0] + n[1] * l[1] + n[2] * l[2];
    double I = o->ambient + o->diffuse * (d > 0 ? d : 0), spec = 0;
    if (d > 0 && o->specular > 0) {
        double rz = 2 * d * n[2] - l[2];
        spec = rz > 0 ? o->specular * pow(rz, o->shininess) : 0;
    }
    for (int k = 0; k < 3; k++)
        out[k] = rgb[k] * I + spec;
}

static uint8_t to_u8(double c)
{
    c *= 255;
    return (uint8_t)(!(c > 0) ? 0 : c >= 255 ? 255 : c + 0.5);
}

void mesh_render_shade(const mesh_render_opts_t *o, const float *a, uint8_t rgb[3])
{
    double c[3];
    if (o->shading == RASTER_PHONG) {
        double n[3] = {a[0], a[1], a[2]}, col[3] = {a[3], a[4], a[5]};
        normalise(n);
        light(o, n, col, c);
    } else {
        c[0] = a[0], c[1] = a[1], c[2] = a[2];
    }
    for (int k = 0; k < 3; k++)
        rgb[k] = to_u8(c[k]);
}

/* ---- per triangle ---- */

typedef struct {
    double clip[4], n[3], rgb[3];   /* n: camera-space normal */
} cvert_t;

static void lerp(const cvert_t *a, const cvert_t *b, double t, cvert_t *out)
{
    for (int k = 0; k < 4; k++)
        out->clip[k] = a->clip[k] + t * (b->clip[k] - a->clip[k]);
    for (int k = 0; k < 3; k++) {
        out->n[k] = a->n[k] + t * (b->n[k] - a->n[k]);
        out->rgb[k] = a->rgb[k] + t * (b->rgb[k] - a->rgb[k]);
    }
}

/* Sutherland-Hodgman against z + w >= 0 and w > 0 (mesh_raster.c's rule). */
static int clip_near(const cvert_t in[3], cvert_t out[4])
{
    int n = 0;
    for (int i = 0; i < 3; i++) {
        const cvert_t *a = &in[i], *b = &in[(i + 1) % 3];
        double da = a->clip[2] + a->clip[3], db = b->clip[2] + b->clip[3];
        bool ina = da >= 0 && a->clip[3] > 0, inb = db >= 0 && b->clip[3] > 0;
        if (ina)
            out[n++] = *a;
        if (ina != inb && da != db) {
            double t = da / (da - db);
            if (t > 0 && t < 1)
                lerp(a, b, t, &out[n++]);
        }
    }
    return n;
}

typedef struct {
    const mesh_render_opts_t *o;
    double clip_from_world[16];
    const double *view;
    int width, height;
} pipe_t;

static void mat4_vec(const double m[16], const double p[4], double out[4])
{
    for (int i = 0; i < 4; i++)
        out[i] = m[4 * i] * p[0] + m[4 * i + 1] * p[1] + m[4 * i + 2] * p[2] + m[4 * i + 3] * p[3];
}

/* Camera-space direction of world vector d (the view is a rigid motion). */
static void view_dir(const double *view, const double d[3], double out[3])
{
    for (int i = 0; i < 3; i++)
        out[i] = view[4 * i] * d[0] + view[4 * i + 1] * d[1] + view[4 * i + 2] * d[2];
}

/* Attributes of one projected vertex; `facing` turns the normal to the viewer. */
static void vertex_attrs(const pipe_t *p, const cvert_t *v, double facing, const double flat[3],
                         tri_vertex_t *out)
{
    double n[3] = {facing * v->n[0], facing * v->n[1], facing * v->n[2]};
    switch (p->o->shading) {
    case RASTER_FLAT: memcpy(out->attr, flat, 3 * sizeof *flat); break;
    case RASTER_GOURAUD: normalise(n); light(p->o, n, v->rgb, out->attr); break;
    case RASTER_PHONG:
        memcpy(out->attr, n, sizeof n);
        memcpy(out->attr + 3, v->rgb, sizeof n);
        break;
    }
}

static bool draw_one(const pipe_t *p, const mesh_soup_t *s, int t, mesh_render_sink_fn sink,
                     void *ctx)
{
    cvert_t tri[3], poly[4];
    for (int c = 0; c < 3; c++) {
        const double *w = s->pos + 9 * (size_t)t + 3 * c;
        double hp[4] = {w[0], w[1], w[2], 1};
        mat4_vec(p->clip_from_world, hp, tri[c].clip);
        view_dir(p->view, s->nrm + 9 * (size_t)t + 3 * c, tri[c].n);
        memcpy(tri[c].rgb, s->rgb + 9 * (size_t)t + 3 * c, sizeof tri[c].rgb);
    }
    int n = clip_near(tri, poly);
    if (n < 3)
        return false;
    tri_vertex_t sv[4];
    for (int i = 0; i < n; i++) {
        double iw = 1 / poly[i].clip[3];
        sv[i].x = 0.5 * (poly[i].clip[0] * iw + 1) * p->width;
        sv[i].y = 0.5 * (1 - poly[i].clip[1] * iw) * p->height;
        sv[i].z = poly[i].clip[2] * iw;
        sv[i].inv_w = iw;
    }
    /* the clipped polygon's signed area (shoelace), so a sliver first
     * triangle cannot decide the facing of a clipped quad */
    double area = 0;
    for (int i = 0; i < n; i++) {
        const tri_vertex_t *a = &sv[i], *b = &sv[(i + 1) % n];
        area += a->x * b->y - b->x * a->y;
    }
    bool front = area < 0;
    if (!front && p->o->cull_back)
        return false;
    double facing = front ? 1 : -1, flat[3] = {0, 0, 0};
    if (p->o->shading == RASTER_FLAT) {
        /* the face normal from the world-space corners, lit with the mean colour */
        const double *a = s->pos + 9 * (size_t)t, *b = a + 3, *c = a + 6;
        double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        double e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]}, fn[3], cn[3], rgb[3];
        fn[0] = e1[1] * e2[2] - e1[2] * e2[1], fn[1] = e1[2] * e2[0] - e1[0] * e2[2];
        fn[2] = e1[0] * e2[1] - e1[1] * e2[0];
        view_dir(p->view, fn, cn);
        for (int k = 0; k < 3; k++)
            cn[k] *= facing, rgb[k] = (tri[0].rgb[k] + tri[1].rgb[k] + tri[2].rgb[k]) / 3;
        normalise(cn);
        light(p->o, cn, rgb, flat);
    }
    for (int i = 0; i < n; i++)
        vertex_attrs(p, &poly[i], facing, flat, &sv[i]);
    bool drawn = false;
    int na = mesh_render_attrs(p->o->shading);
    for (int i = 1; i + 1 < n; i++) {
        tri_setup_t ts;
        if (tri_setup(&ts, &sv[0], &sv[i], &sv[i + 1], na)) {
            sink(ctx, &ts);
            drawn = true;
        }
    }
    return drawn;
}

void mesh_render_triangles(const mesh_soup_t *soup, const raster_camera_t *cam,
                           const mesh_render_opts_t *o, int width, int height,
                           mesh_render_sink_fn sink, void *ctx, mesh_render_stats_t *st)
{
    pipe_t p = {o, {0}, cam->view, width, height};
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            double acc = 0;
            for (int k = 0; k < 4; k++)
                acc += cam->proj[4 * i + k] * cam->view[4 * k + j];
            p.clip_from_world[4 * i + j] = acc;
        }
    st->triangles_in += (uint64_t)soup->n_tris;
    for (int t = 0; t < soup->n_tris; t++)
        st->triangles_drawn += draw_one(&p, soup, t, sink, ctx);
}

/* ---- the full-resolution Z-buffer ---- */

typedef struct {
    int w, h, na;
    double *depth;
    float *attr;
    uint64_t fragments;
} zbuf_t;

static void zbuf_sink(void *ctx, const tri_setup_t *t)
{
    zbuf_t *z = ctx;
    int bx0 = (int)fmax(0, floor(t->xmin - 0.5)), bx1 = (int)fmin(z->w - 1, ceil(t->xmax));
    int by0 = (int)fmax(0, floor(t->ymin - 0.5)), by1 = (int)fmin(z->h - 1, ceil(t->ymax));
    for (int y = by0; y <= by1; y++)
        for (int x = bx0; x <= bx1; x++) {
            double b[3];
            if (!tri_cover(t, x + 0.5, y + 0.5, b))
                continue;
            z->fragments++;
            double d = tri_depth(t, b);
            size_t i = (size_t)y * (size_t)z->w + (size_t)x;
            if (!(d < z->depth[i]) || d < -1 || d > 1)
                continue;
            z->depth[i] = d;
            double a[TRI_MAX_ATTRS];
            tri_attrs(t, b, a);
            for (int k = 0; k < z->na; k++)
                z->attr[i * (size_t)z->na + (size_t)k] = (float)a[k];
        }
}

pp5_status_t mesh_render_full(const mesh_soup_t *soup, const raster_camera_t *cam,
                              const mesh_render_opts_t *o, int width, int height, image8_t *img,
                              mesh_render_stats_t *st)
{
    double t0 = mesh_render_now_ms(), c0 = mesh_render_cpu_ms();
    memset(st, 0, sizeof *st);
    pp5_status_t s = image8_alloc(img, width, height, 3);
    if (s != PP5_OK)
        return s;
    size_t n = (size_t)width * (size_t)height;
    zbuf_t z = {width, height, mesh_render_attrs(o->shading), malloc(n * sizeof(double)),
                malloc(n * (size_t)mesh_render_attrs(o->shading) * sizeof(float)), 0};
    if (!z.depth || !z.attr) {
        free(z.depth), free(z.attr), image8_free(img);
        return pp5_fail(PP5_E_NOMEM, "render: out of memory for a %dx%d Z-buffer", width, height);
    }
    for (size_t i = 0; i < n; i++)
        z.depth[i] = INFINITY;
    double c_tri = mesh_render_cpu_ms();
    mesh_render_triangles(soup, cam, o, width, height, zbuf_sink, &z, st);
    st->cpu_ms_triangles = mesh_render_cpu_ms() - c_tri;
    for (size_t i = 0; i < n; i++) {
        uint8_t *px = img->pixels + 3 * i;
        if (z.depth[i] == INFINITY) {
            memcpy(px, o->background, 3);
            continue;
        }
        mesh_render_shade(o, z.attr + i * (size_t)z.na, px);
        st->pixels_shaded++;
    }
    st->fragments = z.fragments;
    st->samples = n;
    free(z.depth);
    free(z.attr);
    st->ms = mesh_render_now_ms() - t0;
    st->cpu_ms = mesh_render_cpu_ms() - c0;
    return PP5_OK;
}
