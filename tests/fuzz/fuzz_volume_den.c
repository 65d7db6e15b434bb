/* fuzz_volume_den.c: VolPack .den density files (volume_load on a .den). */
#include "common.h"

#include "render/volume.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char path[512];
    fuzz_write("volume.den", data, size, path, sizeof path);
    volume_t v;
    if (volume_load(path, NULL, &v) == PP5_OK)
        volume_free(&v);
    return 0;
}
