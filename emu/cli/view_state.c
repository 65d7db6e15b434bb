/* view_state.c: what the viewer's keys do, its modes and the gaze history behind the replay's latency model (view.h). */
#include <math.h>
#include <string.h>

#include "view.h"

/* Add MIP and DEMIP here when render/ has them: a key, a name, a mode. */
static const view_mode_t modes[] = {
    {'f', "full resolution", RENDER_MODE_FULL},
    {'g', "gaze-directed", RENDER_MODE_GAZE},
};

const view_mode_t *view_modes(int *count)
{
    *count = (int)(sizeof modes / sizeof modes[0]);
    return modes;
}

/* The keys other than the modes'. */
static const struct {
    char key;
    view_action_t act;
    const char *what;
} keys[] = {
    {'m', VIEW_ACT_NEXT_MODE, "next mode"},
    {'p', VIEW_ACT_PROGRESSIVE, "progressive refinement on/off (paper section 7)"},
    {'c', VIEW_ACT_CIRCLES, "sweet-spot circles (12 and 20 degrees) on/off"},
    {'l', VIEW_ACT_LEVELS, "populated 2D mip-map levels (figure 6) on/off"},
    {'h', VIEW_ACT_HUD, "heads-up display on/off"},
    {'s', VIEW_ACT_SCREENSHOT, "save a screenshot"},
    {'r', VIEW_ACT_RESET, "reset the view"},
    {'+', VIEW_ACT_ZOOM_IN, "zoom in (also = and the mouse wheel)"},
    {'=', VIEW_ACT_ZOOM_IN, NULL},
    {'-', VIEW_ACT_ZOOM_OUT, "zoom out"},
    {1, VIEW_ACT_ROT_LEFT, "arrows: rotate (also drag with the left button)"},
    {2, VIEW_ACT_ROT_RIGHT, NULL},
    {3, VIEW_ACT_ROT_UP, NULL},
    {4, VIEW_ACT_ROT_DOWN, NULL},
    {'q', VIEW_ACT_QUIT, "quit (also Escape and closing the window)"},
    {27, VIEW_ACT_QUIT, NULL},
};

view_action_t view_key_action(char key)
{
    for (size_t i = 0; i < sizeof modes / sizeof modes[0]; i++)
        if (modes[i].key == key)
            return VIEW_ACT_MODE;
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++)
        if (keys[i].key == key)
            return keys[i].act;
    return VIEW_ACT_NONE;
}

const char *view_keys_help(void)
{
    static char text[2048];
    size_t used = 0;
    for (size_t i = 0; i < sizeof modes / sizeof modes[0]; i++)
        used += (size_t)snprintf(text + used, sizeof text - used, "  %c      %s mode\n",
                                 modes[i].key, modes[i].name);
    for (size_t i = 0; i < sizeof keys / sizeof keys[0] && used < sizeof text; i++)
        if (keys[i].what)
            used += (size_t)snprintf(text + used, sizeof text - used, "  %-6s %s\n",
                                     keys[i].key == 1 ? "arrows" : (char[2]){keys[i].key, 0},
                                     keys[i].what);
    return text;
}

void view_gaze_history_add(view_gaze_history_t *h, double t_s, double x, double y)
{
    h->head = (h->head + 1) % VIEW_GAZE_HISTORY;
    h->t_s[h->head] = t_s;
    h->x[h->head] = x;
    h->y[h->head] = y;
    if (h->count < VIEW_GAZE_HISTORY)
        h->count++;
}

bool view_gaze_history_at(const view_gaze_history_t *h, double now_s, double latency_s, double *x,
                          double *y)
{
    /* Newest first: the first sample that has arrived is the one replay uses. */
    for (int k = 0; k < h->count; k++) {
        int i = (h->head - k + VIEW_GAZE_HISTORY) % VIEW_GAZE_HISTORY;
        if (h->t_s[i] + latency_s <= now_s + 1e-12) {
            *x = h->x[i];
            *y = h->y[i];
            return true;
        }
    }
    return false;
}

static void rotate(viewer_t *v, float dx_deg, float dy_deg)
{
    v->settings.view.rot_y_deg = fmodf(v->settings.view.rot_y_deg + dx_deg, 360.0f);
    v->settings.view.rot_x_deg = fmodf(v->settings.view.rot_x_deg + dy_deg, 360.0f);
}

void viewer_drag(viewer_t *v, int dx, int dy)
{
    rotate(v, 0.5f * (float)dx, 0.5f * (float)dy);
}

bool viewer_act(viewer_t *v, view_action_t act, char key)
{
    int n;
    const view_mode_t *m = view_modes(&n);
    switch (act) {
    case VIEW_ACT_NONE: return false;
    case VIEW_ACT_QUIT: v->quit = true; return false;
    case VIEW_ACT_MODE:
        for (int i = 0; i < n; i++)
            if (m[i].key == key)
                v->mode_index = i;
        break;
    case VIEW_ACT_NEXT_MODE: v->mode_index = (v->mode_index + 1) % n; break;
    case VIEW_ACT_PROGRESSIVE: v->progressive = !v->progressive; break;
    case VIEW_ACT_CIRCLES: v->circles = !v->circles; break;
    case VIEW_ACT_LEVELS: v->levels = !v->levels; break;
    case VIEW_ACT_HUD: v->hud = !v->hud; break;
    case VIEW_ACT_SCREENSHOT: return false;   /* the loop saves it (it knows the name) */
    case VIEW_ACT_RESET: v->settings.view = v->home; break;
    case VIEW_ACT_ZOOM_IN: v->settings.view.zoom = fminf(v->settings.view.zoom * 1.2f, 50.0f); break;
    case VIEW_ACT_ZOOM_OUT: v->settings.view.zoom = fmaxf(v->settings.view.zoom / 1.2f, 0.05f); break;
    case VIEW_ACT_ROT_LEFT: rotate(v, -10.0f, 0.0f); break;
    case VIEW_ACT_ROT_RIGHT: rotate(v, 10.0f, 0.0f); break;
    case VIEW_ACT_ROT_UP: rotate(v, 0.0f, -10.0f); break;
    case VIEW_ACT_ROT_DOWN: rotate(v, 0.0f, 10.0f); break;
    }
    v->settings.mode = m[v->mode_index].mode;
    v->settings.progressive = v->progressive;
    return true;
}
