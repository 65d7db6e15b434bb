/* colour_sphere.h: the colour sphere of depth-enhanced MIP (seed 002 §3.3).
 *
 * A sphere around the volume carries a front colour and a back colour,
 * interpolated over its surface; the point DEMIP's second ray found is
 * tinted with the colour where the direction from the bounding-box centre to
 * that point meets the sphere:
 *
 *     s      = (1 + dir . front_pole / |dir|) / 2      (1 at the front pole)
 *     colour = back + s (front - back)
 *
 * The sphere is fixed in object space (the paper: "if the user moves the
 * sphere, the mapping makes the colors in the model to be changed
 * accordingly"), so a colour names a side of the object, not a distance from
 * the viewer: that is what resolves a front/back ambiguity.  Its orientation
 * uses the camera's angle convention (raycast.h, Rz Rx Ry): with angles
 * (x, y, z) the front pole points toward the eye of a camera with those
 * angles, i.e. -forward.  Angles (0, 0, 0) put the front pole at -z.
 *
 * The legend (seed 002 figure 1 shows "the front and back spherical
 * mapping") is two small discs in the image's lower left corner: the
 * hemisphere facing the viewer ("near") and the far hemisphere seen from
 * behind ("far"), lightly shaded so they read as a sphere.
 *
 * Maps.  The paper names only red/blue and shows its other predefined maps
 * as pictures (figure 7) whose colours the text does not give; ours are
 * red-blue plus three pairs from Okabe & Ito's Color Universal Design
 * palette (2002, revised 2008), whose colours stay distinct under
 * protanopia, deuteranopia and tritanopia. */
#ifndef PP5_COLOUR_SPHERE_H
#define PP5_COLOUR_SPHERE_H

#include <math.h>
#include "png_io.h"
#include "status.h"

typedef enum {
    SPHERE_RED_BLUE,          /* the paper's example; also pseudo-chromadepth's red near */
    SPHERE_ORANGE_BLUE,       /* Okabe-Ito orange / blue */
    SPHERE_MAGENTA_GREEN,     /* Okabe-Ito reddish purple / bluish green */
    SPHERE_YELLOW_BLUE,       /* Okabe-Ito yellow / blue */
    SPHERE_MAP_COUNT
} sphere_map_t;

typedef struct {
    const char *name;
    float front[3], back[3];
    const char *why;
} sphere_map_info_t;

const sphere_map_info_t *colour_sphere_map_info(sphere_map_t m);
pp5_status_t colour_sphere_map_parse(const char *name, sphere_map_t *out);
/* "red-blue, orange-blue, ..." for --help. */
const char *colour_sphere_map_names(void);

typedef struct {
    float pole[3];            /* unit front pole, object space */
    float front[3], back[3];
} colour_sphere_t;

/* Front pole from the orientation angles (degrees, see above). */
void colour_sphere_init(colour_sphere_t *s, sphere_map_t map, const float rot_deg[3]);

/* The colour for direction `dir` (any length; zero gives the mid colour). */
static inline void colour_sphere_colour(const colour_sphere_t *s, const float dir[3],
                                        float rgb[3])
{
    float len = sqrtf(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
    float c = len > 0.0f ? (dir[0] * s->pole[0] + dir[1] * s->pole[1] + dir[2] * s->pole[2]) / len
                         : 0.0f;
    c = c < -1.0f ? -1.0f : (c > 1.0f ? 1.0f : c);
    float f = 0.5f * (1.0f + c);
    for (int k = 0; k < 3; k++)
        rgb[k] = s->back[k] + f * (s->front[k] - s->back[k]);
}

/* Draws the legend for a camera with axes right/down/forward (object space)
 * into the lower left corner of `img` (RGB); images under 64 pixels on a
 * side get none.  Returns the legend's disc radius in pixels (0: none). */
int colour_sphere_draw_legend(const colour_sphere_t *s, const float right[3],
                              const float down[3], const float forward[3], image8_t *img);

#endif
