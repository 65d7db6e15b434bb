/* volume_nrrd_header.c: what pp5 checks in a NRRD header before Teem reads
 * it: the magic, the header's size, and every detached data file it names.
 *
 * Why before Teem: Teem reads whatever the header names, so a header that
 * names itself ("data file: x.nhdr") reads its own text as voxels, one that
 * names another header reads that header's text as voxels (detached data
 * files hold raw data, never headers: there is no nesting in the format), a
 * "data file: f%03d.raw 1 2000000000 1" pattern makes it open two billion
 * names one by one, and Teem passes the pattern to sprintf as a format.  Teem
 * also falls back to its plain-text, PNM and VTK readers on a file whose first
 * line is not a NRRD magic (and its text reader leaks memory when it fails).  All of these are
 * refused here with a message naming the limit or the file.  So is a data
 * file that does not exist: Teem's own message about a missing file in a
 * LIST reads past the end of its line buffer for some name lengths (found
 * by the fuzzer in Debian 12's libteem2 1.12.0~20160122).
 *
 * Grammar (NRRD0005 "data file"): "data file: NAME", "data file: LIST
 * [SUBDIM]" with one name per line to the end of the header file, or "data
 * file: FORMAT MIN MAX STEP [SUBDIM]" with one integer conversion in FORMAT.
 * Relative names are relative to the header's folder. */
#include "volume.h"
#include "volume_io.h"
#include "input_limits.h"

#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

typedef struct {
    const char *path;        /* the header file */
    struct stat self;        /* its identity, to catch a header naming itself */
    char dir[1024];          /* its folder, for relative data file names */
    size_t checked;          /* data files checked so far */
    char missing[256];       /* the first data file that cannot be found, if any */
    int missing_errno;
} nrrd_precheck_t;

/* Reads up to the PP5_MAX_HEADER_BYTES limit (+1 byte to tell "longer"). */
static pp5_status_t read_header(const char *path, char **text, size_t *len)
{
    uint64_t limit = pp5_limit(PP5_LIMIT_HEADER_BYTES);
    FILE *f = fopen(path, "rb");
    if (!f)
        return pp5_fail(PP5_E_IO, "%s: cannot open: %s", path, strerror(errno));
    char *buf = malloc((size_t)limit + 2);
    if (!buf) {
        fclose(f);
        return pp5_fail(PP5_E_NOMEM, "%s: cannot allocate a header buffer", path);
    }
    size_t n = fread(buf, 1, (size_t)limit + 1, f);
    fclose(f);
    buf[n] = '\0';
    *text = buf;
    *len = n;
    return PP5_OK;
}

/* Length of the header proper: up to and including its first empty line,
 * or the whole text when there is none (a detached .nhdr). */
static size_t header_length(const char *text, size_t len)
{
    for (size_t i = 0; i + 1 < len; i++) {
        if (text[i] != '\n')
            continue;
        if (text[i + 1] == '\n')
            return i + 2;
        if (i + 2 < len && text[i + 1] == '\r' && text[i + 2] == '\n')
            return i + 3;
    }
    return len;
}

/* One conversion %[digits]d (or i, u) with a width of at most 16, and no
 * other '%' but "%%": Teem formats the file number with this pattern. */
static bool safe_number_format(const char *fmt)
{
    int conversions = 0;
    for (const char *p = fmt; *p; p++) {
        if (*p != '%')
            continue;
        if (p[1] == '%') {
            p++;
            continue;
        }
        p++;
        int width_digits = 0;
        while (isdigit((unsigned char)*p)) {
            p++;
            width_digits++;
        }
        if (width_digits > 2 || (width_digits == 2 && (p[-2] - '0') * 10 + (p[-1] - '0') > 16))
            return false;
        if (*p != 'd' && *p != 'i' && *p != 'u')
            return false;
        conversions++;
    }
    return conversions == 1;
}

static pp5_status_t check_data_file(nrrd_precheck_t *c, const char *name)
{
    char full[2200];
    if (name[0] == '/' || !c->dir[0])
        snprintf(full, sizeof full, "%.2100s", name);
    else
        snprintf(full, sizeof full, "%.1024s/%.1100s", c->dir, name);
    c->checked++;
    struct stat sb;
    if (stat(full, &sb) != 0) {
        /* Reported after every name is checked, so that a header naming
         * itself is called that even when an earlier name is missing. */
        if (!c->missing[0]) {
            snprintf(c->missing, sizeof c->missing, "%.200s", name);
            c->missing_errno = errno;
        }
        return PP5_OK;
    }
    if (sb.st_dev == c->self.st_dev && sb.st_ino == c->self.st_ino)
        return pp5_fail(PP5_E_FORMAT, "%s: data file '%s' is the header itself (a header "
                        "cannot be its own detached data)", c->path, name);
    FILE *f = fopen(full, "rb");
    char magic[8] = {0};
    size_t got = f ? fread(magic, 1, sizeof magic, f) : 0;
    if (f)
        fclose(f);
    if (got >= 7 && memcmp(magic, "NRRD000", 7) == 0)
        return pp5_fail(PP5_E_FORMAT, "%s: data file '%s' is itself a NRRD header (detached "
                        "data files hold raw data; headers do not nest)", c->path, name);
    return PP5_OK;
}

/* "data file: FORMAT MIN MAX STEP [SUBDIM]". */
static pp5_status_t check_format_list(nrrd_precheck_t *c, const char *value)
{
    char fmt[1024];
    long long lo, hi, step;
    if (sscanf(value, "%1023s %lld %lld %lld", fmt, &lo, &hi, &step) != 4)
        return pp5_fail(PP5_E_FORMAT, "%s: bad 'data file' line '%.200s'", c->path, value);
    if (!safe_number_format(fmt))
        return pp5_fail(PP5_E_FORMAT, "%s: data file pattern '%.200s' must hold exactly one "
                        "integer conversion such as %%03d", c->path, fmt);
    if (step == 0 || (step > 0 && hi < lo) || (step < 0 && hi > lo) || step == LLONG_MIN)
        return pp5_fail(PP5_E_FORMAT, "%s: data file numbers %lld..%lld step %lld never end",
                        c->path, lo, hi, step);
    /* (hi - lo) / step + 1 files, in unsigned arithmetic so no range overflows. */
    unsigned long long span = step > 0 ? (unsigned long long)hi - (unsigned long long)lo
                                       : (unsigned long long)lo - (unsigned long long)hi;
    unsigned long long files = span / (step > 0 ? (unsigned long long)step
                                                : 0ull - (unsigned long long)step) + 1;
    pp5_status_t st = pp5_limit_check(PP5_LIMIT_DATA_FILES, files, c->path);
    for (unsigned long long i = 0; st == PP5_OK && i < files; i++) {
        char name[1200];
        /* Unsigned steps: the numbers wrap instead of overflowing, as in Teem's int. */
        unsigned long long number = (unsigned long long)lo + i * (unsigned long long)step;
        snprintf(name, sizeof name, fmt, (int)(long long)number);
        st = check_data_file(c, name);
    }
    return st;
}

/* The names after "data file: LIST", one per line to the end of the file. */
static pp5_status_t check_name_list(nrrd_precheck_t *c, char *names)
{
    pp5_status_t st = PP5_OK;
    for (char *line = strtok(names, "\r\n"); st == PP5_OK && line; line = strtok(NULL, "\r\n")) {
        if (!*line)
            continue;
        if (c->checked + 1 > pp5_limit(PP5_LIMIT_DATA_FILES))
            return pp5_limit_check(PP5_LIMIT_DATA_FILES, c->checked + 1, c->path);
        st = check_data_file(c, line);
    }
    return st;
}

static pp5_status_t check_data_files(nrrd_precheck_t *c, char *text, size_t hlen)
{
    for (char *line = text; line < text + hlen;) {
        char *nl = memchr(line, '\n', (size_t)(text + hlen - line));
        char *next = nl ? nl + 1 : text + hlen;
        if (nl)
            *nl = '\0';
        if (nl > line && nl[-1] == '\r')
            nl[-1] = '\0';
        const char *key = NULL;
        if (strncmp(line, "data file:", 10) == 0)
            key = line + 10;
        else if (strncmp(line, "datafile:", 9) == 0)
            key = line + 9;
        if (key) {
            while (*key == ' ')
                key++;
            if (strncmp(key, "LIST", 4) == 0 && (key[4] == '\0' || key[4] == ' '))
                return check_name_list(c, next);
            if (strchr(key, ' ') && strchr(key, '%'))
                return check_format_list(c, key);
            return check_data_file(c, key);
        }
        line = next;
    }
    return PP5_OK;
}

pp5_status_t volume_nrrd_precheck(const char *path)
{
    nrrd_precheck_t c = {.path = path};
    if (stat(path, &c.self) != 0)
        return pp5_fail(PP5_E_IO, "%s: cannot open: %s", path, strerror(errno));
    const char *slash = strrchr(path, '/');
    if (slash)
        snprintf(c.dir, sizeof c.dir, "%.*s", (int)(slash - path), path);
    char *text = NULL;
    size_t len = 0;
    pp5_status_t st = read_header(path, &text, &len);
    if (st != PP5_OK)
        return st;
    /* The whole first line is the magic: anything else sends Teem on to its
     * other readers (plain text, PNM, VTK), not what a .nrrd name promises. */
    bool magic = len >= 9 && memcmp(text, "NRRD000", 7) == 0 && text[7] >= '1' &&
                 text[7] <= '5' && (text[8] == '\n' || (text[8] == '\r' && len >= 10 &&
                                                        text[9] == '\n'));
    if (!magic)
        st = pp5_fail(PP5_E_FORMAT, "%s: not a NRRD file (its first line must be NRRD0001 .. "
                      "NRRD0005)", path);
    size_t hlen = st == PP5_OK ? header_length(text, len) : 0;
    uint64_t limit = pp5_limit(PP5_LIMIT_HEADER_BYTES);
    if (st == PP5_OK && hlen > limit)
        st = pp5_limit_check(PP5_LIMIT_HEADER_BYTES, hlen, path);
    if (st == PP5_OK && memchr(text, '\0', hlen))
        st = pp5_fail(PP5_E_FORMAT, "%s: NUL byte in the NRRD header", path);
    if (st == PP5_OK) {
        text[hlen] = '\0';    /* a LIST of names ends with the header */
        st = check_data_files(&c, text, hlen);
    }
    if (st == PP5_OK && c.missing[0])
        st = pp5_fail(PP5_E_IO, "%s: data file '%s': %s", path, c.missing,
                      strerror(c.missing_errno));
    free(text);
    return st;
}
