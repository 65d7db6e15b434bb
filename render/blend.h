/* blend.h: what a ray does with its samples, orthogonal to full/gaze mode:
 * compositing (the gaze paper's, the default), MIP, depth-enhanced MIP
 * (Díaz & Vázquez 2010, seed 002) and MIDA (Bruckner & Gröller 2009).
 *
 * The settings and their command-line spelling live here, so that every
 * command (render, reproduce, bench) parses them the same way:
 *
 *   --blend composite|mip|demip|mida   (VTK calls this the blend mode)
 *   --window C,W          material = clamp((value - (C - W/2)) / W, 0, 1): the
 *                         window/level transfer function MIP users know
 *                         (seed 002 §3.1: the "material" is the transfer
 *                         function's value at a sample)
 *   --tolerance EPS       DEMIP ray 2 stops at m >= m_max - EPS (§3.1: "a value
 *                         around the value of interest"; no value given)
 *   --depth-weight DW     eq. (1), "around 0.15" (§3.2)
 *   --depth exact|entry-plus-length   (§3.2, see blend_ray.h)
 *   --demip-reading A|B   where eq. (1) applies (see blend_ray.h)
 *   --sphere-weight SW    eq. (2); the paper gives no value (see below)
 *   --sphere-map NAME     front/back colours (colour_sphere.h)
 *   --sphere-rotate X,Y,Z the sphere's orientation in object space
 *   --mip-pyramid max|box the 3D pyramid coarse rays read (scalar_pyramid.h)
 *
 * Default sphere weight 0.3: eq. (2) keeps (1 - SW) of the DEMIP grey-level
 * contrast, so 0.3 keeps 70% of it, while the tint that separates front from
 * back on a white structure is SW * |front - back|: 0.3 in each of R and B
 * for red-blue (77 of 255 levels), far above a just-noticeable difference.
 * 0.5 would halve the detail contrast; 0.15 (the paper's dw) gives a tint of
 * 38 levels that dark structures (grey < 0.3) no longer show.  Default
 * tolerance 0.1: see ARCHITECTURE.md's eps sweep (no paper value). */
#ifndef PP5_BLEND_H
#define PP5_BLEND_H

#include <stdbool.h>
#include "colour_sphere.h"
#include "json.h"
#include "status.h"

typedef enum { BLEND_COMPOSITE, BLEND_MIP, BLEND_DEMIP, BLEND_MIDA } blend_mode_t;
typedef enum { DEMIP_DEPTH_EXACT, DEMIP_DEPTH_ENTRY_PLUS_LENGTH } demip_depth_t;
typedef enum { DEMIP_READING_A, DEMIP_READING_B } demip_reading_t;
typedef enum { SCALAR_PYRAMID_MAX, SCALAR_PYRAMID_BOX } scalar_pyramid_kind_t;

typedef struct {
    blend_mode_t mode;
    /* Window in the volume's own units; width 0 = the volume's value range. */
    float window_centre, window_width;
    float tolerance;              /* eps, material units */
    float depth_weight;           /* dw */
    float sphere_weight;          /* sw; 0 = no colour sphere and no legend */
    sphere_map_t sphere_map;
    float sphere_rot_deg[3];      /* x, y, z in the camera's convention (raycast.h) */
    bool sphere_rot_given;        /* false: callers may substitute the scene's view */
    demip_depth_t depth;
    demip_reading_t reading;
    scalar_pyramid_kind_t pyramid;
    bool legend;                  /* draw the sphere legend (when sw > 0) */
} blend_settings_t;

void blend_settings_defaults(blend_settings_t *b);
/* What the user left unset, from a dataset's defaults: the window (when
 * width 0 and window_width > 0) and the sphere orientation (its front then
 * faces the viewer of the dataset's default view). */
void blend_settings_fill(blend_settings_t *b, float window_centre, float window_width,
                         const float view_rot_deg[3]);
/* Rejects NaN and out-of-range values (PP5_E_RANGE naming the field). */
pp5_status_t blend_settings_check(const blend_settings_t *b);

const char *blend_mode_name(blend_mode_t m);
const char *demip_depth_name(demip_depth_t d);
const char *scalar_pyramid_kind_name(scalar_pyramid_kind_t k);

/* One command-line option: `name` without the dashes ("blend", "window", ...),
 * `value` its argument.  PP5_E_CONFIG naming the option on a bad value or an
 * unknown name. */
pp5_status_t blend_option(const char *name, const char *value, blend_settings_t *b);
/* The --help lines for the options above, with a worked example. */
const char *blend_help(void);
/* The settings as JSON members of the object being written. */
void blend_report_json(json_writer_t *j, const blend_settings_t *b);

#endif
