/* mesh_raster.c: the z-buffered triangle rasteriser (mesh_raster.h): cameras,
 * per-vertex transform and lighting, near-plane clipping, edge functions with
 * the top-left rule, depth test, perspective-correct Gouraud intensities and
 * Phong normals. */
#include "mesh_raster.h"
#include "mesh_tri.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const double PI = 3.14159265358979323846;

pp5_status_t mesh_raster_init(mesh_raster_t *r, int width, int height)
{
    memset(r, 0, sizeof *r);
    if (width < 1 || height < 1 || width > 16384 || height > 16384)
        return pp5_fail(PP5_E_RANGE, "raster: image of %dx%d pixels (1..16384 a side)", width,
                        height);
    pp5_status_t st = image8_alloc(&r->image, width, height, 3);
    if (st != PP5_OK)
        return st;
    r->depth = malloc(sizeof *r->depth * (size_t)width * (size_t)height);
    if (!r->depth) {
        image8_free(&r->image);
        return pp5_fail(PP5_E_NOMEM, "raster: out of memory for %dx%d pixels", width, height);
    }
    for (size_t i = 0; i < (size_t)width * (size_t)height; i++)
        r->depth[i] = INFINITY;
    return PP5_OK;
}

void mesh_raster_free(mesh_raster_t *r)
{
    image8_free(&r->image);
    free(r->depth);
    memset(r, 0, sizeof *r);
}

/* The viewport clipped to the image: false if nothing is left. */
static bool clip_viewport(const mesh_raster_t *r, const raster_viewport_t *vp, int *x0, int *y0,
                          int *x1, int *y1)
{
    *x0 = vp->x0 > 0 ? vp->x0 : 0;
    *y0 = vp->y0 > 0 ? vp->y0 : 0;
    *x1 = vp->x0 + vp->width < r->image.width ? vp->x0 + vp->width : r->image.width;
    *y1 = vp->y0 + vp->height < r->image.height ? vp->y0 + vp->height : r->image.height;
    return *x0 < *x1 && *y0 < *y1;
}

void mesh_raster_clear(mesh_raster_t *r, const raster_viewport_t *vp, const uint8_t rgb[3])
{
    int x0, y0, x1, y1;
    if (!clip_viewport(r, vp, &x0, &y0, &x1, &y1))
        return;
    for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++) {
            size_t i = (size_t)y * (size_t)r->image.width + (size_t)x;
            memcpy(r->image.pixels + 3 * i, rgb, 3);
            r->depth[i] = INFINITY;
        }
}

/* ---- cameras ---- */

static void mat_identity(double m[16])
{
    memset(m, 0, 16 * sizeof *m);
    m[0] = m[5] = m[10] = m[15] = 1.0;
}

void raster_camera_ortho(double x0, double x1, double y0, double y1, double z_near,
                         double z_far, raster_camera_t *cam)
{
    mat_identity(cam->view);
    double *p = cam->proj;
    memset(p, 0, 16 * sizeof *p);
    p[0] = 2 / (x1 - x0), p[3] = -(x1 + x0) / (x1 - x0);
    p[5] = 2 / (y1 - y0), p[7] = -(y1 + y0) / (y1 - y0);
    p[10] = -2 / (z_far - z_near), p[11] = -(z_far + z_near) / (z_far - z_near);
    p[15] = 1;
}

void raster_camera_perspective(double fovy_deg, double aspect, double z_near, double z_far,
                               raster_camera_t *cam)
{
    mat_identity(cam->view);
    double f = 1 / tan(0.5 * fovy_deg * PI / 180), *p = cam->proj;
    memset(p, 0, 16 * sizeof *p);
    p[0] = f / aspect, p[5] = f;
    p[10] = (z_far + z_near) / (z_near - z_far), p[11] = 2 * z_far * z_near / (z_near - z_far);
    p[14] = -1;
}

static void normalise(double v[3])
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (l > 0)
        v[0] /= l, v[1] /= l, v[2] /= l;
}

static void cross3(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

void raster_camera_fit(const mesh_t *m, double yaw_deg, double pitch_deg, double aspect,
                       bool perspective, raster_camera_t *cam)
{
    double lo[3], hi[3];
    mesh_bounds(m, lo, hi);
    double c[3] = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
    double radius = 0.5 * sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) +
                               (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                               (hi[2] - lo[2]) * (hi[2] - lo[2]));
    if (!(radius > 0))
        radius = 1;
    double pitch = fmax(-89.0, fmin(89.0, pitch_deg)) * PI / 180, yaw = yaw_deg * PI / 180;
    double back[3] = {sin(yaw) * cos(pitch), sin(pitch), cos(yaw) * cos(pitch)}; /* eye - c */
    double up[3] = {0, 1, 0}, s[3], u[3];
    cross3(up, back, s);   /* camera x = up x back */
    normalise(s);
    cross3(back, s, u);    /* camera y */
    /* the distance at which every corner of the box is inside both half
     * angles of the view (and, orthographic, the half sizes of the window) */
    double tan_y = tan(0.5 * 30.0 * PI / 180), tan_x = tan_y * aspect, dist = 0;
    double half_w = 0, half_h = 0;
    for (int k = 0; k < 8; k++) {
        double q[3] = {(k & 1 ? hi : lo)[0] - c[0], (k & 2 ? hi : lo)[1] - c[1],
                       (k & 4 ? hi : lo)[2] - c[2]};
        double x = fabs(dot3(q, s)), y = fabs(dot3(q, u)), z = dot3(q, back);
        dist = fmax(dist, fmax(z + x / tan_x, z + y / tan_y));
        half_w = fmax(half_w, x), half_h = fmax(half_h, y);
    }
    dist = perspective ? 1.03 * dist : 3 * radius;
    double eye[3] = {c[0] + dist * back[0], c[1] + dist * back[1], c[2] + dist * back[2]};
    double *v = cam->view;
    const double *rows[3] = {s, u, back};
    for (int i = 0; i < 3; i++) {
        v[4 * i] = rows[i][0], v[4 * i + 1] = rows[i][1], v[4 * i + 2] = rows[i][2];
        v[4 * i + 3] = -dot3(rows[i], eye);
    }
    v[12] = v[13] = v[14] = 0, v[15] = 1;
    double z_near = fmax(dist - 1.1 * radius, 1e-3 * radius), z_far = dist + 1.1 * radius;
    raster_camera_t tmp;
    if (perspective) {
        raster_camera_perspective(30.0, aspect, z_near, z_far, &tmp);
    } else {
        double h = 1.03 * fmax(half_h, half_w / aspect);
        raster_camera_ortho(-h * aspect, h * aspect, -h, h, z_near, z_far, &tmp);
    }
    memcpy(cam->proj, tmp.proj, sizeof tmp.proj);
}

void raster_style_default(raster_style_t *s, raster_shading_t shading)
{
    s->shading = shading;
    s->light_dir[0] = -0.45, s->light_dir[1] = 0.55, s->light_dir[2] = 0.70;
    s->ambient = 0.18, s->diffuse = 0.82;
    s->front_rgb[0] = 214, s->front_rgb[1] = 208, s->front_rgb[2] = 196;
    s->back_rgb[0] = 150, s->back_rgb[1] = 96, s->back_rgb[2] = 84;
    s->specular = 0, s->shininess = 32;
}

void raster_style_orient(raster_style_t *s, const mesh_t *m)
{
    if (!(mesh_signed_volume(m) < 0))
        return;
    uint8_t t[3];
    memcpy(t, s->front_rgb, 3);
    memcpy(s->front_rgb, s->back_rgb, 3);
    memcpy(s->back_rgb, t, 3);
}

/* ---- one triangle ---- */

typedef struct {
    double clip[4];
    double light[2];   /* intensity seen from the front and from behind */
    double n[3];       /* camera-space normal (Phong) */
} rvert_t;

typedef struct {
    double x, y, z, inv_w, light;
    double n[3];
} svert_t;

static void lerp_vert(const rvert_t *a, const rvert_t *b, double t, rvert_t *out)
{
    for (int k = 0; k < 4; k++)
        out->clip[k] = a->clip[k] + t * (b->clip[k] - a->clip[k]);
    for (int k = 0; k < 2; k++)
        out->light[k] = a->light[k] + t * (b->light[k] - a->light[k]);
    for (int k = 0; k < 3; k++)
        out->n[k] = a->n[k] + t * (b->n[k] - a->n[k]);
}

/* Sutherland-Hodgman against the near plane z + w >= 0 (and w > 0). */
static int clip_near(const rvert_t in[3], rvert_t out[4])
{
    int n = 0;
    for (int i = 0; i < 3; i++) {
        const rvert_t *a = &in[i], *b = &in[(i + 1) % 3];
        double da = a->clip[2] + a->clip[3], db = b->clip[2] + b->clip[3];
        bool ina = da >= 0 && a->clip[3] > 0, inb = db >= 0 && b->clip[3] > 0;
        if (ina)
            out[n++] = *a;
        if (ina != inb && da != db) {
            double t = da / (da - db);
            if (t > 0 && t < 1)
                lerp_vert(a, b, t, &out[n++]);
        }
    }
    return n;
}

static double edge_fn(const svert_t *a, const svert_t *b, double px, double py)
{
    return (b->x - a->x) * (py - a->y) - (b->y - a->y) * (px - a->x);
}

/* Does the edge a -> b own the pixels exactly on it (top-left rule)?  s is
 * the sign that makes the edge function positive inside. */
static bool owns_edge(const svert_t *a, const svert_t *b, double s)
{
    double nx = -(b->y - a->y) * s, ny = (b->x - a->x) * s;   /* inward normal */
    return nx > 0 || (nx == 0 && ny > 0);
}

typedef struct {
    mesh_raster_t *r;
    int x0, y0, x1, y1;       /* the viewport clipped to the image */
    const uint8_t *rgb;       /* front or back colour */
    bool gouraud;
    double flat_light;
    /* Phong: the style, the light (normalised, camera space), and the sign
     * that turns the normal toward the viewer (-1 for a face seen from behind) */
    bool phong;
    const raster_style_t *style;
    const double *l;
    double facing;
} tri_ctx_t;

static void put_pixel(const tri_ctx_t *t, int x, int y, double z, double light)
{
    size_t i = (size_t)y * (size_t)t->r->image.width + (size_t)x;
    if (!(z < t->r->depth[i]) || z < -1 || z > 1)
        return;
    t->r->depth[i] = z;
    uint8_t *px = t->r->image.pixels + 3 * i;
    double l = light < 0 ? 0 : light;
    for (int k = 0; k < 3; k++) {
        double c = t->rgb[k] * l;
        px[k] = (uint8_t)(c >= 255 ? 255 : c + 0.5);
    }
}

/* Phong at one pixel: the interpolated normal n (any length) gives
 * I = ambient + diffuse max(0, n.l) and a white highlight
 * specular max(0, r.v)^shininess with r = 2 (n.l) n - l, v = +z. */
static void put_phong(const tri_ctx_t *t, int x, int y, double z, const double n_in[3])
{
    size_t i = (size_t)y * (size_t)t->r->image.width + (size_t)x;
    if (!(z < t->r->depth[i]) || z < -1 || z > 1)
        return;
    t->r->depth[i] = z;
    double n[3] = {t->facing * n_in[0], t->facing * n_in[1], t->facing * n_in[2]};
    normalise(n);
    double d = dot3(n, t->l), light = t->style->ambient + t->style->diffuse * (d > 0 ? d : 0);
    double spec = 0;
    if (d > 0 && t->style->specular > 0) {
        double rz = 2 * d * n[2] - t->l[2];
        spec = rz > 0 ? t->style->specular * pow(rz, t->style->shininess) : 0;
    }
    uint8_t *px = t->r->image.pixels + 3 * i;
    for (int k = 0; k < 3; k++) {
        double c = t->rgb[k] * light + 255 * spec;
        px[k] = (uint8_t)(c >= 255 ? 255 : c + 0.5);
    }
}

static void raster_triangle(const tri_ctx_t *t, const svert_t *v0, const svert_t *v1,
                            const svert_t *v2)
{
    double area = edge_fn(v0, v1, v2->x, v2->y);
    if (area == 0 || !isfinite(area))
        return;
    double s = area > 0 ? 1 : -1, inv_area = 1 / fabs(area);
    const svert_t *v[3] = {v0, v1, v2};
    bool own[3];
    for (int k = 0; k < 3; k++)
        own[k] = owns_edge(v[(k + 1) % 3], v[(k + 2) % 3], s);
    double xmin = fmin(v0->x, fmin(v1->x, v2->x)), xmax = fmax(v0->x, fmax(v1->x, v2->x));
    double ymin = fmin(v0->y, fmin(v1->y, v2->y)), ymax = fmax(v0->y, fmax(v1->y, v2->y));
    int bx0 = (int)fmax(t->x0, floor(xmin - 0.5)), bx1 = (int)fmin(t->x1 - 1, ceil(xmax));
    int by0 = (int)fmax(t->y0, floor(ymin - 0.5)), by1 = (int)fmin(t->y1 - 1, ceil(ymax));
    for (int y = by0; y <= by1; y++)
        for (int x = bx0; x <= bx1; x++) {
            double px = x + 0.5, py = y + 0.5, b[3];
            bool inside = true;
            for (int k = 0; k < 3 && inside; k++) {
                /* b[k]: the edge opposite vertex k, positive inside */
                double e = s * edge_fn(v[(k + 1) % 3], v[(k + 2) % 3], px, py);
                inside = e > 0 || (e == 0 && own[k]);
                b[k] = e * inv_area;
            }
            if (!inside)
                continue;
            double z = b[0] * v0->z + b[1] * v1->z + b[2] * v2->z, light = t->flat_light;
            if (t->phong) {
                const double inv_w[3] = {v0->inv_w, v1->inv_w, v2->inv_w}, *attr[3] = {v0->n, v1->n, v2->n};
                double n[3];
                tri_interp_perspective(b, inv_w, attr, 3, n);
                put_phong(t, x, y, z, n);
                continue;
            }
            if (t->gouraud) {   /* perspective-correct: interpolate light/w and 1/w */
                double iw = b[0] * v0->inv_w + b[1] * v1->inv_w + b[2] * v2->inv_w;
                light = (b[0] * v0->light * v0->inv_w + b[1] * v1->light * v1->inv_w +
                         b[2] * v2->light * v2->inv_w) / iw;
            }
            put_pixel(t, x, y, z, light);
        }
}

/* Clips, projects and fills one face; `flat` holds the face's two intensities. */
static void draw_face(tri_ctx_t *t, const raster_viewport_t *vp, const rvert_t tri[3],
                      const double flat[2], const raster_style_t *style)
{
    rvert_t poly[4];
    int n = clip_near(tri, poly);
    if (n < 3)
        return;
    svert_t sv[4];
    for (int i = 0; i < n; i++) {
        double iw = 1 / poly[i].clip[3];
        sv[i].x = vp->x0 + 0.5 * (poly[i].clip[0] * iw + 1) * vp->width;
        sv[i].y = vp->y0 + 0.5 * (1 - poly[i].clip[1] * iw) * vp->height;
        sv[i].z = poly[i].clip[2] * iw;
        sv[i].inv_w = iw;
        memcpy(sv[i].n, poly[i].n, sizeof sv[i].n);
    }
    /* counter-clockwise on the screen (y up) is the front */
    double area = edge_fn(&sv[0], &sv[1], sv[2].x, sv[2].y);
    bool front = area < 0;
    for (int i = 0; i < n; i++)
        sv[i].light = poly[i].light[front ? 0 : 1];
    t->rgb = front ? style->front_rgb : style->back_rgb;
    t->flat_light = flat[front ? 0 : 1];
    t->facing = front ? 1 : -1;
    for (int i = 1; i + 1 < n; i++)
        raster_triangle(t, &sv[0], &sv[i], &sv[i + 1]);
}

/* ---- the mesh ---- */

static void transform(const double m[16], const double p[4], double out[4])
{
    for (int i = 0; i < 4; i++)
        out[i] = m[4 * i] * p[0] + m[4 * i + 1] * p[1] + m[4 * i + 2] * p[2] + m[4 * i + 3] * p[3];
}

/* The two intensities (front, behind) of a camera-space normal. */
static void light_of(const raster_style_t *st, const double l[3], const double n_cam[3],
                     double out[2])
{
    double d = dot3(n_cam, l);
    out[0] = st->ambient + st->diffuse * (d > 0 ? d : 0);
    out[1] = st->ambient + st->diffuse * (d < 0 ? -d : 0);
}

/* Camera-space vertex normals: the sum of the faces' (area-weighted) normals. */
static double *vertex_normals(const mesh_t *m, const double view[16])
{
    double *n = calloc((size_t)m->n_vertices * 3 + 3, sizeof *n);
    if (!n)
        return NULL;
    for (int f = 0; f < m->n_faces; f++) {
        double fn[3];
        mesh_face_normal(m, f, fn);
        for (int c = 0; c < 3; c++)
            for (int k = 0; k < 3; k++)
                n[3 * m->tri[3 * f + c] + k] += fn[k];
    }
    for (int v = 0; v < m->n_vertices; v++) {
        double w[3] = {0, 0, 0};
        for (int i = 0; i < 3; i++)
            for (int k = 0; k < 3; k++)
                w[i] += view[4 * i + k] * n[3 * v + k];
        normalise(w);
        memcpy(n + 3 * v, w, sizeof w);
    }
    return n;
}

pp5_status_t mesh_raster_draw(mesh_raster_t *r, const raster_viewport_t *vp, const mesh_t *m,
                              const raster_camera_t *cam, const raster_style_t *style)
{
    if (vp->width < 1 || vp->height < 1)
        return pp5_fail(PP5_E_RANGE, "raster: empty viewport %dx%d", vp->width, vp->height);
    pp5_status_t st = mesh_validate(m, m->source);
    if (st != PP5_OK)
        return st;
    tri_ctx_t t = {r, 0, 0, 0, 0, NULL, style->shading == RASTER_GOURAUD, 0,
                   style->shading == RASTER_PHONG, style, NULL, 1};
    if (!clip_viewport(r, vp, &t.x0, &t.y0, &t.x1, &t.y1) || m->n_faces == 0)
        return PP5_OK;
    double clip_from_world[16], l[3];
    memcpy(l, style->light_dir, sizeof l);
    normalise(l);
    t.l = l;
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            double acc = 0;
            for (int k = 0; k < 4; k++)
                acc += cam->proj[4 * i + k] * cam->view[4 * k + j];
            clip_from_world[4 * i + j] = acc;
        }
    bool smooth = t.gouraud || t.phong;
    double *vn = smooth ? vertex_normals(m, cam->view) : NULL;
    if (smooth && !vn)
        return pp5_fail(PP5_E_NOMEM, "raster: out of memory for %d normals", m->n_vertices);
    for (int f = 0; f < m->n_faces; f++) {
        rvert_t tri[3];
        double flat[2] = {0, 0}, fn[3], fc[3] = {0, 0, 0};
        for (int c = 0; c < 3; c++) {
            int v = m->tri[3 * f + c];
            double p[4] = {m->pos[3 * v], m->pos[3 * v + 1], m->pos[3 * v + 2], 1};
            transform(clip_from_world, p, tri[c].clip);
            if (vn)
                light_of(style, l, vn + 3 * v, tri[c].light);
            for (int k = 0; k < 3; k++)
                tri[c].n[k] = t.phong ? vn[3 * v + k] : 0;
        }
        if (!vn) {
            mesh_face_normal(m, f, fn);
            for (int i = 0; i < 3; i++)
                for (int k = 0; k < 3; k++)
                    fc[i] += cam->view[4 * i + k] * fn[k];
            normalise(fc);
            light_of(style, l, fc, flat);
        }
        draw_face(&t, vp, tri, flat, style);
    }
    free(vn);
    return PP5_OK;
}
