/* src/plot/profile_plot.c - the plot of a material profile along a line (Wu 2.3, Fig. 26):
 * one series per material, outside stretches shaded. Reads the profile only through its
 * public accessors (hovox/profile.h), so the material module knows nothing of plots. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/internal.h"
#include "hovox/plot.h"

hv_status hv_profile_plot(const hv_profile *p, int width, int height, hv_plot **out)
{
    *out = NULL;
    hv_plot *pl;
    hv_status s = hv_plot_create(width, height, &pl);
    if (s != HV_OK) return s;
    int n = hv_profile_samples(p), m = hv_profile_materials(p);
    const hv_material_table *table = hv_profile_table(p);
    double *t = hv_malloc_array((size_t)n, sizeof *t);
    double *y = hv_malloc_array((size_t)n, sizeof *y);
    if (!t || !y) {
        free(t);
        free(y);
        hv_plot_destroy(pl);
        return HV_ERR_NOMEM;
    }
    for (int i = 0; i < n; ++i) t[i] = hv_profile_t(p, i);
    double from[3], to[3];
    hv_profile_segment(p, from, to);
    char sub[256];
    snprintf(sub, sizeof sub, "from (%.6g, %.6g, %.6g) to (%.6g, %.6g, %.6g), %d samples", from[0],
             from[1], from[2], to[0], to[1], to[2], n);
    s = hv_plot_set_x(pl, t, (size_t)n);
    if (s == HV_OK) s = hv_plot_set_title(pl, "Material fractions along a line", sub);
    if (s == HV_OK) s = hv_plot_set_labels(pl, "distance along the line (mm)", "material fraction");
    for (int k = 0; k < m && s == HV_OK; ++k) {
        for (int i = 0; i < n; ++i) y[i] = hv_profile_inside(p, i) ? hv_profile_fractions(p, i)[k] : NAN;
        float c[4];
        hv_material_color(table, k, c);
        c[3] = 1.0f;
        s = hv_plot_add_series(pl, hv_material_name(table, k), y, c, NULL);
    }
    const char *unit, *prop = hv_profile_property(p, &unit);
    if (prop && s == HV_OK) { /* the property on its own axis, next to the fractions */
        char label[300], title[300];
        snprintf(label, sizeof label, *unit ? "%s (%s)" : "%s", prop, unit);
        snprintf(title, sizeof title, "Material fractions and %s along a line", prop);
        for (int i = 0; i < n; ++i) y[i] = hv_profile_property_value(p, i);
        static const float k_ink[4] = {0.1f, 0.1f, 0.1f, 1.0f};
        int idx;
        s = hv_plot_set_right_axis(pl, label, NAN, NAN);
        if (s == HV_OK) s = hv_plot_add_series(pl, prop, y, k_ink, &idx);
        if (s == HV_OK) s = hv_plot_set_series_right(pl, idx, 1);
        if (s == HV_OK) s = hv_plot_set_title(pl, title, NULL);
    }
    /* outside stretches: each run of outside samples, widened to the midpoints with its
     * inside neighbours (the boundary lies somewhere between them) */
    for (int i = 0; i < n && s == HV_OK;) {
        if (hv_profile_inside(p, i)) {
            ++i;
            continue;
        }
        int j = i;
        while (j + 1 < n && !hv_profile_inside(p, j + 1)) ++j;
        double a = i > 0 ? 0.5 * (t[i - 1] + t[i]) : t[0];
        double b = j + 1 < n ? 0.5 * (t[j] + t[j + 1]) : t[n - 1];
        s = hv_plot_add_span(pl, a, b, "outside the object");
        i = j + 1;
    }
    free(y);
    free(t);
    if (s != HV_OK) {
        hv_plot_destroy(pl);
        return s;
    }
    *out = pl;
    return HV_OK;
}

hv_status hv_profile_plot_with(const hv_profile *p, const hv_profile_options *o, hv_plot **out)
{
    hv_profile_options d;
    if (!o) {
        hv_profile_options_init(&d);
        o = &d;
    }
    hv_status s = hv_profile_plot(p, o->size[0], o->size[1], out);
    if (s == HV_OK && o->title && *o->title) s = hv_plot_set_title(*out, o->title, NULL); /* keeps the subtitle */
    if (s == HV_OK) s = hv_plot_set_y_range(*out, o->y_range[0], o->y_range[1]);
    for (int k = 0; k < o->marks && s == HV_OK; ++k) s = hv_plot_add_marker(*out, o->mark[k].t, o->mark[k].label);
    if (s != HV_OK) {
        hv_plot_destroy(*out);
        *out = NULL;
    }
    return s;
}

static int is_svg(const char *path) { return hv_has_extension(path, ".svg"); }

hv_status hv_plot_path_check(const char *path)
{
    if (path && (is_svg(path) || hv_has_extension(path, ".png"))) return HV_OK;
    return hv_error_option(HV_ERR_INVALID, "{plot} '%s' has an unknown extension (use .png or .svg)", path ? path : "");
}

hv_status hv_profile_write_files(const hv_profile *p, const hv_profile_options *o, const char *csv, const char *plot)
{
    hv_atomic_file fcsv = {NULL, NULL, NULL}, fplot = {NULL, NULL, NULL};
    hv_plot *pl = NULL; /* everything that can fail on content is done before anything is written */
    hv_status s = plot ? hv_plot_path_check(plot) : HV_OK;
    if (s == HV_OK && plot) s = hv_profile_plot_with(p, o, &pl);
    if (s == HV_OK && csv) s = hv_atomic_open(&fcsv, csv, "w");
    if (s == HV_OK && plot) s = hv_atomic_open(&fplot, plot, "wb");
    if (s == HV_OK && fcsv.fp && (s = hv_profile_write_csv_stream(p, fcsv.fp)) != HV_OK)
        s = hv_error_prefix(s, "%s: ", csv);
    if (s == HV_OK && fplot.fp) {
        s = is_svg(plot) ? hv_plot_write_svg_stream(pl, fplot.fp) : hv_plot_write_png_stream(pl, fplot.fp);
        if (s != HV_OK) s = hv_error_prefix(s, "%s: ", plot);
    }
    if (s == HV_OK && fcsv.fp) s = hv_atomic_commit(&fcsv);
    if (s == HV_OK && fplot.fp) s = hv_atomic_commit(&fplot);
    if (s != HV_OK) {
        if (fcsv.fp) hv_atomic_abort(&fcsv);
        if (fplot.fp) hv_atomic_abort(&fplot);
    }
    hv_plot_destroy(pl);
    return s;
}
