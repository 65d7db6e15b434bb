/* cmd_volume.c: `pp5 volume info FILE` (what a volume file holds, through
 * the same loaders the renderer uses) and `pp5 volume phantom NAME --out
 * FILE` (write a procedural phantom for other tools). */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cliopt.h"
#include "outfile.h"
#include "registry.h"
#include "render/classify_auto.h"
#include "render/classify_io.h"
#include "render/volume.h"
#include "render/volume_histogram.h"

static void usage(void)
{
    printf("usage: pp5 volume info FILE [--dims NXxNYxNZ --type T] [--big-endian|--little-endian]\n"
           "                            [--spacing SX,SY,SZ] [--header-bytes N]\n"
           "       pp5 volume phantom NAME [--size NXxNYxNZ] --out FILE.nrrd|FILE.raw\n\n"
           "info: loads FILE and prints its dimensions, stored voxel type, spacing, value\n"
           "  range, mean and the FNV-1a hash of the float voxels (the hash reports use),\n"
           "  then its histogram: percentiles, the background (the peak of air or padding\n"
           "  at the low end), the other voxels' values, and the transfer function that\n"
           "  `pp5 render --volume FILE` chooses from them (render/classify_auto.h).\n"
           "  Formats: .nrrd/.nhdr (Teem), .nii/.nii.gz (niftilib), .den (VolPack), a\n"
           "  Stanford slice series given as NAME.1 or NAME (16-bit big-endian square\n"
           "  slices unless --dims/--type say otherwise), raw files whose name states\n"
           "  the layout (vol_256x256x113_u16be.raw.gz), or any raw file with --dims and\n"
           "  --type.  Raw files may be gzip-compressed; the size must match exactly.\n"
           "  --type: u8 i8 u16 i16 u32 i32 f32 f64 (raw default: little-endian).\n\n"
           "phantom: writes a procedural volume: %s.\n"
           "  Default sizes 256x256x109, 41x41x41, 64x64x64.  .nrrd is float with the\n"
           "  spacings; .raw is headerless little-endian float32 (its layout is printed).\n\n"
           "examples:\n"
           "  pp5 volume info ../shared/data/volumes/cthead/cthead_256x256x113_u16be.raw.gz\n"
           "  pp5 volume info brain.raw --dims 128x128x84 --type u8\n"
           "  pp5 volume phantom shepp-logan --size 128x128x64 --out sl.nrrd\n",
           phantom_names());
}

static void print_volume(const volume_t *v, const volume_file_info_t *info)
{
    size_t n = volume_voxel_count(v);
    double sum = 0;
    for (size_t i = 0; i < n; i++)
        sum += v->data[i];
    printf("source:   %s\n", v->source);
    if (info)
        printf("format:   %s, stored as %s%s\n", info->format, voxel_type_name(info->stored_type),
               voxel_type_bytes(info->stored_type) > 1
                   ? (info->big_endian ? " big-endian" : " little-endian") : "");
    printf("dims:     %d x %d x %d (%zu voxels)\n", v->nx, v->ny, v->nz, n);
    printf("spacing:  %g %g %g\n", v->spacing[0], v->spacing[1], v->spacing[2]);
    printf("range:    %g .. %g (mean %.4g)\n", v->min_value, v->max_value, n ? sum / n : 0.0);
    printf("hash:     %016llx (FNV-1a 64 of the float voxels)\n", (unsigned long long)v->hash);
}

/* The histogram summary and the default transfer function it gives. */
static void print_histogram(const volume_t *v)
{
    volume_histogram_t *h = malloc(sizeof *h);
    if (!h) {
        printf("histogram: out of memory\n");
        return;
    }
    volume_histogram_compute(v, h);
    printf("histogram:\n");
    volume_histogram_print(h, "  ", stdout);
    classify_tf_t tf;
    classify_auto_info_t ai;
    if (classify_tf_auto(h, &tf, &ai) == PP5_OK) {
        printf("default transfer function (pp5 render --volume; --tf-out FILE saves it):\n");
        classify_tf_write_text(stdout, &tf, NULL);
    } else {
        printf("default transfer function: none (%s)\n", pp5_error_text());
    }
    free(h);
}

static int cmd_info(int argc, char **argv)
{
    static const struct option longopts[] = {
        {"dims", required_argument, NULL, 'd'},
        {"type", required_argument, NULL, 't'},
        {"big-endian", no_argument, NULL, 'B'},
        {"little-endian", no_argument, NULL, 'L'},
        {"spacing", required_argument, NULL, 's'},
        {"header-bytes", required_argument, NULL, 'H'},
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    volume_raw_spec_t raw;
    memset(&raw, 0, sizeof raw);
    bool have_dims = false, have_type = false, have_any_raw = false;
    pp5_status_t st = PP5_OK;
    int c;
    optind = 1;
    while (st == PP5_OK && (c = getopt_long(argc, argv, "d:t:BLs:H:h", longopts, NULL)) != -1) {
        switch (c) {
        case 'd':
            st = volume_parse_size3("--dims", optarg, &raw.nx, &raw.ny, &raw.nz);
            have_dims = have_any_raw = true;
            break;
        case 't':
            st = voxel_type_parse(optarg, &raw.type);
            have_type = have_any_raw = true;
            break;
        case 'B': raw.big_endian = true; have_any_raw = true; break;
        case 'L': raw.big_endian = false; have_any_raw = true; break;
        case 's':
            st = volume_parse_spacing3("--spacing", optarg, raw.spacing);
            have_any_raw = true;
            break;
        case 'H': {
            long v;
            st = cliopt_long("--header-bytes", optarg, 0, 1L << 40, &v);
            raw.header_bytes = (uint64_t)v;
            have_any_raw = true;
            break;
        }
        case 'h': usage(); return 0;
        default: return 2;
        }
    }
    if (st != PP5_OK)
        return cliopt_report("volume info", PP5_E_CONFIG);
    if (optind != argc - 1)
        return cliopt_report("volume info", pp5_fail(PP5_E_CONFIG, "give exactly one FILE "
                                                     "(see pp5 volume --help)"));
    if (have_dims && !have_type)
        return cliopt_report("volume info", pp5_fail(PP5_E_CONFIG, "--dims needs --type"));
    const char *path = argv[optind];
    /* Raw options apply to a raw file or a slice series; with only some of
     * them given, the layout is taken from the file name and overridden. */
    volume_raw_spec_t spec = raw;
    const volume_raw_spec_t *use = NULL;
    if (have_any_raw) {
        volume_raw_spec_t from_name;
        if (!have_dims && volume_raw_spec_from_name(path, &from_name) == PP5_OK) {
            spec.nx = from_name.nx;
            spec.ny = from_name.ny;
            spec.nz = from_name.nz;
            if (!have_type) {
                spec.type = from_name.type;
                spec.big_endian = raw.big_endian || from_name.big_endian;
            }
        }
        use = &spec;
    }
    volume_t v;
    volume_file_info_t info;
    st = volume_load_info(path, use, &v, &info);
    if (st != PP5_OK)
        return cliopt_report("volume info", st);
    print_volume(&v, &info);
    print_histogram(&v);
    volume_free(&v);
    return 0;
}

static bool has_suffix(const char *s, const char *suffix)
{
    size_t ls = strlen(s), lx = strlen(suffix);
    return ls >= lx && strcmp(s + ls - lx, suffix) == 0;
}

static int cmd_phantom(int argc, char **argv)
{
    static const struct option longopts[] = {
        {"size", required_argument, NULL, 's'},
        {"out", required_argument, NULL, 'o'},
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    int nx = 0, ny = 0, nz = 0;
    const char *out = NULL;
    int c;
    optind = 1;
    while ((c = getopt_long(argc, argv, "s:o:h", longopts, NULL)) != -1) {
        switch (c) {
        case 's':
            if (volume_parse_size3("--size", optarg, &nx, &ny, &nz) != PP5_OK)
                return cliopt_report("volume phantom", PP5_E_CONFIG);
            break;
        case 'o': out = optarg; break;
        case 'h': usage(); return 0;
        default: return 2;
        }
    }
    if (optind != argc - 1)
        return cliopt_report("volume phantom", pp5_fail(PP5_E_CONFIG, "give one phantom NAME "
                                                        "(%s)", phantom_names()));
    if (!out)
        return cliopt_report("volume phantom", pp5_fail(PP5_E_CONFIG, "--out FILE.nrrd or "
                                                        "FILE.raw is required"));
    bool nrrd = has_suffix(out, ".nrrd"), raw = has_suffix(out, ".raw");
    if (!nrrd && !raw)
        return cliopt_report("volume phantom", pp5_fail(PP5_E_CONFIG, "--out %s: the name must "
                                                        "end in .nrrd or .raw", out));
    pp5_status_t st = outpath_check("--out", out);
    if (st != PP5_OK)
        return cliopt_report("volume phantom", st);
    volume_t v;
    st = phantom_make(argv[optind], nx, ny, nz, &v);
    if (st != PP5_OK)
        return cliopt_report("volume phantom", st == PP5_E_RANGE ? PP5_E_CONFIG : st);
    st = nrrd ? volume_save_nrrd(&v, out) : volume_save_raw_f32(&v, out);
    if (st == PP5_OK) {
        printf("wrote %s\n", out);
        if (raw)
            printf("raw layout: --dims %dx%dx%d --type f32 --little-endian --spacing %g,%g,%g\n",
                   v.nx, v.ny, v.nz, v.spacing[0], v.spacing[1], v.spacing[2]);
        print_volume(&v, NULL);
    }
    volume_free(&v);
    return st == PP5_OK ? 0 : cliopt_report("volume phantom", st);
}

static int cmd_volume(int argc, char **argv)
{
    if (argc < 2 || strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0 ||
        strcmp(argv[1], "help") == 0) {
        usage();
        return argc < 2 ? 2 : 0;
    }
    if (strcmp(argv[1], "info") == 0)
        return cmd_info(argc - 1, argv + 1);
    if (strcmp(argv[1], "phantom") == 0)
        return cmd_phantom(argc - 1, argv + 1);
    return cliopt_report("volume", pp5_fail(PP5_E_CONFIG, "unknown subcommand '%s' (info, "
                                            "phantom)", argv[1]));
}

PP5_COMMAND(volume, "inspect volume files; write procedural phantoms", cmd_volume)
