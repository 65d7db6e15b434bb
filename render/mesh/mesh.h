/* mesh.h: the indexed triangle mesh every mesh module shares, with its
 * loaders, writers and bounding-box helpers.
 *
 * Positions are doubles (error figures are quoted to 1e-6 of the diagonal);
 * faces are counter-clockwise vertex index triples.  The library depends on
 * emu/util only (status codes), never on the machine. */
#ifndef PP5_MESH_H
#define PP5_MESH_H

#include <stdint.h>
#include "status.h"

/* Upper bounds on counts read from any file header or generator (bunny-class
 * meshes are 1e5 faces; 5e7 leaves room for scans while an absurd count in a
 * header is an error before anything is allocated). */
#define MESH_MAX_VERTICES 50000000
#define MESH_MAX_FACES 50000000
/* Largest (decompressed) mesh file the readers accept. */
#define MESH_MAX_FILE_BYTES ((size_t)4 << 30)

typedef struct {
    int n_vertices;
    int n_faces;
    double *pos;        /* 3 * n_vertices: x y z */
    int32_t *tri;       /* 3 * n_faces: vertex indices, counter-clockwise */
    char source[256];   /* where the mesh came from (file name or generator) */
} mesh_t;

/* Allocates room for nv vertices and nf faces (contents zero).  Errors name
 * the limit. */
pp5_status_t mesh_alloc(mesh_t *m, int nv, int nf);
void mesh_free(mesh_t *m);
pp5_status_t mesh_copy(const mesh_t *src, mesh_t *dst);
/* Every index in range, no face repeating a vertex, every coordinate finite. */
pp5_status_t mesh_validate(const mesh_t *m, const char *what);

/* Axis-aligned bounds of the vertices used by faces (all vertices when none). */
void mesh_bounds(const mesh_t *m, double lo[3], double hi[3]);
double mesh_diagonal(const mesh_t *m);
/* Drops vertices no face uses (order kept); *dropped = how many. */
pp5_status_t mesh_drop_unused(mesh_t *m, int *dropped);
/* Total surface area. */
double mesh_area(const mesh_t *m);
/* The volume the faces enclose, positive when they are counter-clockwise
 * seen from outside (for an open mesh: of the cone sum from the origin). */
double mesh_signed_volume(const mesh_t *m);
/* Unnormalised face normal (cross product of two edges, length = 2 x area). */
void mesh_face_normal(const mesh_t *m, int f, double n[3]);

/* Readers by file extension (.obj, .off, .ply, each optionally .gz).  Every
 * error is one line naming the file (and line, for text formats). */
pp5_status_t mesh_load(const char *path, mesh_t *m);
pp5_status_t mesh_load_obj(const char *path, const char *text, size_t n, mesh_t *m);
pp5_status_t mesh_load_off(const char *path, const char *text, size_t n, mesh_t *m);
pp5_status_t mesh_load_ply(const char *path, const uint8_t *data, size_t n, mesh_t *m);
/* Reads a whole (possibly gzip-compressed) file into a NUL-terminated buffer. */
pp5_status_t mesh_read_file(const char *path, uint8_t **data, size_t *n);

/* Writers by extension (.obj, .off, .ply = binary little-endian); the file is
 * written beside its final name and renamed, so a failed write leaves none. */
pp5_status_t mesh_save(const char *path, const mesh_t *m);

#endif
