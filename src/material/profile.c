/* src/material/profile.c - material distribution on a sample line (Wu 2.3, Fig. 26): a graded
 * model probed at n points of a segment, written as CSV and turned into a plot. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "hovox/profile.h"
#include "material_internal.h"
#include "volumes/schema.h"

struct hv_profile {
    int n, m;
    double from[3], to[3], length;
    hv_material_table *table;
    double *t;           /* n */
    double *pos;         /* 3n */
    unsigned char *in;   /* n */
    double *frac;        /* n*m, row i at frac + i*m */
    char *property;      /* NULL: no property */
    char *unit;
    double *prop;        /* n, NAN where undefined */
};

typedef struct sample_job {
    const hv_volume *vol;
    hv_profile *p;
    int grids[HV_MAX_MATERIALS];
} sample_job;

static hv_status sample_range(void *ctx, size_t begin, size_t end, int thread)
{
    (void)thread;
    sample_job *job = ctx;
    hv_profile *p = job->p;
    hv_accessor acc;
    hv_accessor_init(&acc, job->vol);
    for (size_t i = begin; i < end; ++i) {
        /* (1-u)*a + u*b hits both end points exactly */
        double u = (double)i / (double)(p->n - 1);
        double *x = p->pos + 3 * i;
        for (int a = 0; a < 3; ++a) x[a] = (1.0 - u) * p->from[a] + u * p->to[a];
        p->t[i] = u * p->length;
        int inside;
        hv_model_probe(&acc, p->table, job->grids, x, &inside, p->frac + i * (size_t)p->m);
        p->in[i] = (unsigned char)(inside != 0);
    }
    return HV_OK;
}

hv_status hv_profile_sample(const hv_volume *vol, const double from[3], const double to[3], int n,
                            hv_profile **out)
{
    *out = NULL;
    if (n < 2) return hv_error_set(HV_ERR_INVALID, "profile: %d samples; at least 2 are needed", n);
    for (int a = 0; a < 3; ++a)
        if (!isfinite(from[a]) || !isfinite(to[a]))
            return hv_error_set(HV_ERR_INVALID, "profile: end points (%g, %g, %g) and (%g, %g, %g) must be finite",
                                from[0], from[1], from[2], to[0], to[1], to[2]);
    double len = sqrt((to[0] - from[0]) * (to[0] - from[0]) + (to[1] - from[1]) * (to[1] - from[1]) +
                      (to[2] - from[2]) * (to[2] - from[2]));
    if (!(len > 0))
        return hv_error_set(HV_ERR_INVALID, "profile: the line from (%g, %g, %g) to (%g, %g, %g) has length 0",
                            from[0], from[1], from[2], to[0], to[1], to[2]);
    if (!isfinite(len))
        return hv_error_set(HV_ERR_INVALID, "profile: the line from (%g, %g, %g) to (%g, %g, %g) is too long",
                            from[0], from[1], from[2], to[0], to[1], to[2]);
    hv_material_table *table;
    hv_status s = hv_material_table_load(vol, &table);
    if (s != HV_OK) return s;
    hv_profile *p = hv_calloc(1, sizeof *p);
    if (!p) {
        hv_material_table_destroy(table);
        return HV_ERR_NOMEM;
    }
    p->table = table;
    p->n = n;
    p->m = hv_material_count(table);
    p->length = len;
    memcpy(p->from, from, sizeof p->from);
    memcpy(p->to, to, sizeof p->to);
    p->t = hv_malloc_array((size_t)n, sizeof *p->t);
    p->pos = hv_malloc_array((size_t)n, 3 * sizeof *p->pos);
    p->in = hv_malloc((size_t)n);
    p->frac = hv_malloc_array((size_t)n, (size_t)HV_MAX(p->m, 1) * sizeof *p->frac);
    if (!p->t || !p->pos || !p->in || !p->frac) {
        s = HV_ERR_NOMEM;
        hv_profile_destroy(p);
        return s;
    }
    sample_job job;
    job.vol = vol;
    job.p = p;
    for (int k = 0; k < p->m; ++k) job.grids[k] = hv_material_grid(vol, table, k);
    s = hv_parallel_for((size_t)n, 4096, sample_range, &job, NULL, "profile");
    if (s != HV_OK) {
        hv_profile_destroy(p);
        return s;
    }
    *out = p;
    return HV_OK;
}

void hv_profile_destroy(hv_profile *p)
{
    if (!p) return;
    hv_material_table_destroy(p->table);
    free(p->t);
    free(p->pos);
    free(p->in);
    free(p->frac);
    free(p->property);
    free(p->unit);
    free(p->prop);
    free(p);
}

/* ---- a property along the line ------------------------------------------------------------ */

/* "name[unit]" or "name" */
static void table_label(char *buf, size_t size, const hv_calibration *c)
{
    const char *u = hv_calibration_unit(c);
    snprintf(buf, size, *u ? "%s[%s]" : "%s", hv_calibration_property(c), u);
}

/* Append `label` to the ", "-separated list b unless it is there already. */
static void list_add(hv_buf *b, const char *label)
{
    size_t n = strlen(label);
    for (const char *q = b->len ? b->data : NULL; q; q = strstr(q, ", ")) {
        q += *q == ',' ? 2 : 0;
        if (strncmp(q, label, n) == 0 && (q[n] == '\0' || q[n] == ',')) return;
    }
    hv_buf_printf(b, "%s%s", b->len ? ", " : "", label);
}

static int same_table(const hv_calibration *a, const double *ams, const double *ame, const hv_calibration *b,
                      const double *bms, const double *bme, int m)
{
    if (strcmp(hv_calibration_unit(a), hv_calibration_unit(b)) != 0 || hv_calibration_rows(a) != hv_calibration_rows(b))
        return 0;
    for (int j = 0; j < m; ++j)
        if (ams[j] != bms[j] || ame[j] != bme[j]) return 0;
    for (int i = 0; i < hv_calibration_rows(a); ++i) {
        double ta, va, tb, vb;
        hv_calibration_row(a, i, &ta, &va);
        hv_calibration_row(b, i, &tb, &vb);
        if (ta != tb || va != vb) return 0;
    }
    return 1;
}

/* The one calibration table for `property` among the sources of vol's grading definition, with
 * its source's Ms and Me (m fractions); see hv_profile_sample_with for the rule. */
static hv_status property_table(const hv_volume *vol, const char *property, int m, hv_calibration **out,
                                double *ms, double *me)
{
    *out = NULL;
    json_t *doc = NULL;
    const json_t *srcs = NULL;
    const char *what = hv_schema_key(HV_DOC_OBJECT);
    hv_status s = hv_schema_doc_read(vol, HV_DOC_OBJECT, &doc);
    if (s == HV_ERR_NOT_FOUND) s = HV_OK; /* no definition: no tables */
    if (s == HV_OK && doc) s = hv_json_need(doc, "sources", JSON_ARRAY, what, &srcs);
    hv_buf others, found; /* labels of the other tables; sources holding tables for the property */
    hv_buf_init(&others);
    hv_buf_init(&found);
    int nfound = 0, differ = 0;
    for (size_t i = 0; s == HV_OK && srcs && i < json_array_size(srcs); ++i) {
        const json_t *j = json_array_get(srcs, i);
        char place[300];
        snprintf(place, sizeof place, "%s: sources[%zu]", what, i);
        hv_calibration *c;
        double cms[HV_MAX_MATERIALS], cme[HV_MAX_MATERIALS];
        if ((s = hv_ags_doc_calibration(j, m, place, &c, cms, cme)) != HV_OK || !c) continue;
        const json_t *nj = json_object_get(j, "name");
        const char *name = json_is_string(nj) ? json_string_value(nj) : "";
        if (strcmp(hv_calibration_property(c), property) != 0) {
            char label[300];
            table_label(label, sizeof label, c);
            list_add(&others, label);
            hv_calibration_release(c);
            continue;
        }
        hv_buf_printf(&found, *name ? "%s%zu '%s'" : "%s%zu", nfound ? ", " : "", i + 1, name);
        if (!*out) {
            *out = c;
            memcpy(ms, cms, (size_t)m * sizeof *ms);
            memcpy(me, cme, (size_t)m * sizeof *me);
        } else {
            differ |= !same_table(*out, ms, me, c, cms, cme, m);
            hv_calibration_release(c);
        }
        ++nfound;
    }
    json_decref(doc);
    if (others.failed || found.failed) s = HV_ERR_NOMEM;
    if (s == HV_OK && !*out)
        s = hv_error_set(HV_ERR_NOT_FOUND, "no calibration table for %s in the model's grading definition (%s%s)",
                         property, others.len ? "it has tables for " : "it has no calibration tables",
                         others.len ? others.data : "");
    else if (s == HV_OK && differ)
        s = hv_error_set(HV_ERR_BAD_INPUT,
                         "the model's grading definition has different calibration tables for %s (sources %s): "
                         "its profile needs exactly one",
                         property, found.data);
    hv_buf_free(&others);
    hv_buf_free(&found);
    if (s != HV_OK) {
        hv_calibration_release(*out);
        *out = NULL;
    }
    return s;
}

hv_status hv_profile_sample_with(const hv_volume *vol, const hv_profile_options *o, hv_profile **out)
{
    *out = NULL;
    hv_status s = hv_profile_sample(vol, o->from, o->to, o->samples, out);
    if (s != HV_OK || !o->property) return s;
    hv_profile *p = *out;
    hv_calibration *c = NULL;
    double ms[HV_MAX_MATERIALS], me[HV_MAX_MATERIALS];
    s = property_table(vol, o->property, p->m, &c, ms, me);
    if (s == HV_OK) {
        p->property = hv_strdup(hv_calibration_property(c));
        p->unit = hv_strdup(hv_calibration_unit(c));
        p->prop = hv_malloc_array((size_t)p->n, sizeof *p->prop);
        if (!p->property || !p->unit || !p->prop) s = HV_ERR_NOMEM;
    }
    for (int i = 0; s == HV_OK && i < p->n; ++i) {
        double t;
        p->prop[i] = p->in[i] && hv_segment_t(ms, me, p->m, p->frac + (size_t)i * p->m, &t) ? hv_calibration_eval(c, t)
                                                                                             : NAN;
    }
    hv_calibration_release(c);
    if (s != HV_OK) {
        hv_profile_destroy(p);
        *out = NULL;
    }
    return s;
}

const char *hv_profile_property(const hv_profile *p, const char **unit)
{
    if (unit) *unit = p->unit ? p->unit : "";
    return p->property;
}

double hv_profile_property_value(const hv_profile *p, int i) { return p->prop ? p->prop[i] : NAN; }

int hv_profile_samples(const hv_profile *p) { return p->n; }
int hv_profile_materials(const hv_profile *p) { return p->m; }
double hv_profile_length(const hv_profile *p) { return p->length; }
const hv_material_table *hv_profile_table(const hv_profile *p) { return p->table; }

void hv_profile_segment(const hv_profile *p, double from[3], double to[3])
{
    memcpy(from, p->from, sizeof p->from);
    memcpy(to, p->to, sizeof p->to);
}

double hv_profile_t(const hv_profile *p, int i) { return p->t[i]; }

void hv_profile_position(const hv_profile *p, int i, double xyz[3])
{
    memcpy(xyz, p->pos + 3 * (size_t)i, 3 * sizeof *xyz);
}

int hv_profile_inside(const hv_profile *p, int i) { return p->in[i]; }

const double *hv_profile_fractions(const hv_profile *p, int i) { return p->frac + (size_t)i * p->m; }

/* ---- CSV -------------------------------------------------------------------------------- */

/* Rows go out in blocks of about 64 KiB: one stdio call per block, not per sample. `what`
 * names the output in messages. */
static hv_status csv_emit(const hv_profile *p, FILE *fp, const char *what)
{
    hv_buf b;
    hv_buf_init(&b);
    hv_buf_puts(&b, "t,x,y,z,inside");
    for (int k = 0; k < p->m; ++k) {
        hv_buf_puts(&b, ",");
        hv_buf_puts(&b, hv_material_name(p->table, k));
    }
    if (p->property) hv_buf_printf(&b, *p->unit ? ",%s[%s]" : ",%s", p->property, p->unit);
    hv_buf_puts(&b, "\n");
    hv_status s = HV_OK;
    for (int i = 0; i < p->n && s == HV_OK; ++i) {
        const double *x = p->pos + 3 * (size_t)i, *f = p->frac + (size_t)i * p->m;
        hv_buf_printf(&b, "%.9g,%.9g,%.9g,%.9g,%d", p->t[i], x[0], x[1], x[2], p->in[i]);
        for (int k = 0; k < p->m; ++k) hv_buf_printf(&b, ",%.6g", f[k]);
        if (p->prop) {
            if (isnan(p->prop[i])) hv_buf_puts(&b, ",nan");
            else hv_buf_printf(&b, ",%.6g", p->prop[i]);
        }
        hv_buf_puts(&b, "\n");
        if (b.failed) {
            s = hv_error_set(HV_ERR_NOMEM, "%s: out of memory formatting the CSV", what);
        } else if (b.len >= 1 << 16 || i == p->n - 1) {
            if (fwrite(b.data, 1, b.len, fp) != b.len)
                s = hv_error_set(HV_ERR_IO, "%s: write failed: %s", what, strerror(errno));
            b.len = 0;
            b.data[0] = '\0';
        }
    }
    hv_buf_free(&b);
    if (s == HV_OK && (fflush(fp) != 0 || ferror(fp)))
        s = hv_error_set(HV_ERR_IO, "%s: write failed: %s", what, strerror(errno));
    return s;
}

hv_status hv_profile_write_csv_stream(const hv_profile *p, FILE *fp)
{
    return csv_emit(p, fp, "profile CSV");
}

hv_status hv_profile_write_csv(const hv_profile *p, const char *path)
{
    hv_atomic_file af;
    hv_status s = hv_atomic_open(&af, path, "w");
    if (s != HV_OK) return s;
    if ((s = csv_emit(p, af.fp, path)) != HV_OK) {
        hv_atomic_abort(&af);
        return s;
    }
    return hv_atomic_commit(&af);
}

hv_status hv_model_probe_csv(const hv_volume *vol, const double *xyz, size_t n, FILE *fp)
{
    hv_material_table *t = NULL;
    hv_status s = hv_material_table_load(vol, &t);
    if (s != HV_OK) return s;
    int m = hv_material_count(t), grids[HV_MAX_MATERIALS];
    for (int k = 0; k < m; ++k) grids[k] = hv_material_grid(vol, t, k);
    fputs("x,y,z,inside", fp);
    for (int k = 0; k < m; ++k) fprintf(fp, ",%s", hv_material_name(t, k));
    fputc('\n', fp);
    hv_accessor acc;
    hv_accessor_init(&acc, vol);
    double frac[HV_MAX_MATERIALS];
    for (size_t i = 0; i < n; ++i) {
        const double *x = xyz + 3 * i;
        int inside;
        hv_model_probe(&acc, t, grids, x, &inside, frac);
        fprintf(fp, "%.9g,%.9g,%.9g,%d", x[0], x[1], x[2], inside);
        for (int k = 0; k < m; ++k) fprintf(fp, ",%.6g", frac[k]);
        fputc('\n', fp);
    }
    hv_material_table_destroy(t);
    if (fflush(fp) != 0 || ferror(fp)) return hv_error_set(HV_ERR_IO, "write failed: %s", strerror(errno));
    return HV_OK;
}
