/* tests/fuzz/fuzz_3mf_pull_push.c - differential fuzz target for the 3MF package module
 * (src/io/3mf/package.c, issue 26): on one thread a deflated part is inflated whole and parsed in
 * place by libxml2's pull parser, falling back to the push parser (replaying the elements already
 * handled) for anything not well-formed UTF-8; on two threads it streams through the push parser
 * beside an inflater thread. package.c is compiled into this target with PKG_THREAD_FLOOR 1, so
 * every part, however small, takes those paths. Both runs must give the same status and message,
 * and the same mesh (points, facets, bodies, materials, colours, notes), which must be sound
 * (mesh_fuzz_check.h). Bytes that start with "PK" are a package as they are; any others are the
 * model part's XML, packed with every member deflated. */
#define PKG_THREAD_FLOOR 1
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

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    hv_set_memory_cap(256u << 20);
    uint8_t *packed;
    data = fuzz_3mf_input(data, &size, ZIP_CM_DEFLATE, &packed);
    if (!data) return 0;
    static char pull_msg[FUZZ_MSG], push_msg[FUZZ_MSG];
    hv_mesh *pull = NULL, *push = NULL;
    hv_status s1 = parse_on(data, size, 1, pull_msg, &pull), s2 = parse_on(data, size, 2, push_msg, &push);
    if (s1 != s2 || strcmp(pull_msg, push_msg) != 0) {
        fprintf(stderr, "pull (1 thread) and push (2 threads) differ:\n  %s: %s\n  %s: %s\n", hv_status_name(s1),
                pull_msg, hv_status_name(s2), push_msg);
        abort();
    }
    if (s1 == HV_OK) {
        fuzz_check_mesh(pull);
        if (!same_mesh(pull, push)) {
            fprintf(stderr, "pull (1 thread) and push (2 threads) built different meshes\n");
            abort();
        }
    }
    hv_mesh_destroy(pull);
    hv_mesh_destroy(push);
    hv_set_threads(0);
    free(packed);
    return 0;
}
