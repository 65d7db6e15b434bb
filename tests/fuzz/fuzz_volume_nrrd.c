/* fuzz_volume_nrrd.c: NRRD volumes through Teem (volume_load, the path
 * `pp5 render --volume x.nrrd` takes).
 *
 * The input is the header file: an attached .nrrd, or a detached .nhdr when
 * the first byte is odd.  A 4 KiB data file "data.raw" sits beside it, so a
 * detached header naming it (or a list of names, or a "%d" pattern) reaches
 * the data-reading code too. */
#include "common.h"

#include <string.h>

#include "render/volume.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static int have_data_file;
    char path[512];
    if (!have_data_file) {
        uint8_t bytes[4096];
        for (size_t i = 0; i < sizeof bytes; i++)
            bytes[i] = (uint8_t)(i * 7u);
        fuzz_write("data.raw", bytes, sizeof bytes, path, sizeof path);
        have_data_file = 1;
    }
    if (size < 1)
        return 0;
    fuzz_write((data[0] & 1) ? "volume.nhdr" : "volume.nrrd", data + 1, size - 1, path,
               sizeof path);
    volume_t v;
    if (volume_load(path, NULL, &v) == PP5_OK)
        volume_free(&v);
    return 0;
}
