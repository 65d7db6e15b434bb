/* testpattern_gp.h: the test-pattern scene (shared by the GP program and the tests' native reference) and the program.
 *
 * Scene on a W x H screen (W, H multiples of 128, so even):
 *   background R = floor(x * DR / 2^16), DR = floor(255 * 2^16 / (W - 1))      (linear gradient)
 *              G = floor(y * EG / 2^16), EG = floor(255 * 2^16 / (H - 1))      (linear gradient)
 *              B = floor(KB * ((x - W/2)^2 + (y - H/2)^2) / 2^20),
 *                  KB = floor(255 * 2^20 / ((W/2)^2 + (H/2)^2))               (quadratic gradient)
 *   then TP_DISCS discs in index order (later ones on top): pixel (x, y) is
 *   inside disc i when q = (x-cx)^2 + (y-cy)^2 - r^2 < 0; there the channels
 *   in the disc's colour mask get shade = floor(-q * K / 2^16) with
 *   K = floor(255 * 2^16 / r^2) (bright centre, dark rim) and the others 0.
 * Every value above is one quadratic expression per pixel: exactly what the
 * renderers' QEE evaluates (facts §3.3). */
#ifndef PP5_TESTPATTERN_GP_H
#define PP5_TESTPATTERN_GP_H

#include <stdint.h>
#include "fw_api.h"

#define TP_DISCS 16

/* PP memory layout (bit addresses in the 208-bit pixel memory). */
enum { TP_R = 0, TP_G = 8, TP_B = 16, TP_Q = 24, TP_Q_BITS = 28, TP_P = 52, TP_P_BITS = 32 };

typedef struct {
    int32_t cx, cy, r;
    uint32_t colour;     /* bit 0 red, bit 1 green, bit 2 blue */
} tp_disc_t;

static inline tp_disc_t tp_disc(unsigned i, unsigned w, unsigned h)
{
    unsigned m = w < h ? w : h;
    tp_disc_t d;
    d.cx = (int32_t)(w * ((i * 7u) % 16u) / 16u + w / 32u);
    d.cy = (int32_t)(h * ((i * 5u + 3u) % 16u) / 16u + h / 32u);
    d.r = (int32_t)(m / 20u + ((i * 37u) % 7u) * m / 80u);
    d.colour = 1u + i % 7u;
    return d;
}

/* The GP program: GP g drives renderers j = g, g + n_gp, ...; renderer j
 * renders regions k = j, j + n_renderers, ... (row-major region numbers). */
extern const fw_program_t testpattern_program;

#endif
