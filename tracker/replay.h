/* replay.h: replaying a gaze trace through a renderer with latency.
 *
 * The arithmetic (the seed paper §6 puts the 1990 system's latency at
 * 100-150 ms):
 *   - frames run back to back; frame k starts at start_k, the first one when the
 *     first sample has arrived (t_0 + tracker latency);
 *   - at start_k the newest sample whose arrival time (t_i + tracker latency)
 *     is <= start_k sets the sweet spot (held over blinks; optionally moved by
 *     a predictor to the expected display time);
 *   - the frame takes the time the frame-cost source says (the emulated machine
 *     later; a constant for now), so end_k = start_k + frame_k, start_{k+1} = end_k;
 *   - the image appears at display_k = end_k + display latency and stays until
 *     display_{k+1};
 *   - error_k = angle between the gaze used and the true gaze at display_k (the
 *     trace interpolated linearly between neighbouring valid samples);
 *   - "inside" time: while an image is shown, the time during which the true
 *     gaze lies within fullres_radius_deg of that image's sweet spot (each sample
 *     held until the next, at most 2 sample intervals; missing data counts as
 *     neither inside nor outside).
 * Modelled: fixed tracker and display latencies; per-frame times from the cost
 * source; optionally, frames waiting for the next vertical refresh (refresh_hz).
 * Not modelled: latency jitter; raster scan-out (the image appears top to
 * bottom over one refresh); a renderer that reads the gaze again mid-frame; the
 * paper's Gaussian blend between the 12° and 20° circles (only "inside the
 * full-resolution radius" is scored).
 * Angles are measured on the recording's display, where the subject's eye
 * really was; the sweet spot handed to the renderer is the same direction
 * carried to the rendered display (angles_remap), clamped onto that screen. */
#ifndef PP5_REPLAY_H
#define PP5_REPLAY_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include "gaze.h"
#include "json.h"
#include "png_io.h"
#include "predict.h"
#include "status.h"
#include "trace_file.h"

/* What one frame cost.  `want_image` is an input: false in timing-only mode,
 * so a source can skip pixel work.  `image` is optional (NULL when none); it
 * stays owned by the cost source and is valid until its next call. */
typedef struct {
    bool want_image;       /* in */
    double frame_s;        /* out: time to render this frame, > 0 */
    uint64_t rays;         /* out: rays cast (0 = not known to this source) */
    uint64_t ring_bytes;   /* out: bytes on the ring (0 = not known to this source) */
    const image8_t *image; /* out: optional */
} replay_frame_cost_t;

/* Renders (or times) one frame with the sweet spot at gaze_x, gaze_y (pixels of
 * the rendered display, origin top-left). */
typedef pp5_status_t (*replay_frame_cost_fn)(void *ctx, double gaze_x, double gaze_y,
                                             replay_frame_cost_t *out);

/* The built-in cost source: every frame takes the same time, no rays, no ring
 * traffic, no image.  NOT the emulator: a stand-in until the firmware plugs in
 * (ctx is a replay_constant_cost_t). */
typedef struct {
    double frame_s;
} replay_constant_cost_t;
pp5_status_t replay_constant_cost(void *ctx, double gaze_x, double gaze_y,
                                  replay_frame_cost_t *out);

/* Named frame-cost sources for `pp5 replay --cost NAME[:OPTIONS]`.  The
 * emulator's firmware registers one from its own file (a constructor calling
 * replay_register_cost_source), so nobody edits cmd_replay.c to plug it in.
 * "constant" (replay_constant_cost, options = frame time in ms) is built in.
 *   open:  parses `options` (may be "" ), sees the rendered display, returns ctx
 *   cost:  as replay_frame_cost_fn
 *   close: frees ctx (may be NULL)
 *   describe, report_json (optional, NULL when the source has none): the
 *          source's own figures over the frames so far, as lines (each
 *          starting with two spaces) for the replay's summary and as members
 *          of an object in its JSON report */
typedef struct {
    const char *name;
    const char *summary;
    pp5_status_t (*open)(const char *options, const gaze_geometry_t *display, void **ctx);
    replay_frame_cost_fn cost;
    void (*close)(void *ctx);
    void (*describe)(void *ctx, FILE *out);
    void (*report_json)(void *ctx, json_writer_t *j);
} replay_cost_source_t;

#define REPLAY_MAX_COST_SOURCES 16
/* Keeps the pointer (use static storage).  Later registrations of a name win. */
void replay_register_cost_source(const replay_cost_source_t *src);
const replay_cost_source_t *replay_find_cost_source(const char *name);
int replay_cost_source_count(void);
const replay_cost_source_t *replay_cost_source_at(int i);   /* NULL when out of range */

/* Defaults and where they come from (they sum to the paper's 100-150 ms):
 *   frame 1/15 s    the Stellar simulator's 15 frames/s (paper §6) [C]
 *   tracker 33 ms   one video field pair of the NAC Eye Mark's cameras: [U]
 *   display 17 ms   one 60 Hz field of the monitor: [U]
 * 33 + 67 + 17 = 117 ms, plus on average half a sample interval. */
#define REPLAY_DEFAULT_FRAME_S (1.0 / 15.0)
#define REPLAY_DEFAULT_TRACKER_LATENCY_S 0.033
#define REPLAY_DEFAULT_DISPLAY_LATENCY_S 0.017

typedef struct {
    double tracker_latency_s;
    double display_latency_s;
    double fullres_radius_deg;   /* default 6: the paper's 12° full-resolution circle (§5) */
    double gap_s;                /* a pause in the samples longer than this (default 1 s:
                                    the gaps between EyeLink recording blocks) splits the
                                    trace; a frame whose gaze comes from before such a gap
                                    and is shown after it is counted but not scored */
    double refresh_hz;           /* > 0: an image waits for the next refresh (a multiple of
                                    1/refresh_hz of trace time) before the display latency;
                                    0 (default): shown as soon as the frame ends */
    gaze_geometry_t display;     /* rendered display; default the paper's (angles.h) */
    predict_params_t predict;
    bool timing_only;            /* ask the cost source for no image */
    size_t max_frames;           /* 0 = until the trace ends */
} replay_params_t;

void replay_defaults(replay_params_t *p);

typedef struct {
    size_t index;
    double start_s, end_s, display_s, shown_until_s;  /* trace time, seconds */
    double sample_t_s;        /* time of the newest arrived sample (NaN if none yet) */
    double used_x_px, used_y_px;   /* gaze used, recording pixels (after prediction) */
    double spot_x_px, spot_y_px;   /* sweet spot handed to the renderer, display pixels */
    double true_x_px, true_y_px;   /* true gaze at display time, recording pixels (NaN: no data) */
    double error_deg;              /* NaN when either gaze is unknown, or after_gap */
    bool after_gap;                /* gaze from before a recording gap (not scored) */
    double inside_s, valid_s;      /* over [display_s, shown_until_s) */
    double frame_s;
    uint64_t rays, ring_bytes;
} replay_frame_t;

typedef struct {
    size_t frames;
    size_t frames_with_error;      /* frames where the error could be measured */
    size_t frames_after_gap;       /* frames not scored: gaze from before a recording gap */
    double trace_s;                /* span replayed */
    double valid_display_s;        /* display time with true gaze known */
    double inside_fraction;        /* inside time / valid display time */
    double mean_error_deg, p95_error_deg, max_error_deg;
    double frames_per_s;
    double mean_frame_s;
    double mean_latency_s;         /* display time - time of the sample used, over the
                                      frames whose error is measurable */
    uint64_t rays, ring_bytes;
} replay_summary_t;

typedef struct {
    replay_frame_t *frames;
    size_t count, capacity;
    replay_summary_t summary;
} replay_result_t;

void replay_result_free(replay_result_t *r);

/* Replays `trace` (samples in time order; at least 2) with frame costs from
 * `cost`.  `on_frame` (optional) sees each frame's image while it is valid. */
typedef pp5_status_t (*replay_image_fn)(void *ctx, const replay_frame_t *f, const image8_t *img);
pp5_status_t replay_run(const trace_t *trace, const replay_params_t *p, replay_frame_cost_fn cost,
                        void *cost_ctx, replay_image_fn on_image, void *image_ctx,
                        replay_result_t *out);

/* Percentile by nearest rank (q in 0..1) of n values; sorts a copy. */
double replay_percentile(const double *v, size_t n, double q);

#endif
