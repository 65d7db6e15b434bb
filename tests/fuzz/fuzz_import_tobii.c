/* fuzz_import_tobii.c: the Tobii Pro TSV importer (import_tobii), given the
 * NUL-terminated text that import_file hands it after reading the file. */
#include "common.h"

#include <stdlib.h>

#include "tracker/import.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = fuzz_text(data, size);
    import_options_t o;
    import_defaults(&o);
    /* The format does not record the screen: the command requires
     * --source-px (and angles need a scale), as here. */
    o.source_width_px = 1920;
    o.source_height_px = 1080;
    o.source_px_per_deg = 40;
    trace_t t;
    if (import_tobii(text, size, "fuzz.input", &o, &t) == PP5_OK)
        trace_free(&t);
    /* Detection reads the same bytes first in import_file. */
    (void)import_detect(text, size);
    free(text);
    return 0;
}
