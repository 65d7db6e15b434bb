/* render_figures.h: figures 5 and 6 of Levoy & Whitaker 1990 from a render. */
#ifndef PP5_RENDER_FIGURES_H
#define PP5_RENDER_FIGURES_H

#include "gaze2d.h"
#include "renderer_native.h"

/* Figure 5: target and quantized resolution against distance from the gaze
 * point, for the display model of `g`. */
pp5_status_t render_write_fig5(const gaze_model_t *g, const char *path);
/* Figure 6: each level of the 2D mip map as PREFIX<level>.png, texels whose
 * ray was cast in colour, unpopulated texels dark grey. */
pp5_status_t render_write_mip_levels(const mip2d_t *m, const char *prefix);

#endif
