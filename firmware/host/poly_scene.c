/* poly_scene.c: the throughput scene (poly_scene.h). */
#include "poly_scene.h"

#include <math.h>
#include <stdlib.h>

static double next_unit(unsigned *s)
{
    *s = *s * 1103515245u + 12345u;
    return (double)(*s >> 8) / 16777216.0;
}

pp5_status_t poly_scene_triangles(size_t n, double area, int width, int height, unsigned seed,
                                  poly_tri_in_t **out, raster_camera_t *cam)
{
    *out = NULL;
    if (n < 1 || n > 50000000 || !(area > 0) || area > (double)width * height)
        return pp5_fail(PP5_E_RANGE, "polygon scene: %zu triangles of %g pixels on %dx%d", n, area,
                        width, height);
    poly_tri_in_t *t = calloc(n ? n : 1, sizeof *t);   /* rgb 0: the style's colours */
    if (!t)
        return pp5_fail(PP5_E_NOMEM, "polygon scene: out of memory for %zu triangles", n);
    /* an equilateral triangle of area A has circumradius sqrt(4 A / (3 sqrt 3)) */
    double r = sqrt(4 * area / (3 * sqrt(3.0))), pi = 3.14159265358979323846;
    for (size_t i = 0; i < n; i++) {
        double cx = r + next_unit(&seed) * (width - 2 * r), cy = r + next_unit(&seed) * (height - 2 * r);
        double a0 = next_unit(&seed) * 2 * pi, z = -1.0 - 98.0 * next_unit(&seed);
        for (int c = 0; c < 3; c++) {
            double a = a0 + c * 2 * pi / 3;
            t[i].p[c][0] = (float)(cx + r * cos(a));
            t[i].p[c][1] = (float)(cy + r * sin(a));
            t[i].p[c][2] = (float)z;
            double nx = next_unit(&seed) - 0.5, ny = next_unit(&seed) - 0.5, l = sqrt(nx * nx + ny * ny + 1);
            t[i].n[c][0] = (float)(nx / l), t[i].n[c][1] = (float)(ny / l), t[i].n[c][2] = (float)(1 / l);
        }
    }
    raster_camera_ortho(0, width, 0, height, 0.5, 100.5, cam);
    *out = t;
    return PP5_OK;
}
