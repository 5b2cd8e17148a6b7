/* src/cli/scan_opts.h - the options of a scanned volume that `voxelize` and `layers` share
 * (scan_opts.c). */
#ifndef HOVOX_CLI_SCAN_OPTS_H
#define HOVOX_CLI_SCAN_OPTS_H

#include <stddef.h>

#include "cli.h"
#include "core/internal.h"
#include "hovox/lut.h"
#include "hovox/scan.h"

typedef struct cli_scan {
    double iso, range[2], min_feature;
    const char *labels, *lut;
    int keep_largest, fill_holes;
} cli_scan;

/* The option entries, for a command's local table holding a cli_scan at `member`. */
#define CLI_SCAN_OPTIONS(type, member)                                                                              \
    {.key = "iso", .kind = HV_OPT_NUMBER, .offset = offsetof(type, member.iso), .meta = "VALUE",                    \
     .help = "a scanned volume's solid: where its trilinearly interpolated value is at least VALUE (e.g. 300 HU "   \
             "for bone)",                                                                                           \
     .section = "Scanned volumes (NIfTI, NRRD, MetaImage, DICOM series: one of --iso, --range, --labels)"},        \
    {.key = "range", .kind = HV_OPT_NUMBER, .count = 2, .offset = offsetof(type, member.range), .meta = "LO,HI",   \
     .help = "the solid where the interpolated value lies in [LO, HI]"},                                           \
    {.key = "labels", .kind = HV_OPT_STRING, .offset = offsetof(type, member.labels), .meta = "A,B,...",            \
     .help = "a segmentation's labels (integers): the solid where the interpolated indicator of those labels is "  \
             "at least 1/2"},                                                                                       \
    {.key = "keep_largest", .kind = HV_OPT_FLAG, .offset = offsetof(type, member.keep_largest),                     \
     .help = "keep the largest connected part only"},                                                              \
    {.key = "fill_holes", .kind = HV_OPT_FLAG, .offset = offsetof(type, member.fill_holes),                         \
     .help = "fill every enclosed cavity"},                                                                        \
    {.key = "min_feature", .kind = HV_OPT_NUMBER, .lo = 0, .hi = 1e6, .offset = offsetof(type, member.min_feature), \
     .meta = "MM", .unit = "mm", .help = "drop parts and fill cavities smaller than a ball of this diameter"},      \
    {.key = "lut", .kind = HV_OPT_STRING, .flags = HV_OPT_IN_PATH, .offset = offsetof(type, member.lut),           \
     .meta = "TABLE.csv",                                                                                           \
     .help = "materials from the volume's values: a lookup table of value -> material fractions or an sRGB "       \
             "colour (README 'Lookup tables')"}

/* --icc, --intent, --resins: the colour map's own options (hv_colour_option_set's, their help
 * too), set in the hv_colour_options at `member` of a command's local struct: the colours of a
 * scan's colour --lut (voxelize: also a painted mesh's). */
#define CLI_COLOUR_MAP_OPTIONS(type, member)                                                                        \
    {.key = "icc", .kind = HV_OPT_CUSTOM, .offset = offsetof(type, member), .parse = hv_colour_option_parse},      \
    {.key = "intent", .kind = HV_OPT_CUSTOM, .offset = offsetof(type, member), .parse = hv_colour_option_parse},   \
    {.key = "resins", .kind = HV_OPT_CUSTOM, .offset = offsetof(type, member), .parse = hv_colour_option_parse}

/* The shape and clean-ups into o (*labels: the label list o points at; free it after). Returns -1
 * when they are right, else the exit code (the usage error printed). */
int cli_scan_shape(const cli_args *args, const char *cmd, const cli_scan *c, hv_scan_voxelize_options *o,
                   int32_t **labels);
/* -1 when no scan option was given, else the usage error's exit code: "--iso <why>". */
int cli_scan_refuse(const cli_args *args, const char *cmd, const char *why);
/* The lookup table of --lut (NULL without it) and for a colour table its colour map, made with
 * `co` (the command's --icc, --intent, --resins; NULL: the defaults). */
hv_status cli_scan_lut(const cli_scan *c, const hv_colour_options *co, hv_lut **lut, hv_colour_map **map);
/* "materials   TABLE: N rows, HU LO to HI -> names\n", appended to b or printed. */
void cli_scan_describe_lut(hv_buf *b, const char *path, const hv_lut *lut, hv_colour_map *map);
void cli_scan_print_lut(const char *path, const hv_lut *lut, hv_colour_map *map);

#endif
