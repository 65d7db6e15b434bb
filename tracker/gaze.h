/* gaze.h: the gaze sample type, screen geometry, and gaze_source_t, the one
 * interface behind which recorded traces, synthetic traces and live devices
 * (tracker/hid_*.c, tracker/polhemus*.c) deliver samples to replay and the viewer.
 *
 * Time is integer nanoseconds (STYLE.md L3: integer time, unit in the name):
 * exact for every tracker we read (EyeLink 2000 Hz steps of 0.5 ms, GazeCom and
 * Tobii microseconds, Pupil Neon nanoseconds) and converted to the emulator's
 * picoseconds by * 1000 without rounding. */
#ifndef PP5_GAZE_H
#define PP5_GAZE_H

#include <stdbool.h>
#include <math.h>
#include <stdint.h>
#include <string.h>
#include "status.h"

/* Event labels, the same codes as gaze-trace v1 (shared/data/gaze/PROVENANCE.md). */
typedef enum {
    GAZE_LABEL_NONE = 0,
    GAZE_LABEL_FIXATION = 1,
    GAZE_LABEL_SACCADE = 2,
    GAZE_LABEL_PSO = 3,       /* post-saccadic oscillation */
    GAZE_LABEL_PURSUIT = 4,
    GAZE_LABEL_BLINK = 5,
    GAZE_LABEL_NOISE = 6      /* undefined / noise */
} gaze_label_t;
#define GAZE_LABEL_MAX 6

/* Sample flags. */
#define GAZE_FLAG_VALID 0x1u  /* x_px, y_px hold a gaze point (else they are NaN) */
#define GAZE_FLAG_BLINK 0x2u  /* no gaze because the eye was closed (a blink), not track loss */
#define GAZE_FLAG_HEAD  0x4u  /* head pose present */
#define GAZE_FLAG_HAND  0x8u  /* hand pose present */

/* A 6-degree-of-freedom pose as a Polhemus tracker reports it (the 1990 system
 * had one on the helmet and one in the hand, paper §6): position in mm in the
 * tracker's frame, orientation as azimuth, elevation, roll in degrees. */
typedef struct {
    double pos_mm[3];
    double azimuth_deg, elevation_deg, roll_deg;
} gaze_pose_t;

typedef struct {
    int64_t t_ns;          /* time of the sample, ns since the start of the trace/session */
    double x_px, y_px;     /* gaze on the screen, pixels, origin top-left, x right, y down;
                              NaN when !(flags & GAZE_FLAG_VALID); may lie off the screen */
    uint32_t flags;        /* GAZE_FLAG_* */
    int label;             /* gaze_label_t; GAZE_LABEL_NONE when unknown */
    gaze_pose_t head;      /* meaningful only with GAZE_FLAG_HEAD */
    gaze_pose_t hand;      /* meaningful only with GAZE_FLAG_HAND */
} gaze_sample_t;

/* The display a trace's pixels refer to.  Unknown physical values are 0; then
 * px_per_deg (pixels per degree at the screen centre, e.g. EyeLink's END ... RES)
 * may stand in for width_mm/distance_mm (tracker/angles.h does the arithmetic). */
typedef struct {
    int width_px, height_px;
    double width_mm, height_mm;   /* size of the area width_px x height_px cover; 0 = unknown */
    double distance_mm;           /* eye to screen; 0 = unknown */
    double px_per_deg;            /* 0 = unknown */
} gaze_geometry_t;

/* A sample with all fields set to "no data" at time t_ns. */
static inline void gaze_sample_invalid(gaze_sample_t *s, int64_t t_ns)
{
    memset(s, 0, sizeof *s);
    s->t_ns = t_ns;
    s->x_px = NAN;
    s->y_px = NAN;
}

/* ---- gaze_source_t: a stream of samples in time order ----
 *
 * next_sample fills *out and sets *got = true, or sets *got = false at the end
 * of the stream (a finished trace; a live device that was closed).  Errors
 * (malformed data, device disconnect, timeout) return a status with
 * pp5_error_text() set; a live source must never block longer than the timeout
 * it was opened with.  Samples come out with non-decreasing t_ns.
 * close releases everything, including the gaze_source_t itself when the
 * implementation allocated it; it accepts NULL. */
typedef struct gaze_source gaze_source_t;

typedef struct {
    pp5_status_t (*next_sample)(gaze_source_t *src, gaze_sample_t *out, bool *got);
    void (*close)(gaze_source_t *src);
} gaze_source_ops_t;

struct gaze_source {
    const gaze_source_ops_t *ops;
    void *impl;                 /* the implementation's state */
    const char *name;           /* for messages: a path or a device name */
    double sample_rate_hz;      /* nominal; 0 when unknown */
    gaze_geometry_t geometry;   /* the screen the samples' pixels refer to */
};

static inline pp5_status_t gaze_source_next(gaze_source_t *src, gaze_sample_t *out, bool *got)
{
    return src->ops->next_sample(src, out, got);
}

static inline void gaze_source_close(gaze_source_t *src)
{
    if (src && src->ops && src->ops->close)
        src->ops->close(src);
}

#endif
