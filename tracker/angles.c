/* angles.c: pixels <-> mm <-> visual angle on a flat screen (see angles.h). */
#include "angles.h"

#include <math.h>

#define DEG (M_PI / 180.0)

void angles_paper_geometry(gaze_geometry_t *g)
{
    double width_mm = 2.0 * ANGLES_PAPER_DISTANCE_MM * tan(ANGLES_PAPER_FIELD_DEG / 2.0 * DEG);
    g->width_px = ANGLES_PAPER_WIDTH_PX;
    g->height_px = ANGLES_PAPER_HEIGHT_PX;
    g->width_mm = width_mm;
    g->height_mm = width_mm * ANGLES_PAPER_HEIGHT_PX / ANGLES_PAPER_WIDTH_PX; /* square pixels [I] */
    g->distance_mm = ANGLES_PAPER_DISTANCE_MM;
    g->px_per_deg = 0;
}

pp5_status_t angles_resolve(const gaze_geometry_t *in, gaze_geometry_t *out)
{
    *out = *in;
    if (in->width_px < 1 || in->height_px < 1)
        return pp5_fail(PP5_E_RANGE, "screen size %dx%d px is not positive", in->width_px,
                        in->height_px);
    if (in->width_mm > 0 && in->height_mm > 0 && in->distance_mm > 0)
        return PP5_OK;
    if (!(in->px_per_deg > 0))
        return pp5_fail(PP5_E_CONFIG, "screen geometry unknown: need screen mm and viewing "
                        "distance, or pixels per degree");
    /* Equivalent geometry: pitch p with distance*tan(1°)/p = px_per_deg. */
    out->distance_mm = 600.0;
    double pitch_mm = out->distance_mm * tan(1.0 * DEG) / in->px_per_deg;
    out->width_mm = pitch_mm * in->width_px;
    out->height_mm = pitch_mm * in->height_px;
    return PP5_OK;
}

void angles_px_to_deg(const gaze_geometry_t *g, double x_px, double y_px, double *ax_deg,
                      double *ay_deg)
{
    double xmm = (x_px - g->width_px / 2.0) * (g->width_mm / g->width_px);
    double ymm = (y_px - g->height_px / 2.0) * (g->height_mm / g->height_px);
    *ax_deg = atan(xmm / g->distance_mm) / DEG;
    *ay_deg = atan(ymm / g->distance_mm) / DEG;
}

void angles_deg_to_px(const gaze_geometry_t *g, double ax_deg, double ay_deg, double *x_px,
                      double *y_px)
{
    *x_px = g->width_px / 2.0 + g->distance_mm * tan(ax_deg * DEG) / (g->width_mm / g->width_px);
    *y_px = g->height_px / 2.0 + g->distance_mm * tan(ay_deg * DEG) / (g->height_mm / g->height_px);
}

double angles_between_deg(double ax1, double ay1, double ax2, double ay2)
{
    /* Directions (tan ax, tan ay, 1): the angle from atan2(|a x b|, a.b), which
     * stays accurate for tiny angles where acos does not. */
    double a[3] = {tan(ax1 * DEG), tan(ay1 * DEG), 1.0};
    double b[3] = {tan(ax2 * DEG), tan(ay2 * DEG), 1.0};
    double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    double cross = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    double dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    return atan2(cross, dot) / DEG;
}

double angles_between_px(const gaze_geometry_t *g, double x1, double y1, double x2, double y2)
{
    double ax1, ay1, ax2, ay2;
    angles_px_to_deg(g, x1, y1, &ax1, &ay1);
    angles_px_to_deg(g, x2, y2, &ax2, &ay2);
    return angles_between_deg(ax1, ay1, ax2, ay2);
}

void angles_remap(const gaze_geometry_t *from, const gaze_geometry_t *to, double x_px,
                  double y_px, double *x_out, double *y_out)
{
    double ax, ay;
    angles_px_to_deg(from, x_px, y_px, &ax, &ay);
    angles_deg_to_px(to, ax, ay, x_out, y_out);
}

double angles_px_per_deg_centre(const gaze_geometry_t *g)
{
    return g->distance_mm * tan(1.0 * DEG) / (g->width_mm / g->width_px);
}
