/* src/cli/place.c - a mesh as the command line places it: loaded, moved by the placement options
 * (--unit, --up, --scale, --rotate, --translate; hovox/placement.h), and warned about when its
 * size suggests a wrong unit (issue 27 item 3). */
#include <stdlib.h>

#include "cli.h"
#include "hovox/layers.h"

void cli_warn_mesh_size(const hv_mesh *mesh, const double build[3])
{
    double largest[3] = {0, 0, 0};
    if (!build) { /* no printer named: the largest build volume of the built-in profiles */
        for (int i = 0; i < hv_printer_profile_count(); ++i)
            for (int k = 0; k < 3; ++k)
                if (hv_printer_profile_at(i)->build[k] > largest[k]) largest[k] = hv_printer_profile_at(i)->build[k];
        build = largest[0] > 0 ? largest : NULL;
    }
    char msg[2048];
    if (hv_placement_size_warning(mesh, build)) cli_warn("%s", cli_message(msg, sizeof msg));
}

hv_status cli_mesh_load_placed(const char *path, const hv_placement *place, const double build[3], hv_mesh **out)
{
    hv_status s = hv_mesh_load(path, out);
    if (s == HV_OK) cli_mesh_notes(*out); /* the reader's notes, before the mesh is placed */
    if (s == HV_OK) s = hv_placement_apply(place, out);
    if (s != HV_OK) {
        hv_mesh_destroy(*out);
        *out = NULL;
        return s;
    }
    cli_warn_mesh_size(*out, build);
    return HV_OK;
}
