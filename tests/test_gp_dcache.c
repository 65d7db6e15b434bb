/* test_gp_dcache.c: the i860 data-cache model (hand-counted misses on strides, working sets larger than the cache, write-backs, invalidation), emulated addresses and ring delivery. */
#include <string.h>

#include "gp_addr.h"
#include "gp_cost.h"
#include "gp_dcache.h"
#include "harness.h"
#include "machine.h"

/* The default geometry: 8 KB, 32-byte lines, 2 ways = 128 sets; one way
 * spans 4 KB, so addresses 4 KB apart share a set. */
static void cache_default(gp_dcache_t *c)
{
    REQUIRE(gp_dcache_init(c, 8192, 32, 2) == PP5_OK);
    CHECK_EQ(c->sets, 128);
}

/* Reads [base, base + bytes) in steps of `stride` bytes, 4 bytes each. */
static void sweep(gp_dcache_t *c, uint64_t base, uint64_t bytes, uint64_t stride, bool store,
                  fw_ops_t *o)
{
    for (uint64_t a = base; a < base + bytes; a += stride)
        gp_dcache_access(c, a, 4, store, o);
}

TEST(dcache_sequential_words_miss_once_per_line)
{
    gp_dcache_t c;
    cache_default(&c);
    fw_ops_t o = {0};
    sweep(&c, 0, 1024, 4, false, &o);
    /* 256 word reads over 1024 / 32 = 32 lines: 32 misses, 224 hits. */
    CHECK_EQ(o.dcache_misses, 32);
    CHECK_EQ(o.dcache_hits, 224);
    CHECK_EQ(o.dcache_writebacks, 0);
    /* Again: all 256 hit (1 KB fits). */
    memset(&o, 0, sizeof o);
    sweep(&c, 0, 1024, 4, false, &o);
    CHECK_EQ(o.dcache_misses, 0);
    CHECK_EQ(o.dcache_hits, 256);
    gp_dcache_free(&c);
}

TEST(dcache_line_stride_over_exactly_the_cache_then_hits)
{
    gp_dcache_t c;
    cache_default(&c);
    fw_ops_t o = {0};
    /* One read per line over 8 KB: 256 lines, 2 per set: all miss, all stay. */
    sweep(&c, 0, 8192, 32, false, &o);
    CHECK_EQ(o.dcache_misses, 256);
    CHECK_EQ(gp_dcache_lines_present(&c), 256);
    memset(&o, 0, sizeof o);
    sweep(&c, 0, 8192, 32, false, &o);
    CHECK_EQ(o.dcache_hits, 256);
    CHECK_EQ(o.dcache_misses, 0);
    gp_dcache_free(&c);
}

TEST(dcache_working_set_larger_than_the_cache_thrashes_under_lru)
{
    gp_dcache_t c;
    cache_default(&c);
    fw_ops_t o = {0};
    /* 12 KB by lines, twice: every set sees lines A B C A B C (4 KB apart);
     * with 2 ways and LRU each access evicts the line needed next: the second
     * pass misses as often as the first, 384 each. */
    sweep(&c, 0, 12288, 32, false, &o);
    CHECK_EQ(o.dcache_misses, 384);
    sweep(&c, 0, 12288, 32, false, &o);
    CHECK_EQ(o.dcache_misses, 768);
    CHECK_EQ(o.dcache_hits, 0);
    gp_dcache_free(&c);
}

TEST(dcache_way_stride_conflicts_and_associativity)
{
    gp_dcache_t c;
    cache_default(&c);
    fw_ops_t o = {0};
    /* Two addresses 4 KB apart (one set) alternate: 2 misses, then hits. */
    for (int i = 0; i < 10; i++)
        gp_dcache_access(&c, (uint64_t)(i & 1) * 4096, 4, false, &o);
    CHECK_EQ(o.dcache_misses, 2);
    CHECK_EQ(o.dcache_hits, 8);
    /* Three in the same set, round robin: LRU misses every one of the 9. */
    memset(&o, 0, sizeof o);
    gp_dcache_reset(&c);
    for (int i = 0; i < 9; i++)
        gp_dcache_access(&c, (uint64_t)(i % 3) * 4096, 4, false, &o);
    CHECK_EQ(o.dcache_misses, 9);
    gp_dcache_free(&c);
    /* Direct-mapped 8 KB (256 sets): the two addresses 8 KB apart conflict on
     * every access; 4 KB apart they do not. */
    REQUIRE(gp_dcache_init(&c, 8192, 32, 1) == PP5_OK);
    memset(&o, 0, sizeof o);
    for (int i = 0; i < 10; i++)
        gp_dcache_access(&c, (uint64_t)(i & 1) * 8192, 4, false, &o);
    CHECK_EQ(o.dcache_misses, 10);
    memset(&o, 0, sizeof o);
    for (int i = 0; i < 10; i++)
        gp_dcache_access(&c, (uint64_t)(i & 1) * 4096 + 32768, 4, false, &o);
    CHECK_EQ(o.dcache_misses, 2);
    gp_dcache_free(&c);
}

TEST(dcache_lru_keeps_the_recent_line)
{
    gp_dcache_t c;
    cache_default(&c);
    fw_ops_t o = {0};
    /* A B A C: C evicts B (least recent), so A hits and B then misses. */
    uint64_t A = 0, B = 4096, C = 8192;
    gp_dcache_access(&c, A, 4, false, &o);
    gp_dcache_access(&c, B, 4, false, &o);
    gp_dcache_access(&c, A, 4, false, &o);
    gp_dcache_access(&c, C, 4, false, &o);
    CHECK_EQ(o.dcache_misses, 3);
    gp_dcache_access(&c, A, 4, false, &o);
    CHECK_EQ(o.dcache_hits, 2);
    gp_dcache_access(&c, B, 4, false, &o);
    CHECK_EQ(o.dcache_misses, 4);
    gp_dcache_free(&c);
}

TEST(dcache_stores_allocate_and_write_back_when_evicted)
{
    gp_dcache_t c;
    cache_default(&c);
    fw_ops_t o = {0};
    /* Store every word of 8 KB: 256 misses (write-allocate), 256 lines dirty. */
    sweep(&c, 0, 8192, 4, true, &o);
    CHECK_EQ(o.dcache_misses, 256);
    CHECK_EQ(o.dcache_hits, 2048 - 256);
    CHECK_EQ(o.dcache_writebacks, 0);
    /* Reading another 8 KB evicts all of them: 256 write-backs. */
    memset(&o, 0, sizeof o);
    sweep(&c, 8192, 8192, 32, false, &o);
    CHECK_EQ(o.dcache_misses, 256);
    CHECK_EQ(o.dcache_writebacks, 256);
    /* Those were clean: evicting them again writes nothing back. */
    memset(&o, 0, sizeof o);
    sweep(&c, 0, 8192, 32, false, &o);
    CHECK_EQ(o.dcache_writebacks, 0);
    gp_dcache_free(&c);
}

TEST(dcache_access_across_a_line_boundary_looks_up_both)
{
    gp_dcache_t c;
    cache_default(&c);
    fw_ops_t o = {0};
    gp_dcache_access(&c, 28, 8, false, &o);      /* bytes 28..35: lines 0 and 1 */
    CHECK_EQ(o.dcache_misses, 2);
    gp_dcache_access(&c, 0, 64, false, &o);      /* the same two lines */
    CHECK_EQ(o.dcache_hits, 2);
    gp_dcache_free(&c);
}

TEST(dcache_invalidate_drops_lines_without_write_back)
{
    gp_dcache_t c;
    cache_default(&c);
    fw_ops_t o = {0};
    sweep(&c, 0, 2048, 32, true, &o);            /* 64 dirty lines */
    gp_dcache_invalidate(&c, 0, 1024);           /* the first 32 go */
    CHECK_EQ(gp_dcache_lines_present(&c), 32);
    memset(&o, 0, sizeof o);
    sweep(&c, 0, 2048, 32, false, &o);
    CHECK_EQ(o.dcache_misses, 32);
    CHECK_EQ(o.dcache_hits, 32);
    CHECK_EQ(o.dcache_writebacks, 0);            /* nothing was evicted */
    /* A range longer than the cache (the scan path) drops everything in it. */
    gp_dcache_invalidate(&c, 0, 65536);
    CHECK_EQ(gp_dcache_lines_present(&c), 0);
    gp_dcache_free(&c);
}

TEST(dcache_rejects_geometry_that_is_not_whole_sets)
{
    gp_dcache_t c;
    CHECK_EQ(gp_dcache_init(&c, 8192, 24, 2), PP5_E_CONFIG);   /* line not a power of two */
    CHECK_EQ(gp_dcache_init(&c, 8192, 32, 3), PP5_E_CONFIG);   /* 85.3 sets */
    pp5_params_t p;
    pp5_params_default(&p);
    CHECK_EQ(pp5_params_set(&p, "i860.dcache_ways", "3"), PP5_E_CONFIG);
    CHECK(strstr(pp5_error_text(), "i860.dcache_ways") != NULL);
    CHECK_EQ(pp5_params_set(&p, "i860.dcache_line_bytes", "48"), PP5_E_CONFIG);
    CHECK_EQ(pp5_params_set(&p, "i860.dcache_ways", "4"), PP5_OK);
}

TEST(gp_addr_first_fit_is_deterministic_and_merges)
{
    gp_addr_map_t a;
    gp_addr_init(&a);
    uint64_t x, y, z, w;
    REQUIRE(gp_addr_alloc(&a, 100, &x) == PP5_OK);   /* [0, 128) */
    REQUIRE(gp_addr_alloc(&a, 50, &y) == PP5_OK);    /* [128, 192) */
    CHECK_EQ(x, 0);
    CHECK_EQ(y, 128);
    REQUIRE(gp_addr_release(&a, x, 100) == PP5_OK);
    REQUIRE(gp_addr_alloc(&a, 64, &z) == PP5_OK);    /* first fit: the hole at 0 */
    CHECK_EQ(z, 0);
    REQUIRE(gp_addr_alloc(&a, 100, &w) == PP5_OK);   /* [64, 128) is too small: the top */
    CHECK_EQ(w, 192);
    CHECK_EQ(gp_addr_top_peak(&a), 320);
    /* Freeing out of order merges the holes back into nothing. */
    REQUIRE(gp_addr_release(&a, y, 50) == PP5_OK);
    REQUIRE(gp_addr_release(&a, w, 100) == PP5_OK);
    REQUIRE(gp_addr_release(&a, z, 64) == PP5_OK);
    CHECK_EQ(a.n_free, 0);
    CHECK_EQ(a.top, 0);
    CHECK(gp_addr_release(&a, 0, 64) != PP5_OK);     /* not allocated */
    gp_addr_free_map(&a);
}

/* ---- through the firmware API on a machine ---- */

static fw_ops_t g_dma, g_pio;
static int g_ran;

/* GP 0: two blocks, declared accesses, a deposit, and one bad declaration. */
static fw_status_t cache_prog_start(gp_t *gp)
{
    g_ran++;
    uint8_t *a = fw_alloc(gp, 4096), *b = fw_alloc(gp, 4096);
    if (!a || !b)
        return FW_ERROR;
    fw_ops_t o = {0};
    for (size_t off = 0; off < 4096; off += 32)
        fw_dcache_access(gp, &o, a, off, 4, 0);                  /* 128 misses */
    for (size_t off = 0; off < 4096; off += 32)
        fw_dcache_access(gp, &o, a, off, 4, 0);                  /* 128 hits */
    /* The ring port writes b: under DMA its lines leave the cache, under
     * programmed I/O the GP stores every word through it. */
    for (size_t off = 0; off < 4096; off += 32)
        fw_dcache_access(gp, &o, b, off, 4, 0);                  /* 128 misses; now a+b = 8 KB */
    fw_ops_t d = {0};
    fw_rx_deposit(gp, &d, b, 0, 4096);
    fw_dcache_access(gp, &d, a, 0, 4, 0);
    fw_dcache_access(gp, &d, b, 0, 4, 0);
    if (fw_gp_index(gp) == 0)
        g_dma = d;
    else
        g_pio = d;
    fw_charge(gp, &o);
    return FW_OK;
}

static const fw_program_t cache_prog = {"cache", 1024, cache_prog_start, NULL};

TEST(gp_rx_deposit_dma_and_programmed_io_by_hand)
{
    pp5_params_t p;
    pp5_params_default(&p);
    p.n_gp = 2;
    p.n_renderers = 1;
    p.fb_width = 128;
    p.fb_height = 128;
    machine_t m;
    REQUIRE(machine_init(&m, &p) == PP5_OK);
    m.gp[1].rx_dma = false;                 /* GP 1: programmed I/O */
    REQUIRE(machine_load_program(&m, 0, &cache_prog, NULL, 0) == PP5_OK);
    REQUIRE(machine_load_program(&m, 1, &cache_prog, NULL, 0) == PP5_OK);
    g_ran = 0;
    sched_stop_t why;
    REQUIRE(machine_run_setup(&m, &why) == PP5_OK);
    CHECK_EQ(g_ran, 2);
    /* The program's own sweeps: 256 misses and 128 hits on either GP. */
    CHECK_EQ(m.gp[0].ops_total.dcache_misses, 256);
    CHECK_EQ(m.gp[0].ops_total.dcache_hits, 128);
    /* DMA: no instructions; b's 128 lines are dropped, so a's line hits and
     * b's misses. */
    CHECK_EQ(g_dma.loads + g_dma.stores + g_dma.ext_bytes, 0);
    CHECK_EQ(g_dma.dcache_hits, 1);
    CHECK_EQ(g_dma.dcache_misses, 1);
    /* Programmed I/O: 1024 words, each a port load (4 bytes over the bus)
     * and a store; 256 loop tests; the deposit is one declared range, looked
     * up line by line: b's 128 lines are present (128 hits), and then a's and
     * b's lines both hit. */
    CHECK_EQ(g_pio.loads, 1024);
    CHECK_EQ(g_pio.stores, 1024);
    CHECK_EQ(g_pio.int_ops, 256);
    CHECK_EQ(g_pio.branches, 256);
    CHECK_EQ(g_pio.ext_bytes, 4096);
    CHECK_EQ(g_pio.dcache_misses, 0);
    CHECK_EQ(g_pio.dcache_hits, 128 + 2);
    machine_free(&m);
}

static fw_status_t bad_decl_start(gp_t *gp)
{
    uint8_t *a = fw_alloc(gp, 256);
    fw_ops_t o = {0};
    if (!a)
        return FW_ERROR;
    fw_dcache_access(gp, &o, a, 250, 8, 0);     /* runs past the block */
    return FW_OK;
}

static const fw_program_t bad_decl_prog = {"bad-decl", 1024, bad_decl_start, NULL};

TEST(gp_dcache_access_outside_its_block_is_a_firmware_error)
{
    pp5_params_t p;
    pp5_params_default(&p);
    p.n_gp = 1;
    p.n_renderers = 1;
    p.fb_width = 128;
    p.fb_height = 128;
    machine_t m;
    REQUIRE(machine_init(&m, &p) == PP5_OK);
    REQUIRE(machine_load_program(&m, 0, &bad_decl_prog, NULL, 0) == PP5_OK);
    sched_stop_t why;
    CHECK_EQ(machine_run_setup(&m, &why), PP5_E_FIRMWARE);
    CHECK(strstr(pp5_error_text(), "fw_dcache_access") != NULL);
    CHECK(strstr(pp5_error_text(), "outside the 256-byte block") != NULL);
    machine_free(&m);
}
