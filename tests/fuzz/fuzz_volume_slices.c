/* fuzz_volume_slices.c: Stanford-style slice series (slice.1 .. slice.N).
 *
 * Input: one byte N (1..4 slices, and whether the series starts at 0), then
 * the slices separated by the 4 bytes "\xffSLC"; a missing or extra slice
 * number, unequal sizes and non-square sizes all reach the loader.  Slices
 * of an earlier run are removed first. */
#include "common.h"

#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "render/volume.h"

static const uint8_t separator[4] = {0xff, 'S', 'L', 'C'};

static const uint8_t *next_separator(const uint8_t *p, const uint8_t *end)
{
    for (; p + sizeof separator <= end; p++)
        if (memcmp(p, separator, sizeof separator) == 0)
            return p;
    return end;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char path[512];
    for (int i = 0; i <= 5; i++) {
        snprintf(path, sizeof path, "%s/slice.%d", fuzz_dir(), i);
        unlink(path);
    }
    if (size < 1)
        return 0;
    int first = (data[0] >> 7) & 1, max_slices = 1 + (data[0] & 3);
    const uint8_t *p = data + 1, *end = data + size;
    for (int i = 0; i < max_slices && p <= end; i++) {
        const uint8_t *q = next_separator(p, end);
        char name[32];
        snprintf(name, sizeof name, "slice.%d", first + i);
        fuzz_write(name, p, (size_t)(q - p), path, sizeof path);
        p = q + sizeof separator;
    }
    snprintf(path, sizeof path, "%s/slice.%d", fuzz_dir(), first);
    volume_t v;
    if (volume_load(path, NULL, &v) == PP5_OK)
        volume_free(&v);
    return 0;
}
