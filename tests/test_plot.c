/* test_plot.c: charts decode as PNGs of the requested size, come out as SVG
 * and PDF when the name says so, and data lands where the axes say it should
 * (located from the drawn frame, not from the plotting code's own mapping).
 * Lines and text are anti-aliased, so a series is found by how much of its
 * colour a pixel holds, not by exact values; the frame, grid and reference
 * lines sit on whole pixels and keep their exact colours. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "plot.h"
#include "png_io.h"

static const uint8_t *px(const image8_t *img, int x, int y)
{
    return img->pixels + ((size_t)y * img->width + x) * 3;
}

static bool is_rgb(const image8_t *img, int x, int y, int r, int g, int b)
{
    const uint8_t *p = px(img, x, y);
    return p[0] == r && p[1] == g && p[2] == b;
}

/* How much of a pure red line (255, 0, 0) on white a pixel holds, 0..1:
 * blending red over white lowers green and blue together, by the cover. */
static double red_cover(const image8_t *img, int x, int y)
{
    const uint8_t *p = px(img, x, y);
    if (p[0] < 200 || p[1] != p[2])
        return 0;
    return (p[0] - p[1]) / 255.0;
}

/* Mostly blue (0, 0, 255 blended with white: blue stays high, red = green). */
static bool bluish(const image8_t *img, int x, int y)
{
    const uint8_t *p = px(img, x, y);
    return p[2] > 200 && p[0] < 160 && abs(p[0] - p[1]) < 8;
}

/* The plot frame, found from the picture: its top and bottom edges are the
 * rows with the longest horizontal black runs, its left and right edges the
 * columns with the longest vertical ones (tick marks only lengthen runs
 * along the edges they touch, so rows and columns are found separately). */
static int longest_run(const image8_t *img, int fixed, bool along_x)
{
    int run = 0, longest = 0, n = along_x ? img->width : img->height;
    for (int i = 0; i < n; i++) {
        bool ink = along_x ? is_rgb(img, i, fixed, 0, 0, 0) : is_rgb(img, fixed, i, 0, 0, 0);
        run = ink ? run + 1 : 0;
        if (run > longest)
            longest = run;
    }
    return longest;
}

static void two_longest(const image8_t *img, bool rows, int *a, int *b)
{
    int n = rows ? img->height : img->width, best = -1;
    *a = *b = -1;
    for (int i = 0; i < n; i++) {
        int len = longest_run(img, i, rows);
        if (len > best) {
            best = len;
            *a = i;
            *b = -1;
        } else if (len == best) {
            *b = i;
        }
    }
}

static void find_frame(const image8_t *img, int *x0, int *x1, int *y0, int *y1)
{
    two_longest(img, true, y0, y1);
    two_longest(img, false, x0, x1);
}

TEST(plot_png_has_requested_size_and_decodes)
{
    plot_t p;
    plot_init(&p, "Title", "x axis", "y axis");
    double xs[3] = {0, 1, 2}, ys[3] = {1, 4, 2};
    REQUIRE(plot_add_series(&p, "s", xs, ys, 3) == PP5_OK);
    char path[1200];
    snprintf(path, sizeof path, "%s/chart.png", pp5_test_outdir());
    REQUIRE_MSG(plot_write(&p, path, 437, 291) == PP5_OK, "%s", pp5_error_text());
    image8_t img;
    REQUIRE_MSG(png_read(path, &img, 3) == PP5_OK, "%s", pp5_error_text());
    CHECK_EQ(img.width, 437);
    CHECK_EQ(img.height, 291);
    /* Mostly white background, some ink. */
    size_t white = 0, n = (size_t)img.width * img.height;
    for (size_t i = 0; i < n; i++)
        white += img.pixels[3 * i] == 255 && img.pixels[3 * i + 1] == 255 &&
                 img.pixels[3 * i + 2] == 255;
    CHECK(white > n / 2 && white < n);
    image8_free(&img);
    plot_free(&p);
}

TEST(plot_horizontal_line_lands_on_its_row)
{
    plot_t p;
    plot_init(&p, NULL, NULL, NULL);
    double xs[2] = {0, 10}, ys[2] = {7.5, 7.5};
    REQUIRE(plot_add_series(&p, "level", xs, ys, 2) == PP5_OK);
    plot_set_color(&p, 0, 255, 0, 0);
    plot_set_xrange(&p, 0, 10);
    plot_set_yrange(&p, 0, 10);
    image8_t img;
    REQUIRE_MSG(plot_render(&p, 400, 300, &img) == PP5_OK, "%s", pp5_error_text());
    int x0, x1, y0, y1;
    find_frame(&img, &x0, &x1, &y0, &y1);
    REQUIRE_MSG(y0 >= 0 && y1 > y0 + 50 && x1 > x0 + 50, "frame %d..%d x %d..%d", x0, x1, y0, y1);
    /* y = 7.5 of 0..10 is a quarter of the way down from the top edge (the
     * axis range spans the frame's pixel rows y0..y1). */
    double want = y1 - 0.75 * (y1 - y0);
    int mid = (x0 + x1) / 2 + 3;
    double sum = 0, moment = 0;
    int rows = 0;
    for (int y = 0; y < img.height; y++) {
        double c = red_cover(&img, mid, y);
        sum += c;
        moment += c * y;
        rows += c > 0.05;
    }
    /* A 2-pixel line covers 2 pixel rows, or 3 partly. */
    CHECK_MSG(rows >= 2 && rows <= 3, "line touches %d rows", rows);
    CHECK_NEAR(sum, 2.0, 0.15);
    CHECK_MSG(sum > 0 && fabs(moment / sum - want) <= 0.5, "line centred on row %.2f, expected "
              "%.1f", sum > 0 ? moment / sum : -1.0, want);
    /* The public mapping agrees with the drawn frame. */
    double mx, my;
    REQUIRE(plot_data_to_pixel(&p, 400, 300, 5, 7.5, &mx, &my));
    CHECK_NEAR(my, want, 0.5);
    CHECK_NEAR(mx, x0 + 0.5 * (x1 - x0), 0.5);
    image8_free(&img);
    plot_free(&p);
}

TEST(plot_diagonal_and_stacked_bars_in_place)
{
    plot_t p;
    plot_init(&p, "stack", "x", "y");
    double xs[2] = {2, 6}, a[2] = {2, 1}, b[2] = {3, 6};
    REQUIRE(plot_add_stacked(&p, "bottom", xs, a, 2) == PP5_OK);
    REQUIRE(plot_add_stacked(&p, "top", xs, b, 2) == PP5_OK);
    plot_set_color(&p, 0, 0, 0, 255);
    plot_set_color(&p, 1, 0, 255, 0);
    double dx[2] = {0, 10}, dy[2] = {0, 10};
    REQUIRE(plot_add_series(&p, "diag", dx, dy, 2) == PP5_OK);
    plot_set_color(&p, 2, 255, 0, 0);
    plot_set_xrange(&p, 0, 10);
    plot_set_yrange(&p, 0, 10);
    plot_set_legend(&p, false);
    image8_t img;
    REQUIRE_MSG(plot_render(&p, 500, 400, &img) == PP5_OK, "%s", pp5_error_text());
    int x0, x1, y0, y1;
    find_frame(&img, &x0, &x1, &y0, &y1);
    REQUIRE(y1 > y0 + 50);
    double sx = (x1 - x0) / 10.0, sy = (y1 - y0) / 10.0;
    /* Bar at x = 2: blue from y = 0 to 2, green from 2 to 5, white above 5.
     * Sample half a unit inside each band. */
    int col = (int)lround(x0 + 2 * sx);
    CHECK(is_rgb(&img, col, (int)lround(y1 - 1.0 * sy), 0, 0, 255));
    CHECK(is_rgb(&img, col, (int)lround(y1 - 3.5 * sy), 0, 255, 0));
    CHECK(is_rgb(&img, col, (int)lround(y1 - 5.5 * sy), 255, 255, 255) ||
          is_rgb(&img, col, (int)lround(y1 - 5.5 * sy), 225, 225, 225));   /* grid line */
    /* Bar at x = 6: blue 0..1, green 1..7. */
    col = (int)lround(x0 + 6 * sx);
    CHECK(is_rgb(&img, col, (int)lround(y1 - 0.5 * sy), 0, 0, 255));
    CHECK(is_rgb(&img, col, (int)lround(y1 - 6.5 * sy), 0, 255, 0));
    /* Diagonal y = x: at x = 8.3 (clear of the bars) the red pixels of that
     * column sit at y = 8.3, within a pixel or two. */
    col = (int)lround(x0 + 8.3 * sx);
    double want = y1 - 8.3 * sy;
    int found = 0;
    for (int y = y0; y <= y1; y++)
        if (red_cover(&img, col, y) > 0.5) {
            CHECK_MSG(fabs(y - want) <= 2.0, "red at row %d, expected ~%.1f", y, want);
            found++;
        }
    CHECK(found > 0);
    image8_free(&img);

    /* Stacked areas: between the two x values the bands are filled. */
    plot_set_stack_style(&p, PLOT_STACK_AREA);
    REQUIRE(plot_render(&p, 500, 400, &img) == PP5_OK);
    col = (int)lround(x0 + 4 * sx);   /* halfway: bottom 1.5, top 1.5 + 4.5 = 6 */
    CHECK(is_rgb(&img, col, (int)lround(y1 - 0.7 * sy), 0, 0, 255));
    CHECK(is_rgb(&img, col, (int)lround(y1 - 5.2 * sy), 0, 255, 0));  /* clear of y = x */
    CHECK(is_rgb(&img, col, (int)lround(y1 - 7.0 * sy), 255, 255, 255) ||
          is_rgb(&img, col, (int)lround(y1 - 7.0 * sy), 225, 225, 225));
    image8_free(&img);
    plot_free(&p);
}

TEST(plot_text_is_antialiased)
{
    plot_t p;
    plot_init(&p, "A title in DejaVu Sans", "x (s)", "y (ms)");
    double xs[2] = {0, 1}, ys[2] = {0, 1};
    REQUIRE(plot_add_series(&p, "s", xs, ys, 2) == PP5_OK);
    image8_t img;
    REQUIRE_MSG(plot_render(&p, 640, 400, &img) == PP5_OK, "%s", pp5_error_text());
    int x0, x1, y0, y1;
    find_frame(&img, &x0, &x1, &y0, &y1);
    /* Above the frame there is only the title: dark ink and, at its edges,
     * the intermediate grays of anti-aliasing. */
    int dark = 0, gray = 0;
    for (int y = 0; y < y0 - 1; y++)
        for (int x = 0; x < img.width; x++) {
            const uint8_t *q = px(&img, x, y);
            dark += q[0] < 60;
            gray += q[0] > 60 && q[0] < 200 && q[0] == q[1] && q[1] == q[2];
        }
    CHECK_MSG(dark > 50, "title ink: %d dark pixels", dark);
    CHECK_MSG(gray > 50, "anti-aliased edges: %d gray pixels", gray);
    image8_free(&img);
    plot_free(&p);
}

static bool file_starts_with(const char *path, const char *magic)
{
    char *text = pp5_test_read_file(path);
    bool ok = text && strncmp(text, magic, strlen(magic)) == 0;
    free(text);
    return ok;
}

TEST(plot_format_follows_the_output_name)
{
    plot_t p;
    plot_init(&p, "formats", "x (s)", "y (ms)");
    double xs[3] = {0, 1, 2}, ys[3] = {1, 3, 2};
    REQUIRE(plot_add_series(&p, "s", xs, ys, 3) == PP5_OK);
    const char *dir = pp5_test_outdir();
    char path[1200];
    snprintf(path, sizeof path, "%s/c.svg", dir);
    REQUIRE_MSG(plot_write(&p, path, 500, 300) == PP5_OK, "%s", pp5_error_text());
    CHECK(file_starts_with(path, "<?xml"));
    char *svg = pp5_test_read_file(path);
    CHECK(svg && strstr(svg, "<svg") && strstr(svg, "width=\"500"));
    free(svg);
    snprintf(path, sizeof path, "%s/c.PDF", dir);
    REQUIRE_MSG(plot_write(&p, path, 500, 300) == PP5_OK, "%s", pp5_error_text());
    CHECK(file_starts_with(path, "%PDF-"));
    /* A PNG file holds what plot_render draws (the data, not the bytes, is
     * what is compared). */
    snprintf(path, sizeof path, "%s/c.png", dir);
    REQUIRE_MSG(plot_write(&p, path, 500, 300) == PP5_OK, "%s", pp5_error_text());
    image8_t a, b;
    REQUIRE(png_read(path, &a, 3) == PP5_OK);
    REQUIRE(plot_render(&p, 500, 300, &b) == PP5_OK);
    CHECK(a.width == 500 && a.height == 300 && memcmp(a.pixels, b.pixels, 500 * 300 * 3) == 0);
    image8_free(&a);
    image8_free(&b);
    /* An unknown suffix is refused before anything is written. */
    snprintf(path, sizeof path, "%s/c.jpg", dir);
    CHECK_EQ(plot_write(&p, path, 500, 300), PP5_E_CONFIG);
    CHECK(strstr(pp5_error_text(), "c.jpg") != NULL);
    FILE *f = fopen(path, "r");
    CHECK(f == NULL);
    if (f)
        fclose(f);
    /* A folder that does not exist: an error naming the file, nothing left. */
    snprintf(path, sizeof path, "%s/no/such/dir/c.svg", dir);
    CHECK_EQ(plot_write(&p, path, 500, 300), PP5_E_IO);
    plot_free(&p);
}

TEST(plot_rejects_bad_input_and_is_deterministic)
{
    plot_t p;
    plot_init(&p, "t", "x", "y");
    double xs[3] = {1, 2, 3}, ys[3] = {1, NAN, 3}, ok[3] = {1, 2, 3}, neg[3] = {1, -1, 2};
    image8_t img;
    CHECK_EQ(plot_render(&p, 400, 300, &img), PP5_E_RANGE);          /* no series */
    CHECK_EQ(plot_add_series(&p, "nan", xs, ys, 3), PP5_E_RANGE);
    CHECK_EQ(plot_add_series(&p, "empty", xs, ok, 0), PP5_E_RANGE);
    CHECK_EQ(plot_add_stacked(&p, "neg", xs, neg, 3), PP5_E_RANGE);
    REQUIRE(plot_add_series(&p, "ok", xs, ok, 3) == PP5_OK);
    CHECK_EQ(plot_render(&p, 100, 50, &img), PP5_E_RANGE);           /* too small */
    CHECK_EQ(plot_render(&p, 20000, 300, &img), PP5_E_RANGE);
    plot_set_log_y(&p, true);
    REQUIRE(plot_render(&p, 400, 300, &img) == PP5_OK);
    image8_free(&img);
    double zero[3] = {0, 1, 2};
    REQUIRE(plot_add_series(&p, "zero", xs, zero, 3) == PP5_OK);
    CHECK_EQ(plot_render(&p, 400, 300, &img), PP5_E_RANGE);          /* log of 0 */
    plot_free(&p);

    plot_init(&p, "t", "x", "y");
    double other_x[3] = {1, 2, 4};
    REQUIRE(plot_add_stacked(&p, "a", xs, ok, 3) == PP5_OK);
    REQUIRE(plot_add_stacked(&p, "b", other_x, ok, 3) == PP5_OK);
    CHECK_EQ(plot_render(&p, 400, 300, &img), PP5_E_RANGE);          /* x values differ */
    plot_free(&p);

    for (int i = 0; i < PLOT_MAX_SERIES; i++)
        REQUIRE(plot_add_series(&p, "s", xs, ok, 3) == PP5_OK);
    CHECK_EQ(plot_add_series(&p, "one too many", xs, ok, 3), PP5_E_RANGE);
    image8_t a, b;
    REQUIRE(plot_render(&p, 640, 400, &a) == PP5_OK);
    REQUIRE(plot_render(&p, 640, 400, &b) == PP5_OK);
    CHECK(memcmp(a.pixels, b.pixels, 640 * 400 * 3) == 0);
    image8_free(&a);
    image8_free(&b);
    plot_free(&p);
}

TEST(plot_reference_lines_are_dashed_at_their_value)
{
    plot_t p;
    plot_init(&p, NULL, "x", "y");
    double xs[2] = {0, 10}, ys[2] = {0, 0.5};
    REQUIRE(plot_add_series(&p, "s", xs, ys, 2) == PP5_OK);
    plot_set_xrange(&p, 0, 10);
    plot_set_yrange(&p, 0, 10);
    REQUIRE(plot_add_xref(&p, 3, "12 deg") == PP5_OK);
    REQUIRE(plot_add_yref(&p, 6, NULL) == PP5_OK);
    REQUIRE(plot_add_xref(&p, 42, "off the chart") == PP5_OK);
    CHECK_EQ(plot_add_yref(&p, NAN, "bad"), PP5_E_RANGE);
    image8_t img;
    REQUIRE_MSG(plot_render(&p, 400, 300, &img) == PP5_OK, "%s", pp5_error_text());
    int x0, x1, y0, y1;
    find_frame(&img, &x0, &x1, &y0, &y1);
    int col = (int)lround(x0 + 0.3 * (x1 - x0));
    int row = (int)lround(y1 - 0.6 * (y1 - y0));
    int on = 0, off = 0;
    for (int y = y0 + 1; y < y1; y++) {
        if (is_rgb(&img, col, y, 90, 90, 90))
            on++;
        else
            off++;
    }
    /* Dashes: about 4 of every 7 pixels inked. */
    CHECK_MSG(on > 0 && off > 0 && fabs(on / (double)(on + off) - 4.0 / 7.0) < 0.1,
              "vertical dash pattern %d on, %d off", on, off);
    int hon = 0;
    for (int x = x0 + 1; x < x1; x++)
        hon += is_rgb(&img, x, row, 90, 90, 90);
    CHECK_MSG(hon > (x1 - x0) / 3, "horizontal ref at row %d: %d inked", row, hon);
    image8_free(&img);
    for (int i = p.n_refs; i < PLOT_MAX_REFS; i++)
        REQUIRE(plot_add_yref(&p, 1, "r") == PP5_OK);
    CHECK_EQ(plot_add_yref(&p, 1, "r"), PP5_E_RANGE);
    plot_free(&p);
}

TEST(plot_data_far_outside_fixed_ranges_is_clipped)
{
    plot_t p;
    plot_init(&p, "clip", "x", "y");
    double xs[3] = {-1e30, 5, 1e30}, ys[3] = {1e30, 5, -1e30};
    REQUIRE(plot_add_series(&p, "wild", xs, ys, 3) == PP5_OK);
    plot_set_style(&p, 0, PLOT_LINE_POINTS);
    double bx[2] = {20, 30}, by[2] = {1, 2};
    REQUIRE(plot_add_stacked(&p, "bars off to the right", bx, by, 2) == PP5_OK);
    plot_set_color(&p, 1, 0, 0, 255);
    plot_set_xrange(&p, 0, 10);
    plot_set_yrange(&p, 0, 10);
    image8_t img;
    REQUIRE_MSG(plot_render(&p, 300, 200, &img) == PP5_OK, "%s", pp5_error_text());
    /* Only the legend swatch, right of the frame, may be blue: no bar leaks
     * into the chart or anywhere else. */
    int x0, x1, y0, y1;
    find_frame(&img, &x0, &x1, &y0, &y1);
    int inside = 0, legend = 0, elsewhere = 0;
    for (int y = 0; y < 200; y++)
        for (int x = 0; x < 300; x++) {
            if (!bluish(&img, x, y))
                continue;
            if (x >= x0 && x <= x1 && y >= y0 && y <= y1)
                inside++;
            else if (x > x1)
                legend++;
            else
                elsewhere++;
        }
    CHECK_EQ(inside, 0);
    CHECK(legend > 0);
    CHECK_EQ(elsewhere, 0);
    image8_free(&img);
    plot_free(&p);
}

TEST(plot_y_down_puts_small_values_at_the_top)
{
    /* A gaze trace in pixel coordinates: y = 100 should be near the top. */
    plot_t p;
    plot_init(&p, "gaze", "x (px)", "y (px)");
    double xs[2] = {0, 400}, ys[2] = {100, 100};
    REQUIRE(plot_add_series(&p, "gaze", xs, ys, 2) == PP5_OK);
    plot_set_color(&p, 0, 255, 0, 0);
    plot_set_xrange(&p, 0, 400);
    plot_set_yrange(&p, 0, 400);
    plot_set_y_down(&p, true);
    double sx[1] = {200}, sh[1] = {50};
    REQUIRE(plot_add_stacked(&p, "bar", sx, sh, 1) == PP5_OK);
    plot_set_color(&p, 1, 0, 0, 255);
    image8_t img;
    REQUIRE(plot_render(&p, 400, 300, &img) == PP5_OK);
    int x0, x1, y0, y1;
    find_frame(&img, &x0, &x1, &y0, &y1);
    double want = y0 + 0.25 * (y1 - y0);
    int col = (x0 + x1) / 2 - 40, first = -1;
    for (int y = 0; y < img.height && first < 0; y++)
        if (red_cover(&img, col, y) > 0.4)
            first = y;
    CHECK_MSG(first >= 0 && fabs(first - want) <= 1.5, "red at %d, expected ~%.1f", first, want);
    /* The bar from 0 to 50 hangs from the top edge (a narrow bar: one pixel
     * column, next to the middle one when the frame's width is odd). */
    int bar_col = (x0 + x1) / 2, top_row = (int)lround(y0 + 0.06 * (y1 - y0));
    if (!is_rgb(&img, bar_col, top_row, 0, 0, 255))
        bar_col++;
    CHECK(is_rgb(&img, bar_col, top_row, 0, 0, 255));
    CHECK(!is_rgb(&img, bar_col, (int)lround(y0 + 0.5 * (y1 - y0)), 0, 0, 255));
    image8_free(&img);
    plot_free(&p);
}

/* The same plot from two runs of pp5 (figure 5 of a small render): the SVG
 * bytes are the same, and the PDF's are too once SOURCE_DATE_EPOCH fixes
 * its creation date (2023-11-14T22:13:20Z here).  Two runs, because cairo
 * numbers an SVG's glyphs and surfaces across one process. */
static char *read_bytes(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    char *b = f ? calloc(1, 1 << 20) : NULL;
    *len = b ? fread(b, 1, (1 << 20) - 1, f) : 0;
    if (f)
        fclose(f);
    return b;
}

TEST(plot_vector_files_are_byte_stable_with_a_fixed_date)
{
    const char *dir = pp5_test_outdir();
    const char *names[4] = {"a.svg", "b.svg", "a.pdf", "b.pdf"};
    char *bytes[4] = {NULL};
    size_t len[4] = {0};
    setenv("SOURCE_DATE_EPOCH", "1700000000", 1);
    for (int i = 0; i < 4; i++) {
        char args[1400], path[1200];
        snprintf(path, sizeof path, "%s/%s", dir, names[i]);
        snprintf(args, sizeof args, "render --phantom sphere-shell --size 64x64 --fig5 %s", path);
        CHECK(pp5_test_run_cli(args, NULL, NULL) == 0);
        bytes[i] = read_bytes(path, &len[i]);
    }
    unsetenv("SOURCE_DATE_EPOCH");
    CHECK(len[0] > 0 && len[0] == len[1] && memcmp(bytes[0], bytes[1], len[0]) == 0);
    CHECK(len[2] > 0 && len[2] == len[3] && memcmp(bytes[2], bytes[3], len[2]) == 0);
    CHECK(bytes[2] && memmem(bytes[2], len[2], "20231114221320", 14) != NULL);
    for (int i = 0; i < 4; i++)
        free(bytes[i]);
}
