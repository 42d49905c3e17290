/* core/device_internal.h -- the device's private state, shared by core/device.c, resources.c and draw.c. */
#ifndef INSTESS_DEVICE_INTERNAL_H
#define INSTESS_DEVICE_INTERNAL_H

#include "core.h"

#include <omp.h>
#include <stdarg.h>

/* Threads when the caller asked for "all cores". */
static inline int omp_threads(void) { return omp_get_num_procs(); }

struct is_vertex_buffer {
    is_device *dev;
    unsigned char *data;
    size_t size;
};

struct is_index_buffer {
    is_device *dev;
    unsigned char *data;
    size_t size;
    is_format format;
};

/* One element, resolved at creation: where it reads and which input register it fills. */
typedef struct decl_element {
    is_vertex_element e;
    unsigned size;          /* bytes read */
    unsigned reg_offset;    /* byte offset of the float4 register inside is_vs_input */
} decl_element;

struct is_vertex_declaration {
    is_device *dev;
    unsigned n;
    decl_element el[IS_MAX_ELEMENTS];
    uint32_t stream_mask;   /* streams the declaration reads */
};

typedef struct stream_source {
    is_vertex_buffer *vb;
    unsigned offset, stride;
    uint32_t freq;          /* as given to SetStreamSourceFreq; 1 by default */
} stream_source;

struct is_device {
    rs_context *rs;
    rs_target rt;
    int threads;
    bool reference;         /* dev_set_reference_path */
    uint32_t rs_state[IS_RS_COUNT];
    is_viewport viewport;
    stream_source streams[IS_MAX_STREAMS];
    is_index_buffer *ib;
    is_vertex_declaration *decl;
    const is_vertex_shader *vs;
    is_vs_constants consts;
    float npatch_segments;
    is_npatch_eval_fn npatch_eval;
    rs_stats stats;
    uint64_t shaded;
    char err[512];
    /* scratch of draw calls, kept between draws (bounded by DRAW_CHUNK_VERTICES) */
    rs_vertex *out_v;
    size_t out_v_cap;
    uint32_t *out_i;
    size_t out_i_cap;
};

/* Record a message for dev_last_error and return code. */
is_result dev_fail(is_device *dev, is_result code, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

/* The rasterizer's copy of the device's render states and viewport. */
rs_state dev_rs_state(const is_device *dev);

/* Expand one element at src into a float4 register (D3D9 defaults fill missing components). */
float4 decl_fetch(uint8_t type, const unsigned char *src);

#endif
