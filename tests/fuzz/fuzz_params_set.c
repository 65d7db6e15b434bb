/* fuzz_params_set.c: `--set NAME=VALUE` (pp5_params_set_kv), one setting
 * per input line, applied in order to one parameter set and then validated
 * as pp5_params_build does. */
#include "common.h"

#include <stdlib.h>
#include <string.h>

#include "emu/params.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = fuzz_text(data, size);
    pp5_params_t p;
    pp5_params_default(&p);
    pp5_status_t st = PP5_OK;
    for (char *line = text, *next; line && st == PP5_OK; line = next) {
        next = strchr(line, '\n');
        if (next)
            *next++ = '\0';
        st = pp5_params_set_kv(&p, line);
    }
    if (st == PP5_OK)
        (void)pp5_params_validate(&p);
    free(text);
    return 0;
}
