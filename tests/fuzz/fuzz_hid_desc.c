/* fuzz_hid_desc.c: the HID report-descriptor walker (hid_desc_parse) and the
 * eye-tracker layout built on it (hid_eye_layout_init), as `pp5 track`
 * runs them on the descriptor a device returns. */
#include "common.h"

#include <stdlib.h>

#include "tracker/hid_desc.h"
#include "tracker/hid_eye.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    hid_desc_t *d = malloc(sizeof *d);
    hid_eye_layout_t *l = malloc(sizeof *l);
    if (!d || !l)
        abort();
    if (hid_desc_parse(data, size, d) == PP5_OK) {
        for (int type = 0; type < 3; type++)
            for (unsigned id = 0; id < 256; id++)
                (void)hid_desc_report_bytes(d, (hid_report_type_t)type, (uint8_t)id);
        for (size_t i = 0; i < d->n_fields; i++) {
            double factor;
            (void)hid_field_si_factor(&d->fields[i], &factor);
            (void)hid_field_physical(&d->fields[i], d->fields[i].logical_max);
        }
    }
    (void)hid_eye_layout_init(l, data, size);
    free(l);
    free(d);
    return 0;
}
