/* classify_io.c: reading and writing transfer-function files (classify_io.h). */
#include "classify_io.h"

#include <ctype.h>
#include <errno.h>
#include <jansson.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define TF_MAX_FILE_BYTES (16u << 20)

/* ---- the text format ---- */

/* Up to `max` numbers from `s`; false on anything that is not a finite number. */
static bool numbers(char *s, double *out, int max, int *n)
{
    *n = 0;
    char *save = NULL;
    for (char *tok = strtok_r(s, " \t\r", &save); tok; tok = strtok_r(NULL, " \t\r", &save)) {
        if (*n == max)
            return false;
        char *end;
        errno = 0;
        double v = strtod(tok, &end);
        if (*end || errno || !isfinite(v))
            return false;
        out[(*n)++] = v;
    }
    return true;
}

static bool unit(double v)
{
    return v >= 0.0 && v <= 1.0;
}

typedef struct {
    const char *file;
    int line;
    classify_tf_t *tf;
} text_reader_t;

static pp5_status_t bad(const text_reader_t *r, const char *what)
{
    return pp5_fail(PP5_E_FORMAT, "%s:%d: %s (the format: man pp5, section TRANSFER FUNCTIONS)",
                    r->file, r->line, what);
}

static pp5_status_t read_contour(text_reader_t *r, const double *v, int n, bool ramp)
{
    classify_tf_t *tf = r->tf;
    if (n != 6)
        return bad(r, ramp ? "'ramp' needs VALUE OPACITY WIDTH R G B" :
                             "'contour' needs VALUE OPACITY WIDTH R G B");
    if (tf->count == CLASSIFY_MAX_CONTOURS)
        return bad(r, "more than 4 contours");
    if (!unit(v[1]) || !(v[2] > 0) || !unit(v[3]) || !unit(v[4]) || !unit(v[5]))
        return bad(r, "opacity and colour must lie in 0..1 and the width must be > 0");
    classify_contour_t *c = &tf->contour[tf->count++];
    c->value = (float)v[0];
    c->opacity = (float)v[1];
    c->width_vox = ramp ? 0.0f : (float)v[2];   /* a ramp has no gradient term */
    c->ramp_width = ramp ? (float)v[2] : 0.0f;
    for (int k = 0; k < 3; k++)
        c->rgb[k] = (float)v[3 + k];
    return PP5_OK;
}

static pp5_status_t read_point(text_reader_t *r, const double *v, int n, bool color)
{
    classify_tf_t *tf = r->tf;
    int *count = color ? &tf->n_rgb : &tf->n_alpha;
    if (n != (color ? 4 : 2))
        return bad(r, color ? "'color' needs VALUE R G B" : "'opacity' needs VALUE OPACITY");
    if (*count == CLASSIFY_MAX_POINTS)
        return bad(r, "more than 256 control points of one kind");
    for (int k = 1; k < n; k++)
        if (!unit(v[k]))
            return bad(r, "opacity and colour must lie in 0..1");
    float prev = *count ? (color ? tf->rgb[*count - 1].value : tf->alpha[*count - 1].value) : 0;
    if (*count && !((float)v[0] > prev))
        return bad(r, "control points must come in strictly increasing value order");
    if (color) {
        tf->rgb[*count].value = (float)v[0];
        for (int k = 0; k < 3; k++)
            tf->rgb[*count].rgb[k] = (float)v[1 + k];
    } else {
        tf->alpha[*count] = (classify_alpha_point_t){(float)v[0], (float)v[1]};
    }
    (*count)++;
    return PP5_OK;
}

/* One non-comment line, split into its keyword and the rest. */
static pp5_status_t read_item(text_reader_t *r, char *line, bool *have_magic)
{
    char *save = NULL;
    char *key = strtok_r(line, " \t\r", &save);
    char *rest = strtok_r(NULL, "", &save);
    if (!rest)
        rest = key + strlen(key);
    if (!*have_magic) {
        if (strcmp(key, "pp5-tf") != 0 || strtol(rest, NULL, 10) != 1)
            return bad(r, "the first item must be 'pp5-tf 1'");
        *have_magic = true;
        return PP5_OK;
    }
    if (strcmp(key, "name") == 0) {
        while (isspace((unsigned char)*rest))
            rest++;
        size_t n = strcspn(rest, "\r");
        while (n > 0 && isspace((unsigned char)rest[n - 1]))
            n--;
        if (n == 0 || n >= sizeof r->tf->name)
            return bad(r, "'name' needs a name of 1..31 characters");
        memcpy(r->tf->name, rest, n);
        r->tf->name[n] = '\0';
        return PP5_OK;
    }
    double v[8];
    int n;
    if (!numbers(rest, v, 8, &n))
        return bad(r, "expected finite numbers after the keyword");
    if (strcmp(key, "contour") == 0 || strcmp(key, "ramp") == 0)
        return read_contour(r, v, n, key[0] == 'r');
    if (strcmp(key, "opacity") == 0 || strcmp(key, "color") == 0 || strcmp(key, "colour") == 0)
        return read_point(r, v, n, key[0] == 'c');
    if (strcmp(key, "min-opacity") == 0) {
        if (n != 1 || !unit(v[0]))
            return bad(r, "'min-opacity' needs one value in 0..1");
        r->tf->min_opacity = (float)v[0];
        return PP5_OK;
    }
    return bad(r, "unknown keyword (contour, ramp, opacity, color, min-opacity, name)");
}

pp5_status_t classify_tf_parse_text(const char *text, const char *name, classify_tf_t *tf)
{
    memset(tf, 0, sizeof *tf);
    text_reader_t r = {name, 0, tf};
    bool have_magic = false;
    pp5_status_t st = PP5_OK;
    for (const char *p = text; st == PP5_OK && *p;) {
        size_t n = strcspn(p, "\n");
        r.line++;
        char line[1024];
        if (n >= sizeof line)
            return bad(&r, "line longer than 1023 characters");
        memcpy(line, p, n);
        line[n] = '\0';
        p += n + (p[n] == '\n');
        char *hash = strchr(line, '#');
        if (hash)
            *hash = '\0';
        if (strspn(line, " \t\r") == strlen(line))
            continue;
        st = read_item(&r, line, &have_magic);
    }
    if (st != PP5_OK)
        return st;
    r.line++;
    if (!have_magic)
        return bad(&r, "no 'pp5-tf 1' line: not a pp5 transfer-function file");
    if (tf->count > 0 && (tf->n_alpha > 0 || tf->n_rgb > 0))
        return bad(&r, "a file holds contours or control points, not both");
    if (tf->n_rgb > 0 && tf->n_alpha == 0)
        return bad(&r, "colour points need opacity points");
    if (tf->count == 0 && tf->n_alpha == 0)
        return bad(&r, "no contour, ramp or opacity point: nothing would be visible");
    if (!tf->name[0]) {
        const char *base = strrchr(name, '/');
        snprintf(tf->name, sizeof tf->name, "%s", base ? base + 1 : name);
    }
    return PP5_OK;
}

/* ---- ParaView presets ---- */

/* The numbers of array `key` of preset `o`, `per` per point; *n points. */
static pp5_status_t json_points(json_t *o, const char *key, int per, const char *name,
                                double **out, int *n)
{
    json_t *a = json_object_get(o, key);
    *out = NULL;
    *n = 0;
    if (!a)
        return PP5_OK;
    size_t len = json_is_array(a) ? json_array_size(a) : 0;
    if (len == 0 || len % (size_t)per != 0)
        return pp5_fail(PP5_E_FORMAT, "%s: \"%s\" must be an array of %d numbers per point",
                        name, key, per);
    if (len / (size_t)per > CLASSIFY_MAX_POINTS)
        return pp5_fail(PP5_E_RANGE, "%s: \"%s\" has %zu points (pp5 takes at most %d)", name, key,
                        len / (size_t)per, CLASSIFY_MAX_POINTS);
    double *v = malloc(len * sizeof *v);
    if (!v)
        return pp5_fail(PP5_E_NOMEM, "%s: out of memory", name);
    for (size_t i = 0; i < len; i++) {
        json_t *x = json_array_get(a, i);
        v[i] = json_is_number(x) ? json_number_value(x) : NAN;
        if (!isfinite(v[i])) {
            free(v);
            return pp5_fail(PP5_E_FORMAT, "%s: \"%s\"[%zu] is not a finite number", name, key, i);
        }
    }
    *out = v;
    *n = (int)(len / (size_t)per);
    return PP5_OK;
}

static void add_note(char *note, size_t size, const char *text)
{
    if (!note || size == 0)
        return;
    size_t used = strlen(note);
    snprintf(note + used, size - used, "%s%s", used ? "; " : "", text);
}

/* The points of one preset into tf, checked like the text format's. */
static pp5_status_t preset_to_tf(json_t *o, const char *name, classify_tf_t *tf, char *note,
                                 size_t note_size)
{
    double *rgb = NULL, *alpha = NULL;
    int n_rgb = 0, n_alpha = 0;
    pp5_status_t st = json_points(o, "RGBPoints", 4, name, &rgb, &n_rgb);
    if (st == PP5_OK)
        st = json_points(o, "Points", 4, name, &alpha, &n_alpha);
    if (st == PP5_OK && n_alpha == 0)
        st = pp5_fail(PP5_E_FORMAT, "%s: the preset has no opacity points (\"Points\"): in "
                      "ParaView tick \"Save opacities\" when saving the preset, then export it",
                      name);
    bool shaped = false;
    for (int i = 0; st == PP5_OK && i < n_alpha; i++) {
        const double *p = alpha + 4 * i;
        if (!unit(p[1]) || (i > 0 && !(p[0] > alpha[4 * (i - 1)])))
            st = pp5_fail(PP5_E_FORMAT, "%s: \"Points\" point %d: opacity outside 0..1 or values "
                          "not increasing", name, i);
        shaped = shaped || p[2] != 0.5 || p[3] != 0.0;
        tf->alpha[i] = (classify_alpha_point_t){(float)p[0], (float)p[1]};
    }
    for (int i = 0; st == PP5_OK && i < n_rgb; i++) {
        const double *p = rgb + 4 * i;
        if (!unit(p[1]) || !unit(p[2]) || !unit(p[3]) || (i > 0 && !(p[0] > rgb[4 * (i - 1)])))
            st = pp5_fail(PP5_E_FORMAT, "%s: \"RGBPoints\" point %d: colour outside 0..1 or "
                          "values not increasing", name, i);
        tf->rgb[i].value = (float)p[0];
        for (int k = 0; k < 3; k++)
            tf->rgb[i].rgb[k] = (float)p[1 + k];
    }
    tf->n_alpha = n_alpha;
    tf->n_rgb = n_rgb;
    if (st == PP5_OK && shaped)
        add_note(note, note_size, "opacity midpoint/sharpness other than 0.5/0 read as linear");
    free(rgb);
    free(alpha);
    return st;
}

pp5_status_t classify_tf_parse_paraview(const char *text, size_t len, const char *name,
                                        classify_tf_t *tf, char *note, size_t note_size)
{
    memset(tf, 0, sizeof *tf);
    if (note && note_size)
        note[0] = '\0';
    json_error_t err;
    json_t *root = json_loadb(text, len, 0, &err);
    if (!root)
        return pp5_fail(PP5_E_FORMAT, "%s:%d:%d: not valid JSON: %s", name, err.line, err.column,
                        err.text);
    json_t *o = json_is_array(root) ? json_array_get(root, 0) : root;
    pp5_status_t st = PP5_OK;
    if (!json_is_object(o))
        st = pp5_fail(PP5_E_FORMAT, "%s: expected a ParaView preset (an object, or an array of "
                      "them, with \"RGBPoints\" and \"Points\")", name);
    if (st == PP5_OK && json_is_array(root) && json_array_size(root) > 1) {
        char buf[96];
        snprintf(buf, sizeof buf, "the file holds %zu presets; the first is used",
                 json_array_size(root));
        add_note(note, note_size, buf);
    }
    if (st == PP5_OK)
        st = preset_to_tf(o, name, tf, note, note_size);
    if (st == PP5_OK) {
        const char *pname = json_string_value(json_object_get(o, "Name"));
        snprintf(tf->name, sizeof tf->name, "%s", pname && *pname ? pname : "paraview");
        const char *space = json_string_value(json_object_get(o, "ColorSpace"));
        if (space && strcmp(space, "RGB") != 0) {
            char buf[128];
            snprintf(buf, sizeof buf, "colours interpolated in RGB, not the preset's %.40s", space);
            add_note(note, note_size, buf);
        }
    }
    json_decref(root);
    return st;
}

/* ---- files ---- */

static pp5_status_t slurp(const char *path, char **text, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return pp5_fail(PP5_E_IO, "%s: cannot open the transfer function: %s", path,
                        strerror(errno));
    char *buf = malloc(TF_MAX_FILE_BYTES + 1);
    size_t n = buf ? fread(buf, 1, TF_MAX_FILE_BYTES + 1, f) : 0;
    bool failed = buf && ferror(f);
    fclose(f);
    if (!buf)
        return pp5_fail(PP5_E_NOMEM, "%s: out of memory", path);
    if (failed || n > TF_MAX_FILE_BYTES) {
        free(buf);
        return pp5_fail(failed ? PP5_E_IO : PP5_E_RANGE, "%s: %s", path,
                        failed ? "read error" : "larger than 16 MB: not a transfer function");
    }
    if (memchr(buf, '\0', n)) {
        free(buf);
        return pp5_fail(PP5_E_FORMAT, "%s: binary data, not a transfer function", path);
    }
    buf[n] = '\0';
    *text = buf;
    *len = n;
    return PP5_OK;
}

pp5_status_t classify_tf_read(const char *path, classify_tf_t *tf, char *note, size_t note_size)
{
    if (note && note_size)
        note[0] = '\0';
    char *text = NULL;
    size_t len = 0;
    pp5_status_t st = slurp(path, &text, &len);
    if (st != PP5_OK)
        return st;
    const char *p = text + strspn(text, " \t\r\n");
    if (*p == '[' || *p == '{')
        st = classify_tf_parse_paraview(text, len, path, tf, note, note_size);
    else
        st = classify_tf_parse_text(text, path, tf);
    free(text);
    return st;
}

/* The shortest decimal (6 to 9 significant digits) that reads back as v. */
static const char *fnum(char buf[24], float v)
{
    for (int digits = 6; digits <= 9; digits++) {
        snprintf(buf, 24, "%.*g", digits, v);
        if (strtof(buf, NULL) == v)
            break;
    }
    return buf;
}

void classify_tf_write_text(FILE *out, const classify_tf_t *tf, const char *header)
{
    char a[24], b[24], c[24], d[24], e[24], f[24];
    for (const char *h = header; h && *h;) {
        size_t n = strcspn(h, "\n");
        fprintf(out, "# %.*s\n", (int)n, h);
        h += n + (h[n] == '\n');
    }
    fprintf(out, "pp5-tf 1\nname %s\n", tf->name[0] ? tf->name : "unnamed");
    for (int i = 0; i < tf->count; i++) {
        const classify_contour_t *k = &tf->contour[i];
        bool ramp = k->ramp_width > 0;
        fprintf(out, "%s %s %s %s %s %s %s\n", ramp ? "ramp" : "contour", fnum(a, k->value),
                fnum(b, k->opacity), fnum(c, ramp ? k->ramp_width : k->width_vox),
                fnum(d, k->rgb[0]), fnum(e, k->rgb[1]), fnum(f, k->rgb[2]));
    }
    for (int i = 0; i < tf->n_alpha; i++)
        fprintf(out, "opacity %s %s\n", fnum(a, tf->alpha[i].value), fnum(b, tf->alpha[i].opacity));
    for (int i = 0; i < tf->n_rgb; i++)
        fprintf(out, "color %s %s %s %s\n", fnum(a, tf->rgb[i].value), fnum(b, tf->rgb[i].rgb[0]),
                fnum(c, tf->rgb[i].rgb[1]), fnum(d, tf->rgb[i].rgb[2]));
    fprintf(out, "min-opacity %s\n", fnum(a, tf->min_opacity));
}

pp5_status_t classify_tf_save(const char *path, const classify_tf_t *tf, const char *header)
{
    size_t n = strlen(path) + 8;
    char *tmp = malloc(n);
    if (!tmp)
        return pp5_fail(PP5_E_NOMEM, "%s: out of memory", path);
    snprintf(tmp, n, "%s.part", path);
    FILE *f = fopen(tmp, "w");
    pp5_status_t st = PP5_OK;
    if (!f) {
        st = pp5_fail(PP5_E_IO, "%s: cannot write the transfer function: %s", path,
                      strerror(errno));
    } else {
        classify_tf_write_text(f, tf, header);
        bool failed = ferror(f) != 0;
        if (fclose(f) != 0 || failed)
            st = pp5_fail(PP5_E_IO, "%s: write failed", path);
        else if (rename(tmp, path) != 0)
            st = pp5_fail(PP5_E_IO, "%s: cannot write the transfer function: %s", path,
                          strerror(errno));
        if (st != PP5_OK)
            remove(tmp);
    }
    free(tmp);
    return st;
}
