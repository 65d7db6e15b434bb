/* json.c: streaming JSON writer (see json.h). */
#include "json.h"

#include <inttypes.h>
#include <math.h>

void json_init(json_writer_t *j, FILE *out, bool pretty)
{
    j->out = out;
    j->depth = 0;
    j->need_comma[0] = false;
    j->after_key = false;
    j->pretty = pretty;
}

static void indent(json_writer_t *j)
{
    if (!j->pretty)
        return;
    fputc('\n', j->out);
    for (int i = 0; i < j->depth; i++)
        fputs("  ", j->out);
}

/* Called before every value or key: writes the separating comma and indent. */
static void before_item(json_writer_t *j)
{
    if (j->after_key) {
        j->after_key = false;
        return;
    }
    if (j->need_comma[j->depth])
        fputc(',', j->out);
    if (j->depth > 0)
        indent(j);
    j->need_comma[j->depth] = true;
}

static void open_scope(json_writer_t *j, char c)
{
    before_item(j);
    fputc(c, j->out);
    if (j->depth < JSON_MAX_DEPTH - 1)
        j->depth++;
    j->need_comma[j->depth] = false;
}

static void close_scope(json_writer_t *j, char c)
{
    bool had_items = j->need_comma[j->depth];
    if (j->depth > 0)
        j->depth--;
    if (had_items)
        indent(j);
    fputc(c, j->out);
    if (j->depth == 0 && j->pretty)
        fputc('\n', j->out);
}

void json_begin_object(json_writer_t *j) { open_scope(j, '{'); }
void json_end_object(json_writer_t *j) { close_scope(j, '}'); }
void json_begin_array(json_writer_t *j) { open_scope(j, '['); }
void json_end_array(json_writer_t *j) { close_scope(j, ']'); }

static void write_escaped(FILE *out, const char *s)
{
    fputc('"', out);
    for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
        switch (*p) {
        case '"': fputs("\\\"", out); break;
        case '\\': fputs("\\\\", out); break;
        case '\n': fputs("\\n", out); break;
        case '\r': fputs("\\r", out); break;
        case '\t': fputs("\\t", out); break;
        default:
            if (*p < 0x20)
                fprintf(out, "\\u%04x", *p);
            else
                fputc(*p, out);
        }
    }
    fputc('"', out);
}

void json_key(json_writer_t *j, const char *key)
{
    before_item(j);
    write_escaped(j->out, key);
    fputs(j->pretty ? ": " : ":", j->out);
    j->after_key = true;
}

void json_string(json_writer_t *j, const char *s)
{
    before_item(j);
    if (s)
        write_escaped(j->out, s);
    else
        fputs("null", j->out);
}

void json_double(json_writer_t *j, double v)
{
    before_item(j);
    if (isfinite(v))
        fprintf(j->out, "%.17g", v);
    else
        fputs("null", j->out);
}

void json_int(json_writer_t *j, int64_t v)
{
    before_item(j);
    fprintf(j->out, "%" PRId64, v);
}

void json_uint(json_writer_t *j, uint64_t v)
{
    before_item(j);
    fprintf(j->out, "%" PRIu64, v);
}

void json_bool(json_writer_t *j, bool v)
{
    before_item(j);
    fputs(v ? "true" : "false", j->out);
}

void json_kv_string(json_writer_t *j, const char *key, const char *s) { json_key(j, key); json_string(j, s); }
void json_kv_double(json_writer_t *j, const char *key, double v) { json_key(j, key); json_double(j, v); }
void json_kv_int(json_writer_t *j, const char *key, int64_t v) { json_key(j, key); json_int(j, v); }
void json_kv_uint(json_writer_t *j, const char *key, uint64_t v) { json_key(j, key); json_uint(j, v); }
void json_kv_bool(json_writer_t *j, const char *key, bool v) { json_key(j, key); json_bool(j, v); }
