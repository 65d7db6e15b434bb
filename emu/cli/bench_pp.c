/* bench_pp.c: `pp5 bench pp_array`: PP-array emulation throughput in renderer-cycles
 * per host second per host core (one renderer-cycle = one bit-serial instruction
 * step across all 16384 PPs of a renderer; real hardware: 40 M/s at the design clock). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "pp_array.h"
#include "pp_encode.h"
#include "pp_ref.h"
#include "registry.h"
#include "renderer.h"

static double thread_cpu_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static double wall_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

typedef enum { MIX_ADD, MIX_CMP, MIX_LOGIC, MIX_QEE, MIX_MUL, MIX_ENABLE, MIX_BS, MIX_MIX } mix_t;

/* Builds a representative stream for one op class (or the mix). */
static void build(pp_stream_t *s, mix_t kind)
{
    pp_stream_clear(s);
    for (int rep = 0; rep < 8; rep++) {
        switch (kind) {
        case MIX_ADD:
            pp_emit_add(s, 0, 32, 64, 32);
            pp_emit_sub(s, 96, 32, 64, 32);
            pp_emit_addi(s, 128, 0, 24, 12345);
            break;
        case MIX_CMP:
            pp_emit_cmp(s, PP_CMP_LTS, 0, 32, 24);
            pp_emit_cmpi(s, PP_CMP_EQ, 64, 16, 77);
            break;
        case MIX_LOGIC:
            pp_emit_and(s, 0, 32, 64, 32);
            pp_emit_copy(s, 96, 0, 32);
            pp_emit_sel(s, 128, 0, 32, 32);
            pp_emit_shr(s, 160, 96, 32, 3);
            break;
        case MIX_QEE:
            pp_emit_qee(s, 0, 24, 8, 3, -5, 7, 1000, -2000, 123456);
            pp_emit_qee(s, 32, 16, 0, 0, 0, 0, 1, 1, -100);
            break;
        case MIX_MUL:
            pp_emit_mul(s, 0, 16, 32, 48, 8, false);
            pp_emit_muli(s, 64, 20, 32, 12, true, -1234);
            break;
        case MIX_ENABLE:
            pp_emit_f_ld(s, 5);
            pp_emit_en_flag(s);
            pp_emit_en_not(s);
            pp_emit_en_all(s);
            break;
        case MIX_BS:
            pp_emit_bsstore(s, (unsigned)rep, 0);
            pp_emit_add(s, 32, 64, 96, 32);
            pp_emit_bsload(s, 128, (unsigned)rep + 8);
            pp_emit_add(s, 32, 64, 96, 32);
            break;
        case MIX_MIX:
            /* A shading-like step: QEE a value, arithmetic, compare, masked update. */
            pp_emit_qee(s, 0, 20, 4, 0, 0, 0, 3, -7, 4096);
            pp_emit_add(s, 32, 0, 64, 24);
            pp_emit_add(s, 96, 32, 64, 24);
            pp_emit_sub(s, 128, 96, 0, 24);
            pp_emit_addi(s, 32, 32, 24, 100);
            pp_emit_add(s, 160, 128, 32, 24);
            pp_emit_cmp(s, PP_CMP_LTU, 0, 96, 20);
            pp_emit_cmp(s, PP_CMP_LTS, 32, 160, 24);
            pp_emit_en_flag(s);
            pp_emit_copy(s, 64, 32, 24);
            pp_emit_en_all(s);
            break;
        }
    }
}

static const char *mix_name(mix_t k)
{
    static const char *const names[] = {"add/sub/addi", "compare", "logic/copy/sel/shift", "qee",
                                        "multiply", "enable/flag", "backing store+add",
                                        "MIX (qee+add+cmp+enable)"};
    return names[k];
}

/* Runs the stream repeatedly for at least min_s of CPU time.  The clocks are
 * read after groups of runs that take about a millisecond: reading the thread
 * CPU clock is a system call (2 us in the development VM), which a short
 * stream's run (a few us) would otherwise pay once each time, and count as
 * emulation. */
static int measure(renderer_t *r, const pp_stream_t *s, double min_s, double *cycles_per_s,
                   double *cycles_per_s_wall, uint64_t *cyc_per_stream)
{
    uint64_t cycles = 0;
    double t0 = thread_cpu_s(), w0 = wall_s(), t1 = t0;
    int reps = 0, group = 1;
    do {
        const double group_start = t1;
        for (int g = 0; g < group; g++) {
            renderer_exec_result_t res;
            if (renderer_execute(r, s->words, s->n_words, &res) != PP5_OK) {
                printf("   stream failed: %s\n", pp5_error_text());
                return -1;
            }
            /* Compute cycles are the bit-serial steps the array performs;
             * backing-store transfer time is not array work. */
            cycles += res.compute_cycles - res.stall_cycles;
            *cyc_per_stream = res.compute_cycles - res.stall_cycles;
            reps++;
        }
        t1 = thread_cpu_s();
        if (t1 - group_start < 1e-3 && group < (1 << 20))
            group *= 2;
    } while (t1 - t0 < min_s || reps < 3);
    *cycles_per_s = (double)cycles / (t1 - t0);
    *cycles_per_s_wall = (double)cycles / (wall_s() - w0);
    return 0;
}

/* The MIX stream on each narrower kernel copy the host has (what hosts without
 * the wider vectors run): AVX2 where AVX-512 is the default, then the
 * portable 16-byte kernels, whose line is there even where they are the
 * default (scripts read it); the array runs its fastest copy again after. */
static int measure_narrower_copies(renderer_t *r, pp_stream_t *s, double min_s)
{
    const pp_kernel_level_t best = r->array->kernels;
    const int first = best == PP_KERNELS_PORTABLE ? PP_KERNELS_PORTABLE : (int)best - 1;
    int rc = 0;
    for (int level = first; level >= PP_KERNELS_PORTABLE && rc == 0; level--) {
        if (pp_array_set_kernels(r->array, (pp_kernel_level_t)level) != (pp_kernel_level_t)level)
            continue;
        build(s, MIX_MIX);
        double cps, cps_wall;
        uint64_t per;
        rc = measure(r, s, min_s, &cps, &cps_wall, &per);
        if (rc == 0 && level == PP_KERNELS_PORTABLE)
            printf("   %-26s %8.2f M cycles/s  (portable 16-byte kernels, no AVX2)\n",
                   "MIX, portable kernels", cps / 1e6);
        else if (rc == 0)
            printf("   %-26s %8.2f M cycles/s  (AVX2 32-byte kernels, no AVX-512)\n",
                   "MIX, AVX2 kernels", cps / 1e6);
    }
    pp_array_set_kernels(r->array, best);
    return rc;
}

static int bench_pp_array(const pp5_bench_opts_t *o)
{
    pp_params_t p;
    pp_params_default(&p);
    renderer_t *r = calloc(1, sizeof *r);
    if (!r || renderer_init(r, 0, &p) != PP5_OK) {
        printf("   cannot create a renderer: %s\n", pp5_error_text());
        free(r);
        return 1;
    }
    /* Deterministic non-trivial memory contents. */
    uint64_t x = 88172645463325252ull;
    for (unsigned k = 0; k < PP_MEM_BITS; k++)
        for (unsigned w = 0; w < PP_PLANE_WORDS; w++) {
            x ^= x << 13; x ^= x >> 7; x ^= x << 17;
            r->array->mem[k][w] = x;
        }
    renderer_set_region(r, 384, 256);
    double min_s = o->quick ? 0.05 : 0.5;
    pp_stream_t s;
    pp_stream_init(&s);
    printf("   renderer-cycles per host CPU second (one host core; one renderer-cycle =\n"
           "   one bit step across all %u PPs; real renderer at 40 MHz: 40.0 M/s);\n"
           "   kernels: %s\n", PP_COUNT,
           pp_kernel_level_describe(r->array->kernels));
    int rc = 0;
    for (int k = MIX_ADD; k <= MIX_MIX && rc == 0; k++) {
        build(&s, (mix_t)k);
        double cps, cps_wall;
        uint64_t per;
        rc = measure(r, &s, min_s, &cps, &cps_wall, &per);
        if (rc == 0)
            printf("   %-26s %8.2f M cycles/s  (%5.1f%% of real time; %llu cycles/stream; wall %.2f M/s)\n",
                   mix_name((mix_t)k), cps / 1e6, 100.0 * cps / 40e6, (unsigned long long)per,
                   cps_wall / 1e6);
    }
    if (rc == 0)
        rc = measure_narrower_copies(r, &s, min_s);
    /* The bit-serial reference executor, all 16384 PPs, on the mix. */
    if (rc == 0) {
        unsigned *idx = malloc(PP_COUNT * sizeof *idx);
        pp_ref_t ref;
        if (idx) {
            for (unsigned i = 0; i < PP_COUNT; i++)
                idx[i] = i;
        }
        if (idx && pp_ref_init(&ref, idx, PP_COUNT) == PP5_OK) {
            build(&s, MIX_MIX);
            uint64_t cycles = 0;
            double t0 = thread_cpu_s();
            size_t pos = 0;
            pp_insn_t in;
            while (pos < s.n_words &&
                   pp_isa_decode(s.words, s.n_words, &pos, PP_MEM_BITS, &in) == PP5_OK) {
                pp_ref_exec(&ref, &in, 384, 256);
                cycles += pp_isa_cycles(&in, &p);
            }
            double dt = thread_cpu_s() - t0;
            printf("   %-26s %8.4f M cycles/s  (bit-serial reference, for contrast)\n",
                   "MIX on pp_ref", (double)cycles / dt / 1e6);
            pp_ref_free(&ref);
        }
        free(idx);
    }
    pp_stream_free(&s);
    renderer_free(r);
    free(r);
    return rc;
}

PP5_BENCH(pp_array, "PP-array emulation throughput (renderer-cycles per host second per core)",
          bench_pp_array)
