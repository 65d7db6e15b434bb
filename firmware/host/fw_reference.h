/* fw_reference.h: the like-for-like native reference of the machine's image: render/ on a 3D mip map shaded and quantised as the machine holds it.
 *
 * The machine shades viewpoint-dependently per voxel (as the PPs do) and
 * stores 8-bit formats (common/vr_shade_fixed.h); render/ shades per sample in
 * float.  This reference applies the machine's per-voxel shading for the
 * job's view to render/'s own mip map, quantised exactly like the machine's
 * (quantised = true) or kept in float (false), so that an image test can
 * compare like with like.  For the diffuse case it only quantises. */
#ifndef PP5_FW_REFERENCE_H
#define PP5_FW_REFERENCE_H

#include <stdbool.h>
#include "render/render_job.h"

pp5_status_t fw_reference_init(native_renderer_t *nr, const render_job_t *job, bool quantised);

#endif
