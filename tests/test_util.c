/* test_util.c: tests of the shared utilities (JSON writer, PNG round trip,
 * checked sizes, strict option parsing, the command registry). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cliopt.h"
#include "harness.h"
#include "huge_alloc.h"
#include "json.h"
#include "png_io.h"
#include "registry.h"
#include "status.h"

/* Small and large arrays are aligned to a cache line and zeroed when asked;
 * growing across the huge-page threshold keeps the contents; a size whose
 * rounding would wrap is refused rather than mapped short. */
TEST(util_huge_alloc_sizes_alignment_growth_and_absurd_sizes)
{
    size_t small = 1000, large = (size_t)5 << 20;
    unsigned char *a = huge_alloc(small, true);
    REQUIRE(a);
    CHECK_EQ((uintptr_t)a % 64, 0);
    bool zero = true;
    for (size_t i = 0; i < small; i++)
        zero = zero && a[i] == 0;
    CHECK(zero);
    for (size_t i = 0; i < small; i++)
        a[i] = (unsigned char)(i * 7);
    unsigned char *b = huge_grow(a, small, small, large);
    REQUIRE(b);
    CHECK_EQ((uintptr_t)b % 64, 0);
    bool kept = true;
    for (size_t i = 0; i < small; i++)
        kept = kept && b[i] == (unsigned char)(i * 7);
    CHECK(kept);
    b[large - 1] = 1;   /* the whole length is writable */
    CHECK(b[large - 1] == 1);
    huge_free(b, large);
    CHECK(huge_alloc(SIZE_MAX - 10, false) == NULL);
    CHECK(huge_alloc(SIZE_MAX / 2 + 1, true) == NULL);
    huge_free(NULL, large);
}

TEST(util_json_nesting_and_escapes)
{
    char buf[512] = {0};
    FILE *f = fmemopen(buf, sizeof buf - 1, "w");
    json_writer_t j;
    json_init(&j, f, false);
    json_begin_object(&j);
    json_kv_string(&j, "name", "a\"b\n");
    json_key(&j, "list");
    json_begin_array(&j);
    json_int(&j, -3);
    json_double(&j, NAN);
    json_begin_object(&j);
    json_end_object(&j);
    json_end_array(&j);
    json_kv_bool(&j, "ok", true);
    json_end_object(&j);
    fclose(f);
    CHECK_MSG(strcmp(buf, "{\"name\":\"a\\\"b\\n\",\"list\":[-3,null,{}],\"ok\":true}") == 0,
              "got %s", buf);
}

TEST(util_png_round_trip)
{
    image8_t img, back;
    REQUIRE(image8_alloc(&img, 7, 5, 3) == PP5_OK);
    for (int i = 0; i < 7 * 5 * 3; i++)
        img.pixels[i] = (uint8_t)(i * 37 + 11);
    char path[1200];
    snprintf(path, sizeof path, "%s/rt.png", pp5_test_outdir());
    REQUIRE(png_write(path, &img) == PP5_OK);
    REQUIRE(png_read(path, &back, 3) == PP5_OK);
    CHECK_EQ(back.width, 7);
    CHECK_EQ(back.height, 5);
    CHECK(memcmp(img.pixels, back.pixels, 7 * 5 * 3) == 0);
    image8_free(&img);
    image8_free(&back);
}

TEST(util_png_rejects_garbage_and_truncation)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/bad.png", pp5_test_outdir());
    FILE *f = fopen(path, "wb");
    fputs("not a png at all", f);
    fclose(f);
    image8_t img;
    CHECK(png_read(path, &img, 3) == PP5_E_FORMAT);
    /* A real PNG cut in half must fail cleanly, not crash. */
    image8_t good;
    REQUIRE(image8_alloc(&good, 64, 64, 3) == PP5_OK);
    for (int i = 0; i < 64 * 64 * 3; i++)
        good.pixels[i] = (uint8_t)(rand() & 255);
    REQUIRE(png_write(path, &good) == PP5_OK);
    image8_free(&good);
    char *whole = pp5_test_read_file(path);
    REQUIRE(whole != NULL);
    free(whole);
    FILE *g = fopen(path, "r+b");
    fseek(g, 0, SEEK_END);
    long size = ftell(g);
    fclose(g);
    REQUIRE(truncate(path, size / 2) == 0);
    CHECK(png_read(path, &img, 3) == PP5_E_FORMAT);
}

TEST(util_checked_sizes)
{
    size_t out;
    CHECK(pp5_mul3_size(1000, 1000, 1000, &out) && out == 1000000000u);
    CHECK(!pp5_mul3_size(SIZE_MAX / 2, 3, 1, &out));
    CHECK(!pp5_mul_size(100000000000ull, 1000000000000ull, &out));
}

TEST(util_cliopt_strict)
{
    long v;
    int w, h;
    double x, y;
    CHECK(cliopt_long("--n", "12", 1, 32, &v) == PP5_OK && v == 12);
    CHECK(cliopt_long("--n", "12abc", 1, 32, &v) == PP5_E_CONFIG);
    CHECK(strstr(pp5_error_text(), "--n") != NULL);
    CHECK(cliopt_long("--n", "33", 1, 32, &v) == PP5_E_CONFIG);
    CHECK(cliopt_size2("--size", "640x480", 1, 4096, &w, &h) == PP5_OK && w == 640 && h == 480);
    CHECK(cliopt_size2("--size", "640", 1, 4096, &w, &h) == PP5_E_CONFIG);
    CHECK(cliopt_pair("--gaze", "300,200.5", &x, &y) == PP5_OK && x == 300 && y == 200.5);
    CHECK(cliopt_pair("--gaze", "nan,3", &x, &y) == PP5_E_CONFIG);
    CHECK(cliopt_double("--d", "inf", 0, 10, &x) == PP5_E_CONFIG);
}

TEST(util_registry_sorted)
{
    int n;
    const pp5_command_t *c = pp5_commands(&n);
    CHECK(n >= 1);
    for (int i = 1; i < n; i++)
        CHECK(strcmp(c[i - 1].name, c[i].name) < 0);
    CHECK(pp5_find_command("bench") != NULL);
}

TEST(util_fail_may_wrap_the_previous_message)
{
    pp5_fail(PP5_E_FORMAT, "byte %d is bad", 12);
    pp5_fail(PP5_E_FORMAT, "%s: %s", "/dev/hidraw0", pp5_error_text());
    CHECK_MSG(strcmp(pp5_error_text(), "/dev/hidraw0: byte 12 is bad") == 0, "got '%s'",
              pp5_error_text());
}

TEST(util_grow_doubles_and_refuses_overflow)
{
    void *items = NULL;
    size_t cap = 0;
    REQUIRE(pp5_grow(&items, &cap, 0, sizeof(int), "ints") == PP5_OK);
    CHECK_EQ(cap, 64);
    void *first = items;
    REQUIRE(pp5_grow(&items, &cap, 10, sizeof(int), "ints") == PP5_OK);
    CHECK(cap == 64 && items == first);            /* room left: nothing moves */
    REQUIRE(pp5_grow(&items, &cap, 64, sizeof(int), "ints") == PP5_OK);
    CHECK_EQ(cap, 128);
    size_t huge = (size_t)1 << 62;
    CHECK(pp5_grow(&items, &huge, huge, 16, "ints") == PP5_E_NOMEM);
    CHECK(strstr(pp5_error_text(), "too many ints") != NULL);
    CHECK_EQ(huge, (size_t)1 << 62);
    free(items);
}
