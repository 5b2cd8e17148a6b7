/* hovox/plot.h - publication-style line plots drawn with cairo: one x array, named series in
 * RGBA colours, axis labels, title, legend, 1-2-5 axis ticks, vertical markers and shaded
 * spans; written as PNG or SVG, atomically. Used for material profiles (Wu Fig. 26). */
#ifndef HOVOX_PLOT_H
#define HOVOX_PLOT_H

#include <stdio.h>

#include "hovox/core.h"
#include "hovox/profile.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A plot under construction. Every setter copies its arguments; nothing is drawn until a
 * write call. A plot is not thread-safe while being modified; write calls only read it.
 *
 * Layout: title (and subtitle) above the plot area, tick labels and axis labels to the left
 * and below, a full frame with outward ticks and light grid lines at the ticks. Fonts and
 * line widths scale with sqrt(width * height / (900 * 560)), at least 0.75, so a plot
 * written at twice the size looks the same at twice the resolution. Text uses cairo's toy
 * font API with "DejaVu Sans" (fontconfig substitutes when it is missing).
 *
 * Axes: x spans the finite range of the x values exactly; y is [0, 1] unless changed
 * (hv_plot_set_y_range), drawn with 3% of room above and below so that lines on 0 and 1 are
 * not hidden by the frame. Ticks are the multiples of a 1-2-5 step (..., 0.1, 0.2, 0.5, 1,
 * 2, 5, 10, ...) inside the range: the smallest step leaving at least 45 px (scaled) between
 * y ticks, and at least 80 px between x ticks with their labels 16 px apart.
 *
 * Legend: one entry per named series and one per distinct span label, placed inside the plot
 * area at the first of upper right, upper left, lower right, lower left, centre right,
 * centre left, upper centre, lower centre where it covers no line and no marker; when every
 * place would cover data it goes outside, to the right of the plot area. */
typedef struct hv_plot hv_plot;

/* New empty plot of width x height pixels (PNG) or points (SVG), each in [100, 8192].
 * Errors: HV_ERR_INVALID (size), HV_ERR_NOMEM. Free with hv_plot_destroy. */
HV_API hv_status hv_plot_create(int width, int height, hv_plot **out);

/* Free a plot; NULL is allowed. */
HV_API void hv_plot_destroy(hv_plot *p);

/* Set the n >= 1 x values (copied) shared by every series; replaces earlier x values and
 * drops the series added so far. Errors: HV_ERR_INVALID (n == 0, a value not finite),
 * HV_ERR_NOMEM. */
HV_API hv_status hv_plot_set_x(hv_plot *p, const double *x, size_t n);

/* Add a series: y holds as many values as the x array (copied); NAN leaves a gap (the line
 * breaks; an isolated sample is drawn as a dot). rgba components in [0, 1] are used as given
 * (alpha included); very light colours get a thin grey outline so they stay visible on
 * white. name (UTF-8, may be NULL or "": no legend entry) is copied. *index (may be NULL)
 * receives the series number, from 0. At most 64 series.
 * Errors: HV_ERR_INVALID (no x values yet, an infinite y value, colour out of range, name
 * not UTF-8, too many series), HV_ERR_NOMEM. */
HV_API hv_status hv_plot_add_series(hv_plot *p, const char *name, const double *y,
                                    const float rgba[4], int *index);

/* Draw series `index` dashed (dashed != 0) or solid (the default), e.g. a theoretical curve
 * next to sampled ones. Errors: HV_ERR_INVALID (no such series). */
HV_API hv_status hv_plot_set_series_dashed(hv_plot *p, int index, int dashed);

/* Title (bold, above the plot) and subtitle (smaller, below the title): NULL keeps the
 * current text, "" removes it. A title wider than the plot area is drawn smaller to fit.
 * Errors: HV_ERR_INVALID (not UTF-8), HV_ERR_NOMEM. */
HV_API hv_status hv_plot_set_title(hv_plot *p, const char *title, const char *subtitle);

/* Axis labels (UTF-8): NULL keeps the current label, "" removes it. Errors: HV_ERR_INVALID
 * (not UTF-8), HV_ERR_NOMEM. */
HV_API hv_status hv_plot_set_labels(hv_plot *p, const char *xlabel, const char *ylabel);

/* Fixed y range [lo, hi] (finite, lo < hi; default [0, 1]), or the data range widened to
 * the enclosing tick multiples when both are NAN. Errors: HV_ERR_INVALID. */
HV_API hv_status hv_plot_set_y_range(hv_plot *p, double lo, double hi);

/* A second y axis on the right of the plot area, for series in other units than the left axis
 * (e.g. a property next to fractions): ticks and tick labels on the right edge of the frame (no
 * grid lines: the grid follows the left axis), `label` (UTF-8, may be NULL) along it, read
 * bottom to top. Its range is [lo, hi] (finite, lo < hi), or with both NAN the data range of
 * the series put on it (hv_plot_set_series_right) widened to the enclosing 1-2-5 tick
 * multiples, as hv_plot_set_y_range does for the left axis. Calling it again replaces the label
 * and range. Errors: HV_ERR_INVALID (range, label not UTF-8), HV_ERR_NOMEM. */
HV_API hv_status hv_plot_set_right_axis(hv_plot *p, const char *label, double lo, double hi);
/* Draw series `index` against the right-hand axis (right != 0) or the left one (the default).
 * Errors: HV_ERR_INVALID (no such series; right without hv_plot_set_right_axis first). */
HV_API hv_status hv_plot_set_series_right(hv_plot *p, int index, int right);

/* A vertical dashed marker at x (finite) with an optional label (UTF-8, may be NULL) written
 * at the top of the plot area; markers outside the x range are not drawn. At most 64.
 * Errors: HV_ERR_INVALID, HV_ERR_NOMEM. */
HV_API hv_status hv_plot_add_marker(hv_plot *p, double x, const char *label);

/* A shaded vertical band over [x0, x1] (finite; swapped when x0 > x1), drawn under the grid
 * and the lines, e.g. where a profile line runs outside the object. Spans with the same
 * label (UTF-8, may be NULL: no legend entry) share one legend entry. At most 1000000.
 * Errors: HV_ERR_INVALID, HV_ERR_NOMEM. */
HV_API hv_status hv_plot_add_span(hv_plot *p, double x0, double x1, const char *label);

/* Pixel position of data point (x, y) (y on the left axis) in the written image (0,0 = top left pixel corner),
 * and the plot area box[4] = {left, top, right, bottom} (may be NULL), for callers that
 * check or annotate images. Errors: HV_ERR_INVALID (no x values), HV_ERR_NOMEM. */
HV_API hv_status hv_plot_data_to_pixel(const hv_plot *p, double x, double y, double px[2],
                                       double box[4]);

/* Write the plot as an 8-bit RGB PNG (white background) or as SVG, to a temporary name in the
 * same directory renamed when complete. Output is deterministic for a given cairo version.
 * Errors: HV_ERR_INVALID (no x values), HV_ERR_IO (cannot write or rename; no file is left
 * under `path`), HV_ERR_NOMEM. */
HV_API hv_status hv_plot_write_png(const hv_plot *p, const char *path);
HV_API hv_status hv_plot_write_svg(const hv_plot *p, const char *path);

/* The same, written to an open stream (left open, not flushed), for callers that commit
 * several outputs together. Errors: HV_ERR_INVALID (no x values), HV_ERR_IO ("plot: write
 * failed: <reason>"), HV_ERR_NOMEM. */
HV_API hv_status hv_plot_write_png_stream(const hv_plot *p, FILE *fp);
HV_API hv_status hv_plot_write_svg_stream(const hv_plot *p, FILE *fp);

/* ---- material profiles (hovox/profile.h) ---------------------------------------------- */

/* A plot of the profile (width x height pixels, see hv_plot_create): distance along the line
 * on x ("distance along the line (mm)"), one series per material in its table colour (alpha
 * set to 1) on y ("material fraction", range [0, 1]), drawn only where the samples are inside;
 * stretches outside the object are shaded and labelled "outside the object" (their ends
 * halfway between an inside and an outside sample). Title "Material fractions along a line",
 * subtitle the end points and the sample count; callers may change both, add markers (e.g. a
 * grading source's d- and d- + dg) and then write it. A profile with a property
 * (hv_profile_sample_with) also shows it: a near-black series named after the property on a
 * right-hand axis labelled "<property> (<unit>)" over the data range (gaps where it is
 * undefined), titled "Material fractions and <property> along a line". Free with hv_plot_destroy.
 * Errors: HV_ERR_INVALID (size), HV_ERR_NOMEM. */
HV_API hv_status hv_profile_plot(const hv_profile *p, int width, int height, hv_plot **out);
/* hv_profile_plot with the size, title, y range and markers of `o` (NULL: defaults). */
HV_API hv_status hv_profile_plot_with(const hv_profile *p, const hv_profile_options *o, hv_plot **out);
/* HV_OK when `path` names a plot format: .png or .svg, case aside. Errors: HV_ERR_INVALID
 * ("{plot} 'x.gif' has an unknown extension (use .png or .svg)"). */
HV_API hv_status hv_plot_path_check(const char *path);
/* Write the profile's CSV to `csv` and its plot (hv_profile_plot_with(p, o), format from the
 * name) to `plot`, either may be NULL; both under temporary names renamed at the end, so a
 * failed call leaves neither. Errors: HV_ERR_INVALID (plot name), HV_ERR_IO naming the file,
 * HV_ERR_NOMEM. */
HV_API hv_status hv_profile_write_files(const hv_profile *p, const hv_profile_options *o, const char *csv,
                                        const char *plot);

#ifdef __cplusplus
}
#endif
#endif
