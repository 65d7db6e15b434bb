/* simplify_seed003.c: (in progress) */
#include "simplify_work.h"
pp5_status_t simplify_seed003_run(sw_t *w, const mesh_simplify_opts_t *o)
{
    return pp5_fail(PP5_E_UNSUPPORTED, "seed003: not yet built");
}
