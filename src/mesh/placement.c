/* src/mesh/placement.c - units and transforms (hovox/placement.h): --unit, --up, --scale, --rotate
 * and --translate turned into one 3x4 matrix for hv_mesh_transform (issue 27 item 3), their
 * option parser for the CLI, job files and Lua, and the size check that names a likely unit.
 * A rotation about an axis is Rodrigues' formula; quarter turns about x, y, z are exact. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "hovox/placement.h"

/* ---- units ------------------------------------------------------------------------------------ */

static const struct {
    const char *name, *alias, *words; /* words: "metres" in a warning */
    double mm;
} k_units[] = {{"mm", "millimeter", "millimetres", 1.0},   {"cm", "centimeter", "centimetres", 10.0},
               {"m", "meter", "metres", 1000.0},           {"in", "inch", "inches", 25.4},
               {"ft", "foot", "feet", 304.8},               {"um", "micron", "micrometres", 0.001}};

hv_status hv_placement_unit_parse(const char *name, double *mm)
{
    for (size_t i = 0; i < HV_COUNT(k_units); ++i)
        if (strcmp(name, k_units[i].name) == 0 || strcmp(name, k_units[i].alias) == 0) {
            *mm = k_units[i].mm;
            return HV_OK;
        }
    return hv_error_option(HV_ERR_INVALID, "{unit} must be one of mm, cm, m, in, ft, um, got '%s'", name);
}

static const char *unit_name(double mm)
{
    for (size_t i = 0; i < HV_COUNT(k_units); ++i)
        if (k_units[i].mm == mm) return k_units[i].name;
    return NULL;
}

/* ---- the map ---------------------------------------------------------------------------------- */

void hv_placement_init(hv_placement *p) { memset(p, 0, sizeof *p); }

int hv_placement_given(const hv_placement *p)
{
    return p->unit != 0 || p->up != 0 || p->scale[0] != 0 || p->scale[1] != 0 || p->scale[2] != 0 ||
           p->nrotate > 0 || p->translate[0] != 0 || p->translate[1] != 0 || p->translate[2] != 0;
}

/* c = a b for 3x4 affine maps (the last row 0 0 0 1 implied). */
static void compose(const double a[12], const double b[12], double c[12])
{
    double r[12];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j) {
            double v = j == 3 ? a[4 * i + 3] : 0;
            for (int k = 0; k < 3; ++k) v += a[4 * i + k] * b[4 * k + j];
            r[4 * i + j] = v;
        }
    memcpy(c, r, sizeof r);
}

/* cos and sin of an angle in degrees, exact at multiples of 90. */
static void cos_sin(double deg, double *c, double *s)
{
    double q = fmod(deg, 360.0);
    if (q < 0) q += 360.0;
    if (q == 0) *c = 1, *s = 0;
    else if (q == 90) *c = 0, *s = 1;
    else if (q == 180) *c = -1, *s = 0;
    else if (q == 270) *c = 0, *s = -1;
    else {
        double r = q * (M_PI / 180.0);
        *c = cos(r);
        *s = sin(r);
    }
}

/* Rodrigues: R = c I + s [k]x + (1 - c) k k^T for the unit axis k. */
static void rotation(const hv_placement_rotation *r, double m[12])
{
    double k[3] = {r->axis[0], r->axis[1], r->axis[2]};
    int nonzero = (k[0] != 0) + (k[1] != 0) + (k[2] != 0);
    if (nonzero == 1) /* a coordinate axis: keep the unit length exact */
        for (int i = 0; i < 3; ++i) k[i] = k[i] > 0 ? 1 : k[i] < 0 ? -1 : 0;
    else {
        double n = sqrt(k[0] * k[0] + k[1] * k[1] + k[2] * k[2]);
        for (int i = 0; i < 3; ++i) k[i] /= n;
    }
    double c, s;
    cos_sin(r->degrees, &c, &s);
    double t = 1 - c;
    const double q[12] = {c + t * k[0] * k[0],        t * k[0] * k[1] - s * k[2], t * k[0] * k[2] + s * k[1], 0,
                          t * k[1] * k[0] + s * k[2], c + t * k[1] * k[1],        t * k[1] * k[2] - s * k[0], 0,
                          t * k[2] * k[0] - s * k[1], t * k[2] * k[1] + s * k[0], c + t * k[2] * k[2],        0};
    memcpy(m, q, sizeof q);
}

hv_status hv_placement_matrix(const hv_placement *p, double out[12])
{
    double m[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    if (p->unit != 0) {
        if (!(p->unit > 0) || !isfinite(p->unit))
            return hv_error_option(HV_ERR_INVALID, "{unit} must be a positive length in mm, got %g", p->unit);
        double u[12] = {p->unit, 0, 0, 0, 0, p->unit, 0, 0, 0, 0, p->unit, 0};
        compose(u, m, m);
    }
    if (p->up == 'y') {
        const double y_up[12] = {1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0}; /* rotate x:90 */
        compose(y_up, m, m);
    } else if (p->up != 0 && p->up != 'z')
        return hv_error_option(HV_ERR_INVALID, "{up} must be y or z");
    if (p->scale[0] != 0 || p->scale[1] != 0 || p->scale[2] != 0) {
        for (int i = 0; i < 3; ++i)
            if (!(p->scale[i] != 0) || !isfinite(p->scale[i]))
                return hv_error_option(HV_ERR_INVALID, "{scale} must be finite and not 0 on every axis, got %g,%g,%g",
                                       p->scale[0], p->scale[1], p->scale[2]);
        double sc[12] = {p->scale[0], 0, 0, 0, 0, p->scale[1], 0, 0, 0, 0, p->scale[2], 0};
        compose(sc, m, m);
    }
    if (p->nrotate < 0 || p->nrotate > HV_PLACEMENT_MAX_ROTATIONS)
        return hv_error_option(HV_ERR_INVALID, "{rotate}: at most %d rotations", HV_PLACEMENT_MAX_ROTATIONS);
    for (int i = 0; i < p->nrotate; ++i) {
        const hv_placement_rotation *r = &p->rotate[i];
        if (!isfinite(r->degrees) || !isfinite(r->axis[0]) || !isfinite(r->axis[1]) || !isfinite(r->axis[2]) ||
            (r->axis[0] == 0 && r->axis[1] == 0 && r->axis[2] == 0))
            return hv_error_option(HV_ERR_INVALID, "{rotate} needs a finite angle and a non-zero finite axis");
        double rm[12];
        rotation(r, rm);
        compose(rm, m, m);
    }
    for (int i = 0; i < 3; ++i) {
        if (!isfinite(p->translate[i]))
            return hv_error_option(HV_ERR_INVALID, "{translate} must be finite, got %g,%g,%g", p->translate[0],
                                   p->translate[1], p->translate[2]);
        m[4 * i + 3] += p->translate[i];
    }
    memcpy(out, m, sizeof m);
    return HV_OK;
}

/* A number as the options read it back ("90", "0.5", "1e-05"). */
static void num(hv_buf *b, double v) { hv_buf_printf(b, "%.10g", v); }

const char *hv_placement_describe(const hv_placement *p, char *buf, size_t size)
{
    hv_buf b;
    hv_buf_init(&b);
    const char *sep = "";
    if (p->unit != 0) {
        const char *n = unit_name(p->unit);
        if (n) hv_buf_printf(&b, "unit %s", n);
        else {
            hv_buf_printf(&b, "unit ");
            num(&b, p->unit);
            hv_buf_printf(&b, " mm");
        }
        sep = ", ";
    }
    if (p->up) {
        hv_buf_printf(&b, "%sup %c", sep, (char)p->up);
        sep = ", ";
    }
    if (p->scale[0] != 0 || p->scale[1] != 0 || p->scale[2] != 0) {
        hv_buf_printf(&b, "%sscale ", sep);
        num(&b, p->scale[0]);
        if (p->scale[1] != p->scale[0] || p->scale[2] != p->scale[0]) {
            hv_buf_printf(&b, ",");
            num(&b, p->scale[1]);
            hv_buf_printf(&b, ",");
            num(&b, p->scale[2]);
        }
        sep = ", ";
    }
    for (int i = 0; i < p->nrotate; ++i) {
        const hv_placement_rotation *r = &p->rotate[i];
        hv_buf_printf(&b, "%srotate ", sep);
        int axis = -1;
        for (int k = 0; k < 3; ++k)
            if (r->axis[k] == 1 && r->axis[(k + 1) % 3] == 0 && r->axis[(k + 2) % 3] == 0) axis = k;
        if (axis >= 0) {
            hv_buf_printf(&b, "%c:", "xyz"[axis]);
            num(&b, r->degrees);
        } else {
            num(&b, r->degrees);
            hv_buf_printf(&b, "@");
            for (int k = 0; k < 3; ++k) {
                if (k) hv_buf_printf(&b, ",");
                num(&b, r->axis[k]);
            }
        }
        sep = ", ";
    }
    if (p->translate[0] != 0 || p->translate[1] != 0 || p->translate[2] != 0) {
        hv_buf_printf(&b, "%stranslate ", sep);
        for (int k = 0; k < 3; ++k) {
            if (k) hv_buf_printf(&b, ",");
            num(&b, p->translate[k]);
        }
    }
    snprintf(buf, size, "%s", b.data && !b.failed ? b.data : "");
    hv_buf_free(&b);
    return buf;
}

hv_status hv_placement_transform(const hv_placement *p, const hv_mesh *mesh, hv_mesh **out)
{
    *out = NULL;
    if (p->unit != 0 && hv_mesh_get_report(mesh)->format == HV_MESH_3MF)
        return hv_error_option(HV_ERR_INVALID, "{unit} is for files without a unit; %s is a 3MF package, which "
                                               "states its own", hv_mesh_name(mesh));
    double m[12];
    hv_status s = hv_placement_matrix(p, m);
    return s == HV_OK ? hv_mesh_transform(mesh, m, out) : s;
}

hv_status hv_placement_apply(const hv_placement *p, hv_mesh **mesh)
{
    if (!hv_placement_given(p)) return HV_OK;
    hv_mesh *placed;
    hv_status s = hv_placement_transform(p, *mesh, &placed);
    if (s != HV_OK) return s;
    hv_mesh_destroy(*mesh);
    *mesh = placed;
    return HV_OK;
}

/* ---- the size check ----------------------------------------------------------------------------- */

static void sort3(double v[3])
{
    for (int i = 1; i < 3; ++i)
        for (int j = i; j > 0 && v[j - 1] > v[j]; --j) {
            double t = v[j];
            v[j] = v[j - 1];
            v[j - 1] = t;
        }
}

int hv_placement_size_warning(const hv_mesh *mesh, const double build[3])
{
    const hv_mesh_report *r = hv_mesh_get_report(mesh);
    double side[3], sorted[3], fit[3] = {0, 0, 0};
    for (int i = 0; i < 3; ++i) sorted[i] = side[i] = r->bbox_max[i] - r->bbox_min[i];
    sort3(sorted);
    double largest = sorted[2];
    int small = largest < 1.0, large = 0;
    if (build) {
        memcpy(fit, build, sizeof fit);
        sort3(fit);
        large = sorted[0] > fit[0] || sorted[1] > fit[1] || sorted[2] > fit[2];
    }
    if (!(largest > 0) || (!small && !large)) return 0;
    /* A 3MF package states its unit, so --unit is refused for it (hv_placement_transform): its
     * hint is a scale from the unit it states (as read; a placed mesh's, millimetres) */
    int pkg = r->format == HV_MESH_3MF;
    double unit = 1.0;
    const char *stated = pkg ? hv_mesh_file_unit(mesh) : NULL;
    for (size_t i = 0; stated && i < HV_COUNT(k_units); ++i)
        if (strcmp(stated, k_units[i].alias) == 0) unit = k_units[i].mm;
    /* the likely unit: for a small mesh the largest of m, in, cm (and mm, for a package in a
     * smaller unit) that leaves it fitting the build volume (scans come in metres, American CAD in
     * inches), for a large one micrometres (then mm, cm, for a package in a larger unit) */
    static const int small_units[] = {2, 3, 1, 0}, large_units[] = {5, 0, 1};
    const int *cand = small ? small_units : large_units;
    int ncand = small ? (int)HV_COUNT(small_units) : (int)HV_COUNT(large_units), best = -1;
    for (int i = 0; i < ncand && best < 0; ++i) {
        double f = k_units[cand[i]].mm / unit, s[3] = {sorted[0] * f, sorted[1] * f, sorted[2] * f};
        if (small ? f <= 1 : f >= 1) continue; /* only a larger unit for a small mesh, a smaller one for a large */
        int fits = s[2] >= 1.0 && (!build || (s[0] <= fit[0] && s[1] <= fit[1] && s[2] <= fit[2]));
        if (fits) best = cand[i];
    }
    char what[128];
    if (small) snprintf(what, sizeof what, "smaller than 1 mm");
    else snprintf(what, sizeof what, "larger than the build volume %g x %g x %g mm", build[0], build[1], build[2]);
    const char *name = *hv_mesh_name(mesh) ? hv_mesh_name(mesh) : "the mesh";
    if (best >= 0 && pkg) {
        char says[64] = "";
        if (stated) snprintf(says, sizeof says, " (the package says %s)", stated);
        hv_error_option(HV_OK, "%s is %.4g x %.4g x %.4g mm, %s: if its numbers are %s%s, {scale} %g makes it %.3g mm across",
                        name, side[0], side[1], side[2], what, k_units[best].words, says, k_units[best].mm / unit,
                        largest * k_units[best].mm / unit);
    } else if (best >= 0)
        hv_error_option(HV_OK, "%s is %.4g x %.4g x %.4g mm, %s: if its unit is %s, {unit} %s makes it %.3g mm across",
                        name, side[0], side[1], side[2], what, k_units[best].words, k_units[best].name,
                        largest * k_units[best].mm);
    else
        hv_error_option(HV_OK, "%s is %.4g x %.4g x %.4g mm, %s", name, side[0], side[1], side[2], what);
    return 1;
}

/* ---- options ---------------------------------------------------------------------------------- */

/* "1,2,3" or one number (when one_fills): into v[3]. Returns 1 on success. */
static int parse_triple(const char *text, double v[3], int one_fills)
{
    char *end;
    const char *p = text;
    int n = 0;
    while (n < 3) {
        v[n] = strtod(p, &end);
        if (end == p || !isfinite(v[n])) return 0;
        ++n;
        p = end;
        if (*p == '\0') break;
        if (*p != ',') return 0;
        ++p;
    }
    if (*p != '\0') return 0;
    if (n == 1 && one_fills) v[1] = v[2] = v[0];
    else if (n != 3) return 0;
    return 1;
}

/* The value as numbers: text "1,2,3" or a list; into v[3]. */
static int triple_of(const hv_opt_value *value, double v[3], int one_fills)
{
    if (value->type == HV_VALUE_TEXT) return parse_triple(value->text, v, one_fills);
    if (value->type != HV_VALUE_NUMBERS) return 0;
    if (value->n == 1 && one_fills) {
        v[0] = v[1] = v[2] = value->numbers[0];
    } else if (value->n == 3) {
        memcpy(v, value->numbers, 3 * sizeof(double));
    } else return 0;
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

static hv_status parse_rotate(hv_placement *p, const hv_opt_value *value)
{
    if (value->type != HV_VALUE_TEXT)
        return hv_error_option(HV_ERR_INVALID, "{rotate} must be text such as \"x:90\" or \"30@1,1,0\"");
    if (p->nrotate >= HV_PLACEMENT_MAX_ROTATIONS)
        return hv_error_option(HV_ERR_INVALID, "{rotate}: at most %d rotations", HV_PLACEMENT_MAX_ROTATIONS);
    const char *t = value->text;
    hv_placement_rotation r = {{0, 0, 0}, 0};
    char *end;
    const char *at = strchr(t, '@');
    int ok;
    if ((t[0] == 'x' || t[0] == 'y' || t[0] == 'z') && t[1] == ':') {
        r.axis[t[0] - 'x'] = 1;
        r.degrees = strtod(t + 2, &end);
        ok = end != t + 2 && *end == '\0' && isfinite(r.degrees);
    } else if (at) {
        r.degrees = strtod(t, &end);
        ok = end != t && end == at && isfinite(r.degrees) && parse_triple(at + 1, r.axis, 0) &&
             (r.axis[0] != 0 || r.axis[1] != 0 || r.axis[2] != 0);
    } else ok = 0;
    if (!ok)
        return hv_error_option(HV_ERR_INVALID,
                               "{rotate} must be AXIS:DEGREES (x:90) or DEGREES@X,Y,Z (30@1,1,0, a non-zero axis), "
                               "got '%s'", t);
    p->rotate[p->nrotate++] = r;
    return HV_OK;
}

hv_status hv_placement_option_parse(const hv_option *opt, void *opts, const hv_opt_value *value)
{
    hv_placement *p = (hv_placement *)((char *)opts + opt->offset);
    const char *k = opt->key;
    if (strcmp(k, "rotate") == 0) return parse_rotate(p, value);
    if (strcmp(k, "unit") == 0) {
        if (value->type != HV_VALUE_TEXT) return hv_error_option(HV_ERR_INVALID, "{unit} must be a unit name (mm, cm, m, in)");
        return hv_placement_unit_parse(value->text, &p->unit);
    }
    if (strcmp(k, "up") == 0) {
        if (value->type != HV_VALUE_TEXT || !(strcmp(value->text, "y") == 0 || strcmp(value->text, "z") == 0))
            return hv_error_option(HV_ERR_INVALID, "{up} must be y or z, got '%s'",
                                   value->type == HV_VALUE_TEXT ? value->text : "a non-text value");
        p->up = value->text[0];
        return HV_OK;
    }
    if (strcmp(k, "scale") == 0) {
        double v[3];
        if (!triple_of(value, v, 1) || v[0] == 0 || v[1] == 0 || v[2] == 0)
            return hv_error_option(HV_ERR_INVALID, "{scale} must be S or SX,SY,SZ, finite and not 0, got '%s'",
                                   value->type == HV_VALUE_TEXT ? value->text : "other numbers");
        memcpy(p->scale, v, sizeof v);
        return HV_OK;
    }
    if (strcmp(k, "translate") == 0) {
        double v[3];
        if (!triple_of(value, v, 0))
            return hv_error_option(HV_ERR_INVALID, "{translate} must be X,Y,Z (mm, finite), got '%s'",
                                   value->type == HV_VALUE_TEXT ? value->text : "other numbers");
        memcpy(p->translate, v, sizeof v);
        return HV_OK;
    }
    return hv_error_set(HV_ERR_INTERNAL, "placement: unknown option %s", k);
}

typedef struct placement_opts {
    hv_placement place;
} placement_opts;

static const hv_option k_opts[] = {HV_PLACEMENT_OPTIONS(placement_opts, place)};
static void init(void *o) { hv_placement_init(o); }
static const hv_option_set k_set = {"placement", k_opts, (int)HV_COUNT(k_opts), sizeof(placement_opts), init,
                                    NULL, 0, NULL, NULL, NULL, 0};

const hv_option_set *hv_placement_option_set(void) { return &k_set; }
