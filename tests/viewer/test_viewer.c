/* tests/viewer/test_viewer.c - viewer pages (hovox/viewer.h): the manifest reader against good
 * and damaged manifests, outlines against a brute-force point-in-polygon count, base64 against
 * RFC 4648's vectors, the data a page carries against the layers read by an independent libpng
 * reader (side views, outlines, palette), a model page's slices against the voxels, the
 * sample budget, and errors that leave nothing written. */
#include <criterion/criterion.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <zlib.h>

#include "core/internal.h"
#include "core/json.h"
#include "hovox/generate.h"
#include "hovox/image.h"
#include "hovox/layers.h"
#include "hovox/material.h"
#include "hovox/tray.h"
#include "hovox/viewer.h"
#include "hovox/voxelize.h"
#include "support/support.h"
#include "viewer/viewer_internal.h"

/* ---- helpers ------------------------------------------------------------------------------------ */

/* The data document a page carries (parsed). */
static json_t *page_data(const char *path)
{
    size_t n = 0;
    char *html = t_slurp(path, &n);
    const char *tag = "<script type=\"application/json\" id=\"hovox-data\">";
    char *a = strstr(html, tag);
    cr_assert(a, "%s: no data element", path);
    a += strlen(tag);
    char *b = strstr(a, "</script>");
    cr_assert(b, "%s: the data element is not closed", path);
    for (const char *p = a; p < b; ++p) cr_assert(*p != '<', "%s: a '<' inside the data", path);
    json_t *d = NULL;
    cr_assert_eq(hv_json_parse(a, (size_t)(b - a), "data", &d), HV_OK, "%s", hv_last_error());
    free(html);
    return d;
}

/* Decode "data:image/png;base64,..." with hv_png_decode. */
static int b64v(char c)
{
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    return c == '+' ? 62 : c == '/' ? 63 : -1;
}

static uint8_t *b64_decode(const char *s, size_t *n)
{
    size_t len = strlen(s);
    uint8_t *out = malloc(len * 3 / 4 + 3);
    size_t o = 0;
    uint32_t acc = 0;
    int bits = 0;
    for (size_t i = 0; i < len && s[i] != '='; ++i) {
        int v = b64v(s[i]);
        cr_assert(v >= 0, "base64: bad character %c", s[i]);
        acc = acc << 6 | (uint32_t)v;
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            out[o++] = (uint8_t)(acc >> bits);
        }
    }
    *n = o;
    return out;
}

static void uri_png(const char *uri, hv_png_pixels *px)
{
    const char *pre = "data:image/png;base64,";
    cr_assert(strncmp(uri, pre, strlen(pre)) == 0, "not a PNG data URI");
    size_t n;
    uint8_t *bytes = b64_decode(uri + strlen(pre), &n);
    cr_assert_eq(hv_png_decode(bytes, n, "uri", 1 << 28, px), HV_OK, "%s", hv_last_error());
    free(bytes);
}

static const json_t *get(const json_t *o, const char *k)
{
    const json_t *v = json_object_get(o, k);
    cr_assert(v, "no %s", k);
    return v;
}
static long long iget(const json_t *o, const char *k) { return json_integer_value(get(o, k)); }

static hv_layers_options lopts(hv_layers_mode mode, double dx, double dy, double h)
{
    hv_layers_options o;
    hv_layers_options_init(&o);
    o.mode = mode;
    o.profile = "test";
    o.dpi[0] = dx;
    o.dpi[1] = dy;
    o.layer_height = h;
    o.cache_dir = t_tmpfile("bncache");
    return o;
}

/* a box 10 x 6 x 3 mm graded along x from A to B (0.5 mm voxels) */
static hv_volume *graded_box(const hv_mesh *m)
{
    hv_voxelize_options vo;
    hv_voxelize_options_init(&vo);
    vo.voxel_size[0] = vo.voxel_size[1] = vo.voxel_size[2] = 0.5;
    hv_volume *v = NULL;
    cr_assert_eq(hv_voxelize(m, &vo, &v), HV_OK, "%s", hv_last_error());
    hv_material_table *t = NULL;
    cr_assert_eq(hv_material_table_create(&t), HV_OK);
    float ca[4] = {0.9f, 0.2f, 0.1f, 1}, cb[4] = {0.1f, 0.3f, 0.9f, 1};
    cr_assert_eq(hv_material_add(t, "A", ca, NULL), HV_OK);
    cr_assert_eq(hv_material_add(t, "B", cb, NULL), HV_OK);
    double p0[3] = {0, 0, 0}, nx[3] = {1, 0, 0}, ms[2] = {1, 0}, me[2] = {0, 1};
    hv_frf *frf = NULL;
    cr_assert_eq(hv_frf_plane(p0, nx, &frf), HV_OK);
    hv_dfn *fn = NULL;
    cr_assert_eq(hv_dfn_linear(0.1, 0, &fn), HV_OK);
    hv_ags_desc d = {frf, 0, 10, 0, fn, ms, me, 2, NULL};
    hv_ags *ags = NULL;
    cr_assert_eq(hv_ags_create(&d, &ags), HV_OK, "%s", hv_last_error());
    hv_object *o = NULL;
    cr_assert_eq(hv_object_create(v, "occupancy", 2, &o), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_object_add_ags(o, ags), HV_OK);
    hv_volume *g = NULL;
    cr_assert_eq(hv_object_evaluate(o, t, 0, NULL, &g), HV_OK, "%s", hv_last_error());
    hv_object_destroy(o);
    hv_ags_release(ags);
    hv_dfn_destroy(fn);
    hv_frf_release(frf);
    hv_material_table_destroy(t);
    hv_volume_destroy(v);
    return g;
}

static void write_stack(const char *dir, hv_layers_mode mode, double dx, double dy, double h)
{
    double lo[3] = {0, 0, 0}, hi[3] = {10, 6, 3};
    hv_mesh *m = t_box_mesh(lo, hi);
    hv_volume *g = mode == HV_LAYERS_MASK ? NULL : graded_box(m);
    hv_layers_options o = lopts(mode, dx, dy, h);
    cr_assert_eq(hv_layers_write(m, g, dir, &o, NULL, NULL), HV_OK, "%s", hv_last_error());
    hv_volume_destroy(g);
    hv_mesh_destroy(m);
}

/* ---- paths, colours, base64, script-safe JSON ------------------------------------------------------ */

Test(viewer, paths_inside_the_stack)
{
    const char *ok[] = {"layer-00000.png", "A/layer-00001.png", "a b/c#d?.png", "x..y/z", NULL};
    const char *bad[] = {"", "/etc/passwd", "../x.png", "a/../b", "a/./b", ".", "a//b", "a/", "a\\b", "a\nb",
                         "\x7f", NULL};
    for (int i = 0; ok[i]; ++i) cr_expect(vw_path_ok(ok[i]), "%s refused", ok[i]);
    for (int i = 0; bad[i]; ++i) cr_expect(!vw_path_ok(bad[i]), "'%s' accepted", bad[i]);
    uint8_t rgb[3];
    cr_expect(vw_color_parse("#1f77B4", rgb) && rgb[0] == 0x1f && rgb[1] == 0x77 && rgb[2] == 0xb4);
    cr_expect(!vw_color_parse("#1f77b", rgb) && !vw_color_parse("red", rgb) && !vw_color_parse("#1f77bg", rgb) &&
              !vw_color_parse("#1f77b4ff", rgb) && !vw_color_parse("#1f77b4\");x", rgb));
}

Test(viewer, base64_rfc4648_vectors)
{
    const char *in[] = {"", "f", "fo", "foo", "foob", "fooba", "foobar"};
    const char *out[] = {"", "Zg==", "Zm8=", "Zm9v", "Zm9vYg==", "Zm9vYmE=", "Zm9vYmFy"};
    for (int i = 0; i < 7; ++i) {
        hv_buf b;
        hv_buf_init(&b);
        vw_data_uri(&b, "text/plain", (const uint8_t *)in[i], strlen(in[i]));
        char want[64];
        snprintf(want, sizeof want, "data:text/plain;base64,%s", out[i]);
        cr_expect_str_eq(b.data, want);
        hv_buf_free(&b);
    }
    /* every byte value, and back */
    uint8_t all[256];
    for (int i = 0; i < 256; ++i) all[i] = (uint8_t)i;
    hv_buf b;
    hv_buf_init(&b);
    vw_data_uri(&b, "x/y", all, sizeof all);
    size_t n;
    uint8_t *back = b64_decode(b.data + strlen("data:x/y;base64,"), &n);
    cr_expect(n == 256 && memcmp(back, all, 256) == 0);
    free(back);
    hv_buf_free(&b);
}

Test(viewer, json_in_a_script_cannot_close_it)
{
    json_t *d = json_pack("{s:s, s:[s]}", "title", "</script><script>alert(1)</script>", "x", "<!-- a < b");
    char *t = vw_json_for_script(d);
    cr_assert(t);
    cr_expect(!strchr(t, '<'), "a '<' in %s", t);
    json_t *back = NULL;
    cr_assert_eq(hv_json_parse(t, strlen(t), "back", &back), HV_OK);
    cr_expect(json_equal(d, back), "the text reads back the same");
    json_decref(back);
    json_decref(d);
    free(t);
}

Test(viewer, assets_are_whole)
{
    const char *js = (const char *)vw_asset_viewer_js, *css = (const char *)vw_asset_viewer_css,
               *html = (const char *)vw_asset_page_html;
    cr_expect(strlen(js) > 1000 && strlen(css) > 500 && strstr(html, "{{data}}") && strstr(html, "{{script}}"));
    /* inserted verbatim into <script> and <style>: they must not end them */
    cr_expect(!strstr(js, "</"), "the script holds '</'");
    cr_expect(!strstr(css, "</"), "the style holds '</'");
    cr_expect(!strstr(js, "<!--"), "the script holds '<!--'");
    cr_expect(strstr(html, "Content-Security-Policy") && strstr(html, "default-src 'none'"),
              "the page refuses the network");
}

/* ---- outlines ---------------------------------------------------------------------------------------- */

/* winding number of point (px, py) about the loops */
static int winding(const int32_t *xy, const size_t *st, size_t nl, double px, double py)
{
    int w = 0;
    for (size_t l = 0; l < nl; ++l) {
        size_t n = st[l + 1] - st[l];
        for (size_t k = 0; k < n; ++k) {
            const int32_t *a = xy + 2 * (st[l] + k), *b = xy + 2 * (st[l] + (k + 1) % n);
            if (a[0] != b[0]) continue; /* only vertical edges cross a horizontal ray */
            double ylo = HV_MIN(a[1], b[1]), yhi = HV_MAX(a[1], b[1]);
            if (py >= ylo && py < yhi && a[0] > px) w += b[1] > a[1] ? 1 : -1;
        }
    }
    return w;
}

Test(viewer, outlines_enclose_exactly_the_set_cells)
{
    uint64_t seed = 12345;
    for (int trial = 0; trial < 60; ++trial) {
        int w = 1 + trial % 13, h = 1 + (trial * 7) % 11;
        uint8_t *cells = malloc((size_t)w * h);
        for (int i = 0; i < w * h; ++i) {
            seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
            cells[i] = (uint8_t)((seed >> 33) % 100 < (uint64_t)(20 + trial));
        }
        int32_t *xy;
        size_t *st, nl;
        cr_assert_eq(vw_outline_trace(cells, w, h, &xy, &st, &nl), HV_OK);
        for (size_t l = 0; l < nl; ++l) {
            size_t n = st[l + 1] - st[l];
            cr_expect(n >= 4 && n % 2 == 0, "loop %zu has %zu corners", l, n);
            for (size_t k = 0; k < n; ++k) { /* axis-aligned, no collinear corners */
                const int32_t *a = xy + 2 * (st[l] + k), *b = xy + 2 * (st[l] + (k + 1) % n),
                              *c = xy + 2 * (st[l] + (k + 2) % n);
                cr_expect(a[0] == b[0] || a[1] == b[1]);
                cr_expect(!((a[0] == b[0] && b[0] == c[0]) || (a[1] == b[1] && b[1] == c[1])), "collinear corner");
            }
        }
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                int wn = winding(xy, st, nl, x + 0.5, y + 0.5);
                cr_expect_eq(wn != 0, cells[y * w + x] != 0, "trial %d: cell (%d, %d) set %d, winding %d", trial, x, y,
                             cells[y * w + x], wn);
                cr_expect(wn == 0 || wn == 1 || wn == -1);
            }
        free(cells);
        free(xy);
        free(st);
    }
    /* diagonal neighbours are two loops; a ring is an outer loop and a hole */
    uint8_t diag[4] = {1, 0, 0, 1}, ring[9] = {1, 1, 1, 1, 0, 1, 1, 1, 1};
    int32_t *xy;
    size_t *st, nl;
    cr_assert_eq(vw_outline_trace(diag, 2, 2, &xy, &st, &nl), HV_OK);
    cr_expect_eq(nl, 2);
    free(xy);
    free(st);
    cr_assert_eq(vw_outline_trace(ring, 3, 3, &xy, &st, &nl), HV_OK);
    cr_expect_eq(nl, 2);
    free(xy);
    free(st);
}

/* ---- the manifest -------------------------------------------------------------------------------------- */

static const char *k_good =
    "{\"generator\": \"hovox 0.1.0\", \"mode\": \"halftone\", \"dpi\": [100, 50], \"layer_height_mm\": 0.5,"
    " \"width\": 4, \"height\": 3, \"bit_depth\": 2, \"pixel_mm\": [0.254, -0.508], \"origin_mm\": [0, 1.524],"
    " \"mesh\": \"dir/b.stl\","
    " \"materials\": [{\"name\": \"A\", \"palette_index\": 1, \"color\": \"#ff0000\", \"target\": 0.5}],"
    " \"layers\": [{\"index\": 0, \"file\": \"layer-00000.png\", \"z_mm\": 0.25},"
    "              {\"index\": 1, \"file\": \"layer-00001.png\", \"z_mm\": 0.75}]}";

static hv_status parse_with(const char *from, const char *to, vw_stack *s)
{
    char text[4096];
    const char *at = from ? strstr(k_good, from) : NULL;
    if (from) cr_assert(at, "'%s' not in the good manifest", from);
    if (at) snprintf(text, sizeof text, "%.*s%s%s", (int)(at - k_good), k_good, to, at + strlen(from));
    else snprintf(text, sizeof text, "%s", k_good);
    return vw_stack_parse(text, strlen(text), "m.json", s);
}

Test(viewer, manifest_good)
{
    vw_stack s;
    cr_assert_eq(parse_with(NULL, NULL, &s), HV_OK, "%s", hv_last_error());
    cr_expect(s.mode == HV_LAYERS_HALFTONE && s.width == 4 && s.height == 3 && s.nlayers == 2 && s.channels == 1);
    cr_expect_str_eq(s.files[1], "layer-00001.png");
    cr_expect(s.nparts == 1 && s.parts[0].box[2] == 4 && s.parts[0].l1 == 2);
    cr_expect_str_eq(s.parts[0].name, "b.stl");
    vw_stack_free(&s);
}

Test(viewer, manifest_damaged)
{
    struct {
        const char *from, *to, *msg;
    } k[] = {
        {"\"generator\": \"hovox 0.1.0\"", "\"generator\": \"slic3r\"", "not hovox"},
        {"\"generator\": \"hovox 0.1.0\", ", "", "generator is missing"},
        {"\"halftone\"", "\"rgb\"", "mode \"rgb\""},
        {"\"width\": 4", "\"width\": 0", "width is 0"},
        {"\"width\": 4", "\"width\": \"4\"", "width is a string"},
        {"\"bit_depth\": 2", "\"bit_depth\": 3", "bit_depth 3"},
        {"[0.254, -0.508]", "[0, -0.508]", "pixel_mm"},
        {"\"layer-00001.png\"", "\"../../etc/passwd\"", "not a path inside the stack"},
        {"\"layer-00001.png\"", "\"/etc/passwd\"", "not a path inside the stack"},
        {"\"index\": 1", "\"index\": 0", "does not follow"},
        {"\"#ff0000\"", "\"red\"", "is not #rrggbb"},
        {"\"palette_index\": 1", "\"palette_index\": 0", "palette_index"},
        {"{\"index\": 0, \"file\"", "{\"file\"", "layers[0]: index is missing"},
        {"\"layers\": [", "\"layerz\": [", "layers is missing"},
        {"\"z_mm\": 0.75", "\"z_mm\": 1e300", "z_mm"},
        {"0.75}]}", "0.75}]", "line 1"},
    };
    for (size_t i = 0; i < sizeof k / sizeof k[0]; ++i) {
        vw_stack s;
        hv_status st = parse_with(k[i].from, k[i].to, &s);
        cr_expect_eq(st, HV_ERR_BAD_INPUT, "case %zu (%s) accepted", i, k[i].msg);
        cr_expect(strstr(hv_last_error(), k[i].msg) && strstr(hv_last_error(), "m.json"), "case %zu: '%s' lacks '%s'",
                  i, hv_last_error(), k[i].msg);
    }
    vw_stack s;
    cr_expect_eq(vw_stack_parse("[1, 2]", 6, "a.json", &s), HV_ERR_BAD_INPUT);
    cr_expect(strstr(hv_last_error(), "a.json: not a JSON object"), "%s", hv_last_error());
    char tray[1024];
#define TRAY_FMT "{\"generator\": \"hovox\", \"kind\": \"tray\", \"mode\": \"%s\", \"width\": 10," \
                      " \"height\": 10, \"bit_depth\": 2, \"dpi\": [600, 300], \"layer_height_mm\": 0.027," \
                      " \"plate_mm\": [490, 390], \"layers_total\": 9, \"first\": 2, \"last\": 5," \
                      " \"palette\": [{\"index\": 0, \"resin\": null, \"color\": \"#000000\"}," \
                      " {\"index\": 1, \"resin\": \"X\", \"color\": \"#ffffff\"}]," \
                      " \"parts\": [{\"name\": \"p\", \"copy\": 1, \"image_px\": [%d, 5, 6, 2]," \
                      " \"box_mm\": [0, 0, 1, 1], \"layers\": [3, 9], \"materials\": {}}]}"
    snprintf(tray, sizeof tray, TRAY_FMT, "halftone", 4);
    cr_assert_eq(vw_stack_parse(tray, strlen(tray), "t.json", &s), HV_OK, "%s", hv_last_error());
    cr_expect(s.tray && s.nlayers == 3 && s.index[0] == 2 && s.nparts == 1);
    cr_expect_str_eq(s.files[2], "layer-00004.png");
    cr_expect(s.parts[0].l0 == 1 && s.parts[0].l1 == 3, "the part's layers 3..8 among 2..4 written: positions 1, 2");
    cr_expect(fabs(s.pixel_mm[0] - 25.4 / 600) < 1e-12 && fabs(s.pixel_mm[1] + 25.4 / 300) < 1e-12 &&
              s.origin_mm[1] == 390);
    vw_stack_free(&s);
    snprintf(tray, sizeof tray, TRAY_FMT, "halftone", 5);
    cr_expect_eq(vw_stack_parse(tray, strlen(tray), "t.json", &s), HV_ERR_BAD_INPUT);
    cr_expect(strstr(hv_last_error(), "not inside the 10 x 10 plate"), "%s", hv_last_error());
    /* a tray is halftone or mask: fractions, a mode of layers, is refused (issue 26 item 5: the
     * modes are read by hv_layers_mode_parse, the spelling hv_layers_mode_name writes) */
    snprintf(tray, sizeof tray, TRAY_FMT, "fractions", 4);
#undef TRAY_FMT
    cr_expect_eq(vw_stack_parse(tray, strlen(tray), "t.json", &s), HV_ERR_BAD_INPUT);
    cr_expect(strstr(hv_last_error(), "t.json: mode \"fractions\" is not halftone or mask"), "%s", hv_last_error());
    for (int m = HV_LAYERS_HALFTONE; m <= HV_LAYERS_MASK; ++m) {
        hv_layers_mode back = (hv_layers_mode)-1;
        cr_expect_eq(hv_layers_mode_parse(hv_layers_mode_name((hv_layers_mode)m), &back), HV_OK);
        cr_expect_eq(back, m);
    }
    cr_expect_eq(hv_layers_mode_parse("blue-noise", &(hv_layers_mode){0}), HV_ERR_INVALID);
}

/* ---- a stack's page ------------------------------------------------------------------------------------ */

/* The cut images against the layers read by libpng (tests/support), and the outline against the union. */
static void check_stack_page(const char *dir, const char *page)
{
    json_t *d = page_data(page);
    int W = (int)iget(d, "width"), H = (int)iget(d, "height"), step = (int)iget(d, "cut_step");
    const json_t *files = json_array_get(get(d, "files"), 0);
    size_t N = json_array_size(files);
    cr_assert(N > 0);
    int channels = (int)json_array_size(get(d, "files"));
    /* every layer of every channel, read by the independent reader */
    t_png *L = calloc(N * (size_t)channels, sizeof *L);
    uint8_t *uni = calloc((size_t)W * H, 1);
    for (int ch = 0; ch < channels; ++ch)
        for (size_t i = 0; i < N; ++i) {
            char path[2048];
            snprintf(path, sizeof path, "%s/%s", dir, json_string_value(json_array_get(json_array_get(get(d, "files"), (size_t)ch), i)));
            t_png_load(path, &L[(size_t)ch * N + i]);
            cr_assert(L[(size_t)ch * N + i].w == W && L[(size_t)ch * N + i].h == H);
            for (int p = 0; p < W * H; ++p) uni[p] |= L[(size_t)ch * N + i].px[p] != 0;
        }
    const json_t *cuts = get(d, "cuts");
    cr_assert(json_array_size(cuts) > 0);
    for (size_t c = 0; c < json_array_size(cuts); ++c) {
        const json_t *C = json_array_get(cuts, c);
        int row = strcmp(json_string_value(get(C, "axis")), "row") == 0;
        int pos = (int)iget(C, "pos"), from = (int)iget(C, "from"), to = (int)iget(C, "to");
        int w = (int)iget(C, "w"), h = (int)iget(C, "h"), l0 = (int)iget(C, "l0"), l1 = (int)iget(C, "l1");
        cr_assert_eq(w, (to - from + step - 1) / step);
        cr_assert_eq(h, (l1 - l0 + step - 1) / step);
        for (int ch = 0; ch < channels; ++ch) {
            hv_png_pixels px;
            uri_png(json_string_value(json_array_get(get(C, "images"), (size_t)ch)), &px);
            cr_assert(px.width == w && px.height == h);
            for (int k = 0; k < h; ++k) {
                int la = l0 + k * step, li = la + (HV_MIN(step, l1 - la) - 1) / 2;
                const t_png *im = &L[(size_t)ch * N + (size_t)li];
                for (int t = 0; t < w; ++t) {
                    int a = from + t * step, along = a + (HV_MIN(step, to - a) - 1) / 2;
                    int x = row ? along : pos, y = row ? pos : along;
                    unsigned v = im->px[(size_t)y * W + x];
                    /* the page's image: grey (mask: 0/255 after widening) or the palette's colour */
                    const uint16_t *s = px.samples + ((size_t)(h - 1 - k) * w + t) * px.channels;
                    if (im->color_type == 3) {
                        cr_assert(s[0] == im->pal[3 * v] && s[1] == im->pal[3 * v + 1] && s[2] == im->pal[3 * v + 2],
                                  "cut %zu sample (%d, %d): colour of index %u", c, t, k, v);
                    } else {
                        unsigned want = im->bit_depth == 1 ? v * 255u : v;
                        cr_assert_eq(s[0], want, "cut %zu sample (%d, %d)", c, t, k);
                    }
                }
            }
            hv_png_pixels_free(&px);
        }
    }
    /* the outline of each part encloses its union of object pixels (cells of one pixel here) */
    const json_t *parts = get(d, "parts");
    for (size_t p = 0; p < json_array_size(parts); ++p) {
        const json_t *P = json_array_get(parts, p), *ol = get(P, "outline");
        size_t nl = json_array_size(ol), tot = 0;
        for (size_t l = 0; l < nl; ++l) tot += json_array_size(json_array_get(ol, l)) / 2;
        int32_t *xy = malloc((tot + 1) * 2 * sizeof *xy);
        size_t *st = malloc((nl + 1) * sizeof *st), k = 0;
        for (size_t l = 0; l < nl; ++l) {
            st[l] = k;
            const json_t *a = json_array_get(ol, l);
            for (size_t i = 0; i + 1 < json_array_size(a); i += 2, ++k) {
                xy[2 * k] = (int32_t)json_integer_value(json_array_get(a, i));
                xy[2 * k + 1] = (int32_t)json_integer_value(json_array_get(a, i + 1));
            }
        }
        st[nl] = k;
        const json_t *box = get(P, "box_px");
        int c0 = (int)json_integer_value(json_array_get(box, 0)), r0 = (int)json_integer_value(json_array_get(box, 1));
        int bw = (int)json_integer_value(json_array_get(box, 2)), bh = (int)json_integer_value(json_array_get(box, 3));
        for (int y = r0; y < r0 + bh; ++y)
            for (int x = c0; x < c0 + bw; ++x)
                cr_assert_eq(winding(xy, st, nl, x + 0.5, y + 0.5) != 0, uni[(size_t)y * W + x],
                             "part %zu: pixel (%d, %d)", p, x, y);
        free(xy);
        free(st);
    }
    for (size_t i = 0; i < N * (size_t)channels; ++i) free(L[i].px);
    free(L);
    free(uni);
    json_decref(d);
}

Test(viewer, halftone_stack_page, .timeout = 300)
{
    const char *dir = t_tmpfile("ht");
    write_stack(dir, HV_LAYERS_HALFTONE, 100, 50, 0.5);
    char page[1024];
    snprintf(page, sizeof page, "%s/index.html", dir);
    hv_viewer_report r;
    cr_assert_eq(hv_viewer_stack_write(dir, page, NULL, NULL, &r), HV_OK, "%s", hv_last_error());
    cr_expect(r.kind == HV_VIEWER_STACK && strcmp(r.mode, "halftone") == 0 && r.cut_step == 1 && r.base[0] == '\0');
    cr_expect(r.cut_rows == HV_MIN(32, r.height) && r.cut_cols == HV_MIN(32, r.width));
    cr_expect_str_eq(r.warnings, "");
    check_stack_page(dir, page);
    /* the palette is the layers' (background first), named from the manifest */
    json_t *d = page_data(page);
    const json_t *pal = get(d, "palette");
    cr_expect_eq(json_array_size(pal), 3);
    cr_expect_str_eq(json_string_value(get(json_array_get(pal, 1), "name")), "A");
    cr_expect_str_eq(json_string_value(get(json_array_get(pal, 2), "name")), "B");
    cr_expect_str_eq(json_string_value(get(d, "title")), "ht");
    json_decref(d);
    /* a page elsewhere reaches the stack by a relative path */
    const char *other = t_tmpfile("pages");
    mkdir(other, 0777);
    char p2[1024];
    snprintf(p2, sizeof p2, "%s/view.html", other);
    cr_assert_eq(hv_viewer_stack_write(dir, p2, NULL, NULL, &r), HV_OK, "%s", hv_last_error());
    cr_expect_str_eq(r.base, "../ht/");
    /* a small budget: fewer cuts, then every s-th pixel and layer, and still the layers' values */
    hv_viewer_options o;
    hv_viewer_options_init(&o);
    o.max_samples = 10000;
    cr_assert_eq(hv_viewer_stack_write(dir, page, &o, NULL, &r), HV_OK, "%s", hv_last_error());
    cr_expect(r.samples <= 10000 || (r.cut_rows <= 4 && r.cut_cols <= 4), "samples %llu", (unsigned long long)r.samples);
    cr_expect(r.cut_step > 1 || r.cut_rows < 32);
    check_stack_page(dir, page);
}

Test(viewer, fractions_and_mask_stack_pages, .timeout = 300)
{
    const char *fr = t_tmpfile("fr"), *mk = t_tmpfile("mk");
    write_stack(fr, HV_LAYERS_FRACTIONS, 50, 50, 1);
    write_stack(mk, HV_LAYERS_MASK, 50, 50, 1);
    char page[1024];
    hv_viewer_report r;
    snprintf(page, sizeof page, "%s/index.html", fr);
    cr_assert_eq(hv_viewer_stack_write(fr, page, NULL, NULL, &r), HV_OK, "%s", hv_last_error());
    cr_expect(r.channels == 2 && strcmp(r.mode, "fractions") == 0);
    check_stack_page(fr, page);
    snprintf(page, sizeof page, "%s/index.html", mk);
    cr_assert_eq(hv_viewer_stack_write(mk, page, NULL, NULL, &r), HV_OK, "%s", hv_last_error());
    cr_expect(r.channels == 1 && strcmp(r.mode, "mask") == 0);
    check_stack_page(mk, page);
}

Test(viewer, tray_page_parts_outlines_and_cuts, .timeout = 300)
{
    double lo[3] = {0, 0, 0}, a[3] = {8, 5, 1}, b[3] = {4, 6, 1};
    hv_mesh *ma = t_box_mesh(lo, a), *mb = t_box_mesh(lo, b);
    const char *pa = t_tmpfile("a.stl"), *pb = t_tmpfile("b.stl");
    cr_assert_eq(hv_mesh_save(ma, pa, 0), HV_OK);
    cr_assert_eq(hv_mesh_save(mb, pb, 0), HV_OK);
    hv_mesh_destroy(ma);
    hv_mesh_destroy(mb);
    hv_tray *t = NULL;
    cr_assert_eq(hv_tray_create(&t), HV_OK);
    hv_tray_part p;
    hv_tray_part_init(&p);
    p.mesh = pa;
    p.material = "VeroPureWhite";
    p.at[0] = 30;
    p.at[1] = 370;
    p.placed = 1;
    p.rotation = 90;
    cr_assert_eq(hv_tray_add(t, &p, NULL), HV_OK, "%s", hv_last_error());
    hv_tray_part_init(&p);
    p.mesh = pb;
    p.material = "VeroCyan-V";
    p.copies = 2; /* arranged */
    cr_assert_eq(hv_tray_add(t, &p, NULL), HV_OK, "%s", hv_last_error());
    hv_tray_options o;
    hv_tray_options_init(&o);
    o.arrange = 1;
    o.first = 10;
    o.last = 12;
    o.cache_dir = t_tmpfile("bncache");
    const char *dir = t_tmpfile("tray");
    cr_assert_eq(hv_tray_write(t, dir, &o, NULL, NULL), HV_OK, "%s", hv_last_error());
    hv_tray_destroy(t);
    char page[1024];
    snprintf(page, sizeof page, "%s/index.html", dir);
    hv_viewer_report r;
    hv_viewer_options vo;
    hv_viewer_options_init(&vo);
    vo.cuts = 5;
    cr_assert_eq(hv_viewer_stack_write(dir, page, &vo, NULL, &r), HV_OK, "%s", hv_last_error());
    cr_expect(r.kind == HV_VIEWER_TRAY && r.parts == 3 && r.layers == 2 && r.cut_rows == 5 && r.cut_cols == 5);
    cr_expect(fabs(r.pixel_mm[0] - 25.4 / 600) < 1e-12 && fabs(r.pixel_mm[1] + 25.4 / 300) < 1e-12);
    check_stack_page(dir, page);
    json_t *d = page_data(page);
    const json_t *parts = get(d, "parts");
    cr_assert_eq(json_array_size(parts), 3);
    cr_expect_eq(iget(json_array_get(parts, 2), "copy"), 2);
    cr_expect_eq(json_array_size(get(d, "cuts")), 30, "5 rows and 5 columns per part");
    cr_expect_str_eq(json_string_value(get(json_array_get(get(d, "palette"), 1), "name")), "VeroCyan-V");
    cr_expect_str_eq(json_string_value(json_array_get(json_array_get(get(d, "files"), 0), 1)), "layer-00011.png");
    json_decref(d);
}

/* a finish step that fails */
static hv_status refuse_page(void *user, const char *tmp, const char *dir, const hv_progress *progress)
{
    (void)user;
    (void)dir;
    (void)progress;
    return hv_error_set(HV_ERR_IO, "%s/index.html: refused on purpose", tmp);
}

Test(viewer, page_written_with_the_stack)
{
    double lo[3] = {0, 0, 0}, hi[3] = {6, 4, 2};
    hv_mesh *m = t_box_mesh(lo, hi);
    hv_layers_options o = lopts(HV_LAYERS_MASK, 50, 50, 1);
    hv_viewer_report r;
    memset(&r, 0, sizeof r);
    o.finish = hv_viewer_stack_finish;
    o.finish_user = &r;
    const char *dir = t_tmpfile("with_page");
    cr_assert_eq(hv_layers_write(m, NULL, dir, &o, NULL, NULL), HV_OK, "%s", hv_last_error());
    char page[1024];
    snprintf(page, sizeof page, "%s/index.html", dir);
    cr_expect(t_exists(page));
    cr_expect(r.bytes > 0 && r.layers == 2 && strcmp(r.mode, "mask") == 0);
    json_t *d = page_data(page);
    cr_expect_str_eq(json_string_value(get(d, "base")), "");
    cr_expect_str_eq(json_string_value(get(d, "title")), "with_page", "titled with the stack's name, not the temporary one");
    json_decref(d);
    o.finish_user = NULL;
    /* a stack holding its page is still one hovox replaces with force */
    o.force = 1;
    o.finish = NULL;
    cr_expect_eq(hv_layers_write(m, NULL, dir, &o, NULL, NULL), HV_OK, "%s", hv_last_error());
    cr_expect(!t_exists(page));
    /* a failing step fails the job and leaves nothing */
    const char *dir2 = t_tmpfile("failed_page");
    o.finish = refuse_page;
    cr_expect_eq(hv_layers_write(m, NULL, dir2, &o, NULL, NULL), HV_ERR_IO);
    cr_expect(strstr(hv_last_error(), "refused on purpose"));
    cr_expect(!t_exists(dir2));
    hv_mesh_destroy(m);
}

Test(viewer, phys_that_disagrees_is_a_warning)
{
    const char *dir = t_tmpfile("phys");
    write_stack(dir, HV_LAYERS_MASK, 50, 50, 1); /* 24 x 16 pixels of 0.508 mm, 1-bit */
    char path[1024], page[1024];
    snprintf(page, sizeof page, "%s/index.html", dir);
    hv_viewer_report r;
    cr_assert_eq(hv_viewer_stack_write(dir, page, NULL, NULL, &r), HV_OK, "%s", hv_last_error());
    cr_expect_str_eq(r.warnings, "", "hovox's own layers carry the manifest's pixel size");
    /* layer 1 at 100 x 50 dpi, layer 2 without pHYs: the page still draws the manifest's */
    uint8_t px[24 * 16];
    memset(px, 1, sizeof px);
    hv_png_options po;
    hv_png_options_init(&po);
    po.bit_depth = 1;
    po.dpi[0] = 100;
    po.dpi[1] = 50;
    snprintf(path, sizeof path, "%s/layer-00001.png", dir);
    cr_assert_eq(hv_png_write(path, px, 24, 16, 1, 0, &po), HV_OK, "%s", hv_last_error());
    po.dpi[0] = po.dpi[1] = 0;
    snprintf(path, sizeof path, "%s/layer-00002.png", dir);
    cr_assert_eq(hv_png_write(path, px, 24, 16, 1, 0, &po), HV_OK, "%s", hv_last_error());
    cr_assert_eq(hv_viewer_stack_write(dir, page, NULL, NULL, &r), HV_OK, "%s", hv_last_error());
    cr_expect(strstr(r.warnings, "layer-00001.png: pHYs says 3937 x 1969 pixels per metre, manifest.json's pixel_mm 0.508 x "
                                 "0.508 mm (1969 x 1969 per metre)"),
              "%s", r.warnings);
    cr_expect(strstr(r.warnings, "layer-00002.png: no pHYs"), "%s", r.warnings);
    json_t *d = page_data(page);
    cr_expect_eq(json_array_size(get(d, "warnings")), 2);
    cr_expect(fabs(json_number_value(json_array_get(get(d, "pixel_mm"), 0)) - 0.508) < 1e-12);
    json_decref(d);
}

/* a layer whose image data goes on past its last row (a bomb continues with gigabytes of zeros):
 * refused once more than 64 KiB follow, as hv_png_decode refuses it */
Test(viewer, layer_data_past_the_image_is_refused)
{
    const char *dir = t_tmpfile("tail");
    write_stack(dir, HV_LAYERS_MASK, 50, 50, 1); /* 24 x 16, 1-bit: rows of 1 + 3 bytes */
    enum { W = 24, H = 16, ROW = 1 + 3, EXTRA = 100 << 10 };
    static uint8_t raw[H * ROW + EXTRA], z[EXTRA + 4096], png[EXTRA + 8192];
    unsigned seed = 7;
    for (size_t i = 0; i < sizeof raw; ++i) raw[i] = (uint8_t)((seed = seed * 1103515245u + 12345u) >> 16);
    for (int y = 0; y < H; ++y) raw[y * ROW] = 0;
    z_stream zs;
    memset(&zs, 0, sizeof zs);
    cr_assert_eq(deflateInit(&zs, 6), Z_OK);
    zs.next_in = raw, zs.avail_in = H * ROW, zs.next_out = z, zs.avail_out = sizeof z;
    cr_assert_eq(deflate(&zs, Z_FULL_FLUSH), Z_OK);
    size_t n1 = sizeof z - zs.avail_out;
    zs.next_in = raw + H * ROW, zs.avail_in = EXTRA;
    cr_assert_eq(deflate(&zs, Z_FINISH), Z_STREAM_END);
    size_t nz = sizeof z - zs.avail_out;
    deflateEnd(&zs);
    static const uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    uint8_t ihdr[13] = {0, 0, 0, W, 0, 0, 0, H, 1, 0, 0, 0, 0};
    size_t n = 8;
    memcpy(png, sig, 8);
    n += t_png_chunk(png + n, "IHDR", ihdr, 13);
    n += t_png_chunk(png + n, "IDAT", z, (uint32_t)n1);
    n += t_png_chunk(png + n, "IDAT", z + n1, (uint32_t)(nz - n1));
    n += t_png_chunk(png + n, "IEND", NULL, 0);
    char path[1024], page[1024];
    snprintf(path, sizeof path, "%s/layer-00001.png", dir);
    FILE *f = fopen(path, "wb");
    cr_assert(f && fwrite(png, 1, n, f) == n);
    fclose(f);
    snprintf(page, sizeof page, "%s/index.html", dir);
    cr_expect_eq(hv_viewer_stack_write(dir, page, NULL, NULL, NULL), HV_ERR_BAD_INPUT);
    cr_expect(strstr(hv_last_error(), "layer-00001.png: not a readable PNG: image data goes on past the image"), "%s",
              hv_last_error());
    cr_expect(!t_exists(page));
}

Test(viewer, stack_errors_leave_nothing)
{
    const char *dir = t_tmpfile("bad");
    write_stack(dir, HV_LAYERS_MASK, 50, 50, 1);
    char page[1024], path[1024];
    snprintf(page, sizeof page, "%s/index.html", dir);
    /* no directory, a file, a directory without a manifest */
    cr_expect_eq(hv_viewer_stack_write(t_tmpfile("nothing"), page, NULL, NULL, NULL), HV_ERR_IO);
    cr_expect(strstr(hv_last_error(), "No such file"), "%s", hv_last_error());
    const char *empty = t_tmpfile("empty");
    mkdir(empty, 0777);
    cr_expect_eq(hv_viewer_stack_write(empty, page, NULL, NULL, NULL), HV_ERR_BAD_INPUT);
    cr_expect(strstr(hv_last_error(), "not a slice stack"), "%s", hv_last_error());
    /* the page must be .html */
    snprintf(path, sizeof path, "%s/x.htm", dir);
    cr_expect_eq(hv_viewer_stack_write(dir, path, NULL, NULL, NULL), HV_ERR_INVALID);
    /* a layer missing, then one of another size */
    snprintf(path, sizeof path, "%s/layer-00001.png", dir);
    char moved[1100];
    snprintf(moved, sizeof moved, "%s.away", path);
    cr_assert_eq(rename(path, moved), 0);
    cr_expect_eq(hv_viewer_stack_write(dir, page, NULL, NULL, NULL), HV_ERR_IO);
    cr_expect(strstr(hv_last_error(), "layer-00001.png") && strstr(hv_last_error(), "listed in manifest.json"), "%s",
              hv_last_error());
    uint8_t px[4] = {0, 1, 1, 0};
    cr_assert_eq(hv_png_write(path, px, 2, 2, 1, 0, NULL), HV_OK);
    cr_expect_eq(hv_viewer_stack_write(dir, page, NULL, NULL, NULL), HV_ERR_BAD_INPUT);
    cr_expect(strstr(hv_last_error(), "2 x 2, 8-bit grey") && strstr(hv_last_error(), "the size differs"), "%s",
              hv_last_error());
    /* a damaged manifest */
    cr_assert_eq(rename(moved, path), 0);
    snprintf(path, sizeof path, "%s/manifest.json", dir);
    FILE *f = fopen(path, "w");
    fputs("{\"generator\": \"hovox\", \"mode\": ", f);
    fclose(f);
    cr_expect_eq(hv_viewer_stack_write(dir, page, NULL, NULL, NULL), HV_ERR_BAD_INPUT);
    cr_expect(strstr(hv_last_error(), "manifest.json: line 1"), "%s", hv_last_error());
    cr_expect(!t_exists(page), "a page was written");
}

/* ---- a model's page ------------------------------------------------------------------------------------- */

Test(viewer, model_page_slices_are_the_voxels, .timeout = 300)
{
    double lo[3] = {0, 0, 0}, hi[3] = {10, 6, 3};
    hv_mesh *m = t_box_mesh(lo, hi);
    hv_volume *g = graded_box(m);
    hv_mesh_destroy(m);
    const char *page = t_tmpfile("model.html");
    hv_viewer_options o;
    hv_viewer_options_init(&o);
    o.no_renders = 1;
    hv_viewer_report r;
    cr_assert_eq(hv_viewer_model_write(g, "box.vdb", page, &o, NULL, &r), HV_OK, "%s", hv_last_error());
    cr_expect(r.materials == 2 && r.slice_step == 1 && r.render_count == 0);
    for (int a = 0; a < 3; ++a) cr_expect_eq(r.slices[a], r.dims[a], "every slice of axis %d", a);
    json_t *d = page_data(page);
    const json_t *dims = get(d, "dims"), *org = get(d, "origin_mm");
    int D[3];
    double O[3], wl[3];
    for (int k = 0; k < 3; ++k) {
        D[k] = (int)json_number_value(json_array_get(dims, (size_t)k));
        O[k] = json_number_value(json_array_get(org, (size_t)k));
    }
    hv_volume_world_to_index(g, O, wl);
    int L[3] = {(int)lrint(wl[0]), (int)lrint(wl[1]), (int)lrint(wl[2])};
    int occ = hv_volume_grid_find(g, "occupancy"), ga = hv_volume_grid_find(g, "material.A"),
        gb = hv_volume_grid_find(g, "material.B");
    hv_accessor acc;
    hv_accessor_init(&acc, g);
    static const int U[3] = {1, 0, 0}, V[3] = {2, 2, 1};
    uint64_t checked = 0;
    for (int a = 0; a < 3; ++a) {
        const json_t *A = json_array_get(get(d, "axes"), (size_t)a);
        int w = (int)iget(A, "w"), h = (int)iget(A, "h"), cols = (int)iget(A, "cols");
        cr_expect(w == D[U[a]] && h == D[V[a]]);
        hv_png_pixels img[3];
        for (int c = 0; c < 3; ++c) uri_png(json_string_value(json_array_get(get(A, "images"), (size_t)c)), &img[c]);
        const json_t *sl = get(A, "slices");
        for (size_t s = 0; s < json_array_size(sl); ++s) {
            int si = (int)json_integer_value(json_array_get(sl, s));
            size_t tx = (s % (size_t)cols) * (size_t)w, ty = (s / (size_t)cols) * (size_t)h;
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    int ijk[3];
                    ijk[a] = L[a] + si;
                    ijk[U[a]] = L[U[a]] + x;
                    ijk[V[a]] = L[V[a]] + h - 1 - y;
                    size_t at = (ty + (size_t)y) * (size_t)img[0].width + tx + (size_t)x;
                    int on = hv_accessor_bool(&acc, occ, ijk[0], ijk[1], ijk[2]);
                    cr_assert_eq(img[0].samples[at] != 0, on, "occupancy at %d %d %d", ijk[0], ijk[1], ijk[2]);
                    if (!on) continue;
                    float pa = hv_accessor_float(&acc, ga, ijk[0], ijk[1], ijk[2]);
                    float pb = hv_accessor_float(&acc, gb, ijk[0], ijk[1], ijk[2]);
                    cr_assert(fabs(img[1].samples[at] / 255.0 - pa) <= 0.5 / 255 + 1e-6 &&
                                  fabs(img[2].samples[at] / 255.0 - pb) <= 0.5 / 255 + 1e-6,
                              "fractions at %d %d %d", ijk[0], ijk[1], ijk[2]);
                    ++checked;
                }
        }
        for (int c = 0; c < 3; ++c) hv_png_pixels_free(&img[c]);
    }
    cr_expect(checked > 1000);
    const json_t *mats = get(d, "materials");
    cr_expect_str_eq(json_string_value(get(json_array_get(mats, 0), "name")), "A");
    cr_expect_str_eq(json_string_value(get(json_array_get(mats, 0), "color")), "#e6331a");
    double mean = json_number_value(get(json_array_get(mats, 0), "mean"));
    cr_expect(mean > 0.4 && mean < 0.6, "mean of A %g", mean);
    json_decref(d);
    /* a budget: fewer slices, then every q-th voxel */
    o.max_samples = 10000;
    cr_assert_eq(hv_viewer_model_write(g, "box.vdb", page, &o, NULL, &r), HV_OK, "%s", hv_last_error());
    uint64_t total = 0;
    for (int a = 0; a < 3; ++a)
        total += (uint64_t)r.slices[a] * (uint64_t)((r.dims[U[a]] + r.slice_step - 1) / r.slice_step) *
                 (uint64_t)((r.dims[V[a]] + r.slice_step - 1) / r.slice_step) * 3;
    cr_expect(total <= 10000, "%llu samples", (unsigned long long)total);
    /* an empty model */
    hv_transform xf = {{1, 1, 1}, {0, 0, 0}};
    hv_volume *e = NULL;
    cr_assert_eq(hv_volume_create(&xf, &e), HV_OK);
    const char *p2 = t_tmpfile("empty.html");
    cr_expect_eq(hv_viewer_model_write(e, "e.vdb", p2, &o, NULL, NULL), HV_ERR_BAD_INPUT);
    cr_expect(!t_exists(p2));
    hv_volume_destroy(e);
    hv_volume_destroy(g);
}
