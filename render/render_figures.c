/* render_figures.c: the paper's figure 5 (sweet-spot structure) and figure 6 (the populated 2D mip-map levels) from a gaze model and a rendered 2D mip map. */
#include "render_figures.h"

#include <math.h>
#include <stdio.h>

#include "plot.h"

pp5_status_t render_write_fig5(const gaze_model_t *g, const char *path)
{
    enum { N = 400 };
    double xs[N], target[N], lo[N], hi[N];
    /* Distance in inches on the screen, out to the image's half width. */
    double max_in = 0.5 * g->width * g->inches_per_px;
    for (int i = 0; i < N; i++) {
        double r_in = max_in * i / (N - 1);
        double r_px = r_in / g->inches_per_px;
        float level = gaze_level(g, r_px);
        xs[i] = r_in;
        target[i] = gaze_target_rays_per_px(g, gaze_eccentricity_deg(g, r_px));
        lo[i] = pow(0.25, floor(level));   /* finest populated level: span */
        hi[i] = pow(0.25, ceil(level));    /* coarsest level blended in */
    }
    plot_t p;
    plot_init(&p, "Sweet spot (fig. 5)",
              "distance from gaze (inches on screen)",
              "rays per pixel");
    pp5_status_t st = plot_add_series(&p, "target", xs, target, N);
    if (st == PP5_OK)
        st = plot_add_series(&p, "floor(2DLevel)", xs, lo, N);
    if (st == PP5_OK)
        st = plot_add_series(&p, "ceil(2DLevel)", xs, hi, N);
    /* The paper's circles (diameters): 12 degrees (4.2") and 20 degrees (7"). */
    char label[64];
    snprintf(label, sizeof label, "12deg");
    if (st == PP5_OK)
        st = plot_add_xref(&p, gaze_radius_px(g, g->e_full_deg) * g->inches_per_px, label);
    snprintf(label, sizeof label, "20deg");
    if (st == PP5_OK)
        st = plot_add_xref(&p, gaze_radius_px(g, g->e_edge_deg) * g->inches_per_px, label);
    if (st == PP5_OK) {
        plot_set_style(&p, 1, PLOT_STEPS);
        plot_set_style(&p, 2, PLOT_STEPS);
        plot_set_yrange(&p, 0.0, 1.1);
        st = plot_write(&p, path, 1000, 560);
    }
    plot_free(&p);
    return st;
}

pp5_status_t render_write_mip_levels(const mip2d_t *m, const char *prefix)
{
    for (int l = 0; l < m->levels; l++) {
        image8_t img;
        pp5_status_t st = image8_alloc(&img, m->w[l], m->h[l], 3);
        if (st != PP5_OK)
            return st;
        size_t n = (size_t)m->w[l] * m->h[l];
        for (size_t i = 0; i < n; i++)
            for (int k = 0; k < 3; k++)
                img.pixels[i * 3 + k] = m->cast[l][i] ? render_to_u8(m->rgb[l][i * 3 + k]) : 40;
        char path[1100];
        snprintf(path, sizeof path, "%s%d.png", prefix, l);
        st = png_write(path, &img);
        image8_free(&img);
        if (st != PP5_OK)
            return st;
    }
    return PP5_OK;
}
