/* vr_gp.h: the gaze-directed volume-rendering GP program, as the host loads it.
 *
 * The host gives each GP this program with a vr_config_t block
 * (common/vr_config.h) and drives it with ring messages; what the program
 * counts comes back as named statistics (common/vr_stats.h). */
#ifndef PP5_VR_GP_H
#define PP5_VR_GP_H

#include "fw_api.h"

extern const fw_program_t vr_program;

#endif
