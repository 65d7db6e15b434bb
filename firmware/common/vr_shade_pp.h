/* vr_shade_pp.h: builder of the PP instruction stream that shades every mip-map voxel held by a renderer (viewpoint-dependent part).
 *
 * Slot s of a PP holds one voxel of brick (renderer + s * n_renderers) in
 * backing-store blocks 3s (A), 3s+1 (N) and writes 3s+2 (O); formats and the
 * integer definition are in vr_shade_fixed.h, which the stream reproduces bit
 * for bit (tests/test_fw_pp.c runs it on the emulated renderer). */
#ifndef PP5_VR_SHADE_PP_H
#define PP5_VR_SHADE_PP_H

#include <stddef.h>
#include <stdint.h>
#include "vr_shade_fixed.h"
#include "pp_encode.h"

#define VR_BLOCKS_PER_SLOT_SPECULAR 3u

/* Appends the shading of the listed slots to st.  Returns the number of PP
 * instructions appended (the stream records any encoding error). */
size_t vr_pp_shade_stream(pp_stream_t *st, const vr_shade_consts_t *c, const uint32_t *slots,
                          size_t n_slots);

#endif
