/* mesh_scene.c: scenes of placed meshes (mesh_scene.h): the built-in scene,
 * one-mesh scenes, bounds, cameras, levels of detail and the flattening into
 * one world-space triangle list.  The scene file reader is mesh_scene_file.c. */
#include "mesh_scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_gen.h"
#include "mesh_scene_internal.h"

static const double PI = 3.14159265358979323846;

void mesh_scene_init(mesh_scene_t *s, const char *source)
{
    memset(s, 0, sizeof *s);
    snprintf(s->source, sizeof s->source, "%s", source);
    s->light_dir[0] = -0.45, s->light_dir[1] = 0.55, s->light_dir[2] = 0.70;
    s->ambient = 0.18, s->diffuse = 0.82, s->specular = 0, s->shininess = 32;
    s->background[0] = s->background[1] = s->background[2] = 1;
    s->fovy_deg = 40;
    s->cull_back = true;
}

void mesh_scene_free(mesh_scene_t *s)
{
    for (int i = 0; i < s->n_meshes; i++) {
        mesh_free(&s->meshes[i].mesh);
        if (s->meshes[i].have_rec)
            mesh_record_free(&s->meshes[i].rec);
    }
    free(s->meshes);
    free(s->objects);
    memset(s, 0, sizeof *s);
}

void scene_mat_identity(double m[16])
{
    memset(m, 0, 16 * sizeof *m);
    m[0] = m[5] = m[10] = m[15] = 1;
}

/* m = a x m (a applied after m) */
void scene_mat_premul(const double a[16], double m[16])
{
    double r[16];
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            double acc = 0;
            for (int k = 0; k < 4; k++)
                acc += a[4 * i + k] * m[4 * k + j];
            r[4 * i + j] = acc;
        }
    memcpy(m, r, sizeof r);
}

/* Rotation by deg degrees about the unit axis (x, y, z) (Rodrigues). */
void scene_mat_rotation(double deg, const double axis[3], double m[16])
{
    double x = axis[0], y = axis[1], z = axis[2], c = cos(deg * PI / 180), s = sin(deg * PI / 180);
    double t = 1 - c;
    scene_mat_identity(m);
    m[0] = t * x * x + c, m[1] = t * x * y - s * z, m[2] = t * x * z + s * y;
    m[4] = t * x * y + s * z, m[5] = t * y * y + c, m[6] = t * y * z - s * x;
    m[8] = t * x * z - s * y, m[9] = t * y * z + s * x, m[10] = t * z * z + c;
}

pp5_status_t scene_add_mesh(mesh_scene_t *s, mesh_t *m, int *index)
{
    if (s->n_meshes >= MESH_SCENE_MAX_MESHES)
        return pp5_fail(PP5_E_RANGE, "%s: more than %d distinct meshes", s->source,
                        MESH_SCENE_MAX_MESHES);
    scene_mesh_t *grown = realloc(s->meshes, sizeof *grown * (size_t)(s->n_meshes + 1));
    if (!grown)
        return pp5_fail(PP5_E_NOMEM, "%s: out of memory for meshes", s->source);
    s->meshes = grown;
    scene_mesh_t *sm = &s->meshes[s->n_meshes];
    memset(sm, 0, sizeof *sm);
    sm->mesh = *m;
    memset(m, 0, sizeof *m);
    double lo[3], hi[3];
    mesh_bounds(&sm->mesh, lo, hi);
    for (int k = 0; k < 3; k++)
        sm->centre[k] = 0.5 * (lo[k] + hi[k]);
    sm->radius = 0.5 * sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                            (hi[2] - lo[2]) * (hi[2] - lo[2]));
    *index = s->n_meshes++;
    return PP5_OK;
}

pp5_status_t scene_add_object(mesh_scene_t *s, int mesh, const double rgb[3])
{
    if (s->n_objects >= MESH_SCENE_MAX_OBJECTS)
        return pp5_fail(PP5_E_RANGE, "%s: more than %d objects", s->source,
                        MESH_SCENE_MAX_OBJECTS);
    /* grow by doubling: a scene of 100,000 instances is read in linear time */
    int n = s->n_objects;
    if ((n & (n - 1)) == 0) {
        scene_object_t *grown = realloc(s->objects, sizeof *grown * (size_t)(n ? 2 * n : 1));
        if (!grown)
            return pp5_fail(PP5_E_NOMEM, "%s: out of memory for objects", s->source);
        s->objects = grown;
    }
    scene_object_t *o = &s->objects[s->n_objects++];
    o->mesh = mesh;
    scene_mat_identity(o->xform);
    memcpy(o->rgb, rgb, sizeof o->rgb);
    return PP5_OK;
}

pp5_status_t mesh_scene_from_mesh(mesh_t *m, mesh_scene_t *s)
{
    mesh_scene_init(s, m->source);
    s->cull_back = false;   /* an open scan shows its inside through its holes */
    static const double grey[3] = {214 / 255.0, 208 / 255.0, 196 / 255.0};
    int index;
    pp5_status_t st = scene_add_mesh(s, m, &index);
    if (st == PP5_OK)
        st = scene_add_object(s, index, grey);
    if (st != PP5_OK)
        mesh_scene_free(s);
    return st;
}

/* Colour of grid cell k: hues around the circle at full value, 0.75 saturation. */
static void palette(int k, double rgb[3])
{
    double h = fmod(k * 0.6180339887498949, 1.0) * 6;
    int i = (int)h;
    double f = h - i, lo = 0.25, up = 0.25 + 0.75 * f, dn = 1 - 0.75 * f;
    const double tab[6][3] = {{1, up, lo}, {dn, 1, lo}, {lo, 1, up},
                              {lo, dn, 1}, {up, lo, 1}, {1, lo, dn}};
    memcpy(rgb, tab[i % 6], 3 * sizeof *rgb);
}

pp5_status_t mesh_scene_builtin(const char *name, mesh_scene_t *s)
{
    if (strcmp(name, "gen:spheres100k") != 0)
        return pp5_fail(PP5_E_CONFIG, "%s: unknown built-in scene (gen:spheres100k)", name);
    mesh_scene_init(s, name);
    mesh_t sphere, torus;
    int is, it;
    pp5_status_t st = mesh_gen_uv_sphere(25, 21, 1.0, &sphere);
    if (st != PP5_OK)
        return st;
    if ((st = scene_add_mesh(s, &sphere, &is)) != PP5_OK ||
        (st = mesh_gen_torus(25, 20, 0.8, 0.35, &torus)) != PP5_OK)
        return mesh_scene_free(s), mesh_free(&sphere), st;
    if ((st = scene_add_mesh(s, &torus, &it)) != PP5_OK)
        return mesh_scene_free(s), mesh_free(&torus), st;
    for (int j = 0; j < 10 && st == PP5_OK; j++)
        for (int i = 0; i < 10 && st == PP5_OK; i++) {
            int k = 10 * j + i;
            double rgb[3], r[16], t[16];
            palette(k, rgb);
            if ((st = scene_add_object(s, (i + j) % 2 ? it : is, rgb)) != PP5_OK)
                break;
            double *x = s->objects[s->n_objects - 1].xform;
            const double axis[3] = {0.6, 0.8, 0};
            scene_mat_rotation(37.0 * k, axis, r);     /* the tori face every way */
            scene_mat_premul(r, x);
            scene_mat_identity(t);
            t[3] = 3.0 * (i - 4.5), t[7] = 3.0 * (j - 4.5), t[11] = -2.0 * ((3 * i + 7 * j) % 5);
            scene_mat_premul(t, x);
        }
    s->have_camera = true;
    s->eye[0] = 0, s->eye[1] = 0, s->eye[2] = 36;
    s->target[0] = s->target[1] = 0, s->target[2] = -4;
    s->fovy_deg = 45;
    s->specular = 0.4, s->shininess = 24;
    if (st != PP5_OK)
        mesh_scene_free(s);
    return st;
}

pp5_status_t mesh_scene_load(const char *path, mesh_scene_t *s)
{
    if (strncmp(path, "gen:", 4) == 0)
        return mesh_scene_builtin(path, s);
    return mesh_scene_read_file(path, s);
}

pp5_status_t mesh_scene_load_mesh(const char *path, mesh_scene_t *s)
{
    mesh_t m;
    pp5_status_t st = strncmp(path, "gen:", 4) == 0 ? mesh_gen_by_name(path, &m)
                                                     : mesh_load(path, &m);
    if (st == PP5_OK && m.n_faces == 0) {
        mesh_free(&m);
        st = pp5_fail(PP5_E_FORMAT, "%s: the mesh has no faces", path);
    }
    if (st != PP5_OK)
        return st;
    return mesh_scene_from_mesh(&m, s);
}

static void xform_point(const double m[16], const double p[3], double out[3])
{
    for (int i = 0; i < 3; i++)
        out[i] = m[4 * i] * p[0] + m[4 * i + 1] * p[1] + m[4 * i + 2] * p[2] + m[4 * i + 3];
}

void mesh_scene_bounds(const mesh_scene_t *s, double lo[3], double hi[3])
{
    for (int k = 0; k < 3; k++)
        lo[k] = INFINITY, hi[k] = -INFINITY;
    for (int o = 0; o < s->n_objects; o++) {
        double mlo[3], mhi[3];
        mesh_bounds(&s->meshes[s->objects[o].mesh].mesh, mlo, mhi);
        for (int c = 0; c < 8; c++) {
            double p[3] = {(c & 1 ? mhi : mlo)[0], (c & 2 ? mhi : mlo)[1], (c & 4 ? mhi : mlo)[2]};
            double w[3];
            xform_point(s->objects[o].xform, p, w);
            for (int k = 0; k < 3; k++)
                lo[k] = fmin(lo[k], w[k]), hi[k] = fmax(hi[k], w[k]);
        }
    }
    if (!(lo[0] <= hi[0]))
        for (int k = 0; k < 3; k++)
            lo[k] = -1, hi[k] = 1;
}

static void normalise3(double v[3])
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (l > 0)
        v[0] /= l, v[1] /= l, v[2] /= l;
}

static void cross(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

void mesh_scene_camera(const mesh_scene_t *s, double aspect, raster_camera_t *cam)
{
    double lo[3], hi[3], eye[3], target[3];
    mesh_scene_bounds(s, lo, hi);
    double c[3] = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
    double radius = 0.5 * sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                               (hi[2] - lo[2]) * (hi[2] - lo[2]));
    double fovy = s->fovy_deg;
    if (s->have_camera) {
        memcpy(eye, s->eye, sizeof eye), memcpy(target, s->target, sizeof target);
    } else {
        /* the bounding sphere inside the narrower half angle, seen from +z */
        double half = 0.5 * fovy * PI / 180, narrow = aspect < 1 ? atan(tan(half) * aspect) : half;
        double dist = 1.05 * radius / sin(narrow);
        memcpy(target, c, sizeof target);
        eye[0] = c[0], eye[1] = c[1], eye[2] = c[2] + dist;
    }
    double back[3] = {eye[0] - target[0], eye[1] - target[1], eye[2] - target[2]}, up[3] = {0, 1, 0};
    normalise3(back);
    if (fabs(back[1]) > 0.999)   /* looking straight up or down: +z is up on the screen */
        up[1] = 0, up[2] = 1;
    double x[3], y[3];
    cross(up, back, x);
    normalise3(x);
    cross(back, x, y);
    const double *rows[3] = {x, y, back};
    for (int i = 0; i < 3; i++) {
        cam->view[4 * i] = rows[i][0], cam->view[4 * i + 1] = rows[i][1];
        cam->view[4 * i + 2] = rows[i][2];
        cam->view[4 * i + 3] = -(rows[i][0] * eye[0] + rows[i][1] * eye[1] + rows[i][2] * eye[2]);
    }
    cam->view[12] = cam->view[13] = cam->view[14] = 0, cam->view[15] = 1;
    double dc = sqrt((c[0] - eye[0]) * (c[0] - eye[0]) + (c[1] - eye[1]) * (c[1] - eye[1]) +
                     (c[2] - eye[2]) * (c[2] - eye[2]));
    if (!(radius > 0))
        radius = 1;
    double z_far = dc + 1.1 * radius, z_near = fmax(dc - 1.1 * radius, 1e-3 * z_far);
    raster_camera_t p;
    raster_camera_perspective(fovy, aspect, z_near, z_far, &p);
    memcpy(cam->proj, p.proj, sizeof p.proj);
}

pp5_status_t mesh_scene_build_records(mesh_scene_t *s)
{
    for (int i = 0; i < s->n_meshes; i++) {
        scene_mesh_t *sm = &s->meshes[i];
        if (sm->have_rec)
            continue;
        mesh_simplify_opts_t o;
        mesh_simplify_defaults(&o, MESH_QEM);
        o.target_faces = 0;
        pp5_status_t st = mesh_simplify(&sm->mesh, &o, NULL, &sm->rec, NULL);
        if (st != PP5_OK)
            return st;
        sm->have_rec = true;
    }
    return PP5_OK;
}
