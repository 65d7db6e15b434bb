/* outfile.h: output files that are checked before the work and never seen
 * half-written.
 *
 *   pp5_status_t st = outpath_check("--out", out_png);      // before rendering
 *   ...
 *   outfile_t o;
 *   st = outfile_open(&o, out_png, true);                   // a temporary beside it
 *   fwrite(..., o.f);
 *   st = outfile_commit(&o);                                // rename over the target
 *
 * The temporary lives in the target's folder (".tmp-PID-N-NAME", so the
 * rename cannot cross file systems and the name keeps its extension) and is
 * created with the permissions fopen would give.  A target that exists and
 * is not a regular file (/dev/null, a FIFO, a terminal) or is a symbolic link
 * is written in place: renaming over it would replace the device or the link. */
#ifndef PP5_OUTFILE_H
#define PP5_OUTFILE_H

#include <stdbool.h>
#include <stdio.h>
#include "status.h"

/* PP5_E_IO naming `what` and the path unless the path's folder exists, is a
 * folder and is writable, and the path itself is not a folder. */
pp5_status_t outpath_check(const char *what, const char *path);
/* The same for an output folder (--frames-dir DIR): it exists and is writable. */
pp5_status_t outpath_check_dir(const char *what, const char *dir);
/* outpath_check for each non-NULL path of a NULL-terminated list of
 * (what, path) pairs: outpath_check_all("--out", out, "--report", rep, NULL). */
pp5_status_t outpath_check_all(const char *what, const char *path, ...);

typedef struct {
    FILE *f;                 /* write here (NULL after outfile_release_stream) */
    char path[1024];         /* the target */
    char tmp[1200];          /* the temporary, or "" when writing in place */
} outfile_t;

/* Creates the temporary (or opens the target in place) and o->f on it. */
pp5_status_t outfile_open(outfile_t *o, const char *path, bool binary);
/* The file the caller writes when it does its own I/O (closing o->f first
 * with outfile_release_stream): the temporary, or the target in place. */
const char *outfile_write_path(const outfile_t *o);
void outfile_release_stream(outfile_t *o);
/* Closes o->f (if open) and renames the temporary over the target.  On any
 * write or close error the temporary is removed and the target is untouched. */
pp5_status_t outfile_commit(outfile_t *o);
/* Closes and removes the temporary: the target is left as it was. */
void outfile_discard(outfile_t *o);

#endif
