/* src/viewer/page.c - a viewer page on disk: the embedded HTML template filled with the title,
 * the style, the data document (JSON in a <script type="application/json"> element) and the
 * script; base64 data URIs for the images the page carries inside. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "viewer_internal.h"

hv_status vw_page_begin(const hv_viewer_options **opt, hv_viewer_options *defaults, const char *html_path)
{
    if (!*opt) {
        hv_viewer_options_init(defaults);
        *opt = defaults;
    }
    if (!html_path) return hv_error_set(HV_ERR_INVALID, "viewer: no page path");
    hv_status s = hv_options_check(hv_viewer_option_set(), *opt);
    return s == HV_OK ? hv_check_extension(html_path, ".html", "the page") : s;
}

void vw_warn(hv_viewer_report *r, const char *fmt, ...)
{
    if (!r) return;
    size_t n = strlen(r->warnings);
    if (n + 2 >= sizeof r->warnings) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(r->warnings + n, sizeof r->warnings - n - 1, fmt, ap);
    va_end(ap);
    n = strlen(r->warnings);
    r->warnings[n] = '\n';
    r->warnings[n + 1] = '\0';
}

void vw_data_uri(hv_buf *b, const char *mime, const uint8_t *data, size_t size)
{
    hv_buf_printf(b, "data:%s;base64,", mime);
    hv_base64_append(b, data, size);
}

char *vw_json_for_script(const json_t *doc)
{
    char *text = hv_json_dump(doc);
    if (!text) return NULL;
    size_t lt = 0, n = 0;
    for (; text[n]; ++n) lt += text[n] == '<';
    if (!lt) return text;
    char *out = hv_malloc(n + 5 * lt + 1);
    if (!out) {
        free(text);
        return NULL;
    }
    char *o = out;
    for (const char *p = text; *p; ++p) {
        if (*p == '<') { /* only inside strings: JSON has no '<' of its own */
            memcpy(o, "\\u003c", 6);
            o += 6;
        } else {
            *o++ = *p;
        }
    }
    *o = '\0';
    free(text);
    return out;
}

hv_status vw_page_write(const char *path, const char *title, const char *data_json, uint64_t *bytes)
{
    hv_buf b;
    hv_buf_init(&b);
    /* the template's {{name}} marks, in order */
    const char *t = (const char *)vw_asset_page_html;
    for (;;) {
        const char *m = strstr(t, "{{");
        if (!m) {
            hv_buf_puts(&b, t);
            break;
        }
        hv_buf_append(&b, t, (size_t)(m - t));
        const char *e = strstr(m, "}}");
        if (!e) {
            hv_buf_puts(&b, m);
            break;
        }
        size_t n = (size_t)(e - m - 2);
        if (n == 5 && !strncmp(m + 2, "title", 5)) hv_buf_put_escaped(&b, title);
        else if (n == 5 && !strncmp(m + 2, "style", 5)) hv_buf_puts(&b, (const char *)vw_asset_viewer_css);
        else if (n == 4 && !strncmp(m + 2, "data", 4)) hv_buf_puts(&b, data_json);
        else if (n == 6 && !strncmp(m + 2, "script", 6)) hv_buf_puts(&b, (const char *)vw_asset_viewer_js);
        else hv_buf_append(&b, m, (size_t)(e + 2 - m));
        t = e + 2;
    }
    hv_status s = b.failed ? hv_error_set(HV_ERR_NOMEM, "%s: out of memory for the page", path) : HV_OK;
    if (s == HV_OK) s = hv_atomic_write(path, b.data, b.len);
    if (s == HV_OK && bytes) *bytes = b.len;
    hv_buf_free(&b);
    return s;
}
