/* src/io/3mf/slicer_config.c - what a slicer's project config says of the mesh objects of its 3MF.
 * PrusaSlicer (and Slic3r PE, SuperSlicer) keep all the volumes of an object in its one <mesh> and
 * list them in Metadata/Slic3r_PE_model.config, each a range of the object's triangles with its
 * type; Bambu Studio and OrcaSlicer make each volume a mesh object that a component of the object
 * places, and type it in Metadata/model_settings.config (<part id="the component's objectid"
 * subtype>). A volume is a model part, or a negative volume, a settings modifier, a support blocker
 * or enforcer, which neither slicer prints as solid. The mesh reader drops the latter
 * (mesh_read.c slicer_volumes). */
#include <stdlib.h>
#include <string.h>

#include "package.h"
#include "threemf_internal.h"

#define SLICER_MAX_CONFIG ((uint64_t)16 << 20) /* PrusaSlicer writes about 600 bytes a volume */

typedef struct scan {
    tmf_slicer_config *c;
    uint64_t object, part; /* the <object> being read (0: none), its <part> (Bambu; 0: none) */
    int in_volume;         /* its <volume> being read (PrusaSlicer): the last of c->vols */
} scan;

static int value_is(const tmf_attr *a, const char *s) { return a && a->len == strlen(s) && memcmp(a->value, s, a->len) == 0; }

static void copy_name(char *dst, size_t cap, const tmf_attr *a)
{
    size_t n = a->len < cap - 1 ? a->len : cap - 1;
    memcpy(dst, a->value, n);
    dst[n] = '\0';
}

static hv_status add_volume(tmf_slicer_config *c, const tmf_slicer_volume *v)
{
    hv_status s = hv_grow((void **)&c->vols, &c->cap, c->nvols + 1, sizeof *c->vols);
    if (s == HV_OK) c->vols[c->nvols++] = *v;
    return s;
}

static hv_status add_name(tmf_slicer_config *c, uint64_t object, uint64_t part, const tmf_attr *value)
{
    hv_status s = hv_grow((void **)&c->names, &c->ncap, c->nnames + 1, sizeof *c->names);
    if (s != HV_OK) return s;
    c->names[c->nnames].object = object;
    c->names[c->nnames].part = part;
    copy_name(c->names[c->nnames++].name, sizeof c->names->name, value);
    return HV_OK;
}

static hv_status on_start(void *ctx, tmf_xml *x, const char *local, const char *uri, const tmf_attr *a, int n)
{
    (void)x, (void)uri;
    scan *sc = ctx;
    tmf_slicer_config *c = sc->c;
    if (strcmp(local, "object") == 0) {
        if (tmf_attr_uint(tmf_attr_find(a, n, "id", NULL), INT32_MAX, &sc->object) <= 0) sc->object = 0;
        return HV_OK;
    }
    tmf_slicer_volume v;
    memset(&v, 0, sizeof v);
    v.object = sc->object;
    if (strcmp(local, "volume") == 0 && sc->object) { /* PrusaSlicer: a range of the object's triangles */
        if (tmf_attr_uint(tmf_attr_find(a, n, "firstid", NULL), INT32_MAX, &v.first) <= 0 ||
            tmf_attr_uint(tmf_attr_find(a, n, "lastid", NULL), INT32_MAX, &v.last) <= 0 || v.last < v.first)
            return HV_OK; /* not a range: not a volume the reader can place */
        sc->in_volume = 1;
        return add_volume(c, &v);
    }
    if (strcmp(local, "part") == 0 && sc->object) { /* Bambu: the object its component places */
        static const char *const subtypes[] = {"normal_part", "negative_part", "modifier_part", "support_blocker",
                                               "support_enforcer"};
        const tmf_attr *sub = tmf_attr_find(a, n, "subtype", NULL);
        if (tmf_attr_uint(tmf_attr_find(a, n, "id", NULL), INT32_MAX, &v.part) <= 0 || v.part == 0) return HV_OK;
        sc->part = v.part;
        for (int k = 0; k < (int)(sizeof subtypes / sizeof *subtypes); ++k)
            if (value_is(sub, subtypes[k])) v.kind = k;
        return add_volume(c, &v);
    }
    if (strcmp(local, "metadata") != 0 || !sc->object) return HV_OK;
    const tmf_attr *type = tmf_attr_find(a, n, "type", NULL), *key = tmf_attr_find(a, n, "key", NULL),
                   *value = tmf_attr_find(a, n, "value", NULL);
    if (!key || !value) return HV_OK;
    if (!type && value_is(key, "name")) { /* Bambu: the object's name, or its part's */
        if (sc->part) copy_name(c->vols[c->nvols - 1].name, sizeof v.name, value);
        return add_name(c, sc->object, sc->part, value);
    }
    if (value_is(type, "object") && value_is(key, "name")) return add_name(c, sc->object, 0, value);
    if (value_is(type, "volume") && sc->in_volume) {
        tmf_slicer_volume *last = &c->vols[c->nvols - 1];
        static const char *const kinds[] = {"ModelPart", "NegativeVolume", "ParameterModifier", "SupportBlocker",
                                            "SupportEnforcer"};
        if (value_is(key, "name")) copy_name(last->name, sizeof last->name, value);
        else if (value_is(key, "modifier") && value_is(value, "1")) last->kind = TMF_VOLUME_MODIFIER; /* Slic3r PE 1.41 */
        else if (value_is(key, "volume_type"))
            for (int k = 0; k < (int)(sizeof kinds / sizeof *kinds); ++k)
                if (value_is(value, kinds[k])) last->kind = k;
    }
    return HV_OK;
}

static hv_status on_end(void *ctx, tmf_xml *x, const char *local, const char *uri)
{
    (void)x, (void)uri;
    scan *sc = ctx;
    if (strcmp(local, "volume") == 0) sc->in_volume = 0;
    else if (strcmp(local, "part") == 0) sc->part = 0;
    else if (strcmp(local, "object") == 0) sc->object = sc->part = 0, sc->in_volume = 0;
    return HV_OK;
}

hv_status tmf_slicer_config_read(tmf_pkg *pk, tmf_slicer_config *c)
{
    memset(c, 0, sizeof *c);
    static const char *const configs[][2] = {{"Metadata/Slic3r_PE_model.config", "PrusaSlicer"},
                                             {"Metadata/model_settings.config", "Bambu Studio and OrcaSlicer"}};
    for (int k = 0; k < 2 && !c->part; ++k)
        if (tmf_pkg_has(pk, configs[k][0])) c->part = configs[k][0], c->slicer = configs[k][1];
    if (!c->part) return HV_OK;
    scan sc = {c, 0, 0, 0};
    tmf_xml_handler h = {on_start, on_end};
    hv_status s = tmf_xml_parse(pk, c->part, SLICER_MAX_CONFIG, &h, &sc);
    if (s == HV_ERR_NOMEM) return s;
    if (s != HV_OK) { /* the slicer's own file, not the model: read the model as the spec says */
        snprintf(c->unread, sizeof c->unread, "%s", hv_last_error());
        hv_error_clear();
        free(c->vols);
        free(c->names);
        c->vols = NULL;
        c->names = NULL;
        c->nvols = c->nnames = 0;
    }
    return HV_OK;
}

void tmf_slicer_config_free(tmf_slicer_config *c)
{
    free(c->vols);
    free(c->names);
    c->vols = NULL;
    c->names = NULL;
    c->nvols = c->nnames = 0;
}

const char *tmf_slicer_volume_kind(int kind)
{
    static const char *const names[] = {"model part", "negative volume", "modifier", "support blocker",
                                        "support enforcer"};
    return kind >= 0 && kind <= TMF_VOLUME_ENFORCER ? names[kind] : "?";
}
