/* src/cli/cmd_info.c - `hovox info MESH|VOLUME|MODEL...`: the mesh report, a scanner volume's
 * (NIfTI, NRRD, MetaImage, a DICOM series directory) or a hovox model's (.vdb), as text or JSON. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <jansson.h>

#include "core/internal.h"
#include "core/json.h"
#include "mesh/mesh_internal.h"
#include "cli.h"
#include "hovox/material.h"
#include "hovox/mesh.h"
#include "hovox/model.h"
#include "hovox/volume.h"
#include "io/scan/scan_internal.h"

typedef struct info_cli {
    int json;
} info_cli;

static const hv_option k_local_opts[] = {
    CLI_JSON(info_cli, "one JSON object per mesh or volume (an array when several are given), with its materials and bodies")};
static const hv_option_set k_local = CLI_LOCAL_SET("info", k_local_opts, info_cli);


/* An item's transform: "identity", "translate X Y Z", or its three rows. */
static void transform_text(const double *t, char *buf, size_t size)
{
    int linear_id = t[0] == 1 && t[1] == 0 && t[2] == 0 && t[4] == 0 && t[5] == 1 && t[6] == 0 && t[8] == 0 &&
                    t[9] == 0 && t[10] == 1;
    if (linear_id && t[3] == 0 && t[7] == 0 && t[11] == 0) snprintf(buf, size, "identity");
    else if (linear_id) snprintf(buf, size, "translate %.6g %.6g %.6g", t[3], t[7], t[11]);
    else
        snprintf(buf, size, "[%.6g %.6g %.6g %.6g; %.6g %.6g %.6g %.6g; %.6g %.6g %.6g %.6g]", t[0], t[1], t[2], t[3], t[4],
                 t[5], t[6], t[7], t[8], t[9], t[10], t[11]);
}

/* "3 'name'" or "3": an item's object. */
static int item_label(const hv_mesh_item *it, char *buf, size_t size)
{
    if (it->object_name[0]) return snprintf(buf, size, "%llu '%.160s'", (unsigned long long)it->object_id, it->object_name);
    return snprintf(buf, size, "%llu", (unsigned long long)it->object_id);
}

/* The bodies item `it` became: "plate, core, peg, peg (2)" (an item of components: one per mesh
 * object it places), the first three and a count past five; "-" for none. */
static const char *item_bodies(const hv_mesh *m, const hv_mesh_item *it, char *buf, size_t size)
{
    if (it->body < 0 || !it->bodies) return "-";
    size_t n = 0, shown = it->bodies > 5 ? 3 : it->bodies;
    buf[0] = '\0';
    for (size_t k = 0; k < shown && n < size; ++k)
        n += (size_t)snprintf(buf + n, size - n, "%s%s", k ? ", " : "", hv_mesh_body_at(m, (size_t)it->body + k)->name);
    if (shown < it->bodies && n < size) snprintf(buf + n, size - n, " ... (%zu bodies)", it->bodies);
    return buf;
}

/* The file's build items (3MF): object, the bodies it became, transform. */
static void print_items(const hv_mesh *m)
{
    size_t n = hv_mesh_item_count(m);
    if (!n) return;
    int wo = 6, wb = 4;
    char label[192], names[800];
    for (size_t i = 0; i < n; ++i) {
        const hv_mesh_item *it = hv_mesh_item_at(m, i);
        wo = HV_MAX(wo, item_label(it, label, sizeof label));
        wb = HV_MAX(wb, (int)strlen(item_bodies(m, it, names, sizeof names)));
    }
    printf("build items         %zu\n", n);
    printf("  %4s  %-*s  %-*s  %s\n", "item", wo, "object", wb, "body", "transform");
    for (size_t i = 0; i < n; ++i) {
        const hv_mesh_item *it = hv_mesh_item_at(m, i);
        char t[320];
        transform_text(it->transform, t, sizeof t);
        item_label(it, label, sizeof label);
        printf("  %4zu  %-*s  %-*s  %s\n", i + 1, wo, label, wb, item_bodies(m, it, names, sizeof names), t);
    }
}

static void print_text(const char *path, const hv_mesh *m, const hv_mesh_report *bodies)
{
    const hv_mesh_report *r = hv_mesh_get_report(m);
    int closed = r->open_edges == 0 && r->nonmanifold_edges == 0;
    printf("file                %s\n", path);
    printf("format              %s\n", hv_mesh_format_name(r->format));
    if (hv_mesh_file_unit(m))
        printf("unit                %s%s\n", hv_mesh_file_unit(m),
               strcmp(hv_mesh_file_unit(m), "millimeter") ? " (the file's; the figures here are in mm)" : "");
    printf("facets              %llu\n", (unsigned long long)r->facets);
    printf("vertices            %llu\n", (unsigned long long)r->vertices);
    printf("bbox min            %.6g %.6g %.6g\n", r->bbox_min[0], r->bbox_min[1], r->bbox_min[2]);
    printf("bbox max            %.6g %.6g %.6g\n", r->bbox_max[0], r->bbox_max[1], r->bbox_max[2]);
    printf("size                %.6g x %.6g x %.6g\n", r->bbox_max[0] - r->bbox_min[0],
           r->bbox_max[1] - r->bbox_min[1], r->bbox_max[2] - r->bbox_min[2]);
    printf("volume              %.6g\n", r->volume);
    printf("area                %.6g\n", r->area);
    printf("shells              %llu\n", (unsigned long long)r->shells);
    printf("open edges          %llu\n", (unsigned long long)r->open_edges);
    printf("non-manifold edges  %llu\n", (unsigned long long)r->nonmanifold_edges);
    printf("degenerate facets   %llu\n", (unsigned long long)r->degenerate_facets);
    printf("flipped facets      %llu\n", (unsigned long long)r->flipped_facets);
    printf("normal mismatches   %llu\n", (unsigned long long)r->normal_mismatch);
    size_t inverted = 0;
    for (size_t i = 0; i < hv_mesh_body_count(m); ++i) inverted += (size_t)hv_mesh_report_inside_out(&bodies[i]);
    if (!closed) printf("closed              no\n");
    else if (!inverted) printf("closed              yes\n");
    else if (hv_mesh_body_count(m) == 1) printf("closed              yes, inside-out (negative volume)\n");
    else printf("closed              yes, %zu bod%s inside-out (negative volume)\n", inverted, inverted == 1 ? "y" : "ies");
    size_t nm = hv_mesh_material_count(m), nb = hv_mesh_body_count(m);
    if (nm) {
        int w = 8;
        for (size_t k = 0; k < nm; ++k) w = HV_MAX(w, (int)strlen(hv_mesh_material_at(m, k)->name));
        printf("materials           %zu\n", nm);
        for (size_t k = 0; k < nm; ++k) {
            const hv_mesh_material *mt = hv_mesh_material_at(m, k);
            char col[10];
            printf("  %-*s  %s", w, mt->name, mt->has_color ? hv_mesh_material_color_text(mt, col) : "-");
            for (size_t q = 0; q < mt->nparts; ++q) /* a mixture: its base materials' fractions */
                printf("%s%s %.4g", q ? " + " : "  = ", mt->parts[q].material, mt->parts[q].fraction);
            printf("\n");
        }
    }
    /* appearance: textures with the facets that use them, corner colours */
    size_t nt = hv_mesh_texture_count(m), nf = hv_mesh_facet_count(m);
    const int32_t *ft = hv_mesh_facet_textures(m);
    if (nt) {
        printf("textures            %zu\n", nt);
        for (size_t k = 0; k < nt; ++k) {
            const hv_mesh_texture *t = hv_mesh_texture_at(m, k);
            size_t used = 0;
            for (size_t f = 0; ft && f < nf; ++f) used += ft[f] == (int32_t)k;
            printf("  %s  %u x %u  %zu facet%s\n", t->name, t->width, t->height, used, used == 1 ? "" : "s");
        }
    }
    if (hv_mesh_corner_colours(m)) printf("corner colours      yes\n");
    print_items(m);
    if (nb < 2 && nm == 0) return; /* one body and no material: the report above says it all */
    int wn = 4, wm = 8;
    for (size_t i = 0; i < nb; ++i) {
        const hv_mesh_body *b = hv_mesh_body_at(m, i);
        wn = HV_MAX(wn, (int)strlen(b->name));
        if (b->material >= 0) wm = HV_MAX(wm, (int)strlen(hv_mesh_material_at(m, (size_t)b->material)->name));
    }
    printf("bodies              %zu\n", nb);
    printf("  %-*s  %-*s  %10s  %12s  %6s  %s\n", wn, "body", wm, "material", "facets", "volume", "shells", "closed");
    for (size_t i = 0; i < nb; ++i) {
        const hv_mesh_body *b = hv_mesh_body_at(m, i);
        const hv_mesh_report *br = &bodies[i];
        printf("  %-*s  %-*s  %10llu  %12.6g  %6llu  %s\n", wn, b->name, wm,
               b->material >= 0 ? hv_mesh_material_at(m, (size_t)b->material)->name : "-",
               (unsigned long long)br->facets, br->volume, (unsigned long long)br->shells,
               br->open_edges == 0 && br->nonmanifold_edges == 0 ? hv_mesh_report_inside_out(br) ? "inside-out" : "yes" : "no");
    }
}

/* A closed body wound inside out (issue 27: "closed yes, flipped 0" said nothing of it): slicers
 * orient contours by the winding, so its outlines come out as holes. One warning per body. */
static void warn_inside_out(const char *path, const hv_mesh *m, const hv_mesh_report *bodies)
{
    size_t nb = hv_mesh_body_count(m);
    for (size_t i = 0; i < nb; ++i) {
        if (!hv_mesh_report_inside_out(&bodies[i])) continue;
        if (nb == 1)
            cli_warn("%s: the mesh is closed but inside-out (volume %.6g): every facet faces inward; reverse them "
                     "(admesh --reverse-all, or export it again) before slicing", path, bodies[i].volume);
        else
            cli_warn("%s: body '%s' is closed but inside-out (volume %.6g): every facet faces inward; reverse them "
                     "before slicing", path, hv_mesh_body_at(m, i)->name, bodies[i].volume);
    }
}

static void print_scan_text(const char *path, const hv_scan *sc)
{
    const hv_scan_info *in = hv_scan_get_info(sc);
    size_t d[3];
    double m[12], sp[3], lo[3], hi[3];
    char axes[4];
    hv_scan_dims(sc, d);
    hv_scan_affine(sc, m);
    hv_scan_geometry(sc, sp, axes, lo, hi);
    printf("file                %s\n", path);
    printf("format              %s (%s)\n", in->format_name, in->encoding);
    if (in->files > 1) printf("files               %zu\n", in->files);
    printf("samples             %zu x %zu x %zu %s\n", d[0], d[1], d[2], in->sample_type);
    printf("values              %.6g .. %.6g%s%s\n", in->value_min, in->value_max, in->unit[0] ? " " : "", in->unit);
    if (in->slope != 1 || in->intercept != 0) printf("rescale             stored * %.6g %c %.6g\n", in->slope, in->intercept < 0 ? '-' : '+', fabs(in->intercept));
    printf("spacing             %.6g x %.6g x %.6g mm\n", sp[0], sp[1], sp[2]);
    printf("orientation         %s (axes i, j, k point toward %c, %c, %c)\n", axes, axes[0], axes[1], axes[2]);
    printf("origin              %.6g %.6g %.6g (centre of sample 0,0,0; RAS mm)\n", m[3], m[7], m[11]);
    for (int a = 0; a < 3; ++a) printf("axis %c              %.6g %.6g %.6g\n", "ijk"[a], m[a], m[4 + a], m[8 + a]);
    printf("bbox min            %.6g %.6g %.6g\n", lo[0], lo[1], lo[2]);
    printf("bbox max            %.6g %.6g %.6g\n", hi[0], hi[1], hi[2]);
    printf("size                %.6g x %.6g x %.6g\n", hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
    printf("world from          %s\n", in->space);
}

static void json_nums(hv_buf *b, const char *key, const double *v, int n)
{
    hv_buf_printf(b, ", \"%s\": [", key);
    for (int i = 0; i < n; ++i) hv_buf_printf(b, "%s%.17g", i ? ", " : "", v[i]);
    hv_buf_puts(b, "]");
}

static void scan_json(hv_buf *b, const char *path, const hv_scan *sc)
{
    const hv_scan_info *in = hv_scan_get_info(sc);
    size_t d[3];
    double m[12], sp[3], lo[3], hi[3];
    char axes[4];
    hv_scan_dims(sc, d);
    hv_scan_affine(sc, m);
    hv_scan_geometry(sc, sp, axes, lo, hi);
    json_t *f = json_string(path), *sp_ = json_string(in->space);
    char *fj = f ? json_dumps(f, JSON_ENCODE_ANY) : NULL, *sj = sp_ ? json_dumps(sp_, JSON_ENCODE_ANY) : NULL;
    hv_buf_printf(b, "{\"file\": %s, \"kind\": \"volume\", \"format\": \"%s\", \"encoding\": \"%s\", \"files\": %zu, "
                  "\"dims\": [%zu, %zu, %zu], \"sample_type\": \"%s\", \"unit\": \"%s\"",
                  fj ? fj : "null", in->format_name, in->encoding, in->files, d[0], d[1], d[2], in->sample_type, in->unit);
    hv_buf_printf(b, ", \"value_min\": %.9g, \"value_max\": %.9g, \"slope\": %.17g, \"intercept\": %.17g", in->value_min,
                  in->value_max, in->slope, in->intercept);
    json_nums(b, "spacing", sp, 3);
    hv_buf_printf(b, ", \"orientation\": \"%s\"", axes);
    json_nums(b, "affine", m, 12);
    json_nums(b, "bbox_min", lo, 3);
    json_nums(b, "bbox_max", hi, 3);
    hv_buf_printf(b, ", \"world_from\": %s}", sj ? sj : "null");
    free(fj);
    free(sj);
    json_decref(f);
    json_decref(sp_);
}

/* ---- models (issue 32: `info MODEL.vdb` said "unsupported mesh format 'vdb'") ---------------- */

/* An OpenVDB file by its content: the magic 0x56444220 (" BDV") in its first four bytes. */
static int is_vdb(const char *path)
{
    unsigned char h[4];
    FILE *f = fopen(path, "rb");
    if (!f) return 0;
    size_t n = fread(h, 1, 4, f);
    fclose(f);
    return n == 4 && h[0] == 0x20 && h[1] == 0x42 && h[2] == 0x44 && h[3] == 0x56;
}

/* What info reports of a model, gathered once for the text and the JSON. */
typedef struct model_info {
    const hv_volume *vol;
    hv_material_table *mats; /* NULL: not graded */
    int32_t lo[3], hi[3];
    int empty;
    double wlo[3], whi[3];
    json_t *regions, *leaves; /* borrowed from the parsed documents below (NULL: none) */
    json_t *rdoc, *gdoc;
} model_info;

static void model_info_free(model_info *mi)
{
    hv_material_table_destroy(mi->mats);
    json_decref(mi->rdoc);
    json_decref(mi->gdoc);
}

static hv_status model_info_get(const char *path, const hv_volume *vol, model_info *mi)
{
    memset(mi, 0, sizeof *mi);
    mi->vol = vol;
    hv_status s = hv_material_table_load(vol, &mi->mats);
    if (s == HV_ERR_NOT_FOUND) {
        hv_error_clear();
        s = HV_OK;
    }
    if (s != HV_OK) return hv_error_prefix(s, "%s: ", path);
    mi->empty = !hv_volume_index_bbox(vol, mi->lo, mi->hi);
    if (!mi->empty) {
        double a[3] = {mi->lo[0] - 0.5, mi->lo[1] - 0.5, mi->lo[2] - 0.5}, b[3] = {mi->hi[0] + 0.5, mi->hi[1] + 0.5, mi->hi[2] + 0.5};
        hv_volume_index_to_world(vol, a, mi->wlo);
        hv_volume_index_to_world(vol, b, mi->whi);
    }
    const char *r = hv_volume_meta_string(vol, "hovox.regions.json"), *g = hv_volume_meta_string(vol, "hovox.geometry.json");
    if (r && (mi->rdoc = json_loads(r, 0, NULL))) /* {"regions": [{"name", "voxels", ...}], ...} */
        mi->regions = json_is_array(json_object_get(mi->rdoc, "regions")) ? json_object_get(mi->rdoc, "regions") : NULL;
    if (g && (mi->gdoc = json_loads(g, 0, NULL)) && json_is_array(json_object_get(mi->gdoc, "leaves")))
        mi->leaves = json_object_get(mi->gdoc, "leaves");
    return HV_OK;
}


static const char *json_str_or(const json_t *o, const char *key, const char *dflt)
{
    const char *v = json_string_value(json_object_get(o, key));
    return v && *v ? v : dflt;
}

static void print_model_text(const char *path, const model_info *mi)
{
    const hv_volume *vol = mi->vol;
    hv_transform xf = hv_volume_get_transform(vol);
    printf("file                %s\n", path);
    printf("format              OpenVDB model\n");
    if (mi->empty) printf("dims                0 (no active voxels)\n");
    else {
        printf("dims                %d x %d x %d voxels (index %d,%d,%d to %d,%d,%d)\n", mi->hi[0] - mi->lo[0] + 1,
               mi->hi[1] - mi->lo[1] + 1, mi->hi[2] - mi->lo[2] + 1, mi->lo[0], mi->lo[1], mi->lo[2], mi->hi[0], mi->hi[1],
               mi->hi[2]);
    }
    printf("voxel size          %.6g x %.6g x %.6g mm\n", xf.voxel[0], xf.voxel[1], xf.voxel[2]);
    printf("origin              %.6g %.6g %.6g (centre of voxel 0,0,0)\n", xf.origin[0], xf.origin[1], xf.origin[2]);
    if (!mi->empty) {
        printf("bbox min            %.6g %.6g %.6g\n", mi->wlo[0], mi->wlo[1], mi->wlo[2]);
        printf("bbox max            %.6g %.6g %.6g\n", mi->whi[0], mi->whi[1], mi->whi[2]);
    }
    printf("active voxels       %llu\n", (unsigned long long)hv_volume_active_count(vol));
    int ng = hv_volume_grid_count(vol), w = 4;
    for (int g = 0; g < ng; ++g) w = HV_MAX(w, (int)strlen(hv_volume_grid_name(vol, g)));
    printf("grids               %d\n", ng);
    for (int g = 0; g < ng; ++g) {
        hv_grid_type t = hv_volume_grid_type(vol, g);
        printf("  %-*s  %s", w, hv_volume_grid_name(vol, g), hv_grid_type_name(t));
        if (t == HV_GRID_BOOL) printf("  %llu set", (unsigned long long)hv_volume_mask_count(vol, g));
        printf("\n");
    }
    int m = mi->mats ? hv_material_count(mi->mats) : 0;
    if (!m) printf("materials           none (not graded)\n");
    else {
        int wm = 8;
        for (int j = 0; j < m; ++j) wm = HV_MAX(wm, (int)strlen(hv_material_name(mi->mats, j)));
        printf("materials           %d\n", m);
        for (int j = 0; j < m; ++j) {
            float c[4];
            hv_material_color(mi->mats, j, c);
            printf("  %-*s  #%02x%02x%02x%02x  grid %s\n", wm, hv_material_name(mi->mats, j),
                   (unsigned)lroundf(c[0] * 255), (unsigned)lroundf(c[1] * 255), (unsigned)lroundf(c[2] * 255),
                   (unsigned)lroundf(c[3] * 255), hv_volume_grid_name(vol, hv_material_grid(vol, mi->mats, j)));
        }
    }
    size_t nr = mi->regions ? json_array_size(mi->regions) : 0, nl = mi->leaves ? json_array_size(mi->leaves) : 0;
    if (nr) {
        printf("regions             %zu\n", nr);
        for (size_t k = 0; k < nr; ++k) {
            const json_t *e = json_array_get(mi->regions, k);
            printf("  %s  %lld voxels\n", json_str_or(e, "name", "-"), (long long)json_integer_value(json_object_get(e, "voxels")));
        }
    }
    printf("recorded shapes     %zu%s\n", nl, nl ? "" : " (layers and trays need --mesh)");
    for (size_t k = 0; k < nl; ++k) {
        const json_t *l = json_array_get(mi->leaves, k);
        printf("  %s  %s\n", json_str_or(l, "kind", "-"), json_str_or(l, "name", "-"));
    }
}

static hv_status model_json(hv_buf *b, const char *path, const model_info *mi)
{
    const hv_volume *vol = mi->vol;
    hv_transform xf = hv_volume_get_transform(vol);
    json_t *o = json_object(), *grids = json_array(), *mats = json_array(), *regs = json_array(), *shapes = json_array();
    int fail = !o || hv_json_set(o, "file", hv_json_text(path)) | hv_json_set(o, "kind", json_string("model")) |
                         hv_json_set(o, "format", json_string("vdb"));
    double dims[3] = {0, 0, 0}, lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    for (int k = 0; k < 3 && !mi->empty; ++k) {
        dims[k] = mi->hi[k] - mi->lo[k] + 1;
        lo[k] = mi->lo[k];
        hi[k] = mi->hi[k];
    }
    fail |= hv_json_set(o, "dims", hv_json_numbers(dims, 3)) | hv_json_set(o, "index_min", hv_json_numbers(lo, 3)) |
            hv_json_set(o, "index_max", hv_json_numbers(hi, 3)) |
            hv_json_set(o, "voxel_mm", hv_json_numbers(xf.voxel, 3)) |
            hv_json_set(o, "origin_mm", hv_json_numbers(xf.origin, 3)) |
            hv_json_set(o, "bbox_min", mi->empty ? json_null() : hv_json_numbers(mi->wlo, 3)) |
            hv_json_set(o, "bbox_max", mi->empty ? json_null() : hv_json_numbers(mi->whi, 3)) |
            hv_json_set(o, "active_voxels", json_integer((json_int_t)hv_volume_active_count(vol)));
    for (int g = 0; g < hv_volume_grid_count(vol) && !fail; ++g) {
        json_t *x = json_object();
        fail = !x || hv_json_set(x, "name", hv_json_text(hv_volume_grid_name(vol, g))) |
                         hv_json_set(x, "type", json_string(hv_grid_type_name(hv_volume_grid_type(vol, g))));
        if (!fail && hv_volume_grid_type(vol, g) == HV_GRID_BOOL)
            fail = hv_json_set(x, "set", json_integer((json_int_t)hv_volume_mask_count(vol, g)));
        if (!fail) fail = json_array_append_new(grids, x) != 0;
    }
    for (int j = 0; mi->mats && j < hv_material_count(mi->mats) && !fail; ++j) {
        float c[4];
        double cd[4];
        hv_material_color(mi->mats, j, c);
        for (int k = 0; k < 4; ++k) cd[k] = c[k];
        json_t *x = json_object();
        fail = !x || hv_json_set(x, "name", hv_json_text(hv_material_name(mi->mats, j))) |
                         hv_json_set(x, "rgba", hv_json_numbers(cd, 4)) |
                         hv_json_set(x, "grid", hv_json_text(hv_volume_grid_name(vol, hv_material_grid(vol, mi->mats, j))));
        if (!fail) fail = json_array_append_new(mats, x) != 0;
    }
    for (size_t k = 0; mi->regions && k < json_array_size(mi->regions) && !fail; ++k) {
        const json_t *e = json_array_get(mi->regions, k);
        json_t *x = json_object();
        fail = !x || hv_json_set(x, "name", hv_json_text(json_str_or(e, "name", "-"))) |
                         hv_json_set(x, "voxels", json_integer(json_integer_value(json_object_get(e, "voxels"))));
        if (!fail) fail = json_array_append_new(regs, x) != 0;
    }
    for (size_t k = 0; mi->leaves && k < json_array_size(mi->leaves) && !fail; ++k) {
        const json_t *l = json_array_get(mi->leaves, k);
        json_t *x = json_object();
        fail = !x || hv_json_set(x, "kind", json_string(json_str_or(l, "kind", "-"))) |
                         hv_json_set(x, "name", hv_json_text(json_str_or(l, "name", "-")));
        if (!fail) fail = json_array_append_new(shapes, x) != 0;
    }
    fail |= hv_json_set(o, "grids", grids) | hv_json_set(o, "materials", mats) | hv_json_set(o, "regions", regs) |
            hv_json_set(o, "recorded_shapes", shapes);
    char *text = fail ? NULL : json_dumps(o, JSON_COMPACT | JSON_PRESERVE_ORDER);
    json_decref(o);
    if (!text) return hv_error_set(HV_ERR_NOMEM, "out of memory");
    hv_buf_puts(b, text);
    free(text);
    return HV_OK;
}

/* Each body's own report (one body: the mesh's). */
static hv_status body_reports(const hv_mesh *m, hv_mesh_report **out)
{
    size_t nb = hv_mesh_body_count(m);
    *out = calloc(nb, sizeof **out);
    if (!*out) return hv_error_set(HV_ERR_NOMEM, "out of memory");
    for (size_t i = 0; i < nb; ++i) {
        hv_status s = hv_mesh_body_report(m, i, &(*out)[i]);
        if (s != HV_OK) {
            free(*out);
            *out = NULL;
            return s;
        }
    }
    return HV_OK;
}

static int report(char **paths, int n, const info_cli *opt)
{
    int json = opt->json;
    /* load everything first: no partial report on failure */
    hv_mesh **meshes = calloc((size_t)n, sizeof *meshes);
    hv_mesh_report **bodies = calloc((size_t)n, sizeof *bodies);
    hv_scan **scans = calloc((size_t)n, sizeof *scans);
    hv_volume **models = calloc((size_t)n, sizeof *models);
    model_info *minfo = calloc((size_t)n, sizeof *minfo);
    hv_status s = meshes && bodies && scans && models && minfo ? HV_OK : hv_error_set(HV_ERR_NOMEM, "out of memory");
    for (int i = 0; i < n && s == HV_OK; ++i) {
        if (is_vdb(paths[i])) { /* a model: loaded and checked as every command loads it */
            s = hv_model_load(paths[i], &models[i]);
            if (s == HV_OK) s = model_info_get(paths[i], models[i], &minfo[i]);
            continue;
        }
        if (hv_scan_path_is_scan(paths[i])) {
            s = hv_scan_load(paths[i], NULL, &scans[i]); /* --max-memory caps its budget */
            continue;
        }
        s = hv_mesh_load(paths[i], &meshes[i]);
        if (s == HV_OK) cli_mesh_notes(meshes[i]);
        if (s == HV_OK) s = body_reports(meshes[i], &bodies[i]);
    }
    if (s != HV_OK) {
        for (int k = 0; k < n && meshes && bodies && scans && models && minfo; ++k) {
            hv_mesh_destroy(meshes[k]);
            free(bodies[k]);
            hv_scan_destroy(scans[k]);
            model_info_free(&minfo[k]);
            hv_volume_destroy(models[k]);
        }
        free(meshes);
        free(bodies);
        free(scans);
        free(models);
        free(minfo);
        return cli_fail(s);
    }
    hv_buf out;
    hv_buf_init(&out);
    if (json && n > 1) hv_buf_puts(&out, "[");
    for (int i = 0; i < n; ++i) {
        const char *path = paths[i];
        if (meshes[i]) warn_inside_out(path, meshes[i], bodies[i]);
        if (json) {
            if (i) hv_buf_puts(&out, ",\n ");
            if (models[i]) {
                if (model_json(&out, path, &minfo[i]) != HV_OK) out.failed = 1;
            } else if (scans[i]) scan_json(&out, path, scans[i]);
            else hv_mesh_info_json(&out, path, meshes[i], bodies[i]);
        } else {
            if (i) putchar('\n');
            if (models[i]) print_model_text(path, &minfo[i]);
            else if (scans[i]) print_scan_text(path, scans[i]);
            else print_text(path, meshes[i], bodies[i]);
        }
        hv_mesh_destroy(meshes[i]);
        free(bodies[i]);
        hv_scan_destroy(scans[i]);
        model_info_free(&minfo[i]);
        hv_volume_destroy(models[i]);
    }
    free(meshes);
    free(bodies);
    free(scans);
    free(models);
    free(minfo);
    if (json) {
        if (n > 1) hv_buf_puts(&out, "]");
        hv_buf_puts(&out, "\n");
        if (out.failed) {
            hv_buf_free(&out);
            return cli_fail(hv_error_set(HV_ERR_NOMEM, "out of memory"));
        }
        fputs(out.data, stdout);
    }
    hv_buf_free(&out);
    return EXIT_OK;
}

static int run(const cli_args *args, void *lib, void *local)
{
    (void)lib;
    return report(args->pos, args->npos, (const info_cli *)local);
}

const cli_spec cmd_info = {
    "info", "report on meshes (size, volume, shells, defects, bodies, materials), scanner volumes and models",
    "[--json] MESH.stl|.3mf|.obj|.ply|VOLUME.nii[.gz]|.nrrd|.nhdr|.mha|.mhd|DICOM-DIR|MODEL.vdb [...]",
    "Load meshes (STL binary or ASCII, detected by content; 3MF; OBJ; PLY) and report:\n"
    "facets, vertices after exact welding, bounding box, signed volume, surface area,\n"
    "shells, open and non-manifold edges, degenerate facets, facets whose orientation\n"
    "disagrees with their neighbours, and stored normals that contradict the winding;\n"
    "then the materials the file names, and for a file of several bodies (3MF build\n"
    "items, OBJ groups) each body's material, facets, volume, shells and closedness.\n"
    "Defects are reported, not fatal; unreadable files are errors.\n"
    "A volume (NIfTI-1/2, NRRD, MetaImage, or a directory holding one DICOM series) is\n"
    "read whole and reported: format, samples and their type, value range (DICOM rescaled\n"
    "to Hounsfield units), spacing, orientation, the index-to-world affine and the world\n"
    "box, in RAS millimetres (DICOM, MetaImage and LPS NRRD files are turned from LPS).\n"
    "A hovox model (.vdb, known by its content) is loaded and checked as other commands\n"
    "load it, and reported: dims of its active voxels, voxel size, origin, world box,\n"
    "grids, materials (colour, grid), regions and the shapes it records (meshes).\n",
    NULL, &k_local, NULL, 1, -1, "MESH argument", 0, run, NULL, NULL};
