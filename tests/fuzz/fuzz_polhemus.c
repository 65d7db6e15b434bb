/* fuzz_polhemus.c: Polhemus Patriot/Liberty record parsing
 * (polhemus_parse_records) on one bulk IN transfer, for each record tag. */
#include "common.h"

#include "tracker/polhemus.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *const tags[] = {"PA", "LY"};
    if (size > POLHEMUS_IN_BYTES)
        return 0;   /* one transfer is at most this long */
    polhemus_record_t recs[POLHEMUS_MAX_STATIONS];
    size_t n;
    for (int t = 0; t < 2; t++)
        (void)polhemus_parse_records(data, size, tags[t], recs, POLHEMUS_MAX_STATIONS, &n);
    return 0;
}
