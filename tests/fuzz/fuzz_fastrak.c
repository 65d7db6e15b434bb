/* fuzz_fastrak.c: Polhemus Fastrak records, binary and ASCII
 * (fastrak_parse_binary, fastrak_parse_ascii), consumed the way a serial
 * reader consumes a stream: parse, drop what was consumed, repeat.
 *
 * Input: one byte for the format (values per record 1..16, trailing space),
 * then the stream.  A parser that consumes nothing from a non-empty stream
 * would make a reader loop forever: that is trapped here. */
#include "common.h"

#include <stdlib.h>

#include "tracker/fastrak.h"

static void drain(const uint8_t *buf, size_t len, const fastrak_format_t *fmt, int ascii)
{
    while (len > 0) {
        fastrak_record_t rec;
        size_t used = 0, skipped = 0;
        pp5_status_t st = ascii ? fastrak_parse_ascii((const char *)buf, len, fmt, &rec, &used,
                                                      &skipped)
                                : fastrak_parse_binary(buf, len, fmt, &rec, &used, &skipped);
        if (used > len || skipped > len)
            abort();
        if (used == 0) {
            /* Nothing consumed: only allowed when the data is an incomplete record. */
            if (st == PP5_OK)
                abort();
            return;
        }
        buf += used;
        len -= used;
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    fastrak_format_t fmt = {.n_values = 1 + (data[0] & 15), .trailing_space = (data[0] & 16) != 0};
    uint8_t *copy = malloc(size - 1 ? size - 1 : 1);
    if (!copy)
        abort();
    for (size_t i = 1; i < size; i++)
        copy[i - 1] = data[i];
    drain(copy, size - 1, &fmt, (data[0] & 32) != 0);
    free(copy);
    return 0;
}
