/* src/model/load.c - the one model loader (hovox/model.h): an OpenVDB file or a 3MF Volumetric
 * package, told apart by the first bytes, its grids checked against each other (check.c). */
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "core/internal.h"
#include "hovox/colour.h"
#include "hovox/mesh.h"
#include "hovox/model.h"
#include "hovox/threemf.h"

typedef enum model_kind { MODEL_VDB, MODEL_3MF } model_kind;

/* OpenVDB files start with the int64 magic 0x56444220 ("VDB ") */
static int is_vdb(const unsigned char *magic, size_t got)
{
    return got == 4 && magic[0] == 0x20 && magic[1] == 0x42 && magic[2] == 0x44 && magic[3] == 0x56;
}

/* Which reader: a ZIP archive is a 3MF package; anything else goes to the .vdb reader, which says
 * what is wrong with a file that is neither. */
static hv_status sniff(const char *path, model_kind *kind)
{
    struct stat st;
    if (stat(path, &st) != 0) return hv_error_set(HV_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    if (S_ISDIR(st.st_mode)) return hv_error_set(HV_ERR_IO, "%s: is a directory, not a file", path);
    FILE *fp = fopen(path, "rb");
    if (!fp) return hv_error_set(HV_ERR_IO, "%s: cannot open for reading", path);
    unsigned char magic[4] = {0};
    size_t got = fread(magic, 1, 4, fp);
    fclose(fp);
    *kind = got == 4 && magic[0] == 'P' && magic[1] == 'K' && magic[2] == 3 && magic[3] == 4 ? MODEL_3MF : MODEL_VDB;
    /* a mesh handed to the model loader is told what it is, not "bad magic number" */
    if (*kind == MODEL_VDB && !is_vdb(magic, got) && hv_mesh_sniff(path))
        return hv_error_set(HV_ERR_BAD_INPUT,
                            "%s: a mesh, not a model (a .vdb file or a 3MF Volumetric package): voxelize the mesh instead",
                            path);
    return HV_OK;
}

int hv_model_file_is_mesh(const char *path)
{
    if (hv_3mf_sniff(path)) return !hv_3mf_is_volumetric(path);
    FILE *fp = fopen(path, "rb");
    if (!fp) return 0;
    unsigned char magic[4] = {0};
    size_t got = fread(magic, 1, 4, fp);
    fclose(fp);
    return !is_vdb(magic, got) && hv_mesh_sniff(path);
}

/* A model whose grids disagree is refused whole (hv_model_check). */
static hv_status checked(hv_volume **out)
{
    hv_status s = hv_model_check(*out);
    if (s != HV_OK) {
        hv_volume_destroy(*out);
        *out = NULL;
    }
    return s;
}

hv_status hv_model_load(const char *path, hv_volume **out) { return hv_model_load_colour(path, NULL, out); }

hv_status hv_model_load_colour(const char *path, const hv_colour_options *colour, hv_volume **out)
{
    *out = NULL;
    model_kind kind;
    hv_status s = sniff(path, &kind);
    if (s != HV_OK) return s;
    hv_input_note(path);
    s = kind == MODEL_3MF ? hv_3mf_load_colour(path, colour, out, NULL) : hv_volume_load(path, out);
    return s == HV_OK ? checked(out) : s;
}

hv_status hv_model_load_grids(const char *path, const char *const *names, int n, hv_volume **out)
{
    *out = NULL;
    model_kind kind;
    hv_status s = sniff(path, &kind);
    if (s != HV_OK) return s;
    hv_input_note(path);
    s = kind == MODEL_3MF ? hv_3mf_load(path, out, NULL) : hv_volume_load_grids(path, names, n, out);
    return s == HV_OK ? checked(out) : s;
}
