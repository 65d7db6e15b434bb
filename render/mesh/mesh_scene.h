/* mesh_scene.h: polygon scenes: several meshes placed by 4x4 transforms,
 * each with a colour, seen by one camera under one directional light; the
 * flattening of a scene into one world-space triangle list (the input of
 * the native renderer, mesh_render.h, and of the machine's polygon
 * pipeline); the built-in 100,000-triangle scene.
 *
 * Scene file (text, one statement a line, '#' starts a comment):
 *     mesh PATH            a new object showing PATH (.obj/.off/.ply[.gz],
 *                          relative to the scene file's folder) or gen:NAME
 *                          (sphere, torus, grid, cube); a path named twice is
 *                          loaded once and instanced
 *     translate X Y Z      the transform lines apply to the latest object, each
 *     rotate DEG AX AY AZ  after the ones before it (world = T_n ... T_1 p);
 *     scale S | SX SY SZ   rotate turns DEG degrees about the axis (AX, AY, AZ)
 *     colour R G B         the latest object's colour, 0..1 (also "color")
 *     camera EX EY EZ TX TY TZ [FOVY]   eye, target, vertical field of view
 *                          (degrees, default 40); up is +y.  Without it the
 *                          camera is fitted to the scene's bounds from +z
 *     light DX DY DZ [AMBIENT DIFFUSE [SPECULAR SHININESS]]
 *                          toward the light, world coordinates
 *     background R G B     0..1
 * Every error is one line naming the file and the line. */
#ifndef PP5_MESH_SCENE_H
#define PP5_MESH_SCENE_H

#include <stdbool.h>
#include <stdint.h>

#include "mesh.h"
#include "mesh_raster.h"
#include "mesh_simplify.h"

#define MESH_SCENE_MAX_OBJECTS 100000
#define MESH_SCENE_MAX_MESHES 1000

typedef struct {
    mesh_t mesh;
    double centre[3], radius;  /* bounding sphere (box centre, half diagonal), object space */
    mesh_record_t rec;         /* levels of detail (mesh_scene_build_records) */
    bool have_rec;
} scene_mesh_t;

typedef struct {
    int mesh;                  /* index into meshes */
    double xform[16];          /* object -> world, row-major */
    double rgb[3];             /* 0..1 */
} scene_object_t;

typedef struct {
    scene_mesh_t *meshes;
    int n_meshes;
    scene_object_t *objects;
    int n_objects;
    bool have_camera;
    double eye[3], target[3], fovy_deg;
    double light_dir[3];       /* toward the light, world */
    double ambient, diffuse, specular, shininess;
    double background[3];
    bool cull_back;            /* closed solids: faces seen from behind are dropped */
    char source[512];
} mesh_scene_t;

/* A scene file, or a built-in scene named gen:spheres100k. */
pp5_status_t mesh_scene_load(const char *path, mesh_scene_t *s);
/* gen:spheres100k: 100 objects in a 10 x 10 grid, alternately a UV sphere
 * (25 x 21) and a torus (25 x 20) of 1,000 faces each, turned and coloured
 * by their grid position: 100,000 triangles, two meshes, no external data. */
pp5_status_t mesh_scene_builtin(const char *name, mesh_scene_t *s);
/* A mesh file (.obj/.off/.ply[.gz]) or gen:NAME (mesh_gen_by_name) as a
 * one-object scene (mesh_scene_from_mesh); a mesh without faces is an error. */
pp5_status_t mesh_scene_load_mesh(const char *path, mesh_scene_t *s);
/* One mesh (taken over: *m is left empty) as a scene: identity transform,
 * grey, two-sided (no culling), the camera fitted. */
pp5_status_t mesh_scene_from_mesh(mesh_t *m, mesh_scene_t *s);
void mesh_scene_free(mesh_scene_t *s);

/* World-space bounds of every object (its transformed bounding box). */
void mesh_scene_bounds(const mesh_scene_t *s, double lo[3], double hi[3]);
/* The scene's camera (or one fitted to its bounds, looking down -z) for an
 * image of the given aspect, near and far planes around the bounds. */
void mesh_scene_camera(const mesh_scene_t *s, double aspect, raster_camera_t *cam);
/* Collapse records to the floor for every mesh (QEM, ARCHITECTURE.md), so
 * mesh_scene_flatten can take any level. */
pp5_status_t mesh_scene_build_records(mesh_scene_t *s);

/* A world-space triangle list: triangle t has vertices 3t .. 3t+2; per
 * vertex a position, a unit normal (the mesh's area-weighted vertex normal,
 * transformed by the inverse transpose) and a colour; counter-clockwise
 * seen from outside (a mirroring transform has its faces turned back). */
typedef struct {
    int n_tris;
    double *pos, *nrm, *rgb;   /* 9 * n_tris each */
    int32_t *object;           /* n_tris: the object each came from */
} mesh_soup_t;

/* Flattens every object at its level: levels[o] indexes the object's mesh
 * record (0 = full detail); levels NULL = full detail for all. */
pp5_status_t mesh_scene_flatten(mesh_scene_t *s, const int *levels, mesh_soup_t *out);
void mesh_soup_free(mesh_soup_t *soup);

#endif
