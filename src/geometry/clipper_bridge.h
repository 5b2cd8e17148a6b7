/* src/geometry/clipper_bridge.h - the function table between the solid (src/geometry/solid.c)
 * and the Clipper bridge plugin (src/geometry/clipper_bridge.cpp, built as
 * plugins/hovox-clipper.so): Angus Johnson's Clipper 6 (Debian libpolyclipping), the polygon
 * Booleans slicers such as PrusaSlicer use, on integer coordinates. Internal. The plugin does not
 * link libhovox; on failure its last_error() holds the message. No exception crosses the table. */
#ifndef HOVOX_CLIPPER_BRIDGE_H
#define HOVOX_CLIPPER_BRIDGE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define HV_CLIPPER_ABI 1
#define HV_CLIPPER_ENTRY "hv_clipper_plugin_v1"

enum { HV_CLIP_INTERSECTION = 0, HV_CLIP_UNION = 1, HV_CLIP_DIFFERENCE = 2 };

/* Closed polygons: n of them, polygon i has count[i] points at xy[i] (x0, y0, x1, ...). */
typedef struct hv_clip_paths {
    size_t n;
    const size_t *count;
    const int64_t *const *xy;
} hv_clip_paths;

/* Receives each polygon of a result (outer boundaries with positive area, holes negative); a
 * nonzero return stops the call, which then returns it. */
typedef int (*hv_clip_out_fn)(void *user, size_t count, const int64_t *xy);

typedef struct hv_clipper_api {
    int abi;
    const char *(*last_error)(void);
    /* subject op clip, both filled by the nonzero rule (clip may be empty: then a union cleans
     * the subject alone). |coordinates| must stay below 2^62. */
    int (*boolean)(int op, const hv_clip_paths *subject, const hv_clip_paths *clip, hv_clip_out_fn out, void *user);
} hv_clipper_api;

#ifdef __cplusplus
}
#endif
#endif
