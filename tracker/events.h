/* events.h: gaze event detection: fixations, saccades, post-saccadic
 * oscillations (PSO), blinks and gaps, from the samples of a trace.
 *
 * Three methods (the algorithm, its source and what pp5 changed are written
 * at the top of each file and in tracker/ARCHITECTURE.md):
 *   ivt       velocity threshold (Salvucci & Goldberg 2000, I-VT): events_ivt.c
 *   idt       dispersion threshold (Salvucci & Goldberg 2000, I-DT): events_idt.c
 *   adaptive  data-driven velocity thresholds of Nystrom & Holmqvist 2010
 *             (BRM 42:188-204), with their PSO ("glissade") detection:
 *             events_adaptive.c
 * What every method shares (events.c): the signal (per-axis visual angle,
 * gaze-facts.md §0, and the central-difference speed of gaze-facts §1), the
 * effective sample rate (the median interval: three Lund files say 500 Hz and
 * step 5 ms), and the post-processing: runs of missing samples become blinks
 * (80-900 ms, the range studies accept, gaze-facts §2 [S24]) or gaps; a
 * saccade, PSO or noise sample touching a blink joins it (the lid's apparent
 * movement: "blinks are always embedded in saccades", gaze-facts §2 [S22]);
 * fixations shorter than min_fixation_s become "undefined".  Blink flags in
 * the trace are NOT used: in imported recordings they come from the labels
 * (import_shared.c), which would leak a coder's answer into the detector.
 * Smooth pursuit is not detected (labelled fixation or saccade). */
#ifndef PP5_EVENTS_H
#define PP5_EVENTS_H

#include <stdbool.h>
#include <stddef.h>
#include "gaze.h"
#include "status.h"
#include "trace_file.h"

typedef enum { EVENTS_IVT, EVENTS_IDT, EVENTS_ADAPTIVE } events_method_t;

/* Event classes: the gaze labels (gaze.h) plus one for lost data that is not
 * a blink.  A gap's samples carry GAZE_LABEL_NONE in a label sequence. */
#define EVENTS_GAP 7
#define EVENTS_CLASS_MAX 7

typedef struct {
    events_method_t method;
    double ivt_threshold_dps;      /* ivt: speed above this is saccade */
    double idt_dispersion_deg;     /* idt: (max-min x) + (max-min y) of a fixation window */
    double idt_window_s;           /* idt: shortest fixation window */
    /* adaptive, Nystrom & Holmqvist 2010 §"Method"; defaults are the paper's */
    double nh_filter_s;            /* Savitzky-Golay window: 2 x min saccade (20 ms) */
    double nh_peak_start_dps;      /* first guess of the peak threshold (100) */
    double nh_peak_sigmas;         /* peak threshold = mean + 6 sd of slower samples */
    double nh_onset_sigmas;        /* onset threshold = mean + 3 sd */
    double nh_offset_weight;       /* offset threshold = 0.7 onset + 0.3 local noise */
    double nh_noise_window_s;      /* local noise: the 40 ms before a saccade */
    double nh_pso_window_s;        /* PSOs are looked for in the 40 ms after a saccade */
    double nh_max_speed_dps;       /* faster is noise (1000 deg/s) */
    double nh_max_accel_dps2;      /* higher acceleration is noise (100000 deg/s^2) */
    bool nh_robust;                /* median and 1.4826 MAD for mean and sd (events_adaptive.c) */
    /* every method */
    double min_saccade_s;          /* shorter saccades are dropped (10 ms) */
    double min_fixation_s;         /* shorter fixations are "undefined" (40 ms) */
    double pso_min_rate_hz;        /* no PSO detection below this rate (400 Hz) */
    double blink_min_s, blink_max_s;   /* missing runs in this range are blinks */
    double edge_search_s;          /* how far a saccade edge may move to where the speed
                                      leaves the fixation noise (20 ms; 0 = off) */
    double edge_noise_sigmas;      /* that noise: mean + this many sd of the fixation
                                      samples' speeds */
} events_params_t;

typedef struct {
    int cls;                       /* gaze label code, or EVENTS_GAP */
    size_t first, last;            /* sample indices in the trace, inclusive */
    double onset_s, duration_s;    /* trace time; the event lasts until the next sample */
    double start_x_px, start_y_px, end_x_px, end_y_px;   /* NaN for blinks and gaps */
    double amplitude_deg;          /* start to end; NaN for blinks and gaps */
    double peak_velocity_dps;      /* highest sample speed inside; NaN if none */
} gaze_event_t;

typedef struct {
    gaze_event_t *events;
    size_t count, capacity;
} events_list_t;

/* What a detection found, with the thresholds it settled on. */
typedef struct {
    int *labels;                   /* one gaze label per sample (gaps: GAZE_LABEL_NONE) */
    size_t n;
    events_list_t list;
    double rate_hz;                /* effective rate used (median interval) */
    double peak_threshold_dps;     /* adaptive: final thresholds; ivt: its threshold */
    double onset_threshold_dps;
    bool pso_detected;             /* the rate allowed PSO detection */
} events_result_t;

void events_defaults(events_params_t *p, events_method_t method);
bool events_method_parse(const char *name, events_method_t *m);
const char *events_method_name(events_method_t m);
/* "fixation", "saccade", "pso", "pursuit", "blink", "undefined", "gap"; NULL
 * for codes without an event (0). */
const char *events_class_name(int cls);
/* Inverse of events_class_name; false if unknown. */
bool events_class_parse(const char *name, int *cls);

pp5_status_t events_detect(const trace_t *t, const events_params_t *p, events_result_t *out);
void events_result_free(events_result_t *r);

/* Events from any label sequence (a coder's, the generator's truth, a
 * detector's): runs of one label, with positions and speeds from the trace.
 * Label 0 on a missing sample becomes a gap; label 0 on a valid one, nothing. */
pp5_status_t events_from_labels(const trace_t *t, const int *labels, events_list_t *out);
void events_list_free(events_list_t *l);
pp5_status_t events_list_append(events_list_t *l, const gaze_event_t *e);

/* BIDS-style events.tsv (one header line; onset, duration, trial_type, then
 * sample, n_samples, amplitude, peak_velocity, start_x, start_y, end_x, end_y;
 * "n/a" for no value) and its JSON sidecar (column descriptions and units, the
 * method and its parameters; NULL params: no method).  The reader parses and
 * validates the whole file before it hands over anything. */
pp5_status_t events_write_tsv(const char *path, const events_list_t *l);
pp5_status_t events_write_sidecar(const char *path, const events_params_t *p,
                                  const events_result_t *r, const char *source);
pp5_status_t events_read_tsv(const char *path, events_list_t *out);
pp5_status_t events_parse_tsv(const char *text, size_t len, const char *name,
                              events_list_t *out);

#endif
