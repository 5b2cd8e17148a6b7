/* tests/fuzz/fuzz_3mf_pull_push.c - differential fuzz target for the 3MF package module
 * (src/io/3mf/package.c, issue 26). package.c is compiled into this target with PKG_THREAD_FLOOR 1
 * and PKG_BULK_SHARE 1, so every deflated part, however small, is inflated whole, and every
 * <vertices> and <triangles> asked to be read ahead is cut. Each input is parsed three ways:
 *   pull:   deflated, one thread: the part parsed where it lies by libxml2's pull parser, falling
 *           back to the push parser (replaying the elements already handled) for anything not
 *           well-formed UTF-8;
 *   bulk:   deflated, 2 to 4 threads: the whole part pushed, its bulk elements cut into pieces that
 *           other threads parse (tmf_xml_bulk), a piece given up where its cut or content is not
 *           fit;
 *   stream: stored, one thread: the part streamed chunk by chunk to the push parser, the reference.
 * All must give the same status and message, and the same mesh (points, facets, bodies,
 * materials, colours, notes), which must be sound (mesh_fuzz_check.h). Bytes that start with "PK"
 * are a package as they are (pull against bulk); any others are the model part's XML, packed
 * here. A part is handed to the push parser PKG_CHUNK (64 KiB) at a time, and a bulk element is cut
 * only past what the parser has been fed when it opens, so for every other input the XML is first
 * padded with blanks after the start tag of its first <vertices> or <triangles>, so that the first
 * chunk ends in them, 0 to 96 before its first child (as a large part's would): its children are
 * then cut into pieces. */
#define PKG_THREAD_FLOOR 1
#define PKG_BULK_SHARE 1
#include "io/3mf/package.c"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hovox/mesh.h"
#include "mesh_fuzz_check.h"
#include "threemf_fuzz_pack.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define FUZZ_MSG 4096
#define FUZZ_CHUNK 65536 /* package.c's PKG_CHUNK */

/* The XML with blanks after the start tag of its first <vertices> or <triangles> (`which`), so
 * that the first chunk ends in them, `left` (< 97) of them after its end (malloc'd, *size updated),
 * or NULL when it has none or it lies past the first chunk. */
static uint8_t *padded(const uint8_t *xml, size_t *size, int which, int left)
{
    static const char *const k_tag[2] = {"<vertices", "<triangles"};
    const uint8_t *at = NULL;
    for (int k = 0; k < 2 && !at; ++k) { /* (memmem is not C11) */
        const char *t = k_tag[(which + k) & 1];
        size_t n = strlen(t);
        for (size_t i = 0; !at && i + n <= *size; ++i)
            if (memcmp(xml + i, t, n) == 0) at = xml + i;
    }
    const uint8_t *gt = at ? memchr(at, '>', *size - (size_t)(at - xml)) : NULL;
    size_t head = gt ? (size_t)(gt - xml) + 1 : 0; /* the bytes up to the start tag's end */
    if (!gt || head >= FUZZ_CHUNK) return NULL;
    size_t pad = FUZZ_CHUNK - head + (size_t)left;
    uint8_t *out = malloc(*size + pad);
    if (!out) return NULL;
    memcpy(out, xml, head);
    memset(out + head, ' ', pad);
    memcpy(out + head + pad, gt + 1, *size - head);
    *size += pad;
    return out;
}

static hv_status parse_on(const uint8_t *data, size_t size, int threads, char *msg, hv_mesh **m)
{
    hv_set_threads(threads);
    hv_error_clear();
    *m = NULL;
    hv_status s = hv_mesh_parse_3mf(data, size, "fuzz.3mf", m);
    snprintf(msg, FUZZ_MSG, "%s", s == HV_OK ? "" : hv_last_error());
    if (s != HV_OK && *m) abort(); /* a failure hands out no mesh */
    return s;
}

static int same_bytes(const void *a, const void *b, size_t n)
{
    return (!a && !b) || (a && b && memcmp(a, b, n) == 0);
}

static int same_text(const char *a, const char *b)
{
    return (!a && !b) || (a && b && strcmp(a, b) == 0);
}

/* The two meshes hold the same things; 1 when they do. */
static int same_mesh(const hv_mesh *a, const hv_mesh *b)
{
    size_t nv = hv_mesh_vertex_count(a), nf = hv_mesh_facet_count(a);
    if (nv != hv_mesh_vertex_count(b) || nf != hv_mesh_facet_count(b) ||
        !same_bytes(hv_mesh_vertices(a), hv_mesh_vertices(b), 3 * nv * sizeof(float)) ||
        !same_bytes(hv_mesh_facets(a), hv_mesh_facets(b), 3 * nf * sizeof(uint32_t)) ||
        !same_bytes(hv_mesh_facet_materials(a), hv_mesh_facet_materials(b), nf * sizeof(int32_t)) ||
        !same_bytes(hv_mesh_corner_colours(a), hv_mesh_corner_colours(b), 3 * nf * sizeof(uint32_t)))
        return 0;
    size_t nb = hv_mesh_body_count(a), nm = hv_mesh_material_count(a), nn = hv_mesh_note_count(a);
    if (nb != hv_mesh_body_count(b) || nm != hv_mesh_material_count(b) || nn != hv_mesh_note_count(b)) return 0;
    for (size_t i = 0; i < nb; ++i) {
        const hv_mesh_body *x = hv_mesh_body_at(a, i), *y = hv_mesh_body_at(b, i);
        if (strcmp(x->name, y->name) != 0 || x->material != y->material || x->first_facet != y->first_facet ||
            x->facet_count != y->facet_count || x->coloured != y->coloured)
            return 0;
    }
    for (size_t i = 0; i < nm; ++i) {
        const hv_mesh_material *x = hv_mesh_material_at(a, i), *y = hv_mesh_material_at(b, i);
        if (!same_text(x->name, y->name) || x->has_color != y->has_color || x->rgba != y->rgba ||
            x->nparts != y->nparts)
            return 0;
    }
    for (size_t i = 0; i < nn; ++i)
        if (!same_text(hv_mesh_note_at(a, i), hv_mesh_note_at(b, i))) return 0;
    return same_text(hv_mesh_file_unit(a), hv_mesh_file_unit(b));
}

/* Way `way`'s result against the pull parse's (status s1, message m1, mesh a); aborts when they differ. */
static void same_as_pull(const char *way, hv_status s1, const char *m1, const hv_mesh *a, hv_status s, const char *m,
                         const hv_mesh *b)
{
    if (s1 != s || strcmp(m1, m) != 0) {
        fprintf(stderr, "pull and %s differ:\n  %s: %s\n  %s: %s\n", way, hv_status_name(s1), m1, hv_status_name(s), m);
        abort();
    }
    if (s1 == HV_OK && !same_mesh(a, b)) {
        fprintf(stderr, "pull and %s built different meshes\n", way);
        abort();
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    hv_set_memory_cap(256u << 20);
    static char pull_msg[FUZZ_MSG], msg[FUZZ_MSG];
    uint8_t *pad = NULL;
    if (size % 2 && !(size >= 2 && data[0] == 'P' && data[1] == 'K') &&
        (pad = padded(data, &size, (int)(size / 2 % 2), (int)(size / 4 % 97))) != NULL)
        data = pad;
    uint8_t *deflated = NULL, *stored = NULL;
    size_t dsize = size, ssize = size;
    const uint8_t *d = fuzz_3mf_input(data, &dsize, ZIP_CM_DEFLATE, &deflated);
    const uint8_t *st = deflated ? fuzz_3mf_input(data, &ssize, ZIP_CM_STORE, &stored) : NULL;
    hv_mesh *pull = NULL, *other = NULL;
    hv_status s1 = d ? parse_on(d, dsize, 1, pull_msg, &pull) : HV_OK;
    if (d && s1 == HV_OK) fuzz_check_mesh(pull);
    if (d) {
        hv_status s = parse_on(d, dsize, 2 + (int)(size % 3), msg, &other);
        same_as_pull("bulk", s1, pull_msg, pull, s, msg, other);
        hv_mesh_destroy(other);
    }
    if (st) {
        hv_status s = parse_on(st, ssize, 1, msg, &other);
        same_as_pull("stream", s1, pull_msg, pull, s, msg, other);
        hv_mesh_destroy(other);
    }
    hv_mesh_destroy(pull);
    hv_set_threads(0);
    free(deflated);
    free(stored);
    free(pad);
    return 0;
}
