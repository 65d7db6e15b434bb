/* view_machine.c: the emulated Pixel-Planes 5's cost of the viewer's frames on a worker thread (view.h).
 *
 * The worker keeps one host session (firmware/host/fw_session.h) and sets it
 * up again when the mode or progressive refinement changes (the session fixes
 * them for a sequence); a new view between frames is fw_session_set_view.  It
 * always works on the newest request: requests that arrive while a frame is
 * being emulated replace each other, and the HUD says how far behind the
 * figure it shows is. */
#include <stdio.h>
#include <string.h>

#include "view.h"

static void set_status(view_machine_t *m, const char *fmt, const char *arg)
{
    pthread_mutex_lock(&m->lock);
    snprintf(m->status, sizeof m->status, fmt, arg);
    pthread_mutex_unlock(&m->lock);
}

/* A session for the request's mode and progressiveness. */
static pp5_status_t setup(view_machine_t *m, fw_session_t *s, bool *have,
                          const view_machine_request_t *r)
{
    if (*have)
        fw_session_free(s);
    *have = false;
    render_job_t job = *m->job;
    job.settings.mode = r->mode;
    job.settings.progressive = r->progressive;
    job.settings.view = r->view;
    set_status(m, "setting up the machine (%s: load, GP mip-map build, backing store)",
               render_mode_name(r->mode));
    pp5_status_t st = fw_session_init(s, &job, &m->params, &m->opts);
    *have = st == PP5_OK;
    if (st == PP5_OK)
        set_status(m, "%s", "");
    return st;
}

static bool needs_setup(const fw_session_t *s, bool have, const view_machine_request_t *r)
{
    return !have || s->rs.mode != r->mode || s->rs.progressive != r->progressive ||
           s->rs.view.projection != r->view.projection;
}

static pp5_status_t one_frame(view_machine_t *m, fw_session_t *s, bool *have,
                              const view_machine_request_t *r)
{
    pp5_status_t st = PP5_OK;
    if (needs_setup(s, *have, r))
        st = setup(m, s, have, r);
    else if (memcmp(&s->rs.view, &r->view, sizeof r->view) != 0)
        st = fw_session_set_view(s, &r->view);
    view_machine_answer_t a;
    memset(&a, 0, sizeof a);
    if (st == PP5_OK)
        st = fw_session_frame(s, r->gaze_x, r->gaze_y, m->want_image ? &a.image : NULL, &a.result);
    if (st != PP5_OK)
        return st;
    a.valid = true;
    a.frame = r->frame;
    pthread_mutex_lock(&m->lock);
    image8_free(&m->answer.image);
    m->answer = a;
    pthread_mutex_unlock(&m->lock);
    return PP5_OK;
}

static void *worker_main(void *arg)
{
    view_machine_t *m = arg;
    fw_session_t s;
    bool have = false;
    pthread_mutex_lock(&m->lock);
    while (!m->stop) {
        if (!m->pending) {
            pthread_cond_wait(&m->wake, &m->lock);
            continue;
        }
        view_machine_request_t r = m->request;
        m->pending = false;
        m->busy = true;
        pthread_mutex_unlock(&m->lock);
        pp5_status_t st = one_frame(m, &s, &have, &r);
        pthread_mutex_lock(&m->lock);
        m->busy = false;
        if (st != PP5_OK) {
            snprintf(m->status, sizeof m->status, "failed: %s", pp5_error_text());
            m->failed = true;
            m->stop = true;
        }
        pthread_cond_broadcast(&m->done);
    }
    pthread_cond_broadcast(&m->done);
    pthread_mutex_unlock(&m->lock);
    if (have)
        fw_session_free(&s);
    return NULL;
}

pp5_status_t view_machine_start(view_machine_t *m, const render_job_t *job, const render_cmd_t *c,
                                bool want_image)
{
    memset(m, 0, sizeof *m);
    m->job = job;
    m->want_image = want_image;
    m->opts = c->fw;
    pp5_status_t st = pp5_params_build(&c->params, &m->params);
    if (st != PP5_OK)
        return st;
    pthread_mutex_init(&m->lock, NULL);
    pthread_cond_init(&m->wake, NULL);
    pthread_cond_init(&m->done, NULL);
    if (pthread_create(&m->thread, NULL, worker_main, m) != 0)
        return pp5_fail(PP5_E_IO, "view: cannot start the machine's thread");
    m->started = true;
    return PP5_OK;
}

void view_machine_request(view_machine_t *m, const view_machine_request_t *r)
{
    pthread_mutex_lock(&m->lock);
    m->request = *r;
    m->pending = true;
    pthread_cond_signal(&m->wake);
    pthread_mutex_unlock(&m->lock);
}

void view_machine_wait(view_machine_t *m, long frame)
{
    pthread_mutex_lock(&m->lock);
    while (!m->failed && !(m->answer.valid && m->answer.frame >= frame))
        pthread_cond_wait(&m->done, &m->lock);
    pthread_mutex_unlock(&m->lock);
}

void view_machine_peek(view_machine_t *m, view_machine_answer_t *a, char *status, size_t n,
                       bool *busy)
{
    pthread_mutex_lock(&m->lock);
    *a = m->answer;
    memset(&a->image, 0, sizeof a->image);
    snprintf(status, n, "%s", m->status);
    *busy = m->busy || m->pending;
    pthread_mutex_unlock(&m->lock);
}

bool view_machine_take_image(view_machine_t *m, image8_t *img, long *frame)
{
    pthread_mutex_lock(&m->lock);
    bool got = m->answer.image.pixels != NULL;
    if (got) {
        *img = m->answer.image;
        *frame = m->answer.frame;
        memset(&m->answer.image, 0, sizeof m->answer.image);
    }
    pthread_mutex_unlock(&m->lock);
    return got;
}

void view_machine_stop(view_machine_t *m)
{
    if (!m->started)
        return;
    pthread_mutex_lock(&m->lock);
    m->stop = true;
    pthread_cond_signal(&m->wake);
    pthread_mutex_unlock(&m->lock);
    pthread_join(m->thread, NULL);
    image8_free(&m->answer.image);
    pthread_mutex_destroy(&m->lock);
    pthread_cond_destroy(&m->wake);
    pthread_cond_destroy(&m->done);
    m->started = false;
}
