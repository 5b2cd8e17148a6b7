/* src/material/object.c - heterogeneous objects H = {(O_r, G_r)} (Wu 2.2.3): regions with
 * geometry masks on a shared lattice and grading-source sets; AGS add/delete/move (eq. 24-26),
 * AGS union inside a region (nearest source or inverse-distance blend), the heterogeneous
 * Booleans intersection, union, difference and merge (eq. 27-30) plus CSG subtraction, and
 * the evaluation of an object into material grids, leaf by leaf, in parallel. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "hovox/geometry.h"
#include "hovox/voxelize.h"
#include "material_internal.h"
#include "volumes/schema.h"

typedef struct region {
    hv_volume *mask; /* bool grid 0 "mask"; the topology is exactly the region's voxels */
    int nags;
    size_t cap;
    hv_ags **ags;
    char *name;      /* NULL: unnamed (stored as "region.<index>") */
    double base[HV_MAX_MATERIALS]; /* composition where none of its sources applies */
} region;

struct hv_object {
    int m;
    hv_transform xf;
    int nreg;
    size_t rcap;
    region *reg;
    double base[HV_MAX_MATERIALS]; /* the default base: of new regions, set on all by set_base */
    hv_blend blend;
    double power;
    hv_volume *record; /* what the model recorded before grading, carried into evaluated volumes:
                          its metadata but the grading documents (mesh report, voxelization) and
                          its bool grid "surface" (topology: the surface voxels); NULL: none */
};

/* ---- regions ------------------------------------------------------------------------------ */

static void region_free(region *r)
{
    hv_volume_destroy(r->mask);
    for (int i = 0; i < r->nags; ++i) hv_ags_release(r->ags[i]);
    free(r->ags);
    free(r->name);
    memset(r, 0, sizeof *r);
}

static int region_has(const region *r, const hv_ags *a)
{
    for (int i = 0; i < r->nags; ++i)
        if (r->ags[i] == a) return 1;
    return 0;
}

static hv_status region_add_ags(region *r, hv_ags *a)
{
    if (region_has(r, a)) return HV_OK;
    hv_status s = hv_grow((void **)&r->ags, &r->cap, (size_t)r->nags + 1, sizeof *r->ags);
    if (s != HV_OK) return s;
    r->ags[r->nags++] = hv_ags_retain(a);
    return HV_OK;
}

static hv_status region_add_set(region *r, const region *src)
{
    for (int i = 0; i < src->nags; ++i) {
        hv_status s = region_add_ags(r, src->ags[i]);
        if (s != HV_OK) return s;
    }
    return HV_OK;
}

/* c = a op b on masks (same lattice); the result's topology is restricted to its true voxels. */
static hv_status mask_op(const hv_volume *a, const hv_volume *b, hv_mask_op op, hv_volume **out)
{
    *out = NULL;
    hv_volume *c;
    hv_status s = hv_volume_clone(a, &c);
    if (s != HV_OK) return s;
    int gb = -1;
    if ((s = hv_volume_grid_copy(c, "other", b, 0)) == HV_OK) {
        gb = hv_volume_grid_find(c, "other");
        s = hv_volume_mask_combine(c, 0, 0, gb, op);
    }
    if (s == HV_OK) s = hv_volume_grid_remove(c, gb);
    if (s == HV_OK) s = hv_volume_topology_restrict(c, 0);
    if (s != HV_OK) {
        hv_volume_destroy(c);
        return s;
    }
    *out = c;
    return HV_OK;
}

/* A region's mask: the true voxels of bool grid g of vol, on lattice xf. */
static hv_status mask_of(const hv_volume *vol, int g, const hv_transform *xf, hv_volume **out)
{
    *out = NULL;
    hv_volume *mask;
    hv_status s = hv_volume_create(xf, &mask);
    if (s != HV_OK) return s;
    if ((s = hv_volume_grid_copy(mask, "mask", vol, g)) != HV_OK || (s = hv_volume_topology_restrict(mask, 0)) != HV_OK) {
        hv_volume_destroy(mask);
        return s;
    }
    *out = mask;
    return HV_OK;
}

static hv_status object_new(int m, const hv_transform *xf, hv_object **out)
{
    hv_object *o = hv_calloc(1, sizeof *o);
    if (!o) return HV_ERR_NOMEM;
    o->m = m;
    o->xf = *xf;
    o->base[0] = 1.0;
    o->blend = HV_BLEND_NEAREST;
    o->power = 2.0;
    *out = o;
    return HV_OK;
}

int hv_object_region_find(const hv_object *o, const char *name)
{
    for (int r = 0; name && r < o->nreg; ++r)
        if (o->reg[r].name && strcmp(o->reg[r].name, name) == 0) return r;
    return -1;
}

/* Append a region (taking the mask) with the sources of set1 and set2, the name of `like` (when
 * no region has it yet; else unnamed) and its base (o's default without `like`); empty masks are
 * dropped. */
static hv_status push_region(hv_object *o, hv_volume *mask, const region *set1, const region *set2,
                             const region *like)
{
    if (hv_volume_active_count(mask) == 0) {
        hv_volume_destroy(mask);
        return HV_OK;
    }
    hv_status s = hv_grow((void **)&o->reg, &o->rcap, (size_t)o->nreg + 1, sizeof *o->reg);
    if (s != HV_OK) {
        hv_volume_destroy(mask);
        return s;
    }
    region *r = &o->reg[o->nreg++];
    memset(r, 0, sizeof *r);
    r->mask = mask;
    memcpy(r->base, like ? like->base : o->base, sizeof r->base);
    if (like && like->name && hv_object_region_find(o, like->name) < 0 && !(r->name = hv_strdup(like->name)))
        return HV_ERR_NOMEM;
    if (set1 && (s = region_add_set(r, set1)) != HV_OK) return s;
    if (set2 && (s = region_add_set(r, set2)) != HV_OK) return s;
    return HV_OK;
}

/* ---- the model's record ------------------------------------------------------------------------
 * A model graded from the CLI or from Lua holds the same: the record of its model (see struct
 * hv_object) goes into every evaluated volume. */

static hv_status meta_copy(hv_volume *dst, const hv_volume *src, const char *key)
{
    double num;
    if (hv_volume_meta_number(src, key, &num)) return hv_volume_meta_set_number(dst, key, num);
    return hv_volume_meta_set_string(dst, key, hv_volume_meta_string(src, key));
}

static hv_status record_take(const hv_volume *vol, const hv_transform *xf, hv_volume **out)
{
    *out = NULL;
    hv_volume *r;
    hv_status s = hv_volume_create(xf, &r);
    if (s != HV_OK) return s;
    for (int i = 0; i < hv_volume_meta_count(vol) && s == HV_OK; ++i)
        if (!hv_schema_is_grading_key(hv_volume_meta_key(vol, i))) s = meta_copy(r, vol, hv_volume_meta_key(vol, i));
    int g = hv_volume_grid_find(vol, "surface");
    if (s == HV_OK && g >= 0 && hv_volume_grid_type(vol, g) == HV_GRID_BOOL &&
        (s = hv_volume_grid_copy(r, "surface", vol, g)) == HV_OK)
        s = hv_volume_topology_restrict(r, 0);
    if (s != HV_OK) {
        hv_volume_destroy(r);
        return s;
    }
    *out = r;
    return HV_OK;
}

/* The record of a Boolean's result: the metadata both operands record alike, and the union of
 * their surfaces; none when an operand has none. */
static hv_status record_combine(const hv_volume *a, const hv_volume *b, hv_volume **out)
{
    *out = NULL;
    if (!a || !b) return HV_OK;
    hv_volume *r;
    hv_status s = hv_volume_clone(a, &r);
    if (s != HV_OK) return s;
    for (int i = hv_volume_meta_count(r) - 1; i >= 0 && s == HV_OK; --i) {
        const char *key = hv_volume_meta_key(r, i), *sa = hv_volume_meta_string(r, key), *sb = hv_volume_meta_string(b, key);
        double na, nb;
        int same = sa ? sb && strcmp(sa, sb) == 0
                      : hv_volume_meta_number(r, key, &na) && hv_volume_meta_number(b, key, &nb) && na == nb;
        if (!same) s = hv_volume_meta_set_string(r, key, NULL);
    }
    int gb = hv_volume_grid_find(b, "surface");
    if (s == HV_OK && gb >= 0) {
        int ga = hv_volume_grid_find(r, "surface");
        if (ga < 0) {
            s = hv_volume_grid_copy(r, "surface", b, gb);
        } else if ((s = hv_volume_grid_copy(r, "other", b, gb)) == HV_OK) {
            int go = hv_volume_grid_find(r, "other");
            if ((s = hv_volume_mask_combine(r, ga, ga, go, HV_MASK_UNION)) == HV_OK) s = hv_volume_grid_remove(r, go);
        }
    }
    if (s != HV_OK) {
        hv_volume_destroy(r);
        return s;
    }
    *out = r;
    return HV_OK;
}

/* Put the record into v, an evaluated volume: its metadata, and its surface restricted to v's
 * occupancy (the copy may add voxels outside the graded object, e.g. for a region narrower than
 * the model: restricting drops them again). */
static hv_status record_put(const hv_object *o, hv_volume *v)
{
    const hv_volume *r = o->record;
    if (!r) return HV_OK;
    hv_status s = HV_OK;
    for (int i = 0; i < hv_volume_meta_count(r) && s == HV_OK; ++i) s = meta_copy(v, r, hv_volume_meta_key(r, i));
    int g = hv_volume_grid_find(r, "surface");
    if (s == HV_OK && g >= 0 && (s = hv_volume_grid_copy(v, "surface", r, g)) == HV_OK)
        s = hv_volume_topology_restrict(v, hv_volume_grid_find(v, "occupancy"));
    return s;
}

/* ---- life cycle ---------------------------------------------------------------------------- */

hv_status hv_object_create(const hv_volume *vol, const char *grid, int m, hv_object **out)
{
    *out = NULL;
    if (m < 1 || m > HV_MAX_MATERIALS)
        return hv_error_set(HV_ERR_INVALID, "material count %d out of range [1, %d]", m, HV_MAX_MATERIALS);
    int g = hv_volume_grid_need(vol, grid, HV_GRID_BOOL);
    if (g < 0) return hv_error_prefix(HV_ERR_NOT_FOUND, "the model has ");
    hv_transform xf = hv_volume_get_transform(vol);
    hv_object *o;
    hv_status s = object_new(m, &xf, &o);
    if (s != HV_OK) return s;
    hv_volume *mask;
    if ((s = mask_of(vol, g, &xf, &mask)) == HV_OK) {
        if (hv_volume_active_count(mask) == 0) {
            hv_volume_destroy(mask);
            s = hv_error_set(HV_ERR_INVALID, "bool grid '%s' is empty", grid);
        } else {
            s = push_region(o, mask, NULL, NULL, NULL);
        }
    }
    if (s == HV_OK) s = record_take(vol, &xf, &o->record);
    if (s != HV_OK) {
        hv_object_destroy(o);
        return s;
    }
    *out = o;
    return HV_OK;
}

/* "A, B" into buf: the table's names, for messages. */
static const char *table_list(const hv_material_table *t, char *buf, size_t n)
{
    size_t at = 0;
    buf[0] = '\0';
    for (int j = 0; j < hv_material_count(t) && at + 1 < n; ++j) {
        int k = snprintf(buf + at, n - at, "%s%s", j ? ", " : "", hv_material_name(t, j));
        if (k < 0) break;
        at += (size_t)k;
    }
    return buf;
}

/* Material `material` of region g in table t: found, else added with the region's colour (only
 * when the region's material is that one, not a mixture's part), else refused when the table was
 * given. */
static hv_status region_material(hv_material_table *t, const hv_material_table *given, const hv_region_info *g,
                                 const char *material, int *k)
{
    char name[65];
    hv_material_name_from(material, name);
    *k = hv_material_find(t, name);
    if (*k >= 0) return HV_OK;
    if (given) {
        char list[1024], as[400];
        if (strcmp(name, material) == 0) snprintf(as, sizeof as, "%s", name);
        else snprintf(as, sizeof as, "%s (in the file: %s)", name, material);
        return hv_error_set(HV_ERR_INVALID, "region '%s' is %s %s, which the materials given (%s) do not name", g->name,
                            g->nparts ? "in part material" : "material", as, table_list(t, list, sizeof list));
    }
    return hv_material_add(t, name, g->has_color && !g->nparts ? g->rgba : NULL, k);
}

hv_status hv_object_from_regions(const hv_volume *vol, const hv_material_table *given, hv_material_table **table,
                                 hv_object **out)
{
    *out = NULL;
    *table = NULL;
    hv_regions *rg = NULL;
    hv_status s = hv_voxelize_regions_read(vol, &rg);
    if (s != HV_OK) return s;
    size_t n = hv_regions_count(rg);
    hv_material_table *t = NULL;
    hv_object *o = NULL;
    int *mat = hv_calloc(n ? n * HV_MAX_MIX_PARTS : 1, sizeof *mat); /* per region: its materials' indices */
    if (!mat) s = HV_ERR_NOMEM;
    else s = given ? hv_material_table_clone(given, &t) : hv_material_table_create(&t);
    /* each region's material in the table */
    for (size_t i = 0; i < n && s == HV_OK; ++i) {
        const hv_region_info *g = hv_regions_at(rg, i);
        if (!g->material) {
            if (given) mat[i * HV_MAX_MIX_PARTS] = 0;
            else
                s = hv_error_option(HV_ERR_INVALID, "region '%s' has no material (the mesh names none): give the {materials}",
                                    g->name);
            continue;
        }
        for (size_t q = 0; q < HV_MAX(g->nparts, 1) && s == HV_OK; ++q)
            s = region_material(t, given, g, g->nparts ? g->parts[q].material : g->material, &mat[i * HV_MAX_MIX_PARTS + q]);
    }
    hv_transform xf = hv_volume_get_transform(vol);
    int m = t ? hv_material_count(t) : 0;
    if (s == HV_OK) s = object_new(m, &xf, &o);
    for (size_t i = 0; i < n && s == HV_OK; ++i) {
        const hv_region_info *g = hv_regions_at(rg, i);
        int gi = hv_volume_grid_need(vol, g->grid, HV_GRID_BOOL);
        if (gi < 0) {
            s = hv_error_prefix(HV_ERR_BAD_INPUT, "%s: region '%s': the model has ", hv_schema_key(HV_DOC_REGIONS),
                                g->name);
            break;
        }
        hv_volume *mask;
        if ((s = mask_of(vol, gi, &xf, &mask)) != HV_OK) break;
        region like;
        memset(&like, 0, sizeof like);
        like.name = (char *)g->name;
        if (g->nparts)
            for (size_t q = 0; q < g->nparts; ++q) like.base[mat[i * HV_MAX_MIX_PARTS + q]] += g->parts[q].fraction;
        else
            like.base[mat[i * HV_MAX_MIX_PARTS]] = 1.0;
        if (hv_object_region_find(o, g->name) >= 0) {
            hv_volume_destroy(mask);
            s = hv_error_set(HV_ERR_BAD_INPUT, "%s: region '%s' is named twice", hv_schema_key(HV_DOC_REGIONS), g->name);
            break;
        }
        s = push_region(o, mask, NULL, NULL, &like);
    }
    if (s == HV_OK && o->nreg == 0)
        s = hv_error_set(HV_ERR_BAD_INPUT, "every region of the model is empty");
    if (s == HV_OK) s = record_take(vol, &xf, &o->record);
    free(mat);
    hv_regions_destroy(rg);
    if (s != HV_OK) {
        hv_object_destroy(o);
        hv_material_table_destroy(t);
        return s;
    }
    *out = o;
    *table = t;
    return HV_OK;
}

void hv_object_destroy(hv_object *o)
{
    if (!o) return;
    for (int r = 0; r < o->nreg; ++r) region_free(&o->reg[r]);
    free(o->reg);
    hv_volume_destroy(o->record);
    free(o);
}

hv_status hv_object_clone(const hv_object *o, hv_object **out)
{
    *out = NULL;
    hv_object *c;
    hv_status s = object_new(o->m, &o->xf, &c);
    if (s != HV_OK) return s;
    memcpy(c->base, o->base, sizeof c->base);
    c->blend = o->blend;
    c->power = o->power;
    if (o->record) s = hv_volume_clone(o->record, &c->record);
    for (int r = 0; r < o->nreg && s == HV_OK; ++r) {
        hv_volume *mask;
        if ((s = hv_volume_clone(o->reg[r].mask, &mask)) == HV_OK) s = push_region(c, mask, &o->reg[r], NULL, &o->reg[r]);
    }
    if (s != HV_OK) {
        hv_object_destroy(c);
        return s;
    }
    *out = c;
    return HV_OK;
}

int hv_object_materials(const hv_object *o) { return o->m; }
int hv_object_region_count(const hv_object *o) { return o->nreg; }

uint64_t hv_object_region_voxels(const hv_object *o, int r)
{
    return r >= 0 && r < o->nreg ? hv_volume_active_count(o->reg[r].mask) : 0;
}

uint64_t hv_object_voxels(const hv_object *o)
{
    uint64_t n = 0; /* regions are disjoint by construction */
    for (int r = 0; r < o->nreg; ++r) n += hv_volume_active_count(o->reg[r].mask);
    return n;
}

int hv_object_region_ags_count(const hv_object *o, int r)
{
    return r >= 0 && r < o->nreg ? o->reg[r].nags : 0;
}

hv_status hv_object_set_base(hv_object *o, const double *p)
{
    hv_status s = hv_composition_check(p, o->m, "base composition");
    if (s != HV_OK) return s;
    memcpy(o->base, p, (size_t)o->m * sizeof(double));
    for (int r = 0; r < o->nreg; ++r) memcpy(o->reg[r].base, p, (size_t)o->m * sizeof(double));
    return HV_OK;
}

const char *hv_object_region_name(const hv_object *o, int r) { return r >= 0 && r < o->nreg ? o->reg[r].name : NULL; }

hv_status hv_object_set_region_base(hv_object *o, int r, const double *p)
{
    if (r < 0 || r >= o->nreg)
        return hv_error_set(HV_ERR_INVALID, "region %d out of range (the object has %d)", r, o->nreg);
    char what[300];
    if (o->reg[r].name) snprintf(what, sizeof what, "base composition of region '%s'", o->reg[r].name);
    else snprintf(what, sizeof what, "base composition of region %d", r);
    hv_status s = hv_composition_check(p, o->m, what);
    if (s == HV_OK) memcpy(o->reg[r].base, p, (size_t)o->m * sizeof(double));
    return s;
}

void hv_object_region_base(const hv_object *o, int r, double *p)
{
    if (r >= 0 && r < o->nreg) memcpy(p, o->reg[r].base, (size_t)o->m * sizeof(double));
}

/* "core, shell, region 2" into buf: the regions, for messages. */
static const char *region_list(const hv_object *o, char *buf, size_t n)
{
    size_t at = 0;
    buf[0] = '\0';
    for (int r = 0; r < o->nreg && at + 1 < n; ++r) {
        int k = o->reg[r].name ? snprintf(buf + at, n - at, "%s%s", r ? ", " : "", o->reg[r].name)
                               : snprintf(buf + at, n - at, "%sregion %d (unnamed)", r ? ", " : "", r);
        if (k < 0) break;
        at += (size_t)k;
    }
    return buf;
}

hv_status hv_object_set_blend(hv_object *o, hv_blend blend, double power)
{
    if (!hv_enum_name(hv_blend_enum(), (int)blend))
        return hv_error_set(HV_ERR_INVALID, "unknown blend rule %d", (int)blend);
    if (!(power > 0) || !isfinite(power))
        return hv_error_set(HV_ERR_INVALID, "blend power must be > 0 (got %g)", power);
    o->blend = blend;
    o->power = power;
    return HV_OK;
}

/* ---- AGS operators (Wu eq. 24-26) ---------------------------------------------------------- */

hv_status hv_object_add_ags(hv_object *o, hv_ags *a)
{
    if (a->m != o->m)
        return hv_error_set(HV_ERR_INVALID, "grading source has %d materials, the object %d", a->m, o->m);
    for (int r = 0; r < o->nreg; ++r) {
        hv_status s = region_add_ags(&o->reg[r], a);
        if (s != HV_OK) return s;
    }
    return HV_OK;
}

hv_status hv_object_add_ags_region(hv_object *o, const char *name, hv_ags *a)
{
    if (a->m != o->m)
        return hv_error_set(HV_ERR_INVALID, "grading source has %d materials, the object %d", a->m, o->m);
    int r = hv_object_region_find(o, name);
    int named = 0;
    for (int k = 0; k < o->nreg; ++k) named |= o->reg[k].name != NULL;
    if (r < 0 && !named)
        return hv_error_set(HV_ERR_NOT_FOUND, "the object has no region '%s' (its regions have no names: regions are "
                                              "named after the bodies of a model voxelized from an assembly)",
                            name ? name : "");
    if (r < 0) {
        char list[1024];
        return hv_error_set(HV_ERR_NOT_FOUND, "the object has no region '%s' (regions: %s)", name ? name : "",
                            region_list(o, list, sizeof list));
    }
    return region_add_ags(&o->reg[r], a);
}

hv_status hv_object_delete_ags(hv_object *o, const hv_ags *a)
{
    int found = 0;
    for (int r = 0; r < o->nreg; ++r) {
        region *g = &o->reg[r];
        for (int i = 0; i < g->nags; ++i)
            if (g->ags[i] == a) {
                hv_ags_release(g->ags[i]);
                memmove(&g->ags[i], &g->ags[i + 1], (size_t)(g->nags - i - 1) * sizeof *g->ags);
                --g->nags;
                found = 1;
                break;
            }
    }
    return found ? HV_OK : hv_error_set(HV_ERR_NOT_FOUND, "the object has no such grading source");
}

hv_status hv_object_replace_ags(hv_object *o, const hv_ags *a, hv_ags *b)
{
    if (hv_ags_materials(b) != o->m)
        return hv_error_set(HV_ERR_INVALID, "the source has %d materials, the object %d", hv_ags_materials(b), o->m);
    int found = 0;
    for (int r = 0; r < o->nreg; ++r)
        for (int i = 0; i < o->reg[r].nags; ++i)
            if (o->reg[r].ags[i] == a) {
                hv_ags_release(o->reg[r].ags[i]);
                o->reg[r].ags[i] = hv_ags_retain(b);
                found = 1;
            }
    return found ? HV_OK : hv_error_set(HV_ERR_NOT_FOUND, "the object has no such grading source");
}

hv_status hv_object_move_ags(hv_object *o, const hv_ags *a, double d_neg)
{
    hv_ags *b;
    hv_status s = hv_ags_moved(a, d_neg, &b);
    if (s != HV_OK) return s;
    s = hv_object_replace_ags(o, a, b);
    hv_ags_release(b);
    return s;
}

/* ---- Booleans (Wu eq. 27-30) ---------------------------------------------------------------- */

/* The union of an object's regions, as one mask. */
static hv_status object_mask(const hv_object *o, hv_volume **out)
{
    hv_volume *acc;
    hv_status s = hv_volume_clone(o->reg[0].mask, &acc);
    for (int r = 1; r < o->nreg && s == HV_OK; ++r) {
        hv_volume *next;
        s = mask_op(acc, o->reg[r].mask, HV_MASK_UNION, &next);
        hv_volume_destroy(acc);
        acc = s == HV_OK ? next : NULL;
    }
    *out = acc;
    return s;
}

static hv_status merged_set(const hv_object *o, region *out)
{
    for (int r = 0; r < o->nreg; ++r) {
        hv_status s = region_add_set(out, &o->reg[r]);
        if (s != HV_OK) return s;
    }
    return HV_OK;
}

_Static_assert((int)HV_OP_INTERSECT == (int)HV_GEOMETRY_INTERSECT && (int)HV_OP_UNITE == (int)HV_GEOMETRY_UNITE &&
                   (int)HV_OP_DIFFERENCE == (int)HV_GEOMETRY_DIFFERENCE && (int)HV_OP_MERGE == (int)HV_GEOMETRY_MERGE &&
                   (int)HV_OP_SUBTRACT == (int)HV_GEOMETRY_SUBTRACT,
               "hv_bool_op and hv_geometry_op name the same Booleans");

hv_status hv_object_boolean(const hv_object *a, const hv_object *b, hv_bool_op op, hv_object **out)
{
    *out = NULL;
    if (!hv_transform_same(&a->xf, &b->xf)) {
        const double *va = a->xf.voxel, *vb = b->xf.voxel, *oa = a->xf.origin, *ob = b->xf.origin;
        return hv_error_option(HV_ERR_INVALID, "heterogeneous Boolean: the objects lie on different voxel lattices "
                               "(voxels %g x %g x %g mm from %g, %g, %g against %g x %g x %g mm from %g, %g, %g): "
                               "voxelize the second with {like} set to the first", va[0], va[1], va[2], oa[0], oa[1], oa[2], vb[0],
                               vb[1], vb[2], ob[0], ob[1], ob[2]);
    }
    if (a->m != b->m)
        return hv_error_set(HV_ERR_INVALID, "heterogeneous Boolean: %d materials against %d", a->m, b->m);
    if (a->nreg == 0 || b->nreg == 0)
        return hv_error_set(HV_ERR_INVALID, "heterogeneous Boolean: an operand is empty");
    hv_object *o;
    hv_status s = object_new(a->m, &a->xf, &o);
    if (s != HV_OK) return s;
    memcpy(o->base, a->base, sizeof o->base);
    o->blend = a->blend;
    o->power = a->power;
    hv_volume *O1 = NULL, *O2 = NULL, *mask = NULL;
    if ((s = record_combine(a->record, b->record, &o->record)) != HV_OK) goto done;
    /* the shape's tree follows the voxels (issue 28): hv_bool_op and hv_geometry_op agree */
    if (o->record && (s = hv_geometry_combine_models(a->record, b->record, (hv_geometry_op)op, o->record)) != HV_OK) goto done;
    if ((s = object_mask(a, &O1)) != HV_OK || (s = object_mask(b, &O2)) != HV_OK) goto done;
    switch (op) {
    case HV_OP_INTERSECT: /* (O1 n O2, G1 u G2), pairwise over the regions */
        for (int i = 0; i < a->nreg && s == HV_OK; ++i)
            for (int j = 0; j < b->nreg && s == HV_OK; ++j)
                if ((s = mask_op(a->reg[i].mask, b->reg[j].mask, HV_MASK_INTERSECT, &mask)) == HV_OK)
                    s = push_region(o, mask, &a->reg[i], &b->reg[j], &a->reg[i]);
        break;
    case HV_OP_UNITE: /* (O1 - O2, G1), (O1 n O2, G1 u G2), (O2 - O1, G2) */
        for (int i = 0; i < a->nreg && s == HV_OK; ++i)
            if ((s = mask_op(a->reg[i].mask, O2, HV_MASK_DIFFERENCE, &mask)) == HV_OK)
                s = push_region(o, mask, &a->reg[i], NULL, &a->reg[i]);
        for (int i = 0; i < a->nreg && s == HV_OK; ++i)
            for (int j = 0; j < b->nreg && s == HV_OK; ++j)
                if ((s = mask_op(a->reg[i].mask, b->reg[j].mask, HV_MASK_INTERSECT, &mask)) == HV_OK)
                    s = push_region(o, mask, &a->reg[i], &b->reg[j], &a->reg[i]);
        for (int j = 0; j < b->nreg && s == HV_OK; ++j)
            if ((s = mask_op(b->reg[j].mask, O1, HV_MASK_DIFFERENCE, &mask)) == HV_OK)
                s = push_region(o, mask, &b->reg[j], NULL, &b->reg[j]);
        break;
    case HV_OP_DIFFERENCE: /* (O1 - O2, G1), (O2 n O1, G2) */
        for (int i = 0; i < a->nreg && s == HV_OK; ++i)
            if ((s = mask_op(a->reg[i].mask, O2, HV_MASK_DIFFERENCE, &mask)) == HV_OK)
                s = push_region(o, mask, &a->reg[i], NULL, &a->reg[i]);
        for (int j = 0; j < b->nreg && s == HV_OK; ++j)
            if ((s = mask_op(b->reg[j].mask, O1, HV_MASK_INTERSECT, &mask)) == HV_OK)
                s = push_region(o, mask, &b->reg[j], NULL, &b->reg[j]);
        break;
    case HV_OP_MERGE: { /* (O1 u O2, G1 u G2) */
        region all;
        memset(&all, 0, sizeof all);
        if ((s = merged_set(a, &all)) == HV_OK && (s = merged_set(b, &all)) == HV_OK &&
            (s = mask_op(O1, O2, HV_MASK_UNION, &mask)) == HV_OK)
            s = push_region(o, mask, &all, NULL, NULL);
        for (int i = 0; i < all.nags; ++i) hv_ags_release(all.ags[i]);
        free(all.ags);
        break;
    }
    case HV_OP_SUBTRACT: /* (O1 - O2, G1) */
        for (int i = 0; i < a->nreg && s == HV_OK; ++i)
            if ((s = mask_op(a->reg[i].mask, O2, HV_MASK_DIFFERENCE, &mask)) == HV_OK)
                s = push_region(o, mask, &a->reg[i], NULL, &a->reg[i]);
        break;
    default: s = hv_error_set(HV_ERR_INVALID, "unknown Boolean operation %d", (int)op);
    }
done:
    hv_volume_destroy(O1);
    hv_volume_destroy(O2);
    if (s != HV_OK) {
        hv_object_destroy(o);
        return s;
    }
    *out = o;
    return HV_OK;
}

/* ---- evaluation ----------------------------------------------------------------------------- */

#define MAX_SOURCES 32

typedef struct eval_ctx {
    const hv_object *o;
    const region *r;
    hv_volume *out;
    const int *grids; /* material grid indices in `out` */
} eval_ctx;

/* The AGS weight (f through its table) of 512 distances: hv_ags_weight over a leaf, written
 * branch-free so the compiler vectorises the arithmetic (the table reads stay scalar). The
 * clamps are if-converted only under -fno-trapping-math (set in the Makefile). */
HV_HOT_CLONES static void leaf_weights(const hv_ags *a, const float *d, float *w)
{
    const float dn = (float)a->d_neg;
    if (a->d_grad <= 0) {
#pragma omp simd
        for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) w[n] = d[n] >= dn ? 1.0f : 0.0f;
        return;
    }
    const float scale = (float)(HV_AGS_TABLE / a->d_grad);
    const float *tab = a->table;
    int idx[HV_LEAF_SIZE];
    float frac[HV_LEAF_SIZE];
#pragma omp simd
    for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) {
        /* ternaries, not fminf/fmaxf (those keep NaN rules and stay calls); d is never NaN */
        float s = (d[n] - dn) * scale;
        s = s > 0.0f ? s : 0.0f;
        s = s < (float)HV_AGS_TABLE ? s : (float)HV_AGS_TABLE;
        int i = (int)s;
        i = i < HV_AGS_TABLE - 1 ? i : HV_AGS_TABLE - 1; /* s = T: the last interval at t = 1 */
        idx[n] = i;
        frac[n] = s - (float)i;
    }
    for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) {
        float lo = tab[idx[n]], hi = tab[idx[n] + 1];
        w[n] = lo + frac[n] * (hi - lo);
    }
}

/* Compositions for one region's leaves, written into the output's material leaves. */
HV_HOT_CLONES static hv_status eval_leaves(void *vctx, size_t b, size_t e, int thread)
{
    (void)thread;
    eval_ctx *c = vctx;
    const hv_object *o = c->o;
    const region *r = c->r;
    int m = o->m, k = r->nags;
    float dist[MAX_SOURCES][HV_LEAF_SIZE];
    float val[HV_MAX_MATERIALS][HV_LEAF_SIZE];
    float w[HV_LEAF_SIZE];
    uint8_t sel[HV_LEAF_SIZE];
    hv_accessor acc;
    hv_accessor_init(&acc, c->out);
    const int32_t *org = hv_volume_leaf_origins(r->mask);
    for (size_t l = b; l < e; ++l) {
        const int32_t *lo = org + 3 * l;
        int64_t ol = hv_accessor_leaf(&acc, lo[0], lo[1], lo[2]);
        if (ol < 0)
            return hv_error_set(HV_ERR_INVALID, "evaluation: region voxels near (%d, %d, %d) lie outside the volume",
                                lo[0], lo[1], lo[2]);
        const uint64_t *mask = hv_volume_leaf_mask(r->mask, l), *bits = hv_volume_leaf_bool_c(r->mask, 0, l);
        int full = 1;
        for (int q = 0; q < HV_LEAF_WORDS; ++q) {
            if ((mask[q] & bits[q]) != ~0ull) full = 0;
        }
        if (!full)
            for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) sel[n] = (uint8_t)(HV_BIT_GET(mask, n) & HV_BIT_GET(bits, n));
        if (k == 0) {
            for (int j = 0; j < m; ++j)
                for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) val[j][n] = (float)r->base[j];
        } else {
            for (int s = 0; s < k; ++s) hv_frf_leaf_distances(r->ags[s]->frf, &o->xf, lo, dist[s]);
            if (k == 1) {
                const hv_ags *a = r->ags[0];
                leaf_weights(a, dist[0], w);
                for (int j = 0; j < m; ++j) {
                    const float ms = (float)a->ms[j], dm = (float)(a->me[j] - a->ms[j]);
                    float *vj = full ? hv_volume_leaf_float(c->out, c->grids[j], (size_t)ol) : val[j];
#pragma omp simd
                    for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) vj[n] = ms + w[n] * dm;
                }
                if (full) continue; /* written in place */
            } else if (o->blend == HV_BLEND_NEAREST) {
                /* source by source: where it is strictly nearer than the nearest so far, its
                 * composition replaces the running one (ties keep the earlier source) */
                float best[HV_LEAF_SIZE];
                for (int s = 0; s < k; ++s) {
                    const hv_ags *a = r->ags[s];
                    const float *ds = dist[s];
                    leaf_weights(a, ds, w);
                    /* nearest by |d|: a signed feature's d is negative behind it */
                    if (s == 0)
                        for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) best[n] = fabsf(ds[n]);
                    for (int j = 0; j < m; ++j) {
                        const float ms = (float)a->ms[j], dm = (float)(a->me[j] - a->ms[j]);
                        float *vj = val[j];
                        if (s == 0) {
#pragma omp simd
                            for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) vj[n] = ms + w[n] * dm;
                        } else {
#pragma omp simd
                            for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) {
                                const float v = ms + w[n] * dm; /* unconditional: the select vectorises */
                                vj[n] = fabsf(ds[n]) < best[n] ? v : vj[n];
                            }
                        }
                    }
                    if (s > 0) {
#pragma omp simd
                        for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) best[n] = fabsf(ds[n]) < best[n] ? fabsf(ds[n]) : best[n];
                    }
                }
            } else {
                float eps = (float)(0.5 * hv_voxel_scale(&o->xf));
                for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) {
                    double acc_p[HV_MAX_MATERIALS] = {0}, wsum = 0;
                    for (int s = 0; s < k; ++s) {
                        const hv_ags *a = r->ags[s];
                        double om = pow(fabs((double)dist[s][n]) + eps, -o->power);
                        double ww = hv_ags_weight(a, dist[s][n]);
                        for (int j = 0; j < m; ++j) acc_p[j] += om * (a->ms[j] + ww * (a->me[j] - a->ms[j]));
                        wsum += om;
                    }
                    for (int j = 0; j < m; ++j) val[j][n] = (float)(acc_p[j] / wsum);
                }
            }
        }
        for (int j = 0; j < m; ++j) {
            float *dst = hv_volume_leaf_float(c->out, c->grids[j], (size_t)ol);
            if (full) {
                memcpy(dst, val[j], sizeof val[j]);
            } else {
                for (unsigned n = 0; n < HV_LEAF_SIZE; ++n) dst[n] = sel[n] ? val[j][n] : dst[n];
            }
        }
    }
    return HV_OK;
}

static hv_status occupancy_leaves(void *vctx, size_t b, size_t e, int thread)
{
    (void)thread;
    hv_volume *v = vctx;
    for (size_t l = b; l < e; ++l) memcpy(hv_volume_leaf_bool(v, 0, l), hv_volume_leaf_mask(v, l), 64);
    return HV_OK;
}

uint64_t hv_object_evaluate_estimate(const hv_object *o)
{
    uint64_t leaves = 0, extra = 0;
    int64_t lo[3] = {INT64_MAX, INT64_MAX, INT64_MAX}, hi[3] = {INT64_MIN, INT64_MIN, INT64_MIN};
    int voxel_frfs = 0;
    for (int r = 0; r < o->nreg; ++r) {
        leaves += hv_volume_leaf_count(o->reg[r].mask);
        int32_t a[3], b[3];
        if (hv_volume_index_bbox(o->reg[r].mask, a, b))
            for (int k = 0; k < 3; ++k) {
                lo[k] = HV_MIN(lo[k], (int64_t)a[k]);
                hi[k] = HV_MAX(hi[k], (int64_t)b[k]);
            }
        for (int i = 0; i < o->reg[r].nags; ++i) {
            hv_frf_kind kd = o->reg[r].ags[i]->frf->kind;
            if (kd == HV_FRF_CONTOUR || kd == HV_FRF_MASK || kd == HV_FRF_FACETS) ++voxel_frfs;
            if (kd == HV_FRF_HARMONIC) voxel_frfs += 9; /* CG and multigrid vectors */
        }
    }
    if (lo[0] <= hi[0]) {
        uint64_t box = 1;
        for (int k = 0; k < 3; ++k) box *= (uint64_t)(hi[k] - lo[k] + 5);
        extra = box * 5u * (uint64_t)voxel_frfs; /* dense feature bytes + float field each */
    }
    /* material grids, stored fields of voxel features, region masks */
    int stored = voxel_frfs > 0 ? (voxel_frfs + 8) / 9 : 0;
    int surface = o->record && hv_volume_grid_find(o->record, "surface") >= 0;
    int region_grids = 0;
    for (int r = 0; r < o->nreg; ++r) region_grids += o->nreg > 1 || o->reg[r].name;
    return hv_volume_memory_estimate(leaves, o->m + stored, 1 + surface + region_grids) + extra;
}

/* The distinct features and sources of an object, in first-use order. */
typedef struct catalog {
    int nf, na;
    const hv_frf *f[MAX_SOURCES * 8];
    const hv_ags *a[MAX_SOURCES * 8];
} catalog;

static hv_status make_catalog(const hv_object *o, catalog *c)
{
    memset(c, 0, sizeof *c);
    for (int r = 0; r < o->nreg; ++r)
        for (int i = 0; i < o->reg[r].nags; ++i) {
            const hv_ags *a = o->reg[r].ags[i];
            int k = 0;
            while (k < c->na && c->a[k] != a) ++k;
            if (k == c->na) {
                if (c->na == (int)HV_COUNT(c->a)) return hv_error_set(HV_ERR_LIMIT, "too many grading sources");
                c->a[c->na++] = a;
            }
            k = 0;
            while (k < c->nf && c->f[k] != a->frf) ++k;
            if (k == c->nf) c->f[c->nf++] = a->frf;
        }
    return HV_OK;
}

/* Bool grid of region r in an evaluated volume: "occupancy" for a lone unnamed region,
 * "region.<name>" for a named one, "region.<r>" for an unnamed one among several (with a suffix in
 * the unlikely case a named region took that name). */
static void region_grid(const hv_object *o, int r, char *buf, size_t n)
{
    const region *g = &o->reg[r];
    if (g->name) {
        snprintf(buf, n, "region.%s", g->name);
        return;
    }
    if (o->nreg == 1) {
        snprintf(buf, n, "occupancy");
        return;
    }
    char want[32];
    snprintf(want, sizeof want, "%d", r);
    snprintf(buf, n, "region.%s", want);
    for (int k = 1; hv_object_region_find(o, want) >= 0; ++k) {
        snprintf(want, sizeof want, "%d.%d", r, k);
        snprintf(buf, n, "region.%s", want);
    }
}

/* The object document needs version 2 when regions carry names or bases of their own. */
static int regions_versioned(const hv_object *o)
{
    for (int r = 0; r < o->nreg; ++r)
        if (o->reg[r].name || memcmp(o->reg[r].base, o->base, (size_t)o->m * sizeof(double)) != 0) return 1;
    return 0;
}

static int catalog_index(const void *const *list, int n, const void *p)
{
    for (int i = 0; i < n; ++i)
        if (list[i] == p) return i;
    return -1;
}

/* The grading definition (hovox.object.json): features (analytic parameters, the bool grid of v
 * their field is recomputed from, or the name of their stored field grid), sources (with their
 * f tables), regions (grid and source indices). v NULL: recomputed fields as they were read,
 * other voxel features as stored fields. */
static hv_status object_doc(const hv_object *o, const hv_volume *v, json_t **out)
{
    int v2 = regions_versioned(o);
    *out = NULL;
    catalog c;
    hv_status s = make_catalog(o, &c);
    if (s != HV_OK) return s;
    json_t *feats = json_array(), *srcs = json_array(), *regs = json_array();
    int failed = !feats || !srcs || !regs;
    for (int k = 0; k < c.nf && !failed; ++k) {
        char grid[32];
        snprintf(grid, sizeof grid, "distance.%d", k);
        failed = json_array_append_new(feats, hv_frf_to_doc(c.f[k], grid, hv_frf_derived_grid(c.f[k], v))) != 0;
    }
    for (int k = 0; k < c.na && !failed; ++k)
        failed = json_array_append_new(
                     srcs, hv_ags_to_doc(c.a[k], catalog_index((const void *const *)c.f, c.nf, c.a[k]->frf))) != 0;
    for (int r = 0; r < o->nreg && !failed; ++r) {
        char grid[300];
        region_grid(o, r, grid, sizeof grid);
        json_t *list = json_array();
        failed = !list;
        for (int i = 0; i < o->reg[r].nags && !failed; ++i)
            failed = json_array_append_new(
                         list, json_integer(catalog_index((const void *const *)c.a, c.na, o->reg[r].ags[i]))) != 0;
        json_t *e = failed ? NULL : json_object();
        if (!e) {
            json_decref(list);
            failed = 1;
            break;
        }
        /* version 1 layout unless regions carry names or bases of their own */
        if (v2 && o->reg[r].name) failed |= hv_json_set(e, "name", hv_json_text(o->reg[r].name));
        failed |= hv_json_set(e, "grid", hv_json_text(grid));
        failed |= hv_json_set(e, "voxels", json_integer((json_int_t)hv_volume_active_count(o->reg[r].mask)));
        if (v2) failed |= hv_json_set(e, "base", hv_json_numbers(o->reg[r].base, (size_t)o->m));
        failed |= hv_json_set(e, "sources", list);
        failed |= json_array_append_new(regs, e) != 0;
    }
    json_t *doc = NULL;
    if (!failed)
        doc = json_pack("{s:i, s:s, s:o, s:o, s:o, s:o, s:o}", "materials", o->m, "blend", hv_blend_name(o->blend),
                        "power", hv_json_number(o->power), "base", hv_json_numbers(o->base, (size_t)o->m),
                        "features", feats, "sources", srcs, "regions", regs);
    else {
        json_decref(feats);
        json_decref(srcs);
        json_decref(regs);
    }
    if (!doc) return hv_error_set(HV_ERR_NOMEM, "out of memory (writing %s)", hv_schema_key(HV_DOC_OBJECT));
    *out = doc;
    return HV_OK;
}

hv_status hv_object_to_doc(const hv_object *o, json_t **out) { return object_doc(o, NULL, out); }

static hv_status object_doc_write(const hv_object *o, hv_volume *out)
{
    json_t *doc;
    hv_status s = object_doc(o, out, &doc);
    /* the oldest version that holds the definition, so older hovox reads what it can */
    return s == HV_OK ? hv_schema_doc_write_version(out, HV_DOC_OBJECT, doc, regions_versioned(o) ? 2 : 1) : s;
}

/* Store the masks of several regions or named ones ("region.<name>", "region.R"), and the fields of the voxel features
 * that are not recomputed from one of the model's bool grids on load ("distance.K": features
 * from files, facets, harmonic; hv_frf_derived_grid) in the evaluated volume, so the
 * definition can be rebuilt from the file. The regions go first: a mask feature may be one. */
static hv_status store_definition_grids(const hv_object *o, hv_volume *v)
{
    catalog c;
    hv_status s = make_catalog(o, &c);
    for (int r = 0; r < o->nreg && s == HV_OK; ++r) {
        char grid[300];
        region_grid(o, r, grid, sizeof grid);
        if (strcmp(grid, "occupancy") == 0) continue; /* a lone unnamed region is the occupancy */
        int old = hv_volume_grid_find(v, grid);
        if (old >= 0 && (s = hv_volume_grid_remove(v, old)) != HV_OK) break;
        s = hv_volume_grid_copy(v, grid, o->reg[r].mask, 0);
    }
    for (int k = 0; k < c.nf && s == HV_OK; ++k) {
        if (!hv_frf_is_voxel(c.f[k]) && hv_frf_get_kind(c.f[k]) != HV_FRF_FIELD) continue;
        char grid[32];
        snprintf(grid, sizeof grid, "distance.%d", k);
        int old = hv_volume_grid_find(v, grid);
        if (old >= 0 && (s = hv_volume_grid_remove(v, old)) != HV_OK) break;
        if (!hv_frf_derived_grid(c.f[k], v)) s = hv_frf_store_field(c.f[k], v, grid);
    }
    return s;
}

/* Prepare the voxel features and run the kernel over every region into v's grids. */
static hv_status fill_materials(hv_object *o, hv_volume *v, const int *grids, const hv_progress *progress)
{
    hv_status s = HV_OK;
    /* voxel features: their fields over the whole output box, once */
    int32_t a[3], b[3];
    if (s == HV_OK && hv_volume_index_bbox(v, a, b)) {
        int64_t lo[3], n[3];
        for (int k = 0; k < 3; ++k) {
            lo[k] = a[k] & ~7;
            n[k] = (((int64_t)b[k] | 7) + 1) - lo[k]; /* whole leaves */
        }
        for (int r = 0; r < o->nreg && s == HV_OK; ++r)
            for (int i = 0; i < o->reg[r].nags && s == HV_OK; ++i)
                s = hv_frf_prepare(o->reg[r].ags[i]->frf, &o->xf, lo, n, progress);
    }
    size_t total = 0, done = 0;
    for (int r = 0; r < o->nreg; ++r) total += hv_volume_leaf_count(o->reg[r].mask);
    for (int r = 0; r < o->nreg && s == HV_OK; ++r) {
        eval_ctx ctx = {o, &o->reg[r], v, grids};
        size_t nl = hv_volume_leaf_count(o->reg[r].mask);
        s = hv_parallel_for(nl, 64, eval_leaves, &ctx, NULL, "materials");
        done += nl;
        if (s == HV_OK) s = hv_progress_report(progress, "materials", total ? (double)done / (double)total : 1.0);
    }
    return s;
}

hv_status hv_object_reevaluate(hv_object *o, const hv_material_table *t, hv_volume *vol,
                               const hv_progress *progress)
{
    if (hv_material_count(t) != o->m)
        return hv_error_set(HV_ERR_INVALID, "the material table has %d materials, the object %d",
                            hv_material_count(t), o->m);
    hv_transform xf = hv_volume_get_transform(vol);
    if (!hv_transform_same(&xf, &o->xf))
        return hv_error_set(HV_ERR_INVALID, "re-evaluation: the volume lies on another lattice");
    int grids[HV_MAX_MATERIALS];
    for (int j = 0; j < o->m; ++j)
        if ((grids[j] = hv_material_grid(vol, t, j)) < 0)
            return hv_error_set(HV_ERR_INVALID, "re-evaluation: the volume has no grid 'material.%s'",
                                hv_material_name(t, j));
    hv_status s = fill_materials(o, vol, grids, progress);
    if (s == HV_OK) s = store_definition_grids(o, vol);
    return s == HV_OK ? object_doc_write(o, vol) : s;
}

hv_status hv_object_evaluate(hv_object *o, const hv_material_table *t, uint64_t max_memory,
                             const hv_progress *progress, hv_volume **out)
{
    *out = NULL;
    if (hv_material_count(t) != o->m)
        return hv_error_set(HV_ERR_INVALID, "the material table has %d materials, the object %d",
                            hv_material_count(t), o->m);
    for (int r = 0; r < o->nreg; ++r)
        if (o->reg[r].nags > MAX_SOURCES)
            return hv_error_set(HV_ERR_LIMIT, "region %d has %d grading sources (at most %d)", r,
                                o->reg[r].nags, MAX_SOURCES);
    uint64_t need = hv_object_evaluate_estimate(o);
    uint64_t budget = hv_memory_budget(max_memory);
    if (budget && need > budget) {
        char nt[32], bt[32];
        return hv_error_option(HV_ERR_LIMIT,
                            "evaluating %d materials on %llu voxels needs about %s, more than the "
                            "limit of %s ({max_memory})",
                            o->m, (unsigned long long)hv_object_voxels(o), hv_size_text(nt, sizeof nt, (double)need),
                            hv_size_text(bt, sizeof bt, (double)budget));
    }
    hv_volume *v;
    hv_status s = hv_volume_create(&o->xf, &v);
    if (s != HV_OK) return s;
    int grids[HV_MAX_MATERIALS];
    for (int r = 0; r < o->nreg && s == HV_OK; ++r) s = hv_volume_topology_union(v, o->reg[r].mask);
    if (s == HV_OK) s = hv_volume_grid_add(v, "occupancy", HV_GRID_BOOL, NULL);
    for (int j = 0; j < o->m && s == HV_OK; ++j) {
        char name[80];
        snprintf(name, sizeof name, "material.%s", hv_material_name(t, j));
        s = hv_volume_grid_add(v, name, HV_GRID_FLOAT, &grids[j]);
    }
    if (s == HV_OK) s = hv_parallel_for(hv_volume_leaf_count(v), 256, occupancy_leaves, v, NULL, "materials");
    if (s == HV_OK) s = fill_materials(o, v, grids, progress);
    if (s == HV_OK) s = store_definition_grids(o, v);
    if (s == HV_OK) s = record_put(o, v);
    if (s == HV_OK) s = hv_material_table_store(v, t);
    if (s == HV_OK) s = object_doc_write(o, v);
    if (s != HV_OK) {
        hv_volume_destroy(v);
        return s;
    }
    *out = v;
    return HV_OK;
}

/* ---- rebuilding and direct evaluation ---------------------------------------------------- */

hv_status hv_object_from_doc(const json_t *doc, const hv_volume *vol, hv_object **out)
{
    *out = NULL;
    const char *what = hv_schema_key(HV_DOC_OBJECT);
    const json_t *jf, *ja, *jr;
    long long m;
    hv_status s = hv_json_get_int(doc, "materials", what, 1, HV_MAX_MATERIALS, &m);
    if (s == HV_OK) s = hv_json_need(doc, "features", JSON_ARRAY, what, &jf);
    if (s == HV_OK) s = hv_json_need(doc, "sources", JSON_ARRAY, what, &ja);
    if (s == HV_OK) s = hv_json_need(doc, "regions", JSON_ARRAY, what, &jr);
    if (s == HV_OK && json_array_size(jr) == 0) s = hv_error_set(HV_ERR_BAD_INPUT, "%s: regions is empty", what);
    if (s != HV_OK) return s;
    hv_transform xf = hv_volume_get_transform(vol);
    hv_object *o = NULL;
    size_t nf = json_array_size(jf), na = json_array_size(ja);
    hv_frf **feats = hv_calloc(nf + 1, sizeof *feats);
    hv_ags **srcs = hv_calloc(na + 1, sizeof *srcs);
    char place[300];
    if (!feats || !srcs) s = HV_ERR_NOMEM;
    if (s == HV_OK) s = object_new((int)m, &xf, &o);
    for (size_t i = 0; i < nf && s == HV_OK; ++i) {
        snprintf(place, sizeof place, "%s: features[%zu]", what, i);
        s = hv_frf_from_doc(json_array_get(jf, i), vol, place, &feats[i]);
    }
    for (size_t i = 0; i < na && s == HV_OK; ++i) {
        snprintf(place, sizeof place, "%s: sources[%zu]", what, i);
        s = hv_ags_from_doc(json_array_get(ja, i), feats, nf, (int)m, place, &srcs[i]);
    }
    /* the object's base first: the base of every region that gives none of its own */
    if (s == HV_OK && json_object_get(doc, "base")) {
        double base[HV_MAX_MATERIALS];
        if ((s = hv_json_get_numbers(doc, "base", what, base, (size_t)m)) == HV_OK && (s = hv_object_set_base(o, base)) != HV_OK)
            s = hv_error_prefix(HV_ERR_BAD_INPUT, "%s: ", what);
    }
    for (size_t r = 0; r < json_array_size(jr) && s == HV_OK; ++r) {
        const json_t *e = json_array_get(jr, r), *list;
        const char *grid;
        snprintf(place, sizeof place, "%s: regions[%zu]", what, r);
        if ((s = hv_json_get_string(e, "grid", place, &grid)) != HV_OK ||
            (s = hv_json_need(e, "sources", JSON_ARRAY, place, &list)) != HV_OK)
            break;
        int g = hv_volume_grid_need(vol, grid, HV_GRID_BOOL);
        if (g < 0) {
            s = hv_error_prefix(HV_ERR_BAD_INPUT, "%s: the model has ", place);
            break;
        }
        hv_volume *mask;
        if ((s = mask_of(vol, g, &xf, &mask)) != HV_OK) break;
        /* version 2: a region's own name and base (the object's base when absent) */
        region like;
        memset(&like, 0, sizeof like);
        memcpy(like.base, o->base, sizeof like.base);
        const json_t *jn = json_object_get(e, "name");
        if (jn) {
            if ((s = hv_json_get_string(e, "name", place, (const char **)&like.name)) != HV_OK) {
                hv_volume_destroy(mask);
                break;
            }
            if (hv_object_region_find(o, like.name) >= 0) {
                hv_volume_destroy(mask);
                s = hv_error_set(HV_ERR_BAD_INPUT, "%s: name '%s' is used by an earlier region", place, like.name);
                break;
            }
        }
        if (json_object_get(e, "base")) {
            if ((s = hv_json_get_numbers(e, "base", place, like.base, (size_t)m)) != HV_OK ||
                (s = hv_composition_check(like.base, (int)m, "base")) != HV_OK) {
                hv_volume_destroy(mask);
                s = hv_error_prefix(HV_ERR_BAD_INPUT, "%s: ", place);
                break;
            }
        }
        int before = o->nreg;
        if ((s = push_region(o, mask, NULL, NULL, &like)) != HV_OK || o->nreg == before) continue;
        for (size_t i = 0; i < json_array_size(list) && s == HV_OK; ++i) {
            const json_t *x = json_array_get(list, i);
            double k = json_is_number(x) ? json_number_value(x) : -1;
            if (k != floor(k) || k < 0 || k >= (double)na)
                s = hv_error_set(HV_ERR_BAD_INPUT, "%s: sources[%zu] names no source (there are %zu)", place, i, na);
            else
                s = region_add_ags(&o->reg[o->nreg - 1], srcs[(size_t)k]);
        }
    }
    if (s == HV_OK && json_object_get(doc, "blend")) {
        int blend;
        double power = 2.0;
        s = hv_json_get_name(doc, "blend", what, hv_blend_enum(), &blend);
        if (s == HV_OK && json_object_get(doc, "power")) s = hv_json_get_number(doc, "power", what, &power);
        if (s == HV_OK && (s = hv_object_set_blend(o, (hv_blend)blend, power)) != HV_OK)
            s = hv_error_prefix(HV_ERR_BAD_INPUT, "%s: ", what);
    }
    for (size_t k = 0; feats && k < nf; ++k) hv_frf_release(feats[k]);
    for (size_t k = 0; srcs && k < na; ++k) hv_ags_release(srcs[k]);
    free(feats);
    free(srcs);
    if (s != HV_OK) {
        hv_object_destroy(o);
        return s;
    }
    *out = o;
    return HV_OK;
}

hv_status hv_object_from_model(const hv_volume *vol, hv_object **out)
{
    *out = NULL;
    json_t *doc;
    hv_status s = hv_schema_doc_read(vol, HV_DOC_OBJECT, &doc);
    if (s == HV_ERR_NOT_FOUND)
        return hv_error_set(HV_ERR_NOT_FOUND, "the model carries no grading definition (grade it first)");
    if (s == HV_OK) s = hv_object_from_doc(doc, vol, out);
    json_decref(doc);
    if (s == HV_OK && (s = record_take(vol, &(*out)->xf, &(*out)->record)) != HV_OK) {
        hv_object_destroy(*out);
        *out = NULL;
    }
    return s;
}

hv_status hv_object_prepare(hv_object *o, const hv_progress *progress)
{
    int64_t lo[3] = {INT64_MAX, INT64_MAX, INT64_MAX}, hi[3] = {INT64_MIN, INT64_MIN, INT64_MIN};
    for (int r = 0; r < o->nreg; ++r) {
        int32_t a[3], b[3];
        if (!hv_volume_index_bbox(o->reg[r].mask, a, b)) continue;
        for (int k = 0; k < 3; ++k) {
            lo[k] = HV_MIN(lo[k], (int64_t)(a[k] & ~7));
            hi[k] = HV_MAX(hi[k], (int64_t)(b[k] | 7));
        }
    }
    if (lo[0] > hi[0]) return HV_OK;
    int64_t n[3] = {hi[0] - lo[0] + 1, hi[1] - lo[1] + 1, hi[2] - lo[2] + 1};
    hv_status s = HV_OK;
    for (int r = 0; r < o->nreg && s == HV_OK; ++r)
        for (int i = 0; i < o->reg[r].nags && s == HV_OK; ++i)
            s = hv_frf_prepare(o->reg[r].ags[i]->frf, &o->xf, lo, n, progress);
    return s;
}

/* The region holding the voxel nearest to p, or one holding a voxel within one voxel of it
 * (the nearest first); -1 when none. */
static int region_at(const hv_object *o, const double p[3])
{
    double idx[3];
    for (int k = 0; k < 3; ++k) idx[k] = (p[k] - o->xf.origin[k]) / o->xf.voxel[k];
    int32_t c[3] = {(int32_t)lround(idx[0]), (int32_t)lround(idx[1]), (int32_t)lround(idx[2])};
    int best = -1;
    double best_d = INFINITY;
    for (int q = 0; q < 27; ++q) {
        int32_t v[3] = {c[0] + q / 9 - 1, c[1] + (q / 3) % 3 - 1, c[2] + q % 3 - 1};
        double d = 0;
        for (int k = 0; k < 3; ++k) d += ((double)v[k] - idx[k]) * ((double)v[k] - idx[k]) * o->xf.voxel[k] * o->xf.voxel[k];
        if (d >= best_d) continue;
        for (int r = 0; r < o->nreg; ++r) {
            hv_accessor acc;
            hv_accessor_init(&acc, o->reg[r].mask);
            if (hv_accessor_bool(&acc, 0, v[0], v[1], v[2])) {
                best = r;
                best_d = d;
                break;
            }
        }
    }
    return best;
}

void hv_object_sample(const hv_object *o, const double p[3], int *inside, double *frac)
{
    int r = region_at(o, p), m = o->m;
    for (int j = 0; j < m; ++j) frac[j] = 0;
    *inside = r >= 0;
    if (r < 0) return;
    const region *g = &o->reg[r];
    if (g->nags == 0) {
        memcpy(frac, g->base, (size_t)m * sizeof(double));
        return;
    }
    if (g->nags == 1 || o->blend == HV_BLEND_NEAREST) {
        int best = 0;
        double bd = INFINITY;
        double dbest = 0;
        for (int i = 0; i < g->nags; ++i) {
            double d = hv_frf_sample(g->ags[i]->frf, p);
            if (fabs(d) < bd) { /* nearest by |d|, as the evaluation (signed features) */
                bd = fabs(d);
                dbest = d;
                best = i;
            }
        }
        hv_ags_eval(g->ags[best], dbest, frac);
        return;
    }
    double eps = 0.5 * hv_voxel_scale(&o->xf), wsum = 0, tmp[HV_MAX_MATERIALS];
    for (int i = 0; i < g->nags; ++i) {
        double d = hv_frf_sample(g->ags[i]->frf, p), w = pow(fabs(d) + eps, -o->power);
        hv_ags_eval(g->ags[i], d, tmp);
        for (int j = 0; j < m; ++j) frac[j] += w * tmp[j];
        wsum += w;
    }
    for (int j = 0; j < m; ++j) frac[j] /= wsum;
}
