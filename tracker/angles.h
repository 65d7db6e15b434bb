/* angles.h: screen geometry arithmetic: pixels <-> millimetres <-> visual
 * angle, and carrying gaze from a recording's display to the rendered one
 * through visual angle (gaze-facts.md §0, PROVENANCE.md "To put a trace on
 * another display").
 *
 * Model: the eye sits on the perpendicular through the screen centre at
 * distance_mm; a point's angles are atan(offset_mm / distance_mm) per axis, and
 * the angle between two gaze points is the angle between their 3D directions. */
#ifndef PP5_ANGLES_H
#define PP5_ANGLES_H

#include <stdbool.h>
#include "gaze.h"
#include "status.h"

/* Levoy & Whitaker 1990 §5 (seed paper, "We assume a 19\" television monitor
 * ... viewed from a distance of 20\" ... subtends 37°"), frame buffer
 * 1280 x 1024 (paper §2).  Derived as in gaze-facts.md §0 [I]: width
 * 2*508*tan(18.5°) = 339.9 mm over 1280 square pixels; height 1024 of them. */
#define ANGLES_PAPER_WIDTH_PX 1280
#define ANGLES_PAPER_HEIGHT_PX 1024
#define ANGLES_PAPER_DISTANCE_MM 508.0      /* 20 inches */
#define ANGLES_PAPER_FIELD_DEG 37.0         /* horizontal line through the middle */
/* Full-resolution circle: 12° of arc (4.2" diameter), paper §5. */
#define ANGLES_PAPER_FULLRES_DIAMETER_DEG 12.0

void angles_paper_geometry(gaze_geometry_t *g);

/* A geometry ready for angle arithmetic: when screen_mm/distance_mm are
 * unknown but px_per_deg is known (EyeLink END ... RES), an equivalent
 * distance is chosen (600 mm, arbitrary: only the ratio matters) and the pixel
 * pitch set so that one degree at the centre spans px_per_deg pixels.
 * Errors when neither is known. */
pp5_status_t angles_resolve(const gaze_geometry_t *in, gaze_geometry_t *out);

/* Pixel -> angles (degrees, x right, y down, 0 at the screen centre), and back.
 * The geometry must be resolved (angles_resolve). */
void angles_px_to_deg(const gaze_geometry_t *g, double x_px, double y_px, double *ax_deg,
                      double *ay_deg);
void angles_deg_to_px(const gaze_geometry_t *g, double ax_deg, double ay_deg, double *x_px,
                      double *y_px);
/* Angle in degrees between the lines of sight to two screen points. */
double angles_between_px(const gaze_geometry_t *g, double x1, double y1, double x2, double y2);
/* Same, for two points given as per-axis angles (as angles_px_to_deg returns). */
double angles_between_deg(double ax1, double ay1, double ax2, double ay2);
/* Moves a point from display `from` to display `to` keeping its direction of
 * gaze (both resolved). */
void angles_remap(const gaze_geometry_t *from, const gaze_geometry_t *to, double x_px,
                  double y_px, double *x_out, double *y_out);
/* Pixels per degree at the screen centre, horizontally. */
double angles_px_per_deg_centre(const gaze_geometry_t *g);

#endif
