/* fuzz_hid_report.c: the eye-tracker report parser (hid_eye_parse_tracking
 * and hid_eye_parse_feature) on reports a device might send.
 *
 * Input: a 2-byte little-endian descriptor length, the descriptor, then
 * reports, each a length byte and that many bytes.  The seeds hold pp5's own
 * page-0x12 descriptor, so most runs reach the report code. */
#include "common.h"

#include <stdlib.h>

#include "tracker/hid_eye.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 2)
        return 0;
    size_t desc_len = (size_t)data[0] | (size_t)data[1] << 8;
    if (desc_len > size - 2)
        return 0;
    hid_eye_layout_t *l = malloc(sizeof *l);
    if (!l)
        abort();
    if (hid_eye_layout_init(l, data + 2, desc_len) == PP5_OK) {
        size_t at = 2 + desc_len;
        hid_eye_config_t cfg = {.quality = -1};
        while (at < size) {
            size_t n = data[at++];
            if (n > size - at)
                n = size - at;
            /* an exact-size copy, so ASan sees any read past the report */
            uint8_t *report = malloc(n ? n : 1);
            if (!report)
                abort();
            for (size_t i = 0; i < n; i++)
                report[i] = data[at + i];
            hid_eye_sample_t s;
            (void)hid_eye_parse_tracking(l, report, n, &s);
            (void)hid_eye_parse_feature(l, report, n, &cfg);
            free(report);
            at += n;
        }
    }
    free(l);
    return 0;
}
