/* mesh_io_internal.h: what the format readers share: a growing vertex/face
 * builder that enforces the mesh limits, and a line cursor for text formats. */
#ifndef PP5_MESH_IO_INTERNAL_H
#define PP5_MESH_IO_INTERNAL_H

#include <stddef.h>
#include "mesh.h"

typedef struct {
    double *pos;
    int32_t *tri;
    size_t nv, nf, cap_v, cap_f;
} mesh_builder_t;

pp5_status_t mesh_builder_vertex(mesh_builder_t *b, const double p[3]);
pp5_status_t mesh_builder_face(mesh_builder_t *b, int32_t a, int32_t c, int32_t d);
/* Moves the builder's arrays into m (the builder is left empty). */
pp5_status_t mesh_builder_finish(mesh_builder_t *b, const char *path, mesh_t *m);
/* How every reader ends: with the reader's status `st` so far, a file
 * without faces is an error too; on error the builder is freed, else
 * finished into m. */
pp5_status_t mesh_builder_end(mesh_builder_t *b, pp5_status_t st, const char *path, mesh_t *m);
void mesh_builder_free(mesh_builder_t *b);

/* Text cursor: one line at a time, with 1-based line numbers for errors. */
typedef struct {
    const char *p, *end;
    int line;
} text_cursor_t;

/* The next line (without its newline, NUL not added): false at the end. */
int text_next_line(text_cursor_t *c, const char **line, size_t *len);
/* Strict number parsing of the token at *s (skipping blanks); advances *s. */
int text_double(const char **s, const char *end, double *out);
int text_long(const char **s, const char *end, long *out);
/* True when only blanks (or a # comment) remain. */
int text_rest_blank(const char *s, const char *end);

#endif
