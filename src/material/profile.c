/* src/material/profile.c - material distribution on a sample line (Wu 2.3, Fig. 26): a graded
 * model probed at n points of a segment, written as CSV and turned into a plot. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "hovox/profile.h"

struct hv_profile {
    int n, m;
    double from[3], to[3], length;
    hv_material_table *table;
    double *t;           /* n */
    double *pos;         /* 3n */
    unsigned char *in;   /* n */
    double *frac;        /* n*m, row i at frac + i*m */
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
    free(p);
}

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
    hv_buf_puts(&b, "\n");
    hv_status s = HV_OK;
    for (int i = 0; i < p->n && s == HV_OK; ++i) {
        const double *x = p->pos + 3 * (size_t)i, *f = p->frac + (size_t)i * p->m;
        hv_buf_printf(&b, "%.9g,%.9g,%.9g,%.9g,%d", p->t[i], x[0], x[1], x[2], p->in[i]);
        for (int k = 0; k < p->m; ++k) hv_buf_printf(&b, ",%.6g", f[k]);
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
