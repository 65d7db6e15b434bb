/* pp_params.h: pp_params_t, the renderer/PP rows of the parameter table (pp_params.def).
 *
 * The build-time sizes of the PP array and its memories come with it. */
#ifndef PP5_PP_PARAMS_H
#define PP5_PP_PARAMS_H

#include <stdint.h>
#include "util/status.h"

/* Build-time sizes; the rows pp.array_dim / pp.mem_bits / pp.bs_bits document
 * and cite them (facts §3.1) and allow no other value. */
#define PP_ARRAY_DIM     128u                       /* PPs per side */
#define PP_COUNT         (PP_ARRAY_DIM * PP_ARRAY_DIM) /* 16384 PPs per renderer */
#define PP_MEM_BITS      208u                       /* pixel memory per PP */
#define PP_BS_BITS       4096u                      /* backing store per PP */
#define PP_BS_BLOCK_BITS 32u                        /* transfer granularity, [S] S4 */
#define PP_BS_BLOCKS     (PP_BS_BITS / PP_BS_BLOCK_BITS) /* 128 */
#define PP_PLANE_WORDS   (PP_COUNT / 64u)           /* uint64 words in one bit plane */

typedef struct {
#define PARAM(KIND, NAME, FIELD, DEF, UNIT, DESC, CITE, MIN, MAX, LO, HI) uint32_t FIELD;
#include "pp_params.def"
#undef PARAM
} pp_params_t;

/* Fill with the .def defaults. */
void pp_params_default(pp_params_t *p);
/* Range check of every row (PP5_E_CONFIG naming the row); renderer_init calls it. */
pp5_status_t pp_params_check(const pp_params_t *p);

#endif
