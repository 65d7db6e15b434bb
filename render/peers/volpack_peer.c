/* volpack_peer.c: times VolPack's shear-warp renderer on CThead for
 * `pp5 bench --peers`.  Not part of the pp5 build (render/peers/ is compiled
 * by run_peers.sh against Debian's libvolpack1-dev).
 *
 * usage: volpack_peer RAW_U16BE NX NY NZ IMAGE_SIDE FRAMES
 * Prints "volpack_ms_per_frame <median>" and the classify time. */
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <volpack.h>

typedef struct {
    short normal;             /* VolPack-encoded normal */
    unsigned char density;    /* CThead value / 16 (12 bits -> 8) */
    unsigned char gradient;   /* gradient magnitude, VolPack scale */
} peer_voxel_t;

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static void check(vpContext *vpc, vpResult r, const char *what)
{
    if (r != VP_OK) {
        fprintf(stderr, "volpack_peer: %s: %s\n", what, vpGetErrorString(vpGetError(vpc)));
        exit(1);
    }
}

int main(int argc, char **argv)
{
    if (argc != 7) {
        fprintf(stderr, "usage: volpack_peer RAW_U16BE NX NY NZ IMAGE_SIDE FRAMES\n");
        return 2;
    }
    int nx = atoi(argv[2]), ny = atoi(argv[3]), nz = atoi(argv[4]);
    int side = atoi(argv[5]), frames = atoi(argv[6]);
    if (nx < 2 || ny < 2 || nz < 2 || side < 16 || frames < 1 || frames > 100)
        return 2;
    size_t n = (size_t)nx * ny * nz;
    unsigned char *raw = malloc(n * 2), *density = malloc(n);
    peer_voxel_t *vox = malloc(n * sizeof *vox);
    unsigned char *image = malloc((size_t)side * side * 3);
    FILE *f = fopen(argv[1], "rb");
    if (!raw || !density || !vox || !image || !f || fread(raw, 2, n, f) != n) {
        fprintf(stderr, "volpack_peer: cannot read %s\n", argv[1]);
        return 1;
    }
    fclose(f);
    for (size_t i = 0; i < n; i++) {
        unsigned v = ((unsigned)raw[2 * i] << 8) | raw[2 * i + 1];
        density[i] = (unsigned char)(v >= 4095 ? 255 : v / 16);
    }
    vpContext *vpc = vpCreateContext();
    check(vpc, vpSetVolumeSize(vpc, nx, ny, nz), "size");
    check(vpc, vpSetVoxelSize(vpc, sizeof(peer_voxel_t), 3, 1, 2), "voxel size");
    check(vpc, vpSetVoxelField(vpc, 0, sizeof(short), offsetof(peer_voxel_t, normal),
                               VP_NORM_MAX), "normal field");
    check(vpc, vpSetVoxelField(vpc, 1, 1, offsetof(peer_voxel_t, density), 255), "density");
    check(vpc, vpSetVoxelField(vpc, 2, 1, offsetof(peer_voxel_t, gradient), VP_GRAD_MAX),
          "gradient");
    check(vpc, vpSetRawVoxels(vpc, vox, n * sizeof *vox, sizeof *vox, nx * sizeof *vox,
                              (size_t)nx * ny * sizeof *vox), "raw voxels");
    double t0 = now_ms();
    check(vpc, vpVolumeNormals(vpc, density, n, 1, 2, 0), "normals");
    /* pp5's ct-skin-ramp: opacity 0 at 350 rising to 0.8 at 640 (22 and 40
     * after the /16 to 8 bits), not weighted by gradient (ramp of 1s). */
    static float density_ramp[256], gradient_ramp[VP_GRAD_MAX + 1];
    int dx[4] = {0, 22, 40, 255};
    float dy[4] = {0.0f, 0.0f, 0.8f, 0.8f};
    vpRamp(density_ramp, sizeof(float), 4, dx, dy);
    int gx[3] = {0, 10, VP_GRAD_MAX};
    float gy[3] = {1.0f, 1.0f, 1.0f};
    vpRamp(gradient_ramp, sizeof(float), 3, gx, gy);
    check(vpc, vpSetClassifierTable(vpc, 0, 1, density_ramp, sizeof density_ramp), "table0");
    check(vpc, vpSetClassifierTable(vpc, 1, 2, gradient_ramp, sizeof gradient_ramp), "table1");
    vpSetd(vpc, VP_MIN_VOXEL_OPACITY, 0.05);
    check(vpc, vpClassifyVolume(vpc), "classify");
    double t1 = now_ms();
    static float shade_table[VP_NORM_MAX + 1][3];
    check(vpc, vpSetLookupShader(vpc, 3, 1, 0, &shade_table[0][0], sizeof shade_table, 0, NULL, 0),
          "shader");
    vpSetMaterial(vpc, VP_MATERIAL0, VP_AMBIENT, VP_BOTH_SIDES, 0.15, 0.12, 0.10);
    vpSetMaterial(vpc, VP_MATERIAL0, VP_DIFFUSE, VP_BOTH_SIDES, 0.80, 0.64, 0.53);
    vpSetMaterial(vpc, VP_MATERIAL0, VP_SPECULAR, VP_BOTH_SIDES, 0.0, 0.0, 0.0);
    vpSetMaterial(vpc, VP_MATERIAL0, VP_SHINYNESS, VP_BOTH_SIDES, 10.0, 0.0, 0.0);
    vpSetLight(vpc, VP_LIGHT0, VP_DIRECTION, 0.3, 0.3, 1.0);
    vpSetLight(vpc, VP_LIGHT0, VP_COLOR, 1.0, 1.0, 1.0);
    vpEnable(vpc, VP_LIGHT0, 1);
    vpSeti(vpc, VP_CONCAT_MODE, VP_CONCAT_LEFT);
    vpCurrentMatrix(vpc, VP_MODEL);
    vpIdentityMatrix(vpc);
    vpScale(vpc, 1.0, 1.0, 2.0);   /* 1:1:2 voxels */
    vpRotate(vpc, VP_X_AXIS, -90.0);
    vpRotate(vpc, VP_Z_AXIS, 180.0);
    vpCurrentMatrix(vpc, VP_PROJECT);
    vpIdentityMatrix(vpc);
    vpWindow(vpc, VP_PARALLEL, -0.6, 0.6, -0.6, 0.6, -0.6, 0.6);
    vpCurrentMatrix(vpc, VP_MODEL);
    check(vpc, vpSetImage(vpc, image, side, side, side * 3, VP_RGB), "image");
    vpSetd(vpc, VP_MAX_RAY_OPACITY, 0.95);
    check(vpc, vpShadeTable(vpc), "shade table");
    double ms[100];
    for (int i = 0; i < frames; i++) {
        vpRotate(vpc, VP_Y_AXIS, 1.0);     /* a new view each frame */
        double a = now_ms();
        check(vpc, vpRenderClassifiedVolume(vpc), "render");
        ms[i] = now_ms() - a;
    }
    qsort(ms, (size_t)frames, sizeof ms[0], cmp);
    printf("volpack_classify_ms %.1f\n", t1 - t0);
    printf("volpack_ms_per_frame %.2f\n", ms[frames / 2]);
    if (getenv("PEER_PPM")) {
        FILE *o = fopen(getenv("PEER_PPM"), "wb");
        if (o) {
            fprintf(o, "P6\n%d %d\n255\n", side, side);
            fwrite(image, 3, (size_t)side * side, o);
            fclose(o);
        }
    }
    vpDestroyContext(vpc);
    return 0;
}
