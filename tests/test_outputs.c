/* test_outputs.c: outputs are checked before the work and never half-written
 * (emu/util/outfile.h), and every kind of failure has its own exit code
 * (status.h), documented in `pp5 help`.
 *
 * bad_inputs_give_one_line_and_their_exit_code also writes the table of bad
 * inputs tried, with each message and exit code, to its output folder
 * (bad_inputs.md), for the record. */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "harness.h"
#include "emu/util/outfile.h"
#include "emu/util/png_io.h"
#include "emu/util/status.h"

static void write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    REQUIRE(f != NULL);
    fputs(text, f);
    REQUIRE(fclose(f) == 0);
}

/* Number of ".tmp-" files left in dir. */
static int temporaries_in(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return -1;
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL)
        n += strncmp(e->d_name, ".tmp-", 5) == 0;
    closedir(d);
    return n;
}

TEST(outfile_target_changes_only_at_commit)
{
    const char *dir = pp5_test_outdir();
    char path[1200];
    snprintf(path, sizeof path, "%s/report.json", dir);
    write_text(path, "old\n");
    outfile_t o;
    REQUIRE(outfile_open(&o, path, false) == PP5_OK);
    fputs("new and longer\n", o.f);
    fflush(o.f);
    char *before = pp5_test_read_file(path);
    CHECK(before && strcmp(before, "old\n") == 0);      /* untouched while writing */
    free(before);
    CHECK_EQ(temporaries_in(dir), 1);
    CHECK(strstr(outfile_write_path(&o), "/.tmp-") && strstr(outfile_write_path(&o), "report.json"));
    REQUIRE(outfile_commit(&o) == PP5_OK);
    char *after = pp5_test_read_file(path);
    CHECK(after && strcmp(after, "new and longer\n") == 0);
    free(after);
    CHECK_EQ(temporaries_in(dir), 0);
    /* The new file has fopen's permissions (0666 less the umask), not mkstemp's 0600. */
    mode_t mask = umask(0);
    umask(mask);
    struct stat sb;
    REQUIRE(stat(path, &sb) == 0);
    CHECK_EQ(sb.st_mode & 0777, 0666 & ~mask);
}

TEST(outfile_discard_leaves_the_old_file_and_no_temporary)
{
    const char *dir = pp5_test_outdir();
    char path[1200];
    snprintf(path, sizeof path, "%s/frames.csv", dir);
    write_text(path, "complete old file\n");
    outfile_t o;
    REQUIRE(outfile_open(&o, path, false) == PP5_OK);
    fputs("half of a new fi", o.f);
    outfile_discard(&o);          /* what every writer does on an error */
    char *text = pp5_test_read_file(path);
    CHECK(text && strcmp(text, "complete old file\n") == 0);
    free(text);
    CHECK_EQ(temporaries_in(dir), 0);
}

TEST(outfile_writes_devices_and_links_in_place)
{
    const char *dir = pp5_test_outdir();
    outfile_t o;
    /* /dev/null must stay a device: renaming a file over it would replace it. */
    REQUIRE(outfile_open(&o, "/dev/null", false) == PP5_OK);
    CHECK(strcmp(outfile_write_path(&o), "/dev/null") == 0);
    fputs("x", o.f);
    CHECK_EQ(outfile_commit(&o), PP5_OK);
    struct stat sb;
    CHECK(stat("/dev/null", &sb) == 0 && S_ISCHR(sb.st_mode));
    /* /dev/full: the write error is reported, naming the path. */
    REQUIRE(outfile_open(&o, "/dev/full", false) == PP5_OK);
    for (int i = 0; i < 10000; i++)
        fputs("fill the buffer ", o.f);
    CHECK_EQ(outfile_commit(&o), PP5_E_IO);
    CHECK(strstr(pp5_error_text(), "/dev/full") != NULL);
    /* a symbolic link keeps pointing where it pointed */
    char target[1200], link_path[1200];
    snprintf(target, sizeof target, "%s/target.txt", dir);
    snprintf(link_path, sizeof link_path, "%s/link.txt", dir);
    write_text(target, "old");
    REQUIRE(symlink("target.txt", link_path) == 0);
    REQUIRE(outfile_open(&o, link_path, false) == PP5_OK);
    fputs("new", o.f);
    CHECK_EQ(outfile_commit(&o), PP5_OK);
    CHECK(lstat(link_path, &sb) == 0 && S_ISLNK(sb.st_mode));
    char *text = pp5_test_read_file(target);
    CHECK(text && strcmp(text, "new") == 0);
    free(text);
}

TEST(outpath_check_names_the_path_and_the_reason)
{
    const char *dir = pp5_test_outdir();
    char path[1200];
    CHECK_EQ(outpath_check("--out", "/nonexistent-pp5-dir/x.png"), PP5_E_IO);
    CHECK(strstr(pp5_error_text(), "--out: cannot write /nonexistent-pp5-dir/x.png: folder "
                 "/nonexistent-pp5-dir does not exist") != NULL);
    CHECK_EQ(outpath_check("--report", dir), PP5_E_IO);
    CHECK(strstr(pp5_error_text(), "is a folder, not a file name") != NULL);
    snprintf(path, sizeof path, "%s/plain-file", dir);
    write_text(path, "");
    char under[1300];
    snprintf(under, sizeof under, "%s/x.png", path);
    CHECK_EQ(outpath_check("--plot", under), PP5_E_IO);
    CHECK(strstr(pp5_error_text(), "is not a folder") != NULL);
    CHECK_EQ(outpath_check("--out", ""), PP5_E_CONFIG);
    snprintf(path, sizeof path, "%s/fine.png", dir);
    CHECK_EQ(outpath_check("--out", path), PP5_OK);
    CHECK_EQ(outpath_check_dir("--frames-dir", dir), PP5_OK);
    CHECK_EQ(outpath_check_dir("--frames-dir", path), PP5_E_IO);   /* does not exist */
    if (getuid() != 0) {          /* root may write anywhere */
        snprintf(path, sizeof path, "%s/ro", dir);
        REQUIRE(mkdir(path, 0555) == 0);
        snprintf(under, sizeof under, "%s/x.png", path);
        CHECK_EQ(outpath_check("--out", under), PP5_E_IO);
        CHECK(strstr(pp5_error_text(), "not writable") != NULL);
    }
}

TEST(png_write_failure_leaves_no_file)
{
    const char *dir = pp5_test_outdir();
    image8_t img;
    REQUIRE(image8_alloc(&img, 4, 4, 3) == PP5_OK);
    char path[1200];
    snprintf(path, sizeof path, "%s/missing-folder/x.png", dir);
    CHECK_EQ(png_write(path, &img), PP5_E_IO);
    snprintf(path, sizeof path, "%s/x.png", dir);
    CHECK_EQ(png_write(path, &img), PP5_OK);
    CHECK_EQ(temporaries_in(dir), 0);
    image8_t back;
    REQUIRE(png_read(path, &back, 3) == PP5_OK);
    CHECK_EQ(back.width, 4);
    image8_free(&back);
    image8_free(&img);
}

/* Runs `pp5 ARGS`; returns the exit code and the first line of stderr, and
 * counts stderr's lines. */
static int run(const char *dir, const char *args, char *first_line, size_t size, int *lines)
{
    char err[1200];
    snprintf(err, sizeof err, "%s/stderr.txt", dir);
    int rc = pp5_test_run_cli(args, NULL, err);
    char *text = pp5_test_read_file(err);
    first_line[0] = '\0';
    *lines = 0;
    if (text) {
        for (const char *p = text; *p; p++)
            *lines += *p == '\n';
        char *nl = strchr(text, '\n');
        if (nl)
            *nl = '\0';
        snprintf(first_line, size, "%s", text);
        free(text);
    }
    return rc;
}

TEST(commands_check_outputs_before_the_work)
{
    const char *dir = pp5_test_outdir();
    /* Each command is given a bad output AND an input that would fail (or
     * work that would take long): the output is what it must report. */
    static const struct { const char *args, *says; } cases[] = {
        {"test-pattern --out /nonexistent-pp5/x.png", "--out: cannot write /nonexistent-pp5/x.png"},
        {"test-pattern --report /nonexistent-pp5/r.json", "--report: cannot write"},
        {"test-pattern --timeline /nonexistent-pp5/t.json", "--timeline: cannot write"},
        {"trace synth --mode pursuit --seconds 86000 --out /nonexistent-pp5/s.trace",
         "--out: cannot write /nonexistent-pp5/s.trace"},
        {"trace import /nonexistent-input.asc --out /nonexistent-pp5/e.trace",
         "--out: cannot write /nonexistent-pp5/e.trace"},
        {"volume phantom sphere-shell --out /nonexistent-pp5/v.nrrd", "--out: cannot write"},
        {"track record --device hid --out /nonexistent-pp5/live.trace", "--out: cannot write"},
        {"replay /nonexistent-input.trace --report /nonexistent-pp5/r.json", "--report: cannot write"},
        {"replay /nonexistent-input.trace --csv /nonexistent-pp5/f.csv", "--csv: cannot write"},
        {"replay /nonexistent-input.trace --plot /nonexistent-pp5/p.png", "--plot: cannot write"},
        {"replay /nonexistent-input.trace --frames-dir /nonexistent-pp5", "--frames-dir: folder"},
        {"demo --out-dir /proc/pp5-cannot-exist", "--out-dir: cannot create"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char line[600];
        int lines;
        int rc = run(dir, cases[i].args, line, sizeof line, &lines);
        CHECK_MSG(rc == PP5_EXIT_IO, "pp5 %s: exit %d, expected %d", cases[i].args, rc,
                  PP5_EXIT_IO);
        CHECK_MSG(strstr(line, cases[i].says) != NULL && lines == 1, "pp5 %s said '%s' (%d lines)",
                  cases[i].args, line, lines);
    }
}

TEST(exit_codes_map_every_status)
{
    CHECK_EQ(pp5_exit_code(PP5_OK), 0);
    CHECK_EQ(pp5_exit_code(PP5_E_NOMEM), 1);
    CHECK_EQ(pp5_exit_code(PP5_E_CONFIG), 2);
    CHECK_EQ(pp5_exit_code(PP5_E_FORMAT), 3);
    CHECK_EQ(pp5_exit_code(PP5_E_RANGE), 3);
    CHECK_EQ(pp5_exit_code(PP5_E_IO), 4);
    CHECK_EQ(pp5_exit_code(PP5_E_FIRMWARE), 5);
    CHECK_EQ(pp5_exit_code(PP5_E_MACHINE), 5);
    CHECK_EQ(pp5_exit_code(PP5_E_DEVICE), 6);
    CHECK_EQ(pp5_exit_code(PP5_E_UNSUPPORTED), 7);
    /* pp5 help lists every code */
    const char *dir = pp5_test_outdir();
    char out[1200];
    snprintf(out, sizeof out, "%s/help.txt", dir);
    REQUIRE(pp5_test_run_cli("help", out, NULL) == 0);
    char *help = pp5_test_read_file(out);
    REQUIRE(help != NULL);
    for (int code = 0; code <= 7; code++) {
        char want[24];
        snprintf(want, sizeof want, "\n  %d  ", code);
        CHECK_MSG(strstr(help, want) != NULL, "pp5 help lacks exit code %d", code);
    }
    CHECK(strstr(help, "PP5_MAX_VOXELS") && strstr(help, "PP5_MAX_LINE_BYTES"));
    free(help);
}

/* Writes the bad input files used below into dir. */
static void make_bad_inputs(const char *dir)
{
    char p[1200];
    snprintf(p, sizeof p, "%s/empty.raw", dir);
    write_text(p, "");
    snprintf(p, sizeof p, "%s/short.raw", dir);
    write_text(p, "12345");
    snprintf(p, sizeof p, "%s/huge.nrrd", dir);
    write_text(p, "NRRD0004\ntype: float\ndimension: 3\nsizes: 2048 1024 1024\nendian: little\n"
                  "encoding: raw\n\n");
    snprintf(p, sizeof p, "%s/self.nhdr", dir);
    write_text(p, "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n"
                  "data file: self.nhdr\n");
    snprintf(p, sizeof p, "%s/notnrrd.nrrd", dir);
    write_text(p, "P5 2 2 255\nxxxx");
    snprintf(p, sizeof p, "%s/short.nii", dir);
    write_text(p, "\x5c\x01");
    static const char header[] = "# pp5-trace v1\n# source: t\n# sample_rate_hz: 100\n"
                                 "# screen_px: 100 100\n# screen_mm: 300 200\n# distance_mm: 600\n"
                                 "t_ms\tx_px\ty_px\tstatus\tlabel\n";
    char text[1024];
    snprintf(text, sizeof text, "%s0\t1\t1\tok\t0\n10\tnan\t5\tok\t0\n", header);
    snprintf(p, sizeof p, "%s/nan.trace", dir);
    write_text(p, text);
    snprintf(p, sizeof p, "%s/nul.trace", dir);
    FILE *f = fopen(p, "wb");
    REQUIRE(f != NULL);
    fputs(header, f);
    fwrite("0\t1\0\t1\tok\t0\n", 1, 12, f);
    REQUIRE(fclose(f) == 0);
    snprintf(text, sizeof text, "%s0\t1\t1\tok\t0\n10\t2\t2\tok\t0\n5\t3\t3\tok\t0\n", header);
    snprintf(p, sizeof p, "%s/backwards.trace", dir);
    write_text(p, text);
    snprintf(p, sizeof p, "%s/href.asc", dir);
    write_text(p, "** CONVERTED\nSTART\t1 \tLEFT\tSAMPLES\nSAMPLES\tHREF\tLEFT\tRATE\t250\n"
                  "1\t1\t2\t3\n");
    snprintf(p, sizeof p, "%s/bad.cfg", dir);
    write_text(p, "ring.channels = 8\ngp.count = many\n");
}

TEST(bad_inputs_give_one_line_and_their_exit_code)
{
    const char *dir = pp5_test_outdir();
    make_bad_inputs(dir);
    /* @ stands for the output folder.  `names` must appear in the message. */
    static const struct { const char *what, *args, *names; int code; } cases[] = {
        {"empty raw volume", "volume info @/empty.raw --dims 2x2x2 --type u8", "empty.raw", 3},
        {"truncated raw volume", "volume info @/short.raw --dims 2x2x2 --type u8", "short.raw", 3},
        {"NRRD header of 2^31 voxels", "volume info @/huge.nrrd", "huge.nrrd", 3},
        {"NRRD naming itself as data", "volume info @/self.nhdr", "self.nhdr", 3},
        {"PNM file named .nrrd", "volume info @/notnrrd.nrrd", "notnrrd.nrrd", 3},
        {"truncated NIfTI", "volume info @/short.nii", "short.nii", 3},
        {"missing volume file", "volume info @/none.nrrd", "none.nrrd", 4},
        {"trace with a NaN gaze marked ok", "replay @/nan.trace", "nan.trace", 3},
        {"trace with a NUL byte", "replay @/nul.trace", "nul.trace", 3},
        {"trace whose time goes backwards", "replay @/backwards.trace", "backwards.trace", 3},
        {"EyeLink HREF samples", "trace import @/href.asc --out @/h.trace", "href.asc", 7},
        {"missing trace", "replay @/none.trace", "none.trace", 4},
        {"bad machine config line", "machine --config @/bad.cfg", "bad.cfg", 2},
        {"out-of-range --set", "machine --set ring.channels=0", "ring.channels", 2},
        {"unknown parameter", "machine --set ring.nothing=1", "ring.nothing", 2},
        {"raw size 0x0x0", "volume info @/empty.raw --dims 0x0x0 --type u8", "--dims", 2},
        {"raw size 100000^3", "volume info @/empty.raw --dims 100000x100000x100000 --type u8",
         "--dims", 2},
        {"unknown option (getopt's line, then the usage)", "test-pattern --frobnicate",
         "frobnicate", 2},
        {"output folder missing", "trace synth --mode pursuit --out @/no/dir/x.trace", "@/no/dir", 4},
        {"frame time budget exceeded", "test-pattern --set sim.budget_s=1e-5", "sim.budget_s", 5},
        {"no tracker device", "track record --device hid --out @/live.trace", "HID eye tracker", 6},
    };
    char table[1200];
    snprintf(table, sizeof table, "%s/bad_inputs.md", dir);
    FILE *md = fopen(table, "w");
    REQUIRE(md != NULL);
    fprintf(md, "| bad input | command | exit | message (stderr, one line) |\n|---|---|---|---|\n");
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char args[2000], names[1300], line[1000];
        const char *a = cases[i].args;
        size_t k = 0;
        for (; *a && k + 1200 < sizeof args; a++) {
            if (*a == '@')
                k += (size_t)snprintf(args + k, sizeof args - k, "%s", dir);
            else
                args[k++] = *a;
        }
        args[k] = '\0';
        const char *at = strchr(cases[i].names, '@');
        snprintf(names, sizeof names, "%s%s", at ? dir : "", at ? at + 1 : cases[i].names);
        int lines;
        int rc = run(dir, args, line, sizeof line, &lines);
        CHECK_MSG(rc == cases[i].code, "%s (pp5 %s): exit %d, expected %d: %s", cases[i].what,
                  args, rc, cases[i].code, line);
        /* An unknown option is reported by getopt and followed by the usage. */
        bool usage = strstr(cases[i].what, "unknown option") != NULL;
        CHECK_MSG((usage || (lines == 1 && strncmp(line, "pp5 ", 4) == 0)) && strstr(line, names),
                  "%s: %d lines, first '%s' (should name '%s')", cases[i].what, lines, line, names);
        /* The table shows paths relative to the test folder. */
        char shown[1000];
        const char *src = line;
        size_t o = 0, dl = strlen(dir);
        while (*src && o + 8 < sizeof shown) {
            if (strncmp(src, dir, dl) == 0) {
                o += (size_t)snprintf(shown + o, sizeof shown - o, ".");
                src += dl;
            } else {
                shown[o++] = *src == '|' ? '/' : *src;
                src++;
            }
        }
        shown[o] = '\0';
        fprintf(md, "| %s | `pp5 %s` | %d | %s |\n", cases[i].what, cases[i].args, rc, shown);
    }
    CHECK(fclose(md) == 0);
}
