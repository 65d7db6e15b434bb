/* fuzz_import_eyelink.c: the EyeLink ASC importer (import_eyelink), given the
 * NUL-terminated text that import_file hands it after reading the file. */
#include "common.h"

#include <stdlib.h>

#include "tracker/import.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = fuzz_text(data, size);
    import_options_t o;
    import_defaults(&o);
    trace_t t;
    if (import_eyelink(text, size, "fuzz.input", &o, &t) == PP5_OK)
        trace_free(&t);
    /* Detection reads the same bytes first in import_file. */
    (void)import_detect(text, size);
    free(text);
    return 0;
}
