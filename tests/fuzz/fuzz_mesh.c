/* fuzz_mesh.c: the mesh readers (mesh_load on .obj, .off, .ply and the
 * simplifiers' level records, mesh_record_load on .pmr).  The first byte
 * chooses the format, so one corpus holds them all. */
#include "common.h"

#include "render/mesh/mesh.h"
#include "render/mesh/mesh_simplify.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *const names[] = {"mesh.obj", "mesh.off", "mesh.ply", "mesh.obj.gz",
                                        "levels.pmr"};
    if (size < 1)
        return 0;
    const char *name = names[data[0] % (sizeof names / sizeof names[0])];
    char path[512];
    fuzz_write(name, data + 1, size - 1, path, sizeof path);
    if (data[0] % 5 == 4) {
        mesh_record_t r;
        if (mesh_record_load(path, &r) == PP5_OK)
            mesh_record_free(&r);
        return 0;
    }
    mesh_t m;
    if (mesh_load(path, &m) == PP5_OK)
        mesh_free(&m);
    return 0;
}
