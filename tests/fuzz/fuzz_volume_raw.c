/* fuzz_volume_raw.c: the raw loader with a header (volume_load_raw, plain or
 * gzip-compressed), through a file as `pp5 render --raw` reads it.
 *
 * Input: 4 bytes that choose the layout (nx, ny, nz in 1..16, voxel type,
 * byte order and a header of 0..255 bytes), then the file itself. */
#include "common.h"

#include "render/volume.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 4)
        return 0;
    volume_raw_spec_t spec = {0};
    spec.nx = 1 + (data[0] & 15);
    spec.ny = 1 + (data[0] >> 4);
    spec.nz = 1 + (data[1] & 15);
    spec.type = (voxel_type_t)((data[1] >> 4) % 8);
    spec.big_endian = (data[2] & 1) != 0;
    spec.header_bytes = data[3];
    spec.spacing[0] = spec.spacing[1] = spec.spacing[2] = 1.0;
    char path[512];
    fuzz_write("volume.raw", data + 4, size - 4, path, sizeof path);
    volume_t v;
    if (volume_load_raw(path, &spec, &v) == PP5_OK)
        volume_free(&v);
    return 0;
}
