/* src/cli/scan_opts.c - what `voxelize` and `layers` share for a scanned volume (issue 30): the
 * shape options (--iso, --range, --labels, the clean-ups), the lookup table (--lut) and
 * their summary line, read in one place so both commands take and refuse them alike. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "core/internal.h"
#include "scan_opts.h"

/* "1,2,5" -> labels (malloc'd): the library's parser (job files read the same text). */
static int parse_labels(const char *cmd, const char *text, int32_t **out, size_t *n)
{
    hv_status s = hv_scan_labels_parse(text, out, n);
    if (s == HV_ERR_NOMEM) return cli_fail(s);
    if (s != HV_OK) {
        char msg[1024];
        return cli_usage_error(cmd, "%s", cli_message(msg, sizeof msg));
    }
    return -1;
}

int cli_scan_shape(const cli_args *args, const char *cmd, const cli_scan *c, hv_scan_voxelize_options *o,
                   int32_t **labels)
{
    *labels = NULL;
    int picks = cli_given(args, "iso") + cli_given(args, "range") + cli_given(args, "labels");
    if (picks != 1) return cli_usage_error(cmd, "a scanned volume needs one of --iso, --range or --labels");
    if (cli_given(args, "iso")) {
        o->shape.select = HV_SCAN_SELECT_ISO;
        o->shape.iso = c->iso;
    } else if (cli_given(args, "range")) {
        o->shape.select = HV_SCAN_SELECT_RANGE;
        o->shape.range[0] = c->range[0];
        o->shape.range[1] = c->range[1];
    } else {
        int rc = parse_labels(cmd, c->labels, labels, &o->shape.label_count);
        if (rc >= 0) return rc;
        o->shape.select = HV_SCAN_SELECT_LABELS;
        o->shape.labels = *labels;
    }
    o->keep_largest = c->keep_largest;
    o->fill_holes = c->fill_holes;
    o->min_feature = c->min_feature;
    return -1;
}

int cli_scan_refuse(const cli_args *args, const char *cmd, const char *why)
{
    static const char *const keys[] = {"iso", "range", "labels", "keep_largest", "fill_holes", "min_feature", "lut"};
    for (size_t i = 0; i < sizeof keys / sizeof *keys; ++i)
        if (cli_given(args, keys[i])) return cli_usage_error(cmd, "%s %s", cli_spell(keys[i]), why);
    return -1;
}

hv_status cli_scan_lut(const cli_scan *c, const hv_colour_options *co, hv_lut **lut, hv_colour_map **map)
{
    *lut = NULL;
    *map = NULL;
    if (!c->lut) return HV_OK;
    hv_status s = hv_lut_load(c->lut, lut);
    if (s != HV_OK || hv_lut_kind_of(*lut) != HV_LUT_COLOUR) return s;
    hv_colour_options defaults;
    hv_colour_options_init(&defaults);
    return hv_colour_map_create(co ? co : &defaults, map);
}

void cli_scan_describe_lut(hv_buf *b, const char *path, const hv_lut *lut, hv_colour_map *map)
{
    double lo, hi;
    hv_lut_range(lut, &lo, &hi);
    size_t n = hv_lut_rows(lut);
    hv_buf_printf(b, "materials   %s: %zu row%s, %s %.6g to %.6g ->", path, n, n == 1 ? "" : "s", hv_lut_value_name(lut),
                  lo, hi);
    if (map) {
        hv_buf_printf(b, " colour through %s:", hv_colour_map_description(map));
        for (int k = 0; k < HV_COLOUR_SLOTS; ++k) hv_buf_printf(b, " %s", hv_colour_map_resin(map, k));
    } else {
        for (int k = 0; k < hv_lut_columns(lut); ++k) hv_buf_printf(b, " %s", hv_lut_material(lut, k));
    }
    hv_buf_printf(b, "\n");
}

void cli_scan_print_lut(const char *path, const hv_lut *lut, hv_colour_map *map)
{
    hv_buf b;
    hv_buf_init(&b);
    cli_scan_describe_lut(&b, path, lut, map);
    if (b.data) fputs(b.data, stdout);
    hv_buf_free(&b);
}
