/* pp_params.c: defaults and range checks of the renderer/PP parameter rows (pp_params.def). */
#include "pp_params.h"

void pp_params_default(pp_params_t *p)
{
#define PARAM(KIND, NAME, FIELD, DEF, UNIT, DESC, CITE, MIN, MAX, LO, HI) p->FIELD = (uint32_t)(DEF);
#include "pp_params.def"
#undef PARAM
}

pp5_status_t pp_params_check(const pp_params_t *p)
{
#define PARAM(KIND, NAME, FIELD, DEF, UNIT, DESC, CITE, MIN, MAX, LO, HI)                       \
    if ((double)p->FIELD < (double)(MIN) || (double)p->FIELD > (double)(MAX))           \
        return pp5_fail(PP5_E_CONFIG, "parameter %s = %u is outside [%.0f, %.0f]", NAME, \
                        (unsigned)p->FIELD, (double)(MIN), (double)(MAX));
#include "pp_params.def"
#undef PARAM
    return PP5_OK;
}
