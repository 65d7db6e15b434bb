/* fuzz_params_config.c: the machine parameter file (`--config FILE`,
 * pp5_params_load_config), read from a file as the commands read it. */
#include "common.h"

#include "emu/params.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char path[512];
    fuzz_write("machine.cfg", data, size, path, sizeof path);
    pp5_params_t p;
    pp5_params_default(&p);
    (void)pp5_params_load_config(&p, path);
    return 0;
}
