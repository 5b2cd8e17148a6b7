/* tests/fuzz/fuzz_geometry.c - fuzz target: a model's geometry record (hovox/geometry.h). The
 * first byte picks the part: 'M' the rest is a packed mesh leaf (unpacked, placed, sliced when
 * it unpacks), anything else the text of "hovox.geometry.json" beside one valid leaf (a box; in
 * the text "@HASH@" and "@SIZE@" stand for its hash and size, so a corpus document can name it),
 * read as hv_geometry_read reads a model. Every input must be read or fail with a message and nothing
 * handed out. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/generate.h"
#include "hovox/solid.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void packed_mesh(const uint8_t *data, size_t size)
{
    hv_geometry *g = NULL;
    if (hv_geometry_from_leaf(HV_LEAF_MESH, "fuzz", data, size, NULL, 1, &g) != HV_OK) return;
    hv_mesh *m = NULL;
    hv_status s = hv_geometry_leaf_mesh(g, 0, &m);
    if (s == HV_OK) {
        hv_leaf *l = NULL;
        if (hv_leaf_open(g, 0, NULL, &l) == HV_OK) {
            double lo[3], hi[3], mid[3];
            hv_leaf_bbox(l, lo, hi);
            for (int a = 0; a < 3; ++a) mid[a] = 0.5 * (lo[a] + hi[a]);
            (void)hv_leaf_inside(l, mid);
            hv_leaf_close(l);
        }
        hv_mesh_destroy(m);
    } else if (m || !*hv_last_error()) {
        abort();
    }
    hv_geometry_destroy(g);
}

/* text with every "@HASH@" and "@SIZE@" replaced (NULL when out of memory) */
static char *substitute(const uint8_t *data, size_t size, const hv_geometry_leaf *l)
{
    char hash[24], sz[24];
    snprintf(hash, sizeof hash, "%016llx", (unsigned long long)l->hash);
    snprintf(sz, sizeof sz, "%zu", l->size);
    char *text = malloc(4 * size + 1);
    if (!text) return NULL;
    size_t n = 0;
    for (size_t i = 0; i < size;) {
        const char *rep = size - i >= 6 && memcmp(data + i, "@HASH@", 6) == 0   ? hash
                          : size - i >= 6 && memcmp(data + i, "@SIZE@", 6) == 0 ? sz
                                                                                  : NULL;
        if (rep) {
            memcpy(text + n, rep, strlen(rep));
            n += strlen(rep);
            i += 6;
        } else {
            text[n++] = (char)data[i++];
        }
    }
    text[n] = '\0';
    return text;
}

static void record_text(const uint8_t *data, size_t size)
{
    char *text = NULL;
    hv_transform xf = {{1, 1, 1}, {0, 0, 0}};
    hv_volume *v = NULL;
    hv_mesh *box = NULL;
    double lo[3] = {0, 0, 0}, hi[3] = {1, 2, 3};
    hv_geometry *g = NULL;
    if (hv_volume_create(&xf, &v) == HV_OK && hv_generate_box(lo, hi, &box) == HV_OK &&
        hv_geometry_from_mesh(box, "box.stl", NULL, 1, &g) == HV_OK && hv_geometry_write(g, v) == HV_OK &&
        (text = substitute(data, size, hv_geometry_leaf_at(g, 0))) != NULL && hv_volume_meta_set_string(v, "hovox.geometry.json", text) == HV_OK) {
        hv_geometry *back = NULL;
        hv_status s = hv_geometry_read(v, &back);
        if (s == HV_OK) {
            hv_solid *solid = NULL;
            if (hv_solid_open(back, NULL, &solid) == HV_OK) {
                double p[3] = {0.5, 1, 1.5};
                (void)hv_solid_inside(solid, p);
                hv_solid_close(solid);
            }
            hv_geometry_destroy(back);
        } else if (back || !*hv_last_error()) {
            abort();
        }
    }
    hv_geometry_destroy(g);
    hv_mesh_destroy(box);
    hv_volume_destroy(v);
    free(text);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0) return 0;
    if (data[0] == 'M') packed_mesh(data + 1, size - 1);
    else record_text(data + 1, size - 1);
    return 0;
}
