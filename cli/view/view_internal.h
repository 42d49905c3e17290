/* cli/view/view_internal.h -- `instess view`, private to cli/: the viewer's state and its one key table, shared by
 * the SDL-free half (cli/view/view_state.c: options, keys, frames, HUD text, files; linked into the program) and the
 * window (cli/view/view.c: SDL2 and SDL2_ttf, built as the module libinstess_view.so and opened only by `instess
 * view`, so that no other start of the program loads SDL's fifty libraries).
 *
 * Conventions: a frame is what `instess ... -o` writes for the same options and size (the same render through
 * scene_render_device), drawn again only when the state changed (v->dirty).  Frames are packed RGBA8 with the
 * byte order R, G, B, A in memory (rs_target's, SDL_PIXELFORMAT_RGBA32).  Functions return 0 or -1 with a
 * message in err; what the viewer refuses (a level beyond the limits, a path the patch does not allow) is said
 * in v->status and on stderr, and the state stays as it was. */
#ifndef INSTESS_VIEW_INTERNAL_H
#define INSTESS_VIEW_INTERNAL_H

#include "../run/scene.h"

/* What the frame shows: the colour render, or one AOV mapped to colours, or the crack view (additive coverage,
 * no culling, no depth test: a closed surface covers each pixel an even number of times; odd counts in red). */
typedef enum { VIEW_SHOW_COLOR, VIEW_SHOW_NORMAL, VIEW_SHOW_BARY, VIEW_SHOW_INSTANCE, VIEW_SHOW_GREGORY,
               VIEW_SHOW_CRACKS, VIEW_SHOW_COUNT } view_show;
/* The overlay: none, the HUD, the HUD with the key table. */
typedef enum { VIEW_HUD_OFF, VIEW_HUD_ON, VIEW_HUD_KEYS, VIEW_HUD_COUNT } view_hud;

#define VIEW_PIN_LINES 12   /* the inspector's lines on the HUD */

/* The scripted run (--keys, --frames, --capture, --no-hud). */
typedef struct view_script {
    char keys[64][32];      /* key names (or names joined by '+', pressed together), in order */
    int n_keys;
    int frames;             /* stop after this many frames (0: no limit) */
    const char *capture;    /* write the last frame shown here (PNG) */
    bool pin;               /* --pin X,Y: the inspector's pixel from the first frame */
    int pin_x, pin_y;
} view_script;

typedef struct view_state {
    scene_opts o;           /* the render (the left half when split) */
    vs_patch other;         /* the right half's patch when split */
    bool split;
    view_show show;
    view_hud hud;
    is_mesh mesh;           /* as loaded (its name and hash describe a screenshot) */
    is_mesh fit_copy;       /* scene_fit_mesh's copy, when it made one */
    const is_mesh *draw;    /* the mesh drawn: &mesh or &fit_copy */
    is_image displace_map;  /* --displace's height map, read once (o.displace_map points at it) */
    uint32_t *frame;        /* o.width x o.height: the render, without overlay */
    is_device *dev[2];      /* the devices of the frame's parts (left / whole, right), kept between frames */
    int dev_key[2][4];      /* what each was made for: width, height, samples, view */
    uint64_t triangles;     /* drawn in the last frame */
    double ms_render, ms_setup, ms_tile; /* the last frame: all of it, the set-up regions, the tile passes */
    float times[512][3];    /* per frame (the first 512): render, set-up, tile pass, ms */
    int n_times;
    char status[480];       /* the last refusal or notice ("" if none) */
    int shots;              /* screenshots written */
    bool dirty, quit;
    bool overlay_dirty;     /* the overlay's text changed (a refusal, a notice, h): compose and show the frame
                               again, without rendering it */
    bool size_default;      /* no --size: the window is VIEW_DEFAULT_WIDTH x _HEIGHT (or fits the display) */
    view_script script;
    /* the pipeline inspector (cli/view/view_inspect.c: the I key, a click, --pin X,Y): the pinned pixel of the
     * frame, its history as HUD lines, and the picked instance drawn over the frame */
    bool pinned;
    int pin_x, pin_y;
    char pin_lines[VIEW_PIN_LINES][160];
    int n_pin_lines;
    /* instance-by-instance playback (the X key): o.instances grows by step_speed per frame up to the mesh's
     * triangle count */
    const char *texture_path; /* --texture's file or the mesh's own (u turns o.texture off and on), or NULL */
    bool stepping;
    bool step_drawn;        /* the playback's first frame was drawn */
    unsigned step_speed;
} view_state;

/* One key: the SDL key names it answers to (space-separated, compared case-insensitively: SDL_GetKeyName's
 * "]", "P", "Tab", "Escape"), how the help shows it, what it does, and the action. */
typedef struct view_key {
    const char *names;
    const char *label;
    const char *help;
    void (*action)(view_state *v);
} view_key;
extern const view_key view_keys[];
extern const size_t view_key_count;
/* (cli/view/view_inspect.c) Pin the frame's pixel (x, y) (the window's coordinates; x < 0 unpins): the next frame
 * records it.  After a frame is rendered, view_inspect_frame fills v->pin_lines and draws the picked instance over
 * v->frame when a pixel is pinned; before a frame is rendered, view_step_frame moves the playback on.  The keys' actions: act_inspect
 * (pin the centre, or unpin), act_step (playback on / off), act_step_faster / act_step_slower (its speed). */
void view_pin(view_state *v, int x, int y);
void view_inspect_frame(view_state *v);
void view_step_frame(view_state *v);
void act_inspect(view_state *v);
void act_step(view_state *v);
void act_step_faster(view_state *v);
void act_step_slower(view_state *v);

/* The window's size without --size: room for the split screen's halves, the HUD with the key table and the split
 * labels (the key table's longest line is about 840 pixels wide, the HUD with it about 440 high). */
#define VIEW_DEFAULT_WIDTH 1280
#define VIEW_DEFAULT_HEIGHT 720
/* The key row answering to the SDL key name `name`, or NULL. */
const view_key *view_find_key(const char *name);
/* Apply the key called name (a no-op for keys without a row); true if it had a row. */
bool view_press(view_state *v, const char *name);

/* Mouse: orbit by a drag of (dx, dy) pixels; zoom by wheel steps (positive: closer); a new window size. */
void view_orbit(view_state *v, int dx, int dy);
void view_zoom(view_state *v, int steps);
int view_resize(view_state *v, int width, int height, char *err, size_t errlen);

/* Render v's state into v->frame (timing it); 0 or -1 with a message. */
int view_render(view_state *v, char *err, size_t errlen);
/* Free v's devices, frame and meshes. */
void view_free(view_state *v);
/* The label of the split screen's half `half` (0 left, 1 right): "left: smooth", "right: npatch". */
void view_split_label(const view_state *v, int half, char *buf, size_t len);
/* The overlay's lines for v's state (the HUD, and with VIEW_HUD_KEYS the key table) into lines; their count. */
int view_hud_lines(const view_state *v, double ms_frame, char lines[][160], int max);
/* Write pixels (v's size, RGBA8) to path as PNG, described as the CLI describes its render when cli_equal (the
 * frame is exactly what `instess -o` writes), else as a view frame; 0 or -1 with a message. */
int view_write_png(const view_state *v, const uint32_t *pixels, bool cli_equal, const char *path, char *err,
                   size_t errlen);
/* Whether v->frame is what `instess -o` writes for v->o (no split, the colour view). */
bool view_frame_is_cli(const view_state *v);
/* The `s` key's work: the frame into the next free instess-view-NNNN.png of the current folder. */
void view_screenshot(view_state *v);

/* The module's entry point (cli/view/view.c): run the window until v->quit; the exit code. */
typedef int (*view_module_fn)(view_state *v);
#define VIEW_MODULE "libinstess_view.so"
#define VIEW_MODULE_ENTRY "view_module_run"

#endif
