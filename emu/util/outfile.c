/* outfile.c: early output-path checks and write-to-temporary-then-rename
 * (see outfile.h). */
#include "outfile.h"

#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* The folder part of `path` ("." when it has none). */
static void folder_of(const char *path, char *dir, size_t size)
{
    const char *slash = strrchr(path, '/');
    if (!slash)
        snprintf(dir, size, ".");
    else if (slash == path)
        snprintf(dir, size, "/");
    else
        snprintf(dir, size, "%.*s", (int)(slash - path), path);
}

pp5_status_t outpath_check(const char *what, const char *path)
{
    if (!path || !*path)
        return pp5_fail(PP5_E_CONFIG, "%s: empty output file name", what);
    if (strlen(path) >= sizeof ((outfile_t *)0)->path)
        return pp5_fail(PP5_E_CONFIG, "%s: output file name is too long", what);
    struct stat sb;
    if (stat(path, &sb) == 0 && S_ISDIR(sb.st_mode))
        return pp5_fail(PP5_E_IO, "%s: %s is a folder, not a file name", what, path);
    char dir[1024];
    folder_of(path, dir, sizeof dir);
    if (stat(dir, &sb) != 0)
        return pp5_fail(PP5_E_IO, "%s: cannot write %s: folder %s does not exist", what, path,
                        dir);
    if (!S_ISDIR(sb.st_mode))
        return pp5_fail(PP5_E_IO, "%s: cannot write %s: %s is not a folder", what, path, dir);
    if (access(dir, W_OK | X_OK) != 0)
        return pp5_fail(PP5_E_IO, "%s: cannot write %s: folder %s is not writable (%s)", what,
                        path, dir, strerror(errno));
    if (access(path, F_OK) == 0 && access(path, W_OK) != 0)
        return pp5_fail(PP5_E_IO, "%s: cannot write %s: %s", what, path, strerror(errno));
    return PP5_OK;
}

pp5_status_t outpath_check_dir(const char *what, const char *dir)
{
    struct stat sb;
    if (!dir || !*dir)
        return pp5_fail(PP5_E_CONFIG, "%s: empty folder name", what);
    if (stat(dir, &sb) != 0)
        return pp5_fail(PP5_E_IO, "%s: folder %s does not exist", what, dir);
    if (!S_ISDIR(sb.st_mode))
        return pp5_fail(PP5_E_IO, "%s: %s is not a folder", what, dir);
    if (access(dir, W_OK | X_OK) != 0)
        return pp5_fail(PP5_E_IO, "%s: folder %s is not writable (%s)", what, dir,
                        strerror(errno));
    return PP5_OK;
}

pp5_status_t outpath_check_all(const char *what, const char *path, ...)
{
    va_list ap;
    va_start(ap, path);
    pp5_status_t st = PP5_OK;
    while (what && st == PP5_OK) {
        if (path)
            st = outpath_check(what, path);
        what = va_arg(ap, const char *);
        if (what)
            path = va_arg(ap, const char *);
    }
    va_end(ap);
    return st;
}

/* True when the target must be written in place (see outfile.h). */
static bool write_in_place(const char *path)
{
    struct stat sb;
    if (lstat(path, &sb) != 0)
        return false;
    return !S_ISREG(sb.st_mode);
}

static atomic_uint temp_counter;

pp5_status_t outfile_open(outfile_t *o, const char *path, bool binary)
{
    memset(o, 0, sizeof *o);
    if (strlen(path) >= sizeof o->path)
        return pp5_fail(PP5_E_CONFIG, "%s: output file name is too long", path);
    snprintf(o->path, sizeof o->path, "%s", path);
    const char *mode = binary ? "wb" : "w";
    if (write_in_place(path)) {
        o->f = fopen(path, mode);
        if (!o->f)
            return pp5_fail(PP5_E_IO, "%s: cannot create: %s", path, strerror(errno));
        return PP5_OK;
    }
    char dir[1024];
    folder_of(path, dir, sizeof dir);
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    for (int attempt = 0; attempt < 100; attempt++) {
        snprintf(o->tmp, sizeof o->tmp, "%s/.tmp-%ld-%u-%s", dir, (long)getpid(),
                 atomic_fetch_add(&temp_counter, 1u), base);
        /* 0666 less the umask: the permissions fopen would have given. */
        int fd = open(o->tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd < 0 && errno == EEXIST)
            continue;
        if (fd < 0)
            break;
        o->f = fdopen(fd, mode);
        if (!o->f) {
            close(fd);
            unlink(o->tmp);
            break;
        }
        return PP5_OK;
    }
    pp5_status_t st = pp5_fail(PP5_E_IO, "%s: cannot create a temporary file beside it: %s",
                               path, strerror(errno));
    o->tmp[0] = '\0';
    return st;
}

const char *outfile_write_path(const outfile_t *o)
{
    return o->tmp[0] ? o->tmp : o->path;
}

void outfile_release_stream(outfile_t *o)
{
    if (o->f)
        fclose(o->f);
    o->f = NULL;
}

pp5_status_t outfile_commit(outfile_t *o)
{
    int err = 0;
    if (o->f) {
        if (ferror(o->f))
            err = errno ? errno : EIO;
        if (fclose(o->f) != 0 && !err)
            err = errno;
        o->f = NULL;
    }
    if (err) {
        outfile_discard(o);
        return pp5_fail(PP5_E_IO, "%s: write failed: %s", o->path, strerror(err));
    }
    if (o->tmp[0] && rename(o->tmp, o->path) != 0) {
        err = errno;
        outfile_discard(o);
        return pp5_fail(PP5_E_IO, "%s: cannot move the finished file into place: %s", o->path,
                        strerror(err));
    }
    o->tmp[0] = '\0';
    return PP5_OK;
}

void outfile_discard(outfile_t *o)
{
    if (o->f)
        fclose(o->f);
    o->f = NULL;
    if (o->tmp[0])
        unlink(o->tmp);
    o->tmp[0] = '\0';
}
