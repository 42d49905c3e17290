/* cli/view/view.c -- the window of `instess view` (SDL2, SDL2_ttf), built as the module libinstess_view.so: the
 * event loop (keys through the key table of cli/view/view_state.c, mouse orbit and zoom, resizing), the HUD drawn
 * with DejaVu Sans Mono over a copy of the frame, the frame shown through a streaming texture, the scripted
 * keys of --keys and the --capture file.  Everything else -- options, renders, files -- is the program's
 * (cli/view/view_state.c), which this module calls back (the program exports its symbols, -rdynamic). */
#include "view_internal.h"

#include <SDL.h>
#include <SDL_ttf.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define VIEW_FONT "/usr/share/fonts/truetype/dejavu/DejaVuSansMono.ttf"
enum { FONT_PX = 14, HUD_MARGIN = 6, HUD_MAX_LINES = 40 };

typedef struct view_window {
    SDL_Window *win;
    SDL_Renderer *ren;
    SDL_Texture *tex;
    int tex_w, tex_h;
    TTF_Font *font;
    uint32_t *shown;        /* the frame with the overlay: what the texture holds */
    bool dragged;           /* the left button moved since it went down (a drag orbits; a click pins a pixel) */
} view_window;

/* Free the window's resources and shut SDL down. */
static void close_window(view_window *w)
{
    if (w->font) TTF_CloseFont(w->font);
    if (TTF_WasInit()) TTF_Quit();
    if (w->tex) SDL_DestroyTexture(w->tex);
    if (w->ren) SDL_DestroyRenderer(w->ren);
    if (w->win) SDL_DestroyWindow(w->win);
    SDL_Quit();
    free(w->shown);
    memset(w, 0, sizeof *w);
}

/* A streaming texture and overlay buffer of v's size (again after a resize); 0 or -1 with the reason in err. */
static int size_buffers(view_window *w, const view_state *v, char *err, size_t errlen)
{
    if (w->tex && w->tex_w == v->o.width && w->tex_h == v->o.height) return 0;
    if (w->tex) SDL_DestroyTexture(w->tex);
    free(w->shown);
    w->shown = calloc((size_t)v->o.width * v->o.height, sizeof *w->shown);
    w->tex = SDL_CreateTexture(w->ren, SDL_PIXELFORMAT_RGBA32, SDL_TEXTUREACCESS_STREAMING, v->o.width, v->o.height);
    if (!w->shown || !w->tex)
        return snprintf(err, errlen, "%s", w->tex ? "out of memory for the frame" : SDL_GetError()), -1;
    w->tex_w = v->o.width, w->tex_h = v->o.height;
    return 0;
}

/* Open SDL, the window (v's size, resizable), a renderer and the HUD's font; 0 or -1 with the reason. */
static int open_window(view_window *w, view_state *v, char *err, size_t errlen)
{
    if (SDL_Init(SDL_INIT_VIDEO) != 0)
        return snprintf(err, errlen, "%s (no display? SDL_VIDEODRIVER=dummy with --keys, --frames or --capture runs "
                        "without one)", SDL_GetError()), -1;
    const char *driver = SDL_GetCurrentVideoDriver();
    bool scripted = v->script.n_keys || v->script.frames || v->script.capture;
    if (!scripted && driver && (!strcmp(driver, "dummy") || !strcmp(driver, "offscreen")))
        return snprintf(err, errlen, "SDL's video driver %s shows nothing and takes no input: without --keys, "
                        "--frames or --capture the window could not be closed", driver), -1;
    if (v->size_default && driver && strcmp(driver, "dummy") && strcmp(driver, "offscreen")) {
        SDL_Rect r;   /* the default size, smaller where the display is (room for the window's title bar) */
        if (SDL_GetDisplayUsableBounds(0, &r) == 0 && r.w > 0 && r.h > 64 &&
            (r.w < v->o.width || r.h - 48 < v->o.height) &&
            view_resize(v, r.w < v->o.width ? r.w : v->o.width, r.h - 48 < v->o.height ? r.h - 48 : v->o.height,
                        err, errlen) != 0)
            return -1;
    }
    char title[300];
    snprintf(title, sizeof title, "instess view: %s", v->mesh.name);
    w->win = SDL_CreateWindow(title, SDL_WINDOWPOS_UNDEFINED, SDL_WINDOWPOS_UNDEFINED, v->o.width, v->o.height,
                              SDL_WINDOW_RESIZABLE);
    if (!w->win) return snprintf(err, errlen, "%s", SDL_GetError()), -1;
    w->ren = SDL_CreateRenderer(w->win, -1, 0);
    if (!w->ren) w->ren = SDL_CreateRenderer(w->win, -1, SDL_RENDERER_SOFTWARE);
    if (!w->ren) return snprintf(err, errlen, "%s", SDL_GetError()), -1;
    if (TTF_Init() == 0) w->font = TTF_OpenFont(VIEW_FONT, FONT_PX);
    if (!w->font) {
        fprintf(stderr, "instess view: warning: no HUD (font %s: %s; Debian's fonts-dejavu-core has it)\n", VIEW_FONT,
                TTF_GetError());
        v->hud = VIEW_HUD_OFF;
    }
    return size_buffers(w, v, err, errlen);
}

/* ------------------------------------ the overlay ------------------------------------ */

/* Blend colour c (0xAABBGGRR with its alpha a, 0..255) over pixel *p. */
static void blend(uint32_t *p, uint32_t c, uint32_t a)
{
    uint32_t d = *p, out = 0xff000000u;
    for (int s = 0; s < 24; s += 8) {
        uint32_t x = ((c >> s) & 0xff) * a + ((d >> s) & 0xff) * (255 - a);
        out |= ((x + 127) / 255) << s;
    }
    *p = out;
}

/* Darken the box (x, y, bw, bh) of w->shown (width W, height H), clipped. */
static void darken(view_window *w, int W, int H, int x, int y, int bw, int bh)
{
    for (int j = y < 0 ? 0 : y; j < y + bh && j < H; j++)
        for (int i = x < 0 ? 0 : x; i < x + bw && i < W; i++) blend(&w->shown[(size_t)j * W + i], 0, 150);
}

/* Draw one line of text with its top-left corner at (x, y) into w->shown; its width in pixels. */
static int draw_text(view_window *w, int W, int H, int x, int y, const char *text)
{
    SDL_Color white = {235, 235, 235, 255};
    SDL_Surface *s = *text ? TTF_RenderUTF8_Blended(w->font, text, white) : NULL;
    SDL_Surface *c = s ? SDL_ConvertSurfaceFormat(s, SDL_PIXELFORMAT_RGBA32, 0) : NULL;
    int width = c ? c->w : 0;
    if (c && SDL_LockSurface(c) == 0) {
        for (int j = 0; j < c->h && y + j < H; j++) {
            const uint32_t *row = (const uint32_t *)((const uint8_t *)c->pixels + (size_t)j * c->pitch);
            for (int i = 0; i < c->w && x + i < W; i++)
                if (y + j >= 0 && x + i >= 0 && row[i] >> 24)
                    blend(&w->shown[(size_t)(y + j) * W + x + i], row[i], row[i] >> 24);
        }
        SDL_UnlockSurface(c);
    }
    SDL_FreeSurface(c);
    SDL_FreeSurface(s);
    return width;
}

/* Label each half of the split screen at its bottom left ("left: smooth", "right: npatch") in w->shown. */
static void label_halves(view_window *w, const view_state *v, int W, int H)
{
    const int step = TTF_FontLineSkip(w->font), y = H - step - 2 * HUD_MARGIN;
    for (int half = 0; half < 2; half++) {
        char label[64];
        int tw = 0, x = half ? W / 2 + 1 : 0;
        view_split_label(v, half, label, sizeof label);
        TTF_SizeUTF8(w->font, label, &tw, NULL);
        darken(w, W, H, x, y, tw + 2 * HUD_MARGIN, step + 2 * HUD_MARGIN);
        draw_text(w, W, H, x + HUD_MARGIN, y + HUD_MARGIN, label);
    }
}

/* w->shown = v->frame with the HUD (and the split screen's divider and labels) drawn over it. */
static void compose(view_window *w, const view_state *v, double ms_frame)
{
    const int W = v->o.width, H = v->o.height;
    memcpy(w->shown, v->frame, (size_t)W * H * sizeof *w->shown);
    if (v->hud == VIEW_HUD_OFF || !w->font) return;
    if (v->split) {
        for (int y = 0; y < H; y++) w->shown[(size_t)y * W + W / 2] = 0xffd0d0d0u;
        label_halves(w, v, W, H);
    }
    char lines[HUD_MAX_LINES][160];
    int n = view_hud_lines(v, ms_frame, lines, HUD_MAX_LINES), step = TTF_FontLineSkip(w->font), width = 0;
    for (int k = 0; k < n; k++) {
        int tw = 0;
        TTF_SizeUTF8(w->font, lines[k], &tw, NULL);
        if (tw > width) width = tw;
    }
    darken(w, W, H, 0, 0, width + 2 * HUD_MARGIN, n * step + 2 * HUD_MARGIN);
    for (int k = 0; k < n; k++) draw_text(w, W, H, HUD_MARGIN, HUD_MARGIN + k * step, lines[k]);
}

/* Show w->shown. */
static void present(view_window *w)
{
    SDL_UpdateTexture(w->tex, NULL, w->shown, w->tex_w * (int)sizeof *w->shown);
    SDL_RenderClear(w->ren);
    SDL_RenderCopy(w->ren, w->tex, NULL, NULL);
    SDL_RenderPresent(w->ren);
}

/* ------------------------------------ events ------------------------------------ */

/* Feed the scripted key `name` as the window system would: a key press (or, for `close`, the window closed);
 * names joined by '+' are all pushed before the next frame. */
static void push_key(view_window *w, const char *name)
{
    char buf[64];
    SDL_strlcpy(buf, name, sizeof buf);
    for (char *save = NULL, *t = SDL_strtokr(buf, "+", &save); t; t = SDL_strtokr(NULL, "+", &save)) {
        SDL_Event e;
        memset(&e, 0, sizeof e);
        if (SDL_strcasecmp(t, "close") == 0) {
            e.type = SDL_QUIT;
        } else {
            e.type = SDL_KEYDOWN;
            e.key.state = SDL_PRESSED;
            e.key.windowID = SDL_GetWindowID(w->win);
            e.key.keysym.sym = SDL_GetKeyFromName(t);
            e.key.keysym.scancode = SDL_GetScancodeFromKey(e.key.keysym.sym);
        }
        SDL_PushEvent(&e);
    }
}

/* Apply one event to v. */
static void handle(view_state *v, view_window *w, const SDL_Event *e)
{
    char err[600];
    switch (e->type) {
    case SDL_QUIT: v->quit = true; break;
    case SDL_KEYDOWN: view_press(v, SDL_GetKeyName(e->key.keysym.sym)); break;
    case SDL_MOUSEMOTION:
        if (e->motion.state & SDL_BUTTON_LMASK) view_orbit(v, e->motion.xrel, e->motion.yrel), w->dragged = true;
        break;
    case SDL_MOUSEBUTTONDOWN:
        if (e->button.button == SDL_BUTTON_LEFT) w->dragged = false;
        break;
    case SDL_MOUSEBUTTONUP:   /* a click without a drag pins the pixel for the inspector */
        if (e->button.button == SDL_BUTTON_LEFT && !w->dragged) view_pin(v, e->button.x, e->button.y);
        break;
    case SDL_MOUSEWHEEL: view_zoom(v, e->wheel.y); break;
    case SDL_WINDOWEVENT:
        if (e->window.event == SDL_WINDOWEVENT_SIZE_CHANGED) {
            if (view_resize(v, e->window.data1, e->window.data2, err, sizeof err) != 0 ||
                size_buffers(w, v, err, sizeof err) != 0)
                fprintf(stderr, "instess view: %s\n", err), v->quit = true;
        } else if (e->window.event == SDL_WINDOWEVENT_EXPOSED) {
            present(w);
        }
        break;
    default: break;
    }
}

/* Render, compose and show one frame; 0, or -1 with the message in err. */
static int show_frame(view_state *v, view_window *w, double *ms_frame, char *err, size_t errlen)
{
    Uint64 t0 = SDL_GetPerformanceCounter();
    v->dirty = v->overlay_dirty = false;
    if (view_render(v, err, errlen) != 0) return -1;
    compose(w, v, *ms_frame);
    present(w);
    *ms_frame = (double)(SDL_GetPerformanceCounter() - t0) * 1e3 / (double)SDL_GetPerformanceFrequency();
    return 0;
}

/* Whether the scripted run is over: a script was given (keys, a capture or --frames), all keys were fed and
 * nothing waits to be drawn.  With --frames N a scene that stands still ends the run too: a frame is drawn only
 * when something changed, so waiting for the N-th could last for ever. */
static bool script_done(const view_state *v, int next_key)
{
    const view_script *s = &v->script;
    return (s->frames || s->n_keys || s->capture) && next_key >= s->n_keys && !v->dirty && !v->overlay_dirty;
}

/* The event loop until v->quit, the frame limit or the end of the script; 0 or 1 (the first frame failed). */
static int loop(view_state *v, view_window *w)
{
    char err[1024];
    int frames = 0, next_key = 0;
    double ms_frame = 0;
    while (!v->quit) {
        if (v->dirty) {
            if (show_frame(v, w, &ms_frame, err, sizeof err) != 0) {
                fprintf(stderr, "instess: %s\n", err);
                if (frames == 0) return 1;
                snprintf(v->status, sizeof v->status, "%.300s", err);
                v->overlay_dirty = true;
            }
            if (++frames == v->script.frames) break;
        } else if (v->overlay_dirty) {   /* a refusal or a notice: shown at once, over the frame as it was */
            v->overlay_dirty = false;
            compose(w, v, ms_frame);
            present(w);
        }
        if (frames >= 1 && next_key < v->script.n_keys) push_key(w, v->script.keys[next_key++]);
        else if (script_done(v, next_key)) {
            if (v->script.frames && frames < v->script.frames)
                fprintf(stderr, "instess view: --frames %d: the scene stood still after %d frame(s) (a frame is drawn "
                        "only when something changed): stopping\n", v->script.frames, frames);
            break;
        }
        SDL_Event e;
        bool busy = v->dirty || next_key < v->script.n_keys;
        int got = busy ? SDL_PollEvent(&e) : SDL_WaitEventTimeout(&e, 250);
        for (; got && !v->quit; got = SDL_PollEvent(&e)) handle(v, w, &e);
    }
    return 0;
}

/* The module's entry point (view_internal.h): the window until the user or the script ends it; the exit code. */
int view_module_run(view_state *v);
int view_module_run(view_state *v)
{
    view_window w;
    char err[1024];
    memset(&w, 0, sizeof w);
    if (open_window(&w, v, err, sizeof err) != 0) {
        fprintf(stderr, "instess: cannot open the window: %s\n", err);
        close_window(&w);
        return 1;
    }
    int rc = loop(v, &w);
    double ms = 0;
    if (rc == 0 && v->script.capture && v->dirty && show_frame(v, &w, &ms, err, sizeof err) != 0) /* keys since */
        fprintf(stderr, "instess: %s\n", err), rc = 1;   /* the last frame: capture their state */
    else if (rc == 0 && v->script.capture && v->overlay_dirty)   /* a refusal at the close: its text */
        compose(&w, v, ms);
    if (rc == 0 && v->script.capture) {
        bool cli = v->hud == VIEW_HUD_OFF && view_frame_is_cli(v);
        if (view_write_png(v, w.shown, cli, v->script.capture, err, sizeof err) != 0)
            fprintf(stderr, "instess: %s\n", err), rc = 1;
    }
    close_window(&w);
    return rc;
}
