/* mesh_scene_internal.h: what mesh_scene.c, mesh_scene_file.c and
 * mesh_scene_flatten.c share: building a scene and 4x4 helpers. */
#ifndef PP5_MESH_SCENE_INTERNAL_H
#define PP5_MESH_SCENE_INTERNAL_H

#include "mesh_scene.h"

void mesh_scene_init(mesh_scene_t *s, const char *source);
/* Takes over *m (left empty). */
pp5_status_t scene_add_mesh(mesh_scene_t *s, mesh_t *m, int *index);
pp5_status_t scene_add_object(mesh_scene_t *s, int mesh, const double rgb[3]);
pp5_status_t mesh_scene_read_file(const char *path, mesh_scene_t *s);

void scene_mat_identity(double m[16]);
void scene_mat_premul(const double a[16], double m[16]);
void scene_mat_rotation(double deg, const double axis[3], double m[16]);

#endif
