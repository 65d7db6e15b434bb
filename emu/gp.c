/* gp.c: one graphics processor: inbox, run-to-completion callbacks, local clock and memory. */
#include "gp.h"
#include "ring_payload.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>


pp5_status_t gp_init(gp_t *gp, unsigned index, const pp5_params_t *p, const fw_machine_info_t *info,
                     sched_t *sched, gp_send_fn send, void *send_ctx)
{
    memset(gp, 0, sizeof *gp);
    gp->index = index;
    gp->info = *info;
    gp_cost_init(&gp->cost, p);
    gp->period_ps = clock_period_ps(p->gp_clock_hz);
    gp->send_cycles = p->gp_send_cycles;
    gp->rx_msg_cycles = p->gp_rx_msg_cycles;
    gp->rx_dma = p->gp_rx_dma != 0;
    gp->mem_capacity_bytes = p->gp_local_mem_bytes;
    gp->sched = sched;
    gp->send = send;
    gp->send_ctx = send_ctx;
    gp_addr_init(&gp->addr);
    return gp_dcache_init(&gp->dcache, p->i860_dcache_bytes, p->i860_dcache_line_bytes,
                          p->i860_dcache_ways);
}

static void gp_drop_inbox(gp_t *gp)
{
    while (gp->inbox_count > 0) {
        ring_payload_free(gp->inbox[gp->inbox_head].payload_copy);
        gp->inbox_head = (gp->inbox_head + 1) % gp->inbox_cap;
        gp->inbox_count--;
    }
}

void gp_free(gp_t *gp)
{
    gp_drop_inbox(gp);
    free(gp->inbox);
    gp_block_t *lists[2] = {gp->blocks, gp->spare};
    for (int i = 0; i < 2; i++) {
        gp_block_t *b = lists[i];
        while (b) {
            gp_block_t *next = b->next;
            free(b->host_base);
            b = next;
        }
    }
    gp_dcache_free(&gp->dcache);
    gp_addr_free_map(&gp->addr);
    memset(gp, 0, sizeof *gp);
}

void gp_set_program(gp_t *gp, const fw_program_t *prog)
{
    gp->prog = prog;
}

void gp_charge_cycles(gp_t *gp, uint64_t cycles)
{
    gp->local_ps += clock_cycles_ps(cycles, gp->period_ps);
    gp->busy_cycles += cycles;
}

bool gp_busy(const gp_t *gp, pp5_tick_t now)
{
    return gp->local_ps > now || gp->inbox_count > 0 || gp->run_scheduled;
}

/* ---- running callbacks ---- */

static pp5_status_t gp_run_event(void *ctx, uint64_t arg, pp5_tick_t now);

static pp5_status_t gp_schedule(gp_t *gp, pp5_tick_t now)
{
    if (gp->run_scheduled) {
        return PP5_OK;
    }
    gp->run_scheduled = true;
    return sched_at(gp->sched, tick_max(now, gp->local_ps), SCHED_PRIO_UNIT, gp_run_event, gp, 0);
}

static pp5_status_t gp_error_status(gp_t *gp, const char *where)
{
    return pp5_fail(PP5_E_FIRMWARE, "GP %u (%s) %s: %s", gp->index,
                    gp->prog ? gp->prog->name : "no program", where,
                    gp->error[0] ? gp->error : "callback returned an error without fw_fail");
}

static pp5_status_t gp_run_event(void *ctx, uint64_t arg, pp5_tick_t now)
{
    gp_t *gp = ctx;
    gp->run_scheduled = false;
    if (gp->local_ps < now) {
        gp->local_ps = now;       /* idle until now */
    }
    pp5_tick_t start = gp->local_ps;
    const char *what;
    fw_status_t rc = FW_OK;
    if (gp->loaded && !gp->started) {
        gp->started = true;
        what = "on_start";
        if (gp->prog && gp->prog->on_start) {
            rc = gp->prog->on_start(gp);
        }
    } else if (gp->inbox_count > 0) {
        gp_inbox_item_t item = gp->inbox[gp->inbox_head];
        gp->inbox_head = (gp->inbox_head + 1) % gp->inbox_cap;
        gp->inbox_count--;
        what = ring_msg_kind_name(item.msg.kind);
        gp_charge_cycles(gp, gp->rx_msg_cycles);   /* [U] taking it off the port */
        gp->handling_payload = item.payload_copy;
        if (gp->prog && gp->prog->on_message) {
            rc = gp->prog->on_message(gp, &item.msg);
        }
        ring_payload_free(gp->handling_payload);   /* unless the program kept it */
        gp->handling_payload = NULL;
    } else {
        return PP5_OK;
    }
    gp->busy_ps += gp->local_ps - start;
    if (gp->trace && gp->local_ps > start) {
        gp->trace(gp->trace_ctx, gp, what, start, gp->local_ps);
    }
    if (rc != FW_OK || gp->fw_error) {
        return gp_error_status(gp, what);
    }
    if (gp->inbox_count > 0) {
        return gp_schedule(gp, gp->local_ps);
    }
    return PP5_OK;
}

static pp5_status_t gp_host_load(gp_t *gp, const ring_msg_t *msg, pp5_tick_t now)
{
    if (gp->loaded) {
        return pp5_fail(PP5_E_FIRMWARE, "GP %u: loaded twice", gp->index);
    }
    size_t image = msg->args[0];
    if (image > msg->payload_bytes) {
        return pp5_fail(PP5_E_FIRMWARE, "GP %u: HOST_LOAD image of %zu bytes in a %zu-byte message",
                        gp->index, image, msg->payload_bytes);
    }
    /* The program image and its data both live in local memory. */
    if (!fw_alloc(gp, image)) {
        return gp_error_status(gp, "HOST_LOAD (program image)");
    }
    size_t data_bytes = msg->payload_bytes - image;
    if (data_bytes > 0) {
        void *data = fw_alloc(gp, data_bytes);
        if (!data) {
            return gp_error_status(gp, "HOST_LOAD (data)");
        }
        memcpy(data, (const char *)msg->payload + image, data_bytes);
        gp->host_data = data;
    }
    gp->host_data_bytes = data_bytes;
    gp->loaded = true;
    return gp_schedule(gp, now);
}

pp5_status_t gp_deliver_owned(gp_t *gp, const ring_msg_t *msg, void *payload_buf, pp5_tick_t now)
{
    gp->msgs_received++;
    if (msg->kind == RING_MSG_HOST_LOAD) {
        ring_payload_free(payload_buf);   /* gp_host_load copies what it keeps */
        return gp_host_load(gp, msg, now);
    }
    if (gp->inbox_count == gp->inbox_cap) {
        size_t cap = gp->inbox_cap ? gp->inbox_cap * 2 : 16;
        gp_inbox_item_t *q = malloc(cap * sizeof *q);
        if (!q) {
            ring_payload_free(payload_buf);
            return pp5_fail(PP5_E_NOMEM, "GP %u: out of memory for the inbox", gp->index);
        }
        for (size_t i = 0; i < gp->inbox_count; i++) {
            q[i] = gp->inbox[(gp->inbox_head + i) % gp->inbox_cap];
        }
        free(gp->inbox);
        gp->inbox = q;
        gp->inbox_head = 0;
        gp->inbox_cap = cap;
    }
    gp_inbox_item_t *it = &gp->inbox[(gp->inbox_head + gp->inbox_count) % gp->inbox_cap];
    it->msg = *msg;
    it->payload_copy = NULL;
    if (payload_buf) {
        it->payload_copy = payload_buf;
    } else if (msg->payload_bytes > 0) {
        it->payload_copy = ring_payload_alloc(msg->payload_bytes);
        if (!it->payload_copy) {
            return pp5_fail(PP5_E_NOMEM, "GP %u: out of memory for a message", gp->index);
        }
        memcpy(it->payload_copy, msg->payload, msg->payload_bytes);
    }
    it->msg.payload = it->payload_copy;
    gp->inbox_count++;
    if (!gp->loaded) {
        return PP5_OK;            /* runs after HOST_LOAD */
    }
    return gp_schedule(gp, now);
}
