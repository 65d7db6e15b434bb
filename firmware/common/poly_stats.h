/* poly_stats.h: the statistics the polygon GP program publishes through fw_api (fw_stat_*), by name, for the host and the reports.
 *
 * As vr_stats.h: the GP declares each row at start; the host reads
 * "gp.G.prog.NAME" from emu's statistics (counters as differences around a
 * frame, values as the last frame's).
 *   X(ID, "name", kind, "unit", "meaning") */
#ifndef PP5_POLY_STATS_H
#define PP5_POLY_STATS_H

#define POLY_STATS(X)                                                                            \
    X(TRIS_IN, "tris_in", FW_STAT_COUNTER, "count", "input triangles transformed")              \
    X(TRIS_SETUP, "tris_setup", FW_STAT_COUNTER, "count", "screen triangles set up (after clipping and culling)") \
    X(PAIRS_BINNED, "pairs_binned", FW_STAT_COUNTER, "count", "(triangle, region) pairs of the triangles' boxes") \
    X(PAIRS_SENT, "pairs_sent", FW_STAT_COUNTER, "count", "(triangle, region) pairs sent to a renderer")       \
    X(EDGES_SENT, "edges_sent", FW_STAT_COUNTER, "count", "QEE edge expressions sent")          \
    X(STREAM_WORDS, "stream_words", FW_STAT_COUNTER, "words", "PP instruction words sent")       \
    X(REGIONS, "regions", FW_STAT_COUNTER, "count", "region streams sent (this GP's part)")     \
    X(CYC_TRANSFORM, "cycles_transform", FW_STAT_COUNTER, "i860 cycles", "transform, light, clip, project, set-up") \
    X(CYC_SORT, "cycles_sort", FW_STAT_COUNTER, "i860 cycles", "sorting into regions")            \
    X(CYC_ENCODE, "cycles_encode", FW_STAT_COUNTER, "i860 cycles", "the PP streams of regions")  \
    X(CYC_LEVELS, "cycles_levels", FW_STAT_COUNTER, "i860 cycles", "gaze: the populated regions and the band's 2DLevels") \
    X(CYC_RESAMPLE, "cycles_resample", FW_STAT_COUNTER, "i860 cycles", "gaze: texels placed, RenderPixel of the band") \
    X(REGIONS_PLANNED, "regions_planned", FW_STAT_COUNTER, "count", "gaze: populated level tiles planned (every GP plans all)") \
    X(TEXELS_IN, "texels_in", FW_STAT_COUNTER, "count", "gaze: texels received for the band") \
    X(T_START, "t_start_ps", FW_STAT_VALUE, "ps", "last frame: FRAME_START handled")             \
    X(T_SORTED, "t_sorted_ps", FW_STAT_VALUE, "ps", "last frame: transform and sort done")       \
    X(T_DONE, "t_done_ps", FW_STAT_VALUE, "ps", "last frame: its last region stream sent")

#define POLY_STAT_ENUM(id, name, kind, unit, meaning) POLY_STAT_##id,
enum { POLY_STATS(POLY_STAT_ENUM) POLY_STAT_COUNT };
#undef POLY_STAT_ENUM

#endif
