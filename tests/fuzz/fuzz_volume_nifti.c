/* fuzz_volume_nifti.c: NIfTI-1 volumes through niftilib (volume_load on a
 * .nii, or a .nii.gz when the input starts with the gzip magic). */
#include "common.h"

#include "render/volume.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char path[512];
    int gz = size >= 2 && data[0] == 0x1f && data[1] == 0x8b;
    fuzz_write(gz ? "volume.nii.gz" : "volume.nii", data, size, path, sizeof path);
    volume_t v;
    if (volume_load(path, NULL, &v) == PP5_OK)
        volume_free(&v);
    return 0;
}
