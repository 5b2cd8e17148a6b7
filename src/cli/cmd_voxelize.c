/* src/cli/cmd_voxelize.c - `hovox voxelize MESH -o MODEL.vdb`: surface + interior voxels. */
#include <getopt.h>
#include <stdio.h>
#include <string.h>

#include "core/internal.h"
#include "core/json.h"
#include "cli.h"
#include "hovox/voxelize.h"

static const char *VOX_HELP =
    "usage: hovox voxelize MESH.stl -o MODEL.vdb [options]\n"
    "\n"
    "Voxelize a mesh (Wu 2.1; Huang et al. 1998): triangles mark the voxels in their face\n"
    "slab, edge cylinders and vertex spheres; the interior is filled. Writes bool grids\n"
    "'occupancy' (surface and interior) and 'surface', voxel (i,j,k) centred at\n"
    "origin + (i*Lx, j*Ly, k*Lz), the grid centred on the mesh's bounding box.\n"
    "\n"
    "Resolution (one of; default --dims 128):\n"
    "  --dims N             N voxels along the longest axis, cubic voxels\n"
    "  --dims X,Y,Z         voxels per axis (Wu's 64,64,45); voxels may be anisotropic\n"
    "  --voxel-size L       cubic voxels of size L (mesh units, mm)\n"
    "  --voxel-size X,Y,Z   voxel size per axis\n"
    "  --like MODEL.vdb     the lattice of another model (to combine them by Booleans)\n"
    "With --voxel-size the lattice is global (voxel centres at (n + 1/2) * L), so meshes\n"
    "voxelized with the same size line up; with --dims the grid is centred on the mesh.\n"
    "Options:\n"
    "  --adjacency 6|26     6: thinnest surface without 6-connected tunnels; 26 (default):\n"
    "                       no 26-connected tunnels (every voxel a triangle touches)\n"
    "  --fill MODE          auto (default): flood for closed, manifold, consistently oriented\n"
    "                       meshes, else vote; flood: flood the outside from the border;\n"
    "                       vote (alias winding): majority of the x/y/z lines of even\n"
    "                       crossing parity, the generalized winding number where they\n"
    "                       leave a voxel undecided; robust to holes and flipped facets;\n"
    "                       none: surface only\n"
    "  --max-memory SIZE    refuse jobs that would need more (default: half of RAM), e.g. 8G\n"
    "  --dry-run            print the plan and its memory estimate, write nothing\n"
    "  --threads N          worker threads (default: all cores)\n"
    "  --json               print the summary as JSON\n"
    "  -q, --quiet          no progress bar\n"
    "  -o, --output FILE    the .vdb to write (atomically)\n"
    "  -h, --help           this text\n";

static int parse_dims(const char *s, int64_t dims[3])
{
    double v[3];
    dims[0] = dims[1] = dims[2] = 0;
    if (strchr(s, ',')) {
        if (cli_parse_vec("voxelize", "--dims", s, 3, v)) return EXIT_USAGE;
        for (int a = 0; a < 3; ++a) {
            if (v[a] < 1 || v[a] > 2147483647.0 || v[a] != (double)(int64_t)v[a])
                return cli_usage_error("voxelize", "--dims: '%s' must be positive integers", s);
            dims[a] = (int64_t)v[a];
        }
        return 0;
    }
    long n;
    if (cli_parse_int("voxelize", "--dims", s, 1, 2147483647L, &n)) return EXIT_USAGE;
    dims[0] = n;
    return 0;
}

int cmd_voxelize(int argc, char **argv)
{
    enum { O_ADJ = 256, O_VS, O_DIMS, O_FILL, O_MEM, O_DRY, O_THREADS, O_JSON, O_LIKE };
    static const struct option opts[] = {
        {"output", required_argument, NULL, 'o'},   {"adjacency", required_argument, NULL, O_ADJ},
        {"voxel-size", required_argument, NULL, O_VS}, {"dims", required_argument, NULL, O_DIMS},
        {"fill", required_argument, NULL, O_FILL},  {"max-memory", required_argument, NULL, O_MEM},
        {"dry-run", no_argument, NULL, O_DRY},      {"threads", required_argument, NULL, O_THREADS},
        {"json", no_argument, NULL, O_JSON},        {"quiet", no_argument, NULL, 'q'},
        {"like", required_argument, NULL, O_LIKE},
        {"help", no_argument, NULL, 'h'},           {NULL, 0, NULL, 0}};
    hv_voxelize_options opt;
    hv_voxelize_options_init(&opt);
    const char *output = NULL, *like = NULL;
    int dry = 0, json = 0, quiet = 0, c, have_res = 0;
    optind = 1;
    opterr = 0;
    while ((c = getopt_long(argc, argv, ":o:qh", opts, NULL)) != -1) {
        long n;
        unsigned long long size;
        switch (c) {
        case 'o': output = optarg; break;
        case 'q': quiet = 1; break;
        case 'h': fputs(VOX_HELP, stdout); return EXIT_OK;
        case O_ADJ:
            if (strcmp(optarg, "6") != 0 && strcmp(optarg, "26") != 0)
                return cli_usage_error("voxelize", "--adjacency must be 6 or 26 (got '%s')", optarg);
            opt.adjacency = optarg[0] == '6' ? 6 : 26;
            break;
        case O_VS:
            if (have_res++) return cli_usage_error("voxelize", "give one of --dims, --voxel-size and --like");
            if (strchr(optarg, ',')) {
                if (cli_parse_vec("voxelize", "--voxel-size", optarg, 3, opt.voxel_size)) return EXIT_USAGE;
            } else {
                if (cli_parse_double("voxelize", "--voxel-size", optarg, &opt.voxel_size[0])) return EXIT_USAGE;
                opt.voxel_size[1] = opt.voxel_size[2] = opt.voxel_size[0];
            }
            for (int a = 0; a < 3; ++a)
                if (!(opt.voxel_size[a] > 0))
                    return cli_usage_error("voxelize", "--voxel-size must be positive (got '%s')", optarg);
            break;
        case O_DIMS:
            if (have_res++) return cli_usage_error("voxelize", "give one of --dims, --voxel-size and --like");
            if (parse_dims(optarg, opt.dims)) return EXIT_USAGE;
            break;
        case O_FILL:
            if (strcmp(optarg, "auto") == 0) opt.fill = HV_FILL_AUTO;
            else if (strcmp(optarg, "flood") == 0) opt.fill = HV_FILL_FLOOD;
            else if (strcmp(optarg, "vote") == 0 || strcmp(optarg, "winding") == 0) opt.fill = HV_FILL_VOTE;
            else if (strcmp(optarg, "none") == 0) opt.fill = HV_FILL_NONE;
            else return cli_usage_error("voxelize", "--fill must be auto, flood, vote or none (got '%s')", optarg);
            break;
        case O_MEM:
            if (cli_parse_size("voxelize", "--max-memory", optarg, &size)) return EXIT_USAGE;
            opt.max_memory = size;
            break;
        case O_DRY: dry = 1; break;
        case O_THREADS:
            if (cli_parse_int("voxelize", "--threads", optarg, 1, 1024, &n)) return EXIT_USAGE;
            hv_set_threads((int)n);
            break;
        case O_JSON: json = 1; break;
        case O_LIKE:
            if (have_res++) return cli_usage_error("voxelize", "give one of --dims, --voxel-size and --like");
            like = optarg;
            break;
        case ':': return cli_usage_error("voxelize", "option '%s' needs a value", argv[optind - 1]);
        default: return cli_usage_error("voxelize", "unknown option '%s'", argv[optind - 1]);
        }
    }
    if (optind >= argc) return cli_usage_error("voxelize", "missing MESH argument");
    if (argc - optind > 1) return cli_usage_error("voxelize", "one MESH at a time (got '%s' too)", argv[optind + 1]);
    if (!output && !dry) return cli_usage_error("voxelize", "missing -o MODEL.vdb");
    const char *path = argv[optind];

    hv_transform lattice;
    if (like) {
        hv_volume *ref;
        hv_status ls = hv_volume_load(like, &ref);
        if (ls != HV_OK) return cli_fail(ls);
        lattice = hv_volume_get_transform(ref);
        hv_volume_destroy(ref);
        opt.lattice = &lattice;
    }
    hv_mesh *mesh;
    hv_status s = hv_mesh_load_stl(path, &mesh);
    if (s != HV_OK) return cli_fail(s);
    hv_voxel_plan plan;
    s = hv_voxelize_plan(mesh, &opt, &plan);
    if (s != HV_OK) {
        hv_mesh_destroy(mesh);
        return cli_fail(s);
    }
    hv_volume *vol = NULL;
    uint64_t occupied = 0, surface = 0;
    if (plan.fill == HV_FILL_FLOOD && hv_mesh_get_report(mesh)->open_edges > 0)
        fprintf(stderr, "hovox: warning: %s is open (%zu open edges): --fill flood leaks through its holes "
                        "and may leave it hollow; --fill vote (auto's choice for open meshes) does not\n",
                path, (size_t)hv_mesh_get_report(mesh)->open_edges);
    if (!dry) {
        cli_progress bar;
        cli_progress_init(&bar, quiet);
        hv_progress prog = {cli_progress_fn, &bar};
        opt.progress = &prog;
        s = hv_voxelize(mesh, &opt, &vol);
        cli_progress_done(&bar);
        if (s == HV_OK) s = hv_volume_save(vol, output);
        if (s != HV_OK) {
            hv_volume_destroy(vol);
            hv_mesh_destroy(mesh);
            return cli_fail(s);
        }
        occupied = hv_volume_mask_count(vol, hv_volume_grid_find(vol, "occupancy"));
        surface = hv_volume_mask_count(vol, hv_volume_grid_find(vol, "surface"));
    }
    const hv_mesh_report *r = hv_mesh_get_report(mesh);
    double vv = plan.xf.voxel[0] * plan.xf.voxel[1] * plan.xf.voxel[2];
    if (json) {
        json_t *j = json_pack("{s:o, s:[I, I, I], s:o, s:o, s:i, s:s, s:I}", "mesh", hv_json_text(path), "dims",
                              (json_int_t)plan.dims[0], (json_int_t)plan.dims[1], (json_int_t)plan.dims[2], "voxel",
                              hv_json_numbers(plan.xf.voxel, 3), "origin", hv_json_numbers(plan.xf.origin, 3),
                              "adjacency", opt.adjacency, "fill", hv_fill_mode_name(plan.fill), "memory_estimate",
                              (json_int_t)plan.memory_bytes);
        if (!dry && json_object_update_new(j, json_pack("{s:I, s:I, s:o, s:o, s:o}", "occupied", (json_int_t)occupied,
                                                        "surface", (json_int_t)surface, "voxel_volume",
                                                        hv_json_number((double)occupied * vv), "mesh_volume",
                                                        hv_json_number(r->volume), "output", hv_json_text(output))) != 0) {
            json_decref(j);
            j = NULL;
        }
        char *text = j ? hv_json_dump(j) : NULL;
        json_decref(j);
        if (text) printf("%s\n", text);
        free(text);
        if (!text) {
            hv_volume_destroy(vol);
            hv_mesh_destroy(mesh);
            return cli_fail(hv_error_set(HV_ERR_NOMEM, "out of memory"));
        }
    } else {
        printf("mesh        %s (%llu facets)\n", path, (unsigned long long)r->facets);
        printf("grid        %lld x %lld x %lld voxels of %.6g x %.6g x %.6g\n", (long long)plan.dims[0],
               (long long)plan.dims[1], (long long)plan.dims[2], plan.xf.voxel[0], plan.xf.voxel[1],
               plan.xf.voxel[2]);
        printf("origin      %.6g %.6g %.6g (centre of voxel 0,0,0)\n", plan.xf.origin[0],
               plan.xf.origin[1], plan.xf.origin[2]);
        printf("surface     adjacency %d, fill %s\n", opt.adjacency, hv_fill_mode_name(plan.fill));
        printf("memory      about %.1f MiB\n", (double)plan.memory_bytes / 1048576.0);
        if (!dry) {
            printf("occupied    %llu voxels (%llu surface), volume %.6g (mesh %.6g)\n",
                   (unsigned long long)occupied, (unsigned long long)surface, (double)occupied * vv,
                   r->volume);
            printf("wrote       %s\n", output);
        }
    }
    hv_volume_destroy(vol);
    hv_mesh_destroy(mesh);
    return EXIT_OK;
}
