/* mesh_lod.c: levels of detail by eccentricity and screen size (mesh_lod.h). */
#include "mesh_lod.h"

#include <math.h>

static const double PI = 3.14159265358979323846;

static void mat4_vec(const double m[16], const double p[4], double out[4])
{
    for (int i = 0; i < 4; i++)
        out[i] = m[4 * i] * p[0] + m[4 * i + 1] * p[1] + m[4 * i + 2] * p[2] + m[4 * i + 3] * p[3];
}

/* The largest factor by which x stretches a length (its largest column norm
 * bounds it for the scale-and-rotate transforms of scene files). */
static double stretch(const double x[16])
{
    double s = 0;
    for (int c = 0; c < 3; c++)
        s = fmax(s, sqrt(x[c] * x[c] + x[4 + c] * x[4 + c] + x[8 + c] * x[8 + c]));
    return s;
}

/* The face budget of one object (-1: keep full detail; 0: off the image). */
static double budget(const scene_mesh_t *sm, const scene_object_t *o, const raster_camera_t *cam,
                     const gaze_model_t *g, double gaze_x, double gaze_y)
{
    double c[4] = {sm->centre[0], sm->centre[1], sm->centre[2], 1}, wc[4], vc[4], cc[4];
    mat4_vec(o->xform, c, wc);
    mat4_vec(cam->view, wc, vc);
    mat4_vec(cam->proj, vc, cc);
    double radius = sm->radius * stretch(o->xform), w = cc[3];
    if (!(w > radius) || !(radius > 0))
        return -1;
    double sx = 0.5 * (cc[0] / w + 1) * g->width, sy = 0.5 * (1 - cc[1] / w) * g->height;
    double r_px = radius * fabs(cam->proj[5]) / w * 0.5 * g->height;
    if (sx + r_px < 0 || sx - r_px > g->width || sy + r_px < 0 || sy - r_px > g->height)
        return 0;
    /* pixel (x, y) has its centre at x + 0.5; the gaze is given in pixel indices */
    double d = hypot(sx - 0.5 - gaze_x, sy - 0.5 - gaze_y) - r_px;
    double rho = gaze_target_rays_per_px(g, gaze_eccentricity_deg(g, d > 0 ? d : 0));
    return 2 * PI * r_px * r_px * rho / MESH_LOD_SAMPLES_PER_FACE;
}

void mesh_lod_choose(const mesh_scene_t *s, const raster_camera_t *cam, const gaze_model_t *g,
                     double gaze_x, double gaze_y, int *levels, long *faces)
{
    *faces = 0;
    for (int i = 0; i < s->n_objects; i++) {
        const scene_object_t *o = &s->objects[i];
        const scene_mesh_t *sm = &s->meshes[o->mesh];
        double b = budget(sm, o, cam, g, gaze_x, gaze_y);
        int level = 0;
        if (sm->have_rec && b >= 0 && b < sm->mesh.n_faces)
            level = mesh_record_level_for_faces(&sm->rec, (int)ceil(b));
        levels[i] = level;
        *faces += sm->have_rec ? sm->rec.level_faces[level] : sm->mesh.n_faces;
    }
}
