/* classify_io.h: transfer functions in files: pp5's small text format (read and written) and ParaView's exported presets (JSON, read with jansson).
 *
 * The text format (render/ARCHITECTURE.md, "Transfer-function files"), one
 * item per line, '#' starts a comment:
 *
 *     pp5-tf 1                          the first item: format and version
 *     name skull                        optional, up to 31 characters
 *     contour V A W R G B               an iso-value contour (classify.h): value,
 *                                       opacity 0..1, thickness in voxels > 0,
 *                                       colour 0..1; at most 4
 *     ramp V A RW R G B                 a value ramp of width RW > 0 centred on V
 *     opacity V A                       a control point of value -> opacity
 *     color V R G B                     a control point of value -> colour
 *     min-opacity A                     voxels below A are made transparent
 *
 * A file holds contours/ramps or control points, not both; control points
 * come in strictly increasing value order (at most 256 of each kind);
 * colour points need opacity points (opacity alone means white).
 *
 * ParaView: "Save to preset" with "Save opacities" ticked, then "Export",
 * writes a JSON array of presets; the first is used.  "RGBPoints" holds
 * x, r, g, b per point and "Points" x, opacity, midpoint, sharpness.  pp5
 * interpolates linearly in RGB: it says so when the preset asks for another
 * colour space, or for a midpoint or sharpness other than the linear 0.5, 0. */
#ifndef PP5_CLASSIFY_IO_H
#define PP5_CLASSIFY_IO_H

#include <stddef.h>
#include <stdio.h>
#include "classify.h"

/* Reads FILE in either format (JSON when its first non-blank character is
 * '[' or '{').  `note` (may be NULL) receives what the user should know about
 * the reading ("" when nothing).  Errors name the file and, for the text
 * format, the line; for JSON, jansson's line and column. */
pp5_status_t classify_tf_read(const char *path, classify_tf_t *tf, char *note, size_t note_size);
/* The same from text in memory; `name` is used in messages. */
pp5_status_t classify_tf_parse_text(const char *text, const char *name, classify_tf_t *tf);
pp5_status_t classify_tf_parse_paraview(const char *text, size_t len, const char *name,
                                        classify_tf_t *tf, char *note, size_t note_size);
/* Writes tf in the text format, after `header` as comment lines (may be
 * NULL; newlines start new comment lines).  Values are written with 9
 * significant digits, so a float reads back exactly. */
void classify_tf_write_text(FILE *out, const classify_tf_t *tf, const char *header);
/* The same into a file, whole or not at all. */
pp5_status_t classify_tf_save(const char *path, const classify_tf_t *tf, const char *header);

#endif
