/* reproduce_demip_machine.c: the emulated Pixel-Planes 5's columns of `pp5 reproduce demip`: MIP, DEMIP, MIDA and compositing as firmware (firmware/ARCHITECTURE.md "Blends") under each work division, full resolution and gaze-directed, each image against render/'s on the same settings. */
#include "reproduce_demip.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "render/quality.h"

static const fw_division_t divisions[DEMIP_MDIVISIONS] = {
    FW_DIVISION_IMAGE_BANDS, FW_DIVISION_RESIDENT, FW_DIVISION_OBJECT_SLABS};
static const char *const mpanel_names[DEMIP_MPANELS] = {"MIP", "DEMIP", "MIDA", "compositing"};

const char *demip_machine_division_name(int division)
{
    return fw_division_name(divisions[division]);
}

static blend_mode_t mpanel_blend(int panel)
{
    return panel == DEMIP_MPANEL_MIP     ? BLEND_MIP
           : panel == DEMIP_MPANEL_DEMIP ? BLEND_DEMIP
           : panel == DEMIP_MPANEL_MIDA  ? BLEND_MIDA
                                         : BLEND_COMPOSITE;
}

/* The machine's image against render/'s on the same settings (2DLevel by
 * the paper's tables, as the firmware computes it). */
static pp5_status_t agreement(native_renderer_t *r, const render_settings_t *s, const image8_t *img,
                              double gx, double gy, demip_machine_cell_t *c)
{
    image8_t ref = {0};
    render_settings_t ns = *s;
    ns.gaze_x = gx;
    ns.gaze_y = gy;
    render_stats_t stats;
    pp5_status_t st = native_renderer_frame(r, &ns, &ref, &stats);
    quality_t q;
    if (st == PP5_OK)
        st = quality_compare(img, &ref, &r->gaze, gx, gy, &q);
    if (st == PP5_OK) {
        c->psnr_db = q.psnr_db;
        c->bytes = (size_t)img->width * img->height * img->channels;
        c->bytes_differing = 0;
        for (size_t i = 0; i < c->bytes; i++)
            c->bytes_differing += img->pixels[i] != ref.pixels[i];
    }
    image8_free(&ref);
    return st;
}

/* A cell whose session or frame failed on the machine (a limit of the
 * firmware, such as local memory under object slabs): noted and printed,
 * the other cells still run. */
static pp5_status_t cell_failed(demip_machine_cell_t *c)
{
    c->failed = true;
    snprintf(c->error, sizeof c->error, "%s", pp5_error_text());
    return PP5_OK;
}

/* Two frames of one session: the gaze at the centre, then 12 pixels to the
 * right (the second is reported: resident has its units by then). */
static pp5_status_t run_cell(const scene_t *sc, const render_settings_t *s, fw_division_t division,
                             native_renderer_t *r, demip_machine_cell_t *c)
{
    memset(c, 0, sizeof *c);
    shade_params_t sh;
    shade_defaults(&sh);
    render_job_t job = {.volume = &sc->volume, .volume_name = sc->volume.source, .tf = sc->tf,
                        .shade = sh, .settings = *s, .frames = 2};
    pp5_params_t p;
    pp5_params_default(&p);
    p.n_gp = 16;                  /* Pixel-Planes 5 as seed 004 describes it (§2) */
    p.n_renderers = 16;
    /* A full-resolution blend at 512x512 takes 12-20 emulated seconds on
     * CThead: the default 10 s guard against runaway frames would stop it. */
    if (p.sim_budget_s < 120.0)
        p.sim_budget_s = 120.0;
    fw_options_t o;
    fw_options_default(&o);
    o.division = division;
    fw_session_t sess;
    pp5_status_t st = fw_session_init(&sess, &job, &p, &o);
    if (st == PP5_E_UNSUPPORTED && s->blend.mode != BLEND_COMPOSITE) {
        c->refused = true;        /* the reason is in firmware/ARCHITECTURE.md "Blends" */
        return PP5_OK;
    }
    if (st != PP5_OK)
        return cell_failed(c);
    double cx = 0.5 * (s->width - 1), gx = cx + 12.0;
    image8_t img = {0};
    for (int f = 0; st == PP5_OK && f < 2; f++) {
        image8_free(&img);
        st = fw_session_frame(&sess, f ? gx : cx, cx, &img, &c->r);
    }
    bool machine_ok = st == PP5_OK;
    if (machine_ok)
        st = agreement(r, s, &img, gx, cx, c);
    image8_free(&img);
    fw_session_free(&sess);
    return machine_ok ? st : cell_failed(c);
}

pp5_status_t demip_machine_measure(const scene_t *sc, const render_settings_t *base, int size,
                                   native_renderer_t *r, const char *tag, demip_machine_t *out)
{
    memset(out, 0, sizeof *out);
    out->size = size;
    pp5_status_t st = PP5_OK;
    for (int d = 0; st == PP5_OK && d < DEMIP_MDIVISIONS; d++)
        for (int p = 0; st == PP5_OK && p < DEMIP_MPANELS; p++)
            for (int m = 0; st == PP5_OK && m < 2; m++) {
                render_settings_t s = *base;
                s.width = s.height = size;
                s.mode = m ? RENDER_MODE_GAZE : RENDER_MODE_FULL;
                s.level_tables = true;
                s.blend.mode = mpanel_blend(p);
                s.blend.sphere_weight = 0.0f;   /* the paper's DEMIP column */
                if (isatty(2))
                    fprintf(stderr, "\r  %s: machine, %s, %s, %s%-12s", tag,
                            demip_machine_division_name(d), mpanel_names[p], m ? "gaze" : "full",
                            "");
                st = run_cell(sc, &s, divisions[d], r, &out->cell[d][p][m]);
            }
    if (isatty(2))
        fprintf(stderr, "\r%70s\r", "");
    return st;
}

double demip_machine_ms(const demip_machine_t *m, int division, int panel, int mode)
{
    const demip_machine_cell_t *c = &m->cell[division][panel][mode];
    return c->refused || c->failed ? NAN : 1e3 * c->r.frame_time_s;
}

int demip_machine_best(const demip_machine_t *m, int panel, int mode)
{
    int best = -1;
    for (int d = 0; d < DEMIP_MDIVISIONS; d++) {
        double t = demip_machine_ms(m, d, panel, mode);
        if (!isnan(t) && (best < 0 || t < demip_machine_ms(m, best, panel, mode)))
            best = d;
    }
    return best;
}

static void print_cell(const demip_machine_cell_t *c)
{
    if (c->refused || c->failed) {
        printf(" %10s %-22s", c->refused ? "refused" : "failed", "");
        return;
    }
    char agree[32];
    if (c->bytes_differing == 0)
        snprintf(agree, sizeof agree, "identical");
    else
        snprintf(agree, sizeof agree, "%.1f dB, %.2f%% bytes", c->psnr_db,
                 100.0 * (double)c->bytes_differing / (double)c->bytes);
    printf(" %10.1f %-22s", 1e3 * c->r.frame_time_s, agree);
}

void demip_machine_print(const demip_machine_t *m)
{
    printf("  emulated Pixel-Planes 5 (16 GPs, 16 renderers), %dx%d, the frame after the first\n"
           "  (gaze moved 12 px), machine ms and the image against render/'s on the same\n"
           "  settings (compositing: against render/'s float mip map, so the machine's 8-bit\n"
           "  formats show; firmware/ARCHITECTURE.md \"Where the machine's image differs\"):\n",
           m->size, m->size);
    for (int mode = 0; mode < 2; mode++) {
        printf("  %-13s %-13s %10s %-22s %s\n", mode ? "gaze" : "full", "division", "ms",
               " vs native", "bottleneck");
        for (int d = 0; d < DEMIP_MDIVISIONS; d++)
            for (int p = 0; p < DEMIP_MPANELS; p++) {
                const demip_machine_cell_t *c = &m->cell[d][p][mode];
                printf("    %-11s %-13s", mpanel_names[p], demip_machine_division_name(d));
                print_cell(c);
                printf(" %s\n", c->refused  ? "(firmware/ARCHITECTURE.md \"Blends\")"
                                 : c->failed ? c->error
                                             : c->r.bottleneck);
            }
    }
    printf("  best division per blend (shortest frame):\n");
    for (int mode = 0; mode < 2; mode++) {
        printf("    %-5s", mode ? "gaze" : "full");
        for (int p = 0; p < DEMIP_MPANELS; p++) {
            int b = demip_machine_best(m, p, mode);
            printf("  %s: %s", mpanel_names[p], b < 0 ? "-" : demip_machine_division_name(b));
        }
        int bm = demip_machine_best(m, DEMIP_MPANEL_MIP, mode);
        int bd = demip_machine_best(m, DEMIP_MPANEL_DEMIP, mode);
        printf("\n           DEMIP's second ray %s the best division against MIP's\n",
               bm == bd ? "does not change" : "changes");
    }
}
