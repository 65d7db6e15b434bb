/* test_layers.c: the house's floors, checked from the includes.
 *
 * Every .c/.h/.inc/.def under emu/ render/ tracker/ firmware/ gets a layer
 * from its path (README, "Layout"):
 *   1 emu/util/ (and the build's generated headers)
 *   2 emu/ and emu/api/: the machine
 *   3 render/, tracker/, and the firmware programs: firmware/{gp,pp,common}/ and the
 *     .c files directly in firmware/
 *   4 firmware/host/: host sessions
 *   5 emu/cli/: the commands
 * Each `#include "..."` is resolved the way the compiler does it: the
 * including file's folder first, then the -iquote folders of its compile line
 * (the Makefile passes both lists in, so they cannot drift).  The test fails,
 * naming file:line and the include, when a file reaches a higher layer, when
 * render/ and tracker/ include each other, or when a firmware program
 * includes anything but emu/api/, firmware/common/ or its own folder
 * (relative paths such as "../../emu/machine.h" get past -iquote, so the
 * compile line alone does not stop them).  Computed includes
 * (`#include NAME`, the kernels' two copies in emu/) are not resolved; in a
 * firmware program they fail, since they cannot be checked. */
#include <dirent.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "harness.h"

#if !defined(PP5_LAYERS_LIB_IQUOTE) || !defined(PP5_LAYERS_FW_IQUOTE) || \
    !defined(PP5_LAYERS_GEN_DIR)
#error "the Makefile passes the -iquote folders of both compile lines to this test"
#endif

#define LAYERS_PATH_MAX 512
#define LAYERS_MSG_MAX 400
#define LAYERS_MAX_VIOLATIONS 64

/* One run of the checker over any number of files. */
typedef struct {
    int files, includes;                       /* files read, quoted includes resolved */
    int n_violations;                          /* all found (messages: the first ones) */
    char violation[LAYERS_MAX_VIOLATIONS][LAYERS_MSG_MAX];
} layer_check_t;

static const char *const layer_names[] = {
    "no layer", "1 (emu/util)", "2 (emu: the machine)",
    "3 (render/, tracker/, firmware programs)", "4 (firmware/host: host sessions)",
    "5 (emu/cli: commands)",
};

static bool has_prefix(const char *s, const char *prefix)
{
    return strncmp(s, prefix, strlen(prefix)) == 0;
}

/* Whether `path` lies directly in folder `dir` ("a/b" for "a/b/x.h"). */
static bool directly_in(const char *path, const char *dir)
{
    size_t n = strlen(dir);
    return strncmp(path, dir, n) == 0 && path[n] == '/' && !strchr(path + n + 1, '/');
}

/* The GP/PP programs: what may see only emu/api/ and firmware/common/. */
static bool is_firmware_program(const char *path)
{
    return has_prefix(path, "firmware/gp/") || has_prefix(path, "firmware/pp/") ||
           has_prefix(path, "firmware/common/") || directly_in(path, "firmware");
}

static int layer_of(const char *path)
{
    if (has_prefix(path, PP5_LAYERS_GEN_DIR "/") || has_prefix(path, "emu/util/"))
        return 1;
    if (has_prefix(path, "emu/cli/"))
        return 5;
    if (has_prefix(path, "emu/"))
        return 2;
    if (has_prefix(path, "render/") || has_prefix(path, "tracker/") || is_firmware_program(path))
        return 3;
    if (has_prefix(path, "firmware/host/"))
        return 4;
    return 0;
}

/* "a/./b/../c.h" -> "a/c.h"; false when ".." leaves the tree. */
static bool normalise(const char *in, char *out, size_t cap)
{
    char tmp[LAYERS_PATH_MAX];
    if (snprintf(tmp, sizeof tmp, "%s", in) >= (int)sizeof tmp)
        return false;
    const char *part[64];
    int n = 0;
    for (char *save = NULL, *t = strtok_r(tmp, "/", &save); t; t = strtok_r(NULL, "/", &save)) {
        if (strcmp(t, ".") == 0)
            continue;
        if (strcmp(t, "..") == 0) {
            if (n == 0)
                return false;
            n--;
        } else if (n < 64) {
            part[n++] = t;
        } else {
            return false;
        }
    }
    size_t len = 0;
    out[0] = '\0';
    for (int i = 0; i < n; i++) {
        int w = snprintf(out + len, cap - len, "%s%s", i ? "/" : "", part[i]);
        if (w < 0 || (size_t)w >= cap - len)
            return false;
        len += (size_t)w;
    }
    return n > 0;
}

static bool is_file(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0 && S_ISREG(sb.st_mode);
}

/* Tries folder/name; on success the normalised path is in out. */
static bool try_folder(const char *folder, const char *name, char *out, size_t cap)
{
    char joined[LAYERS_PATH_MAX * 2];
    snprintf(joined, sizeof joined, "%s/%s", folder, name);
    return normalise(joined, out, cap) && is_file(out);
}

/* Resolves `name` included from `as_path` as the compiler would. */
static bool resolve(const char *as_path, const char *name, char *out, size_t cap)
{
    char folder[LAYERS_PATH_MAX];
    snprintf(folder, sizeof folder, "%s", as_path);
    char *slash = strrchr(folder, '/');
    if (slash)
        *slash = '\0';
    else
        snprintf(folder, sizeof folder, ".");
    if (try_folder(folder, name, out, cap))
        return true;
    char list[LAYERS_PATH_MAX];
    snprintf(list, sizeof list, "%s",
             is_firmware_program(as_path) ? PP5_LAYERS_FW_IQUOTE
                                          : PP5_LAYERS_LIB_IQUOTE " " PP5_LAYERS_GEN_DIR);
    for (char *save = NULL, *d = strtok_r(list, " ", &save); d; d = strtok_r(NULL, " ", &save))
        if (try_folder(d, name, out, cap))
            return true;
    return false;
}

static void layer_check_violation(layer_check_t *c, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

static void layer_check_violation(layer_check_t *c, const char *fmt, ...)
{
    if (c->n_violations < LAYERS_MAX_VIOLATIONS) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(c->violation[c->n_violations], LAYERS_MSG_MAX, fmt, ap);
        va_end(ap);
    }
    c->n_violations++;
}

/* The rules for one resolved include of `from` (line `line`). */
static void layer_check_include(layer_check_t *c, const char *from, int line, const char *name,
                                const char *target)
{
    int lf = layer_of(from), lt = layer_of(target);
    if (lt > lf || lt == 0)
        layer_check_violation(c, "%s:%d: #include \"%s\" reaches %s, layer %s, from layer %s: "
                              "no file may include a higher layer", from, line, name, target,
                              layer_names[lt], layer_names[lf]);
    bool r_to_t = has_prefix(from, "render/") && has_prefix(target, "tracker/");
    bool t_to_r = has_prefix(from, "tracker/") && has_prefix(target, "render/");
    if (r_to_t || t_to_r)
        layer_check_violation(c, "%s:%d: #include \"%s\" reaches %s: render/ and tracker/ must "
                              "not include each other", from, line, name, target);
    if (is_firmware_program(from)) {
        char own[LAYERS_PATH_MAX];
        snprintf(own, sizeof own, "%s", from);
        *strrchr(own, '/') = '\0';
        if (!has_prefix(target, "emu/api/") && !has_prefix(target, "firmware/common/") &&
            !directly_in(target, own))
            layer_check_violation(c, "%s:%d: #include \"%s\" reaches %s: firmware programs may "
                                  "include only emu/api/ and firmware/common/ (and their own "
                                  "folder)", from, line, name, target);
    }
}

/* Removes comments from one line; *in_comment carries a block comment over
 * to the next line. */
static void strip_comments(char *s, bool *in_comment)
{
    char *w = s;
    bool in_string = false;
    for (char *r = s; *r; r++) {
        if (*in_comment) {
            if (r[0] == '*' && r[1] == '/') {
                *in_comment = false;
                r++;
            }
            continue;
        }
        if (!in_string && r[0] == '/' && r[1] == '*') {
            *in_comment = true;
            r++;
            continue;
        }
        if (!in_string && r[0] == '/' && r[1] == '/')
            break;
        if (*r == '"')
            in_string = !in_string;
        *w++ = *r;
    }
    *w = '\0';
}

/* The include on this (comment-free) line: 1 quoted (name set), 2 computed,
 * 0 none or <system>. */
static int include_on_line(const char *s, char *name, size_t cap)
{
    while (*s == ' ' || *s == '\t')
        s++;
    if (*s++ != '#')
        return 0;
    while (*s == ' ' || *s == '\t')
        s++;
    if (!has_prefix(s, "include"))
        return 0;
    s += strlen("include");
    while (*s == ' ' || *s == '\t')
        s++;
    if (*s == '<')
        return 0;
    if (*s != '"')
        return 2;
    const char *end = strchr(s + 1, '"');
    if (!end || (size_t)(end - s - 1) >= cap)
        return 2;
    memcpy(name, s + 1, (size_t)(end - s - 1));
    name[end - s - 1] = '\0';
    return 1;
}

/* Checks the file at real_path as if it stood at as_path in the tree. */
static bool layer_check_file(layer_check_t *c, const char *real_path, const char *as_path)
{
    FILE *f = fopen(real_path, "r");
    if (!f)
        return false;
    c->files++;
    if (layer_of(as_path) == 0)
        layer_check_violation(c, "%s: belongs to no layer (see tests/test_layers.c)", as_path);
    char line[4096], name[LAYERS_PATH_MAX], target[LAYERS_PATH_MAX];
    bool in_comment = false;
    for (int n = 1; fgets(line, sizeof line, f); n++) {
        strip_comments(line, &in_comment);
        int kind = include_on_line(line, name, sizeof name);
        if (kind == 2 && is_firmware_program(as_path))
            layer_check_violation(c, "%s:%d: a computed #include cannot be checked in a "
                                  "firmware program", as_path, n);
        if (kind != 1)
            continue;
        if (!resolve(as_path, name, target, sizeof target)) {
            layer_check_violation(c, "%s:%d: #include \"%s\" does not resolve to a file of the "
                                  "tree", as_path, n, name);
            continue;
        }
        c->includes++;
        layer_check_include(c, as_path, n, name, target);
    }
    fclose(f);
    return true;
}

static bool checked_suffix(const char *name)
{
    const char *dot = strrchr(name, '.');
    return dot && (strcmp(dot, ".c") == 0 || strcmp(dot, ".h") == 0 ||
                   strcmp(dot, ".inc") == 0 || strcmp(dot, ".def") == 0);
}

/* Every checked file below `dir`, in name order (so messages are stable). */
static void layer_check_tree(layer_check_t *c, const char *dir)
{
    struct dirent **list = NULL;
    int n = scandir(dir, &list, NULL, alphasort);
    for (int i = 0; i < n; i++) {
        const char *e = list[i]->d_name;
        char path[LAYERS_PATH_MAX];
        if (e[0] != '.' && snprintf(path, sizeof path, "%s/%s", dir, e) < (int)sizeof path) {
            struct stat sb;
            if (stat(path, &sb) == 0 && S_ISDIR(sb.st_mode))
                layer_check_tree(c, path);
            else if (checked_suffix(e))
                layer_check_file(c, path, path);
        }
        free(list[i]);
    }
    free(list);
}

TEST(layers_no_file_includes_a_higher_layer)
{
    REQUIRE_MSG(is_file("emu/machine.h"), "run the tests from the repository root");
    layer_check_t c;
    memset(&c, 0, sizeof c);
    const char *const roots[] = {"emu", "render", "tracker", "firmware"};
    for (size_t i = 0; i < sizeof roots / sizeof roots[0]; i++)
        layer_check_tree(&c, roots[i]);
    /* The tree has well over a hundred files and a few hundred includes:
     * far fewer would mean the walk or the parser missed them. */
    CHECK_MSG(c.files > 150, "read %d files", c.files);
    CHECK_MSG(c.includes > 300, "resolved %d includes", c.includes);
    for (int i = 0; i < c.n_violations && i < LAYERS_MAX_VIOLATIONS; i++)
        CHECK_MSG(false, "%s", c.violation[i]);
    CHECK_MSG(c.n_violations == 0, "%d layering violations", c.n_violations);
}

/* Line of the first line of `path` that contains `text` (0: none), found
 * independently of the checker. */
static int line_containing(const char *path, const char *text)
{
    FILE *f = fopen(path, "r");
    char line[1024];
    int found = 0;
    for (int n = 1; f && !found && fgets(line, sizeof line, f); n++)
        if (strstr(line, text))
            found = n;
    if (f)
        fclose(f);
    return found;
}

/* Runs the checker on one probe file and requires exactly `want` messages,
 * the first naming file:line of `include` and containing `reason`. */
static void check_probe(const char *fixture, const char *as_path, const char *include,
                        int want, const char *reason)
{
    char real[LAYERS_PATH_MAX];
    snprintf(real, sizeof real, "tests/fixtures/layers/%s", fixture);
    layer_check_t c;
    memset(&c, 0, sizeof c);
    REQUIRE_MSG(layer_check_file(&c, real, as_path), "%s: cannot read the probe", real);
    CHECK_MSG(c.n_violations == want, "%s as %s: %d messages, want %d (first: %s)", fixture,
              as_path, c.n_violations, want, c.n_violations ? c.violation[0] : "none");
    if (want == 0 || c.n_violations == 0)
        return;
    char where[LAYERS_PATH_MAX + 64], quoted[LAYERS_PATH_MAX];
    snprintf(where, sizeof where, "%s:%d: ", as_path, line_containing(real, include));
    snprintf(quoted, sizeof quoted, "#include \"%s\"", include);
    CHECK_MSG(has_prefix(c.violation[0], where), "%s: message names %s: %s", fixture, where,
              c.violation[0]);
    CHECK_MSG(strstr(c.violation[0], quoted) != NULL, "%s: message quotes %s: %s", fixture,
              quoted, c.violation[0]);
    CHECK_MSG(strstr(c.violation[0], reason) != NULL, "%s: message says \"%s\": %s", fixture,
              reason, c.violation[0]);
}

TEST(layers_checker_rejects_probe_includes)
{
    /* A GP program reaching into the machine by a relative path (which
     * -iquote does not stop, and which compiles). */
    check_probe("gp_includes_machine.c", "firmware/gp/probe.c", "../../emu/machine.h", 1,
                "firmware programs may include only emu/api/ and firmware/common/");
    /* The native renderer calling a host session: layer 3 to layer 4. */
    check_probe("render_includes_session.c", "render/x.c", "firmware/host/fw_session.h", 1,
                "from layer 3 (render/, tracker/, firmware programs)");
    check_probe("render_includes_session.c", "render/x.c", "firmware/host/fw_session.h", 1,
                "layer 4 (firmware/host: host sessions)");
    /* Same layer, but render/ and tracker/ stay apart. */
    check_probe("tracker_includes_render.c", "tracker/x.c", "render/volume.h", 1,
                "render/ and tracker/ must not include each other");
    /* The machine including the native renderer: layer 2 to layer 3. */
    check_probe("emu_includes_render.c", "emu/x.c", "render/volume.h", 1,
                "no file may include a higher layer");
    /* A firmware program that keeps to the firmware API passes, so the
     * rejections above are not the checker rejecting everything. */
    check_probe("gp_includes_api_only.c", "firmware/gp/probe.c", "", 0, "");
}
