/* scene.h: the named datasets the render commands and benchmarks use (the
 * paper's MR subject, CThead, phantoms), each with its transfer-function
 * preset and a default view, falling back to the Shepp-Logan phantom when
 * the shared data is absent. */
#ifndef PP5_SCENE_H
#define PP5_SCENE_H

#include <stdbool.h>
#include "classify.h"
#include "volume.h"

typedef struct {
    volume_t volume;
    classify_tf_t tf;
    float rot_x_deg, rot_y_deg, rot_z_deg;   /* a view that shows the subject's face/side */
    /* Window/level for MIP, DEMIP and MIDA (blend.h), in the data's units;
     * width 0: none (the volume's value range is used). */
    float window_centre, window_width;
    char name[64];                            /* "mrbrain", "cthead", "phantom shepp-logan" */
    bool fell_back;                           /* the data was absent: phantom used instead */
    bool tf_from_data;                        /* a file: the default transfer function is
                                                 chosen from its histogram (classify_auto.h) */
    char note[4400];                          /* why, when fell_back */
} scene_t;

/* Root of the shared data: $PP5_SHARED_DATA, else ../shared/data from the
 * working directory, else from the binary's place in the checkout. */
const char *scene_data_root(void);
/* dataset: "mrbrain" (brainsmall 128x128x84 u8), "cthead" (256x256x113 u16be,
 * spacing 1:1:2), or a phantom name.  With allow_fallback a missing file
 * yields the 256x256x109 Shepp-Logan phantom and fell_back = true. */
pp5_status_t scene_load(const char *dataset, bool allow_fallback, scene_t *s);
void scene_free(scene_t *s);
/* The paper's Pixel-Planes 5 workload size (seed 004 §6: 128x128x109). */
#define SCENE_PAPER_NX 128
#define SCENE_PAPER_NY 128
#define SCENE_PAPER_NZ 109
/* The scene's volume resampled (trilinearly) to the paper's size, keeping
 * the object's shape: each axis's spacing grows by n_in / n_out.  Used by
 * every machine study (projections, sweep, replay, benchmarks). */
pp5_status_t scene_paper_volume(const scene_t *s, volume_t *out);
/* Preset and view for an arbitrary loaded volume (guessed from its range). */
void scene_guess_tf(const volume_t *v, classify_tf_t *tf);

#endif
