/* src/cli/cmd_probe.c - `hovox probe MODEL.vdb X,Y,Z ... [--points FILE.csv]`: material
 * fractions of a graded model at points, as CSV on stdout. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "cli.h"
#include "hovox/model.h"
#include "hovox/material.h"

typedef struct probe_cli {
    const char *files[64];
    int nfiles;
} probe_cli;

static hv_status add_points_file(const hv_option *o, void *opts, const hv_opt_value *v)
{
    probe_cli *c = opts;
    if (c->nfiles == (int)HV_COUNT(c->files)) return hv_error_option(HV_ERR_INVALID, "at most %d {%s} files", (int)HV_COUNT(c->files), o->key);
    c->files[c->nfiles++] = v->text;
    return HV_OK;
}

static const hv_option k_local_opts[] = {
    {.key = "points", .kind = HV_OPT_CUSTOM, .flags = HV_OPT_REPEAT, .meta = "FILE", .parse = add_points_file,
     .help = "read points from a CSV file of x,y,z rows (repeatable); a header line (x,y,z) is allowed, blank "
             "lines and lines starting with # are skipped"},
};
static const hv_option_set k_local = CLI_LOCAL_SET("probe", k_local_opts, probe_cli);

/* A point argument: three numbers, in the library's vector syntax. */
static const hv_option k_point = {.key = "point", .kind = HV_OPT_NUMBER, .count = 3, .meta = "X,Y,Z"};



typedef struct points {
    double *xyz;
    size_t n, cap;
} points;

static int points_add(points *p, const double v[3])
{
    if (hv_grow((void **)&p->xyz, &p->cap, 3 * (p->n + 1), sizeof *p->xyz) != HV_OK) return -1;
    memcpy(p->xyz + 3 * p->n, v, 3 * sizeof *v);
    ++p->n;
    return 0;
}

static int probe(const char *model, const points *pts)
{
    hv_volume *vol = NULL;
    hv_status s = hv_model_load(model, &vol);
    if (s == HV_OK && (s = hv_model_probe_csv(vol, pts->xyz, pts->n, stdout)) != HV_OK)
        hv_error_prefix(s, "%s: ", s == HV_ERR_IO ? "stdout" : model);
    hv_volume_destroy(vol);
    return s == HV_OK ? EXIT_OK : cli_fail(s);
}

static int run(const cli_args *args, void *lib, void *local)
{
    const probe_cli *c = local;
    points pts = {NULL, 0, 0};
    int rc = -1;
    (void)lib;
    for (int i = 1; rc < 0 && i < args->npos; ++i) {
        double v[3];
        if (hv_option_set_text(&k_point, v, args->pos[i]) != HV_OK) rc = cli_usage_error("probe", "%s", hv_last_error());
        else if (points_add(&pts, v) != 0) rc = cli_fail(HV_ERR_NOMEM);
    }
    if (rc < 0 && pts.n == 0 && c->nfiles == 0)
        rc = cli_usage_error("probe", "no points: give X,Y,Z arguments or --points FILE.csv");
    for (int f = 0; f < c->nfiles && rc < 0; ++f) {
        hv_status s = hv_points_read_csv(c->files[f], &pts.xyz, &pts.n);
        pts.cap = 3 * pts.n; /* the library grew the array past what pts knew */
        if (s != HV_OK) rc = cli_fail(s);
    }
    if (rc < 0) rc = probe(args->pos[0], &pts);
    free(pts.xyz);
    return rc;
}

const cli_spec cmd_probe = {
    "probe", "material fractions at points of a model", "MODEL.vdb X,Y,Z [X,Y,Z ...] [--points FILE.csv]",
    "Material fractions of a graded model at points (world coordinates, mm). Prints CSV on\n"
    "stdout: a header 'x,y,z,inside,<material names...>' and one row per point, the points\n"
    "given as arguments first, then those of the --points files, in order.\n"
    "  inside     1 when the trilinear occupancy at the point is at least 0.5, else 0\n"
    "  fractions  trilinear over the occupied voxels around the point, renormalised so they\n"
    "             sum to 1 up to the boundary; just outside the boundary they are those of\n"
    "             the nearest occupied voxels, far from the object 0\n",
    NULL, &k_local, "Negative coordinates need no quoting: 'hovox probe m.vdb -1.5,0,2' is a point.\n",
    1, -1, "MODEL argument", CLI_NUMERIC_POS, run, NULL, NULL};
