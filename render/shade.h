/* shade.h: gradients by central differences and the Phong-style shading of
 * Levoy 1988 (ambient + diffuse + optional specular) used by the renderers.
 *
 * Vectors are in "object space": the volume's axes, scaled so that one unit is
 * the smallest voxel spacing (so CThead's 1:1:2 slices are 2 units apart). */
#ifndef PP5_SHADE_H
#define PP5_SHADE_H

#include <stdbool.h>
#include "volume.h"

/* Which shading terms are viewpoint-independent and so may be filtered into
 * the 3D mip map (gaze paper §5 "Shading issues"); see mip3d.h for the
 * components each case stores. */
typedef enum {
    SHADE_DIFFUSE_FIXED_LIGHT,   /* Lambertian, light fixed to the object: colour+opacity stored */
    SHADE_SPECULAR_FIXED_LIGHT,  /* + specular computed per sample from stored normals */
    SHADE_MOVING_OBJECT          /* light and observer fixed, object moves: all shading per sample */
} shade_case_t;

typedef struct {
    shade_case_t lighting;
    float ambient, diffuse, specular;   /* ka, kd, ks */
    float specular_exponent;            /* n in (N.H)^n */
    /* Unit vector towards the light: in object space for the fixed-light cases,
     * in eye space (x right, y down, z into the screen) for SHADE_MOVING_OBJECT. */
    float light_dir[3];
    bool two_sided;                     /* use |N.L| so back faces are lit too */
} shade_params_t;

void shade_defaults(shade_params_t *s);
const char *shade_case_name(shade_case_t c);

/* Gradient at voxel (x,y,z) by central differences (one-sided at the faces),
 * in value units per object-space unit.  inv_spacing: 1/spacing per axis in
 * object-space units. */
void shade_gradient(const volume_t *v, int x, int y, int z, const float inv_spacing[3],
                    float g[3]);

/* Diffuse intensity ka + kd * max(N.L, 0) (or |N.L| when two-sided) for a unit
 * normal n and unit light l; 0 normal gives ka + kd (unshaded: no surface). */
float shade_diffuse(const shade_params_t *s, const float n[3], const float l[3]);
/* Specular ks * max(N.H, 0)^n for unit normal, unit half vector h. */
float shade_specular(const shade_params_t *s, const float n[3], const float h[3]);

/* Unit half vector between unit light l and unit view-towards-eye e. */
void shade_half_vector(const float l[3], const float e[3], float h[3]);

#endif
