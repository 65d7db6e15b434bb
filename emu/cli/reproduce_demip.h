/* reproduce_demip.h: the emulated machine's part of `pp5 reproduce demip`
 * (reproduce_demip_machine.c): MIP, DEMIP, MIDA and compositing as firmware
 * under each work division, full resolution and gaze-directed, with each
 * image against render/'s on the same settings. */
#ifndef PP5_REPRODUCE_DEMIP_H
#define PP5_REPRODUCE_DEMIP_H

#include <stdbool.h>
#include <stddef.h>

#include "firmware/host/fw_session.h"
#include "render/scene.h"

/* The machine's panels: the paper's four columns. */
enum { DEMIP_MPANEL_MIP, DEMIP_MPANEL_DEMIP, DEMIP_MPANEL_MIDA, DEMIP_MPANEL_DVR, DEMIP_MPANELS };
enum { DEMIP_MDIVISIONS = 3 };   /* image-bands, resident, object slabs */

/* One blend under one division in one mode (0 full, 1 gaze). */
typedef struct {
    bool refused;                 /* the division does not cast this blend (object slabs) */
    bool failed;                  /* the machine stopped with an error (why: error) */
    char error[200];
    fw_frame_result_t r;          /* the frame after the first (steady) */
    double psnr_db;               /* against render/ on the same settings */
    size_t bytes_differing, bytes;
} demip_machine_cell_t;

typedef struct {
    int size;                     /* image side of the machine's frames */
    demip_machine_cell_t cell[DEMIP_MDIVISIONS][DEMIP_MPANELS][2];
} demip_machine_t;

/* All cells for the scene under `base` (its blend settings, view and
 * window), at size x size on the paper's 16 GPs and 16 renderers.  r is
 * the scene's native renderer with its max value pyramid built. */
pp5_status_t demip_machine_measure(const scene_t *sc, const render_settings_t *base, int size,
                                   native_renderer_t *r, const char *tag, demip_machine_t *out);
/* Frame time (ms) of a panel under a division and mode; NAN if refused or
 * failed. */
double demip_machine_ms(const demip_machine_t *m, int division, int panel, int mode);
/* The division with the shortest frame for a panel and mode. */
int demip_machine_best(const demip_machine_t *m, int panel, int mode);
const char *demip_machine_division_name(int division);
/* The per-division table, the image agreement and the best division per
 * blend, with whether DEMIP's second ray moves it. */
void demip_machine_print(const demip_machine_t *m);

#endif
