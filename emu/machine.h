/* machine.h: the whole Pixel-Planes 5: owns and wires every unit, maps node names to ring positions, runs frames.
 *
 * Ring order (1-D unidirectional ring, facts §5.1 S10; the physical order
 * is [U]): position 0 = host, 1..n_gp = GP 0..n_gp-1, then renderers
 * 0..n_r-1, then the frame buffer.  So a renderer's pixels travel
 * n_r - j hops to the FB and a GP's command to renderer j travels
 * n_gp - g + j hops.
 *
 * machine_run_setup runs the loads (HOST_LOAD, on_start) to completion (or
 * until its own budget sim.setup_budget_s is exceeded) and is not a frame.  A frame starts with the host sending FRAME_START to every
 * GP (in GP order) and runs until the event queue is empty (IDLE: all work done) or the
 * emulated-time budget sim.budget_s is exceeded (BUDGET_EXCEEDED, naming the
 * busy units) or a unit reports a firmware error (FIRMWARE_ERROR).  The frame
 * time is from the frame's start to the last activity of any unit (last ring
 * delivery, last GP or renderer busy instant).  The scheduler runs on one
 * thread; with sim.host_threads > 1, worker threads run the renderers'
 * functional steps (renderer_node.h), which cannot change any result.  No
 * host clocks or randomness in emu/. */
#ifndef PP5_MACHINE_H
#define PP5_MACHINE_H

#include <stdbool.h>
#include <stdint.h>
#include "fb.h"
#include "fw_api.h"
#include "gp.h"
#include "host.h"
#include "params.h"
#include "renderer_node.h"
#include "ring.h"
#include "pp5_sched.h"
#include "timeline.h"

#define MACHINE_MAX_FRAMES 64

#define MACHINE_MAX_CHANNELS 64   /* = the ring.channels maximum */

/* One frame: its span and the ring activity inside it (the load phase and
 * earlier frames excluded), for per-frame utilisation. */
typedef struct {
    pp5_tick_t start_ps, end_ps;
    sched_stop_t stop;
    pp5_tick_t ch_busy_ps[MACHINE_MAX_CHANNELS];
    uint64_t bytes_by_class[RING_CLASS_COUNT];
    pp5_tick_t busy_by_class[RING_CLASS_COUNT];
} machine_frame_t;

typedef struct {
    pp5_params_t params;
    fw_machine_info_t info;
    sched_t sched;
    ring_t ring;
    host_t host;
    gp_t *gp;
    renderer_node_t *rn;
    fb_t fb;
    unsigned n_gp, n_rn;
    timeline_t *tl;                   /* NULL unless machine_enable_timeline */
    rpool_t pool;                     /* workers when sim.host_threads > 1 */
    bool pool_running;
    uint32_t tid_host, tid_gp0, tid_rn0, tid_ch0, tid_fb;
    machine_frame_t frames[MACHINE_MAX_FRAMES];
    unsigned n_frames;
    pp5_tick_t setup_ps;              /* time spent in machine_run_setup */
} machine_t;

pp5_status_t machine_init(machine_t *m, const pp5_params_t *p);
void machine_free(machine_t *m);
/* Record a timeline from now on (call before loading programs). */
pp5_status_t machine_enable_timeline(machine_t *m);

/* Ring position of a node, or PP5_E_FIRMWARE for a node that does not exist. */
pp5_status_t machine_position(const machine_t *m, ring_addr_t a, unsigned *pos);
/* Send a message over the ring at time t (validates the addresses). */
pp5_status_t machine_send(machine_t *m, const ring_msg_t *msg, pp5_tick_t t);

/* Give GP `gp` a program and have the host load it (image + data) at the
 * current time; on_start runs when the load arrives. */
pp5_status_t machine_load_program(machine_t *m, unsigned gp, const fw_program_t *prog, const void *data,
                                  size_t data_bytes);

/* The same program on every GP (no data). */
pp5_status_t machine_load_all(machine_t *m, const fw_program_t *prog);

/* Run until idle without recording a frame (program loading). */
pp5_status_t machine_run_setup(machine_t *m, sched_stop_t *stop);

/* Run one frame (see above).  Returns PP5_OK when the machine went idle. */
pp5_status_t machine_run_frame(machine_t *m, sched_stop_t *stop);

/* Names of busy units at time `now` into buf. */
void machine_describe_busy(void *ctx, char *buf, size_t n);

#endif
