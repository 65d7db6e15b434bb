/* ring_msg.h: ring node addresses, traffic classes and message kinds (firmware-facing).
 *
 * Included by firmware (which sees only emu/api/) and by the emulator.  A
 * message is: source, destination, kind, traffic class, up to RING_MSG_ARGS
 * 32-bit header arguments and an optional payload.  On the wire the ring
 * charges header_bytes (parameter ring.header_bytes, [U]: no source gives
 * the packet format, facts §5.1) + payload_bytes; the header arguments are
 * assumed to fit in that header.
 *
 * Message kinds and their arguments (a = args[]):
 *
 *   kind                    dst       a[0]    a[1]   a[2]     a[3]       a[4]  payload
 *   RENDERER_EXEC           renderer  -       -      -        -          -     uint32 PP instruction words
 *   RENDERER_SET_REGION     renderer  x0      y0     -        -          -     none
 *   RENDERER_WRITE_FIELD    renderer  addr    bits   -        -          -     16384 x uint32 (one per PP)
 *   RENDERER_WRITE_BS       renderer  block   -      -        -          -     16384 x uint32
 *   RENDERER_READ_FIELD     renderer  addr    bits   reply_to tag        -     none -> RENDERER_DATA
 *   RENDERER_READ_BS        renderer  block   -      reply_to tag        -     none -> RENDERER_DATA
 *   RENDERER_READ_BS_BOX    renderer  block   dims   reply_to tag  origin size   none -> RENDERER_DATA of
 *                           the words of a box of PPs, the block seen as a bx x by x bz array (PP i
 *                           holds element i, x fastest): a[1] = bx | bz << 8 | by << 16,
 *                           a[4] = x0 | z0 << 8 | y0 << 16 (origin), a[5] = sx | sy << 8 | sz << 16
 *                           (size); the reply holds sx*sy*sz words, x fastest
 *   RENDERER_SEND_PIXELS    renderer  r_addr  g_addr b_addr   reply_to   -     none -> FB_PIXELS of the
 *                                     (three 8-bit fields)    (the FB)         renderer's 128x128 region
 *   RENDERER_DATA           any       tag     bits   -        -          -     16384 x uint32
 *   FB_PIXELS               fb        x       y      w        h          -     w*h*3 bytes RGB8, row-major
 *   FB_SWAP                 fb        -       -      -        -          -     none (show the back buffer)
 *   HOST_LOAD               gp        image   -      -        -          -     image_bytes of program image, then data
 *   FRAME_START             gp        frame   -      -        -          -     none (host: start frame number a[0])
 *   GP_USER                 gp        free for firmware use                     any
 *
 * PP data words travel as one 32-bit word per PP whatever the field width
 * ([U]: the renderer port format is unknown, facts §3.5 / open question 4).
 * reply_to is a packed address, ring_addr_pack(). */
#ifndef PP5_RING_MSG_H
#define PP5_RING_MSG_H

#include <stddef.h>
#include <stdint.h>

#define RING_MSG_ARGS 6

typedef enum {
    RING_NODE_HOST = 0,
    RING_NODE_GP = 1,
    RING_NODE_RENDERER = 2,
    RING_NODE_FB = 3
} ring_node_type_t;

/* A node is named by type and index (GP 3, renderer 7); the machine maps
 * names to positions on the ring (see emu/ARCHITECTURE.md, "Ring order"). */
typedef struct {
    uint16_t type;    /* ring_node_type_t */
    uint16_t index;
} ring_addr_t;

static inline ring_addr_t ring_addr(ring_node_type_t type, unsigned index)
{
    ring_addr_t a = { (uint16_t)type, (uint16_t)index };
    return a;
}
static inline uint32_t ring_addr_pack(ring_addr_t a)
{
    return ((uint32_t)a.type << 16) | a.index;
}
static inline ring_addr_t ring_addr_unpack(uint32_t v)
{
    ring_addr_t a = { (uint16_t)(v >> 16), (uint16_t)(v & 0xffffu) };
    return a;
}

/* Traffic classes: every byte on the ring is counted under one of these. */
typedef enum {
    RING_CLASS_HOST = 0,      /* host interface: firmware and data loads */
    RING_CLASS_COMMAND,       /* GP -> renderer instruction streams and commands */
    RING_CLASS_DATA,          /* renderer -> GP data, GP <-> renderer field/backing-store data */
    RING_CLASS_PIXELS,        /* finished pixels to the frame buffer */
    RING_CLASS_GP,            /* GP <-> GP messages */
    RING_CLASS_COUNT
} ring_class_t;

typedef enum {
    RING_MSG_RENDERER_EXEC = 1,
    RING_MSG_RENDERER_SET_REGION,
    RING_MSG_RENDERER_WRITE_FIELD,
    RING_MSG_RENDERER_WRITE_BS,
    RING_MSG_RENDERER_READ_FIELD,
    RING_MSG_RENDERER_READ_BS,
    RING_MSG_RENDERER_SEND_PIXELS,
    RING_MSG_RENDERER_DATA,
    RING_MSG_FB_PIXELS,
    RING_MSG_FB_SWAP,
    RING_MSG_HOST_LOAD,
    RING_MSG_GP_USER,
    RING_MSG_FRAME_START,     /* host -> GP: start frame a[0] */
    RING_MSG_RENDERER_READ_BS_BOX,
    RING_MSG_KIND_COUNT
} ring_msg_kind_t;

/* Short lower-case name of a kind ("exec", "fb_pixels", ...; "?" if unknown). */
static inline const char *ring_msg_kind_name(uint32_t kind)
{
    static const char *const names[RING_MSG_KIND_COUNT] = {
        "?", "exec", "set_region", "write_field", "write_bs", "read_field", "read_bs",
        "send_pixels", "data", "fb_pixels", "fb_swap", "host_load", "gp_user", "frame_start",
        "read_bs_box"
    };
    return kind < RING_MSG_KIND_COUNT ? names[kind] : "?";
}

/* A message as seen by firmware and by the emulator's units.  While a
 * receiver's callback runs, `payload` points at ring-owned memory that stays
 * valid until the callback returns. */
typedef struct {
    ring_addr_t src, dst;
    uint32_t kind;            /* ring_msg_kind_t */
    uint32_t cls;             /* ring_class_t */
    uint32_t args[RING_MSG_ARGS];
    const void *payload;
    size_t payload_bytes;
} ring_msg_t;

/* A complete message: every field is set, so none goes out with stale header
 * words.  args: RING_MSG_ARGS words, or NULL for all zero; the payload is
 * referenced, not copied (the ring copies it when the message is sent). */
static inline ring_msg_t ring_msg_make(ring_addr_t src, ring_addr_t dst, uint32_t kind,
                                       uint32_t cls, const uint32_t *args, const void *payload,
                                       size_t payload_bytes)
{
    ring_msg_t m = {src, dst, kind, cls, {0}, payload, payload_bytes};
    for (unsigned i = 0; args && i < RING_MSG_ARGS; i++) {
        m.args[i] = args[i];
    }
    return m;
}

#endif
