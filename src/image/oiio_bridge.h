/* src/image/oiio_bridge.h - the function table between the C image writer (image.c) and the
 * OpenImageIO bridge plugin (oiio_bridge.cpp, built as plugins/hovox-oiio.so and loaded only
 * when an EXR or TIFF is requested). Internal: callers use hovox/render.h. Every entry returns
 * an hv_status; on failure the plugin's last_error() holds the message. No C++ exception
 * crosses this table. */
#ifndef HOVOX_OIIO_BRIDGE_H
#define HOVOX_OIIO_BRIDGE_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#define HV_OIIO_ABI 1

enum { HV_OIIO_UINT8 = 0, HV_OIIO_HALF = 1, HV_OIIO_FLOAT = 2 };

typedef struct hv_oiio_api {
    int abi;
    const char *(*last_error)(void);
    /* Write `channels` interleaved float channels (rows top to bottom) to `path` in the file
     * format `format` (an OpenImageIO format or extension name: "exr", "tiff"), stored as
     * `type` (HV_OIIO_*). unassociated_alpha: the pixels carry straight alpha and the file
     * must say so (TIFF ExtraSamples). */
    int (*write)(const char *path, const char *format, int width, int height, int channels,
                 const float *pixels, int type, int unassociated_alpha);
} hv_oiio_api;

/* The plugin's one exported symbol. */
typedef const hv_oiio_api *(*hv_oiio_entry_fn)(void);
#define HV_OIIO_ENTRY "hv_oiio_plugin_v1"

#ifdef __cplusplus
}
#endif
#endif
