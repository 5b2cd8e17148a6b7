/* src/voxel/voxelize_options.c - the voxelizer's options (hovox/voxelize.h, hovox/options.h):
 * names, domains and defaults in one table for the library, the CLI and Lua. */
#include <stddef.h>
#include <string.h>

#include "core/internal.h"
#include "hovox/voxelize.h"

static const char *const k_fill_names[] = {"auto", "flood", "vote", "none", NULL};
static const char *const k_fill_aliases[] = {"winding", "vote", NULL};
static const hv_enum_def k_fill = {"fill mode", k_fill_names, NULL, k_fill_aliases};
static const char *const k_adj_names[] = {"6", "26", NULL};
static const int k_adj_values[] = {6, 26};
static const hv_enum_def k_adj = {"adjacency", k_adj_names, k_adj_values, NULL};

const hv_enum_def *hv_fill_mode_enum(void) { return &k_fill; }

const char *hv_fill_mode_name(hv_fill_mode m)
{
    const char *n = hv_enum_name(&k_fill, (int)m);
    return n ? n : "?";
}

hv_status hv_fill_mode_parse(const char *name, hv_fill_mode *out)
{
    int v;
    hv_status s = hv_enum_parse(&k_fill, name, &v);
    if (s == HV_OK) *out = (hv_fill_mode)v;
    return s;
}

#define OFF(f) offsetof(hv_voxelize_options, f)
static const hv_option k_opts[] = {
    {.key = "dims", .kind = HV_OPT_NUMBER, .elem = HV_ELEM_INT64, .count = 3, .flags = HV_OPT_FIRST,
     .lo = 1, .hi = 2147483647, .offset = OFF(dims), .meta = "N|X,Y,Z",
     .help = "N voxels along the longest axis (cubic voxels), or X,Y,Z voxels per axis (Wu's 64,64,45; "
             "anisotropic voxels when the ratios differ); the grid is centred on the mesh (default 128 on the "
             "longest axis)",
     .section = "Resolution (one of)"},
    {.key = "voxel_size", .kind = HV_OPT_NUMBER, .count = 3, .flags = HV_OPT_SCALAR, .lo = 1e-4,
     .hi = 1e6, .offset = OFF(voxel_size), .meta = "L|X,Y,Z", .unit = "mm",
     .help = "cubic voxels of size L, or a size per axis; the lattice is global (voxel centres at (n + 1/2) L), "
             "so meshes voxelized with the same size line up"},
    {.key = "adjacency", .kind = HV_OPT_ENUM, .enumdef = &k_adj, .offset = OFF(adjacency), .meta = "6|26",
     .help = "6: thinnest surface without 6-connected tunnels; 26: no 26-connected tunnels (every voxel a "
             "triangle touches)",
     .section = "Surface and interior"},
    {.key = "fill", .kind = HV_OPT_ENUM, .enumdef = &k_fill, .offset = OFF(fill), .meta = "MODE",
     .help = "auto: flood for one closed, manifold, consistently oriented shell, else vote (a hollow part's cavity stays empty); flood: flood the "
             "outside from the border; vote (alias winding): majority of the x/y/z lines of even crossing "
             "parity, the generalized winding number where they leave a voxel undecided; none: surface only"},
    {.key = "max_memory", .kind = HV_OPT_BYTES, .offset = OFF(max_memory), .meta = "SIZE",
     .help = "refuse jobs that would need more (default: half of RAM), e.g. 8G", .section = "Resources"},
};
#undef OFF

static const hv_opt_rule k_rules[] = {{HV_RULE_EXCLUDES, "dims", "voxel_size", NULL, NULL}};

static hv_status validate(const void *opts)
{
    const hv_voxelize_options *o = opts;
    int dims = o->dims[0] || o->dims[1] || o->dims[2];
    int size = o->voxel_size[0] != 0 || o->voxel_size[1] != 0 || o->voxel_size[2] != 0;
    if (dims && (o->dims[1] || o->dims[2]) && !(o->dims[1] && o->dims[2]))
        return hv_error_option(HV_ERR_INVALID, "{dims} must be N or X,Y,Z with all three > 0, got %lld,%lld,%lld",
                               (long long)o->dims[0], (long long)o->dims[1], (long long)o->dims[2]);
    if (size && !(o->voxel_size[0] > 0 && o->voxel_size[1] > 0 && o->voxel_size[2] > 0))
        return hv_error_option(HV_ERR_INVALID, "{voxel_size} must be > 0 on every axis, got %g,%g,%g",
                               o->voxel_size[0], o->voxel_size[1], o->voxel_size[2]);
    if (dims && size) return hv_error_option(HV_ERR_INVALID, "{dims} and {voxel_size} exclude each other");
    if (o->lattice && dims) return hv_error_option(HV_ERR_INVALID, "{like} and {dims} exclude each other");
    if (o->lattice && size) return hv_error_option(HV_ERR_INVALID, "{like} and {voxel_size} exclude each other");
    return HV_OK;
}

void hv_voxelize_options_init(hv_voxelize_options *o)
{
    memset(o, 0, sizeof *o);
    o->adjacency = 26;
    o->fill = HV_FILL_AUTO;
}

static void init(void *o) { hv_voxelize_options_init(o); }

static const hv_option_set k_set = {"voxelize", k_opts, (int)HV_COUNT(k_opts), sizeof(hv_voxelize_options), init,
                                    k_rules, (int)HV_COUNT(k_rules), NULL, validate, NULL, 0};

const hv_option_set *hv_voxelize_option_set(void) { return &k_set; }

hv_status hv_voxelize_options_check(const hv_voxelize_options *o) { return hv_options_check(&k_set, o); }
