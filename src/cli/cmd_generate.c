/* src/cli/cmd_generate.c - `hovox generate SHAPE [key=value ...] -o OUT.stl`: parametric
 * closed meshes (test shapes, the bench input, Wu's shaft and gear). */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "hovox/generate.h"

static const char *GEN_HELP =
    "usage: hovox generate SHAPE [key=value ...] -o OUT.stl [--ascii]\n"
    "\n"
    "Write a closed, consistently oriented mesh (millimetres). Shapes and keys (defaults):\n"
    "  sphere     radius=10 segments=64 rings=32 cx=0 cy=0 cz=0\n"
    "  box        sx=20 sy=20 sz=20           (corner at the origin)\n"
    "  holed-box  sx=40 sy=30 sz=20 hole=8 segments=64   (through hole along z)\n"
    "  torus      R=20 r=6 segments=96 rings=48\n"
    "  cylinder   radius=27.5 length=150 axis=0 segments=128   (Wu's 150x55x55 shaft)\n"
    "  knot       facets=200000 p=2 q=3 R=30 r=12 tube=5   (tube around a torus knot)\n"
    "  gear       teeth=24 root=34.5 tip=39.45 bore=9.54 height=39.45 twist=0\n"
    "             segments=12 layers=1   (Wu's gear: bore 9.54, tip radius 39.45)\n"
    "\n"
    "Options:\n"
    "  -o, --output FILE   where to write (written atomically)\n"
    "  --ascii             ASCII STL instead of binary\n"
    "  -h, --help          this text\n";

typedef struct kv {
    const char *key;
    double value;
    int used;
} kv;

static double get(kv *kvs, int n, const char *key, double def)
{
    for (int i = 0; i < n; ++i)
        if (strcmp(kvs[i].key, key) == 0) {
            kvs[i].used = 1;
            return kvs[i].value;
        }
    return def;
}

static int as_int(double v) { return v > 2e9 ? 2000000000 : v < -2e9 ? -2000000000 : (int)lround(v); }

int cmd_generate(int argc, char **argv)
{
    static const struct option opts[] = {{"output", required_argument, NULL, 'o'},
                                         {"ascii", no_argument, NULL, 'a'},
                                         {"help", no_argument, NULL, 'h'},
                                         {NULL, 0, NULL, 0}};
    const char *output = NULL;
    int ascii = 0, c;
    optind = 1;
    opterr = 0;
    while ((c = getopt_long(argc, argv, ":o:h", opts, NULL)) != -1) {
        switch (c) {
        case 'o': output = optarg; break;
        case 'a': ascii = 1; break;
        case 'h': fputs(GEN_HELP, stdout); return EXIT_OK;
        case ':': return cli_usage_error("generate", "option '%s' needs a value", argv[optind - 1]);
        default: return cli_usage_error("generate", "unknown option '%s'", argv[optind - 1]);
        }
    }
    if (optind >= argc) return cli_usage_error("generate", "missing SHAPE");
    if (!output) return cli_usage_error("generate", "missing -o OUT.stl");
    const char *shape = argv[optind];
    int nkv = argc - optind - 1;
    kv kvs[64];
    if (nkv > 64) return cli_usage_error("generate", "too many parameters");
    for (int i = 0; i < nkv; ++i) {
        char *arg = argv[optind + 1 + i], *eq = strchr(arg, '=');
        if (!eq) return cli_usage_error("generate", "parameter '%s' is not key=value", arg);
        *eq = '\0';
        kvs[i].key = arg;
        kvs[i].used = 0;
        if (cli_parse_double("generate", arg, eq + 1, &kvs[i].value)) return EXIT_USAGE;
    }
    hv_mesh *mesh = NULL;
    hv_status s;
    if (strcmp(shape, "sphere") == 0) {
        double ctr[3] = {get(kvs, nkv, "cx", 0), get(kvs, nkv, "cy", 0), get(kvs, nkv, "cz", 0)};
        s = hv_generate_sphere(ctr, get(kvs, nkv, "radius", 10), as_int(get(kvs, nkv, "segments", 64)),
                               as_int(get(kvs, nkv, "rings", 32)), &mesh);
    } else if (strcmp(shape, "box") == 0) {
        double lo[3] = {0, 0, 0}, hi[3] = {get(kvs, nkv, "sx", 20), get(kvs, nkv, "sy", 20),
                                            get(kvs, nkv, "sz", 20)};
        s = hv_generate_box(lo, hi, &mesh);
    } else if (strcmp(shape, "holed-box") == 0) {
        double lo[3] = {0, 0, 0}, hi[3] = {get(kvs, nkv, "sx", 40), get(kvs, nkv, "sy", 30),
                                            get(kvs, nkv, "sz", 20)};
        s = hv_generate_box_with_hole(lo, hi, get(kvs, nkv, "hole", 8),
                                      as_int(get(kvs, nkv, "segments", 64)), &mesh);
    } else if (strcmp(shape, "torus") == 0) {
        double ctr[3] = {0, 0, 0};
        s = hv_generate_torus(ctr, get(kvs, nkv, "R", 20), get(kvs, nkv, "r", 6),
                              as_int(get(kvs, nkv, "segments", 96)), as_int(get(kvs, nkv, "rings", 48)),
                              &mesh);
    } else if (strcmp(shape, "cylinder") == 0) {
        double base[3] = {0, 0, 0};
        s = hv_generate_cylinder(base, as_int(get(kvs, nkv, "axis", 0)), get(kvs, nkv, "length", 150),
                                 get(kvs, nkv, "radius", 27.5), as_int(get(kvs, nkv, "segments", 128)),
                                 &mesh);
    } else if (strcmp(shape, "knot") == 0) {
        double facets = get(kvs, nkv, "facets", 200000);
        int nv = 64;
        int nu = as_int(facets / (2.0 * nv));
        s = hv_generate_torus_knot(as_int(get(kvs, nkv, "p", 2)), as_int(get(kvs, nkv, "q", 3)),
                                   get(kvs, nkv, "R", 30), get(kvs, nkv, "r", 12),
                                   get(kvs, nkv, "tube", 5), nu, nv, &mesh);
    } else if (strcmp(shape, "gear") == 0) {
        s = hv_generate_gear(as_int(get(kvs, nkv, "teeth", 24)), get(kvs, nkv, "root", 34.5),
                             get(kvs, nkv, "tip", 39.45), get(kvs, nkv, "bore", 9.54),
                             get(kvs, nkv, "height", 39.45), get(kvs, nkv, "twist", 0),
                             as_int(get(kvs, nkv, "segments", 12)), as_int(get(kvs, nkv, "layers", 1)),
                             &mesh);
    } else {
        return cli_usage_error("generate", "unknown shape '%s'", shape);
    }
    for (int i = 0; i < nkv; ++i)
        if (!kvs[i].used) {
            hv_mesh_destroy(mesh);
            return cli_usage_error("generate", "shape '%s' has no parameter '%s'", shape, kvs[i].key);
        }
    if (s != HV_OK) return cli_fail(s);
    s = hv_mesh_write_stl(mesh, output, ascii);
    hv_mesh_destroy(mesh);
    if (s != HV_OK) return cli_fail(s);
    return EXIT_OK;
}
