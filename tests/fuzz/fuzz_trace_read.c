/* fuzz_trace_read.c: pp5's own trace reader (trace_parse, what
 * trace_read_file runs on a file's text). */
#include "common.h"

#include <stdlib.h>

#include "tracker/trace_file.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = fuzz_text(data, size);
    trace_t t;
    if (trace_parse(text, size, "fuzz.trace", &t) == PP5_OK)
        trace_free(&t);
    free(text);
    return 0;
}
