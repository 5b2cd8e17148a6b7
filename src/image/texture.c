/* src/image/texture.c - pictures read as 8-bit RGBA (hovox/image.h "textures"): PNG through the
 * hostile-input PNG decoder (its iCCP profile found by walking the chunks, PNG 1.2 section 4.2.2.4),
 * JPEG through libjpeg (an error or a warning about damaged data refuses the file; the ICC profile
 * from the APP2 markers, ICC.1:2010 annex B.4). */
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <jpeglib.h>
#include <zlib.h>

#include "core/internal.h"
#include "hovox/image.h"

#define ICC_MAX ((size_t)8 << 20)

void hv_rgba8_free(hv_rgba8 *img)
{
    if (!img) return;
    free(img->rgba);
    free(img->icc);
    memset(img, 0, sizeof *img);
}

static uint32_t be32(const uint8_t *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

/* The profile of a PNG's iCCP chunk (before IDAT), inflated; NULL when there is none or it does not
 * inflate (a damaged profile is ignored as libpng ignores it: the pixels are still sRGB-ish). */
static uint8_t *png_icc(const uint8_t *d, size_t n, size_t *size)
{
    size_t at = 8;
    while (at + 12 <= n) {
        uint32_t len = be32(d + at);
        const uint8_t *type = d + at + 4, *body = d + at + 8;
        if (len > n - at - 12) return NULL;
        if (memcmp(type, "IDAT", 4) == 0 || memcmp(type, "IEND", 4) == 0) return NULL;
        if (memcmp(type, "iCCP", 4) == 0) {
            const uint8_t *z = memchr(body, 0, len < 80 ? len : 80);
            if (!z || (size_t)(z - body) + 2 > len || z[1] != 0) return NULL;
            const uint8_t *comp = z + 2;
            size_t clen = len - (size_t)(comp - body);
            uint8_t *out = malloc(ICC_MAX);
            if (!out) return NULL;
            uLongf olen = ICC_MAX;
            if (uncompress(out, &olen, comp, clen) != Z_OK || olen < 128) {
                free(out);
                return NULL;
            }
            uint8_t *fit = realloc(out, olen);
            *size = olen;
            return fit ? fit : out;
        }
        at += 12 + (size_t)len;
    }
    return NULL;
}

static hv_status decode_png_rgba8(const void *data, size_t size, const char *name, uint64_t max_pixels,
                                  hv_rgba8 *out)
{
    hv_png_pixels p;
    uint64_t max_samples = max_pixels > UINT64_MAX / 4 ? UINT64_MAX : max_pixels * 4;
    hv_status s = hv_png_decode(data, size, name, max_samples, &p);
    if (s != HV_OK) return s;
    if ((uint64_t)p.width * (uint64_t)p.height > max_pixels) {
        s = hv_error_set(HV_ERR_LIMIT, "%s: a picture of %d x %d pixels is larger than allowed here (%llu pixels)",
                         name, p.width, p.height, (unsigned long long)max_pixels);
        hv_png_pixels_free(&p);
        return s;
    }
    size_t np = (size_t)p.width * (size_t)p.height;
    out->rgba = hv_malloc_array(np, 4);
    if (!out->rgba) {
        hv_png_pixels_free(&p);
        return HV_ERR_NOMEM;
    }
    int c = p.channels;
    for (size_t i = 0; i < np; ++i) {
        const uint16_t *q = p.samples + i * (size_t)c;
        uint8_t v[4] = {0, 0, 0, 255};
        for (int k = 0; k < c && k < 4; ++k)
            v[k] = p.bit_depth == 16 ? (uint8_t)(((uint32_t)q[k] * 255u + 32767u) / 65535u) : (uint8_t)q[k];
        uint8_t *o = out->rgba + 4 * i;
        if (c <= 2) {
            o[0] = o[1] = o[2] = v[0];
            o[3] = c == 2 ? v[1] : 255;
        } else {
            o[0] = v[0];
            o[1] = v[1];
            o[2] = v[2];
            o[3] = c == 4 ? v[3] : 255;
        }
    }
    out->width = p.width;
    out->height = p.height;
    hv_png_pixels_free(&p);
    out->icc = png_icc(data, size, &out->icc_size);
    return HV_OK;
}

/* ---- JPEG ------------------------------------------------------------------------------------ */

typedef struct jpeg_err {
    struct jpeg_error_mgr mgr;
    jmp_buf jump;
    char msg[JMSG_LENGTH_MAX];
    int warned;
} jpeg_err;

static void jpeg_fail(j_common_ptr cinfo)
{
    jpeg_err *e = (jpeg_err *)cinfo->err;
    if (!e->msg[0]) (*cinfo->err->format_message)(cinfo, e->msg);
    longjmp(e->jump, 1);
}

/* Warnings (level -1) are damaged data libjpeg would paper over (a truncated file becomes grey):
 * the first is kept and refuses the file. Trace messages are dropped. */
static void jpeg_note(j_common_ptr cinfo, int level)
{
    jpeg_err *e = (jpeg_err *)cinfo->err;
    if (level == -1 && !e->warned) {
        e->warned = 1;
        if (!e->msg[0]) (*cinfo->err->format_message)(cinfo, e->msg);
    }
}

typedef struct jpeg_job {
    struct jpeg_decompress_struct cinfo;
    jpeg_err err;
    uint8_t *rgba;
    JOCTET *icc;
} jpeg_job;

static hv_status decode_jpeg(jpeg_job *j, const void *data, size_t size, const char *name, uint64_t max_pixels,
                             hv_rgba8 *out)
{
    struct jpeg_decompress_struct *ci = &j->cinfo;
    if (setjmp(j->err.jump))
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: not a readable JPEG: %s", name, j->err.msg);
    jpeg_mem_src(ci, (const unsigned char *)data, (unsigned long)size);
    jpeg_save_markers(ci, JPEG_APP0 + 2, 0xFFFF);
    jpeg_read_header(ci, TRUE);
    if (ci->jpeg_color_space == JCS_CMYK || ci->jpeg_color_space == JCS_YCCK)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: a CMYK JPEG (textures are RGB or grey)", name);
    if ((uint64_t)ci->image_width * ci->image_height > max_pixels)
        return hv_error_set(HV_ERR_LIMIT, "%s: a picture of %u x %u pixels is larger than allowed here (%llu pixels)",
                            name, (unsigned)ci->image_width, (unsigned)ci->image_height,
                            (unsigned long long)max_pixels);
    unsigned int icc_len = 0;
    if (jpeg_read_icc_profile(ci, &j->icc, &icc_len) && icc_len > 0 && icc_len <= ICC_MAX) {
        out->icc = hv_malloc(icc_len);
        if (!out->icc) return HV_ERR_NOMEM;
        memcpy(out->icc, j->icc, icc_len);
        out->icc_size = icc_len;
    }
    ci->out_color_space = JCS_EXT_RGBA;
    jpeg_start_decompress(ci);
    size_t w = ci->output_width, h = ci->output_height;
    j->rgba = hv_malloc_array(w * h, 4);
    if (!j->rgba) return HV_ERR_NOMEM;
    while (ci->output_scanline < ci->output_height) {
        JSAMPROW row = j->rgba + (size_t)ci->output_scanline * w * 4;
        jpeg_read_scanlines(ci, &row, 1);
    }
    jpeg_finish_decompress(ci);
    if (j->err.warned) return hv_error_set(HV_ERR_BAD_INPUT, "%s: not a readable JPEG: %s", name, j->err.msg);
    out->width = (int)w;
    out->height = (int)h;
    out->rgba = j->rgba;
    j->rgba = NULL;
    return HV_OK;
}

hv_status hv_rgba8_decode(const void *data, size_t size, const char *name, uint64_t max_pixels, hv_rgba8 *out)
{
    memset(out, 0, sizeof *out);
    const uint8_t *d = data;
    hv_status s;
    if (size >= 8 && memcmp(d, "\x89PNG\r\n\x1a\n", 8) == 0) {
        s = decode_png_rgba8(data, size, name, max_pixels, out);
    } else if (size >= 3 && d[0] == 0xFF && d[1] == 0xD8 && d[2] == 0xFF) {
        jpeg_job *j = hv_calloc(1, sizeof *j);
        if (!j) return HV_ERR_NOMEM;
        j->cinfo.err = jpeg_std_error(&j->err.mgr);
        j->err.mgr.error_exit = jpeg_fail;
        j->err.mgr.emit_message = jpeg_note;
        jpeg_create_decompress(&j->cinfo);
        s = decode_jpeg(j, data, size, name, max_pixels, out);
        jpeg_destroy_decompress(&j->cinfo);
        free(j->rgba);
        free(j->icc);
        free(j);
    } else {
        s = hv_error_set(HV_ERR_BAD_INPUT, "%s: not an image (neither PNG nor JPEG)", name);
    }
    if (s != HV_OK) hv_rgba8_free(out);
    return s;
}
