/* src/io/vtk/vtk_plugin.c - the VTK bridge plugin (plugins/hovox-vtk.so: VTK XML files written, fields
 * probed), loaded on first use. */
#include "core/plugin.h"
#include "vtk_bridge.h"

static hv_plugin g_vtk_plugin = HV_PLUGIN_DEF("hovox-vtk", HV_VTK_ENTRY, HV_VTK_ABI, "VTK bridge");

hv_status hv_vtk_bridge(const hv_vtk_api **api)
{
    const void *t = NULL;
    hv_status s = hv_plugin_api(&g_vtk_plugin, &t);
    *api = t;
    return s;
}
