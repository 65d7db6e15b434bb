/* test_params.c: parameter defaults, presets, --set/--config validation naming the parameter. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "harness.h"
#include "params.h"

static int contains(const char *s, const char *sub) { return strstr(s, sub) != NULL; }

TEST(params_defaults_follow_the_facts_sheet)
{
    pp5_params_t p;
    pp5_params_default(&p);
    CHECK_EQ(p.n_gp, 16);
    CHECK_EQ(p.n_renderers, 16);
    CHECK_EQ(p.gp_clock_hz, 40e6);
    CHECK_EQ(p.renderer_clock_hz, 40e6);
    CHECK_EQ(p.ring_channels, 8);
    CHECK_EQ(p.fb_width, 1280);
    CHECK_EQ(p.fb_height, 1024);
    /* 8 x 32 bit x 20 MHz = 640 MB/s = 5.12 Gb/s (facts §5.2). */
    CHECK_NEAR(pp5_params_ring_aggregate_bytes_per_s(&p), 640e6, 1e-3);
    CHECK(pp5_params_validate(&p) == PP5_OK);
}

TEST(params_gaze_literal_preset_is_80_megabytes_per_second)
{
    pp5_params_t p;
    REQUIRE(pp5_params_preset(&p, "gaze1990-literal") == PP5_OK);
    CHECK_NEAR(pp5_params_ring_aggregate_bytes_per_s(&p), 80e6, 1e-3);
    CHECK(pp5_params_preset(&p, "nonsense") == PP5_E_CONFIG);
}

TEST(params_every_row_is_cited_and_its_default_in_range)
{
    pp5_params_t p;
    pp5_params_default(&p);
    for (size_t i = 0; i < params_count(); i++) {
        const param_info_t *r = params_info(i);
        double v = params_get(&p, r);
        CHECK_MSG(v >= r->min && v <= r->max, "%s: default %g outside %g..%g", r->name, v, r->min,
                  r->max);
        CHECK_MSG(r->citation && strlen(r->citation) > 3 && r->unit && r->description,
                  "%s: needs a citation, a unit and a description", r->name);
        /* names are unique */
        CHECK_MSG(params_find(r->name) == r, "%s: another row has the same name", r->name);
    }
    CHECK(params_count() >= 20);
}

TEST(params_set_rejects_bad_values_naming_the_parameter)
{
    pp5_params_t p;
    pp5_params_default(&p);
    pp5_params_t before = p;
    CHECK(pp5_params_set_kv(&p, "ring.channels=0") == PP5_E_CONFIG);
    CHECK(contains(pp5_error_text(), "ring.channels") && contains(pp5_error_text(), "'0'") &&
          contains(pp5_error_text(), "1..64"));
    CHECK(pp5_params_set_kv(&p, "gp.count=33") == PP5_E_CONFIG);
    CHECK(contains(pp5_error_text(), "gp.count") && contains(pp5_error_text(), "33"));
    CHECK(pp5_params_set_kv(&p, "gp.clock_hz=fast") == PP5_E_CONFIG);
    CHECK(contains(pp5_error_text(), "not a number"));
    CHECK(pp5_params_set_kv(&p, "gp.count=2.5") == PP5_E_CONFIG);
    CHECK(pp5_params_set_kv(&p, "ring.clock_hz=nan") == PP5_E_CONFIG);
    CHECK(pp5_params_set_kv(&p, "ring.width_bits=12") == PP5_E_CONFIG);
    CHECK(contains(pp5_error_text(), "multiple of 8"));
    CHECK(pp5_params_set_kv(&p, "fb.width=1000") == PP5_E_CONFIG);
    CHECK(pp5_params_set_kv(&p, "no.such=1") == PP5_E_CONFIG);
    CHECK(contains(pp5_error_text(), "no.such"));
    CHECK(memcmp(&p, &before, sizeof p) == 0);   /* nothing committed */
    CHECK(pp5_params_set_kv(&p, "ring.channels = 4") == PP5_OK);
    CHECK_EQ(p.ring_channels, 4);
}

TEST(params_config_file_is_all_or_nothing)
{
    char path[512];
    snprintf(path, sizeof path, "%s/m.cfg", pp5_test_outdir());
    FILE *f = fopen(path, "w");
    REQUIRE(f != NULL);
    fprintf(f, "# a comment\n\nring.channels = 2   # two channels\ngp.count = 4\n");
    fclose(f);
    pp5_params_t p;
    pp5_params_default(&p);
    REQUIRE(pp5_params_load_config(&p, path) == PP5_OK);
    CHECK_EQ(p.ring_channels, 2);
    CHECK_EQ(p.n_gp, 4);

    f = fopen(path, "w");
    REQUIRE(f != NULL);
    fprintf(f, "ring.channels = 3\nrenderer.clock_hz = -5\n");
    fclose(f);
    pp5_params_default(&p);
    CHECK(pp5_params_load_config(&p, path) == PP5_E_CONFIG);
    CHECK(contains(pp5_error_text(), ":2:") && contains(pp5_error_text(), "renderer.clock_hz") &&
          contains(pp5_error_text(), "-5"));
    CHECK_EQ(p.ring_channels, 8);   /* line 1 not committed */
}

TEST(params_dump_reloads_to_the_same_values)
{
    char path[512];
    snprintf(path, sizeof path, "%s/dump.cfg", pp5_test_outdir());
    pp5_params_t p, q;
    pp5_params_default(&p);
    REQUIRE(pp5_params_set_kv(&p, "ring.clock_hz=33333333.3") == PP5_OK);
    REQUIRE(pp5_params_set_kv(&p, "gp.count=7") == PP5_OK);
    FILE *f = fopen(path, "w");
    REQUIRE(f != NULL);
    pp5_params_dump(&p, f);
    fclose(f);
    pp5_params_default(&q);
    REQUIRE(pp5_params_load_config(&q, path) == PP5_OK);
    CHECK(memcmp(&p, &q, sizeof p) == 0);
}

TEST(params_machine_command_prints_both_ring_bandwidths)
{
    char out[512];
    snprintf(out, sizeof out, "%s/m.txt", pp5_test_outdir());
    REQUIRE(pp5_test_run_cli("machine", out, NULL) == 0);
    char *text = pp5_test_read_file(out);
    REQUIRE(text != NULL);
    CHECK(contains(text, "ring aggregate bandwidth = 640 MB/s"));
    CHECK(contains(text, "ring.channels"));
    free(text);
    REQUIRE(pp5_test_run_cli("machine --preset gaze1990-literal", out, NULL) == 0);
    text = pp5_test_read_file(out);
    REQUIRE(text != NULL);
    CHECK(contains(text, "ring aggregate bandwidth = 80 MB/s"));
    free(text);
    CHECK(pp5_test_run_cli("machine --set ring.channels=99", NULL, NULL) != 0);
}

/* Every [U] and [I] row carries a plausible range for the sensitivity study,
 * inside what the model accepts and around its default, justified in its
 * citation; known and run-control rows carry none. */
TEST(params_uncertain_rows_have_a_justified_plausible_range)
{
    pp5_params_t p;
    pp5_params_default(&p);
    int ranged = 0;
    for (size_t i = 0; i < params_count(); i++) {
        const param_info_t *r = params_info(i);
        bool uncertain = contains(r->citation, "[U]") || contains(r->citation, "[I]");
        double v = params_get(&p, r);
        CHECK_MSG(r->min <= r->plausible_lo && r->plausible_lo <= v && v <= r->plausible_hi &&
                      r->plausible_hi <= r->max,
                  "%s: plausible %g..%g must lie in %g..%g around the default %g", r->name,
                  r->plausible_lo, r->plausible_hi, r->min, r->max, v);
        if (uncertain)
            CHECK_MSG(params_has_range(r) && contains(r->citation, "range"),
                      "%s is [U]/[I]: needs a plausible range, justified in its citation", r->name);
        if (!params_has_range(r))
            CHECK_MSG(r->plausible_lo == v && r->plausible_hi == v, "%s: no range means lo = hi = default",
                      r->name);
        if (r->kind != PARAM_KIND_F64)
            CHECK_MSG(r->plausible_lo == floor(r->plausible_lo) && r->plausible_hi == floor(r->plausible_hi),
                      "%s: an integer row needs integer bounds", r->name);
        ranged += params_has_range(r);
        /* Each end is itself a valid machine. */
        if (params_has_range(r)) {
            char lo[64], hi[64];
            snprintf(lo, sizeof lo, "%.17g", r->plausible_lo);
            snprintf(hi, sizeof hi, "%.17g", r->plausible_hi);
            pp5_params_t q = p;
            CHECK_MSG(pp5_params_set(&q, r->name, lo) == PP5_OK, "%s = %s: %s", r->name, lo, pp5_error_text());
            q = p;
            CHECK_MSG(pp5_params_set(&q, r->name, hi) == PP5_OK, "%s = %s: %s", r->name, hi, pp5_error_text());
        }
    }
    const param_info_t *dma = params_find("gp.rx_dma");
    REQUIRE(dma != NULL);
    CHECK_EQ(dma->plausible_lo, 0);
    CHECK_EQ(dma->plausible_hi, 1);
    CHECK(!params_has_range(params_find("i860.dcache_bytes")));   /* [C] 8 KB */
    CHECK(ranged >= 30);
}

TEST(params_machine_command_shows_plausible_ranges)
{
    char out[512];
    snprintf(out, sizeof out, "%s/m_ranges.txt", pp5_test_outdir());
    REQUIRE(pp5_test_run_cli("machine", out, NULL) == 0);
    char *text = pp5_test_read_file(out);
    REQUIRE(text != NULL);
    CHECK(contains(text, "i860.dcache_line_bytes"));
    CHECK(contains(text, "plausible: 16 .. 64"));
    CHECK(contains(text, "plausible: 0 .. 1"));
    free(text);
}
