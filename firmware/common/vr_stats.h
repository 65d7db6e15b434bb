/* vr_stats.h: the statistics the volume-rendering GP program publishes through fw_api (fw_stat_*), by name, for the host and the reports.
 *
 * One table for both sides: the GP program declares each row at start and
 * updates it as it works; the host reads "gp.G.prog.NAME" from emu's
 * statistics (emu/stats.h), never the program's memory.  Counters accumulate
 * over the run (the host takes differences around a frame); values hold the
 * figure of the last frame (emulated times of the phase boundaries, in ps
 * since power-on).
 *   X(ID, "name", kind, "unit", "meaning") */
#ifndef PP5_VR_STATS_H
#define PP5_VR_STATS_H

#define VR_STATS(X)                                                                            \
    X(RAYS, "rays", FW_STAT_COUNTER, "count", "rays started (TraceRay calls of new texels)")  \
    X(SAMPLES, "samples", FW_STAT_COUNTER, "count", "3D samples taken")                        \
    X(SKIPPED, "samples_skipped", FW_STAT_COUNTER, "count", "sample positions skipped by the octree") \
    X(SKIPS, "octree_skips", FW_STAT_COUNTER, "count", "octree skips (jumps over empty nodes)") \
    X(RAY2_SAMPLES, "demip_ray2_samples", FW_STAT_COUNTER, "count", "DEMIP: samples of ray 2 and of reading B's occluder test (in samples)") \
    X(SATURATED, "mip_rays_saturated", FW_STAT_COUNTER, "count", "MIP/DEMIP: rays whose ray 1 stopped at material 1") \
    X(OCCLUDED, "demip_rays_occluded", FW_STAT_COUNTER, "count", "DEMIP reading B: rays whose ray 2 stopped at an occluder") \
    X(TERMINATED, "mida_rays_terminated", FW_STAT_COUNTER, "count", "MIDA: rays stopped early (opacity and maximum at the threshold)") \
    X(BRICKS_FETCHED, "bricks_fetched", FW_STAT_COUNTER, "count", "bricks requested from the renderers") \
    X(BYTES_FETCHED, "bytes_fetched", FW_STAT_COUNTER, "bytes", "brick payload bytes received")  \
    X(FB_BYTES, "fb_bytes", FW_STAT_COUNTER, "bytes", "pixel bytes sent to the frame buffer")    \
    X(PP_STREAM_WORDS, "pp_stream_words", FW_STAT_COUNTER, "words", "PP shading-stream words sent") \
    X(CYC_PREP, "cycles_prep", FW_STAT_COUNTER, "i860 cycles", "2DLevel, marks, footprints")   \
    X(CYC_EXEC_BUILD, "cycles_pp_stream_build", FW_STAT_COUNTER, "i860 cycles", "building PP shading streams") \
    X(CYC_FORWARD, "cycles_forward", FW_STAT_COUNTER, "i860 cycles", "forwarding other GPs' brick requests") \
    X(CYC_RECEIVE, "cycles_receive", FW_STAT_COUNTER, "i860 cycles", "taking in received bricks") \
    X(CYC_SHADE, "cycles_shade", FW_STAT_COUNTER, "i860 cycles", "GP-side viewpoint-dependent shading") \
    X(CYC_CAST, "cycles_cast", FW_STAT_COUNTER, "i860 cycles", "ray casting")                  \
    X(CYC_RESAMPLE, "cycles_resample", FW_STAT_COUNTER, "i860 cycles", "RenderPixel and sections") \
    X(WAIT_PS, "wait_ps", FW_STAT_COUNTER, "ps", "waiting for a pass's bricks")                \
    X(CAST_PS, "cast_ps", FW_STAT_COUNTER, "ps", "casting passes")                              \
    X(SETUP_BRICKS, "setup_bricks_written", FW_STAT_COUNTER, "count", "non-empty bricks written in setup") \
    X(SETUP_VOXELS, "setup_voxels_built", FW_STAT_COUNTER, "count", "level-0 voxels built in setup") \
    X(T_START, "t_start_ps", FW_STAT_VALUE, "ps", "last frame: FRAME_START handled")           \
    X(T_PREP_DONE, "t_prep_done_ps", FW_STAT_VALUE, "ps", "last frame: first requests out")    \
    X(T_CAST_DONE, "t_cast_done_ps", FW_STAT_VALUE, "ps", "last frame: casting finished")      \
    X(T_BOUNDARY, "t_boundary_ps", FW_STAT_VALUE, "ps", "last frame: boundary rows in, resampling starts") \
    X(T_DONE, "t_done_ps", FW_STAT_VALUE, "ps", "last frame: last section sent")               \
    X(PASSES, "passes", FW_STAT_VALUE, "count", "last frame: passes (column ranges x depth segments)") \
    X(ALL_LEVEL0, "all_level0", FW_STAT_VALUE, "bool", "last frame: every own pixel at 2D level 0") \
    X(BRICKS_TOTAL, "bricks_total", FW_STAT_VALUE, "count", "bricks of the 3D mip map, empty ones included") \
    X(SLOTS_USED, "backing_slots_used", FW_STAT_VALUE, "count", "backing-store slots per PP the mip map needs") \
    X(SETUP_CYCLES, "setup_start_cycles", FW_STAT_VALUE, "i860 cycles", "GP clock when on_start finished")

#define VR_STAT_ENUM(id, name, kind, unit, meaning) VR_STAT_##id,
enum { VR_STATS(VR_STAT_ENUM) VR_STAT_COUNT };
#undef VR_STAT_ENUM

#endif
