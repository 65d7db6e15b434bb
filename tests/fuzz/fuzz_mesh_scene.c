/* fuzz_mesh_scene.c: the polygon scene file reader (mesh_scene_load on a
 * scene file; its mesh lines may name gen: meshes or files beside it). */
#include "common.h"

#include "render/mesh/mesh_scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char path[512];
    fuzz_write("fuzz.scene", data, size, path, sizeof path);
    mesh_scene_t s;
    if (mesh_scene_load(path, &s) == PP5_OK)
        mesh_scene_free(&s);
    return 0;
}
