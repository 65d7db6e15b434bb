/* bit_transpose.c: bit planes <-> one uint32 per PP by word-parallel 32x32 bit-matrix transposes. */
#include "bit_transpose.h"

#include <string.h>

#include "pp_params.h"

/* Plane words gathered per pass: one 64-byte cache line of each plane, so the
 * 32 planes (2 KB apart in backing_t, which maps them onto two L1 sets) are each
 * read once per line rather than once per word. */
#define TILE_WORDS 8u

/* Transposes the two 32x32 bit matrices held in x[0..31] (matrix h is bits
 * 32h..32h+31 of every word): bit j of row i moves to bit i of row j.  Stage s
 * swaps the off-diagonal s x s sub-blocks of every 2s x 2s block; the masks are
 * the low s bits of every 2s-bit group, repeated in both halves, and shifts by
 * s < 32 under those masks never carry bits between the halves. */
static inline void transpose_2x32x32(uint64_t x[32])
{
    static const uint64_t mask[5] = {
        0x0000ffff0000ffffull, 0x00ff00ff00ff00ffull, 0x0f0f0f0f0f0f0f0full,
        0x3333333333333333ull, 0x5555555555555555ull,
    };
    unsigned stage = 0;
    for (unsigned s = 16; s; s >>= 1, stage++) {
        const uint64_t m = mask[stage];
        for (unsigned i = 0; i < 32; i++) {
            if (i & s)
                continue;
            uint64_t t = ((x[i] >> s) ^ x[i + s]) & m;
            x[i + s] ^= t;
            x[i] ^= t << s;
        }
    }
}

void bit_transpose_planes_to_words(const uint64_t *first, size_t plane_stride, unsigned bits,
                                   uint32_t *out)
{
    uint64_t tile[32][TILE_WORDS];
    memset(tile, 0, sizeof tile);                 /* planes at and above `bits` read as 0 */
    for (unsigned w0 = 0; w0 < PP_PLANE_WORDS; w0 += TILE_WORDS) {
        for (unsigned k = 0; k < bits; k++)
            memcpy(tile[k], first + k * plane_stride + w0, sizeof tile[k]);
        for (unsigned v = 0; v < TILE_WORDS; v++) {
            uint64_t x[32];
            for (unsigned k = 0; k < 32; k++)
                x[k] = tile[k][v];
            transpose_2x32x32(x);
            /* Row j now holds PP 64w + j (low half) and PP 64w + 32 + j (high half). */
            uint32_t *o = out + (size_t)(w0 + v) * 64u;
            for (unsigned j = 0; j < 32; j++) {
                o[j] = (uint32_t)x[j];
                o[j + 32] = (uint32_t)(x[j] >> 32);
            }
        }
    }
}

void bit_transpose_words_to_planes(const uint32_t *in, unsigned bits, uint64_t *first,
                                   size_t plane_stride)
{
    uint64_t tile[32][TILE_WORDS];
    for (unsigned w0 = 0; w0 < PP_PLANE_WORDS; w0 += TILE_WORDS) {
        for (unsigned v = 0; v < TILE_WORDS; v++) {
            const uint32_t *p = in + (size_t)(w0 + v) * 64u;
            uint64_t x[32];
            for (unsigned j = 0; j < 32; j++)
                x[j] = (uint64_t)p[j] | (uint64_t)p[j + 32] << 32;
            transpose_2x32x32(x);
            /* Row k now holds bit k of the 64 PPs of word w0 + v. */
            for (unsigned k = 0; k < 32; k++)
                tile[k][v] = x[k];
        }
        for (unsigned k = 0; k < bits; k++)
            memcpy(first + k * plane_stride + w0, tile[k], sizeof tile[k]);
    }
}
