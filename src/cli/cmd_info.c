/* src/cli/cmd_info.c - `hovox info MESH...`: the mesh report as text or JSON. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "mesh/mesh_internal.h"
#include "cli.h"
#include "hovox/mesh.h"

typedef struct info_cli {
    int json;
} info_cli;

static const hv_option k_local_opts[] = {CLI_JSON(info_cli, "one JSON object per mesh (an array when several meshes are given)")};
static const hv_option_set k_local = CLI_LOCAL_SET("info", k_local_opts, info_cli);


static void print_text(const char *path, const hv_mesh_report *r)
{
    int closed = r->open_edges == 0 && r->nonmanifold_edges == 0;
    printf("file                %s\n", path);
    printf("format              %s\n", hv_mesh_format_name(r->format));
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
    printf("closed              %s\n", closed ? "yes" : "no");
}

static int report(char **paths, int n, int json)
{
    /* load everything first: no partial report on failure */
    hv_mesh **meshes = calloc((size_t)n, sizeof *meshes);
    if (!meshes) return cli_fail(hv_error_set(HV_ERR_NOMEM, "out of memory"));
    for (int i = 0; i < n; ++i) {
        hv_status s = hv_mesh_load(paths[i], &meshes[i]);
        if (s != HV_OK) {
            for (int k = 0; k < i; ++k) hv_mesh_destroy(meshes[k]);
            free(meshes);
            return cli_fail(s);
        }
    }
    hv_buf out;
    hv_buf_init(&out);
    if (json && n > 1) hv_buf_puts(&out, "[");
    for (int i = 0; i < n; ++i) {
        const char *path = paths[i];
        const hv_mesh_report *r = hv_mesh_get_report(meshes[i]);
        if (json) {
            if (i) hv_buf_puts(&out, ",\n ");
            hv_mesh_report_json(&out, path, r);
        } else {
            if (i) putchar('\n');
            print_text(path, r);
        }
        hv_mesh_destroy(meshes[i]);
    }
    free(meshes);
    if (json) {
        if (n > 1) hv_buf_puts(&out, "]");
        hv_buf_puts(&out, "\n");
        fputs(out.data, stdout);
    }
    hv_buf_free(&out);
    return EXIT_OK;
}

static int run(const cli_args *args, void *lib, void *local)
{
    (void)lib;
    return report(args->pos, args->npos, ((const info_cli *)local)->json);
}

const cli_spec cmd_info = {
    "info", "report on an STL mesh: size, volume, shells, defects", "[--json] MESH.stl [MESH.stl ...]",
    "Load STL meshes (binary or ASCII, detected by content) and report: facets,\n"
    "vertices after exact welding, bounding box, signed volume, surface area, shells,\n"
    "open and non-manifold edges, degenerate facets, facets whose orientation disagrees\n"
    "with their neighbours, and stored normals that contradict the winding.\n"
    "Defects are reported, not fatal; unreadable files are errors.\n",
    NULL, &k_local, NULL, 1, -1, "MESH argument", 0, run, NULL, NULL};
