/* json.h: a small streaming JSON writer for reports and timelines.
 *
 * The writer tracks nesting so callers never place commas by hand:
 *   json_begin_object(j); json_key(j, "frame_time_s"); json_double(j, 0.1);
 *   json_end_object(j);
 * Non-finite doubles are written as null (JSON has no NaN). */
#ifndef PP5_JSON_H
#define PP5_JSON_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#define JSON_MAX_DEPTH 32

typedef struct {
    FILE *out;
    int depth;
    bool need_comma[JSON_MAX_DEPTH];
    bool after_key;
    bool pretty;
} json_writer_t;

void json_init(json_writer_t *j, FILE *out, bool pretty);
void json_begin_object(json_writer_t *j);
void json_end_object(json_writer_t *j);
void json_begin_array(json_writer_t *j);
void json_end_array(json_writer_t *j);
void json_key(json_writer_t *j, const char *key);
void json_string(json_writer_t *j, const char *s);
void json_double(json_writer_t *j, double v);
void json_int(json_writer_t *j, int64_t v);
void json_uint(json_writer_t *j, uint64_t v);
void json_bool(json_writer_t *j, bool v);

/* Shorthands for "key": value inside an object. */
void json_kv_string(json_writer_t *j, const char *key, const char *s);
void json_kv_double(json_writer_t *j, const char *key, double v);
void json_kv_int(json_writer_t *j, const char *key, int64_t v);
void json_kv_uint(json_writer_t *j, const char *key, uint64_t v);
void json_kv_bool(json_writer_t *j, const char *key, bool v);

#endif
