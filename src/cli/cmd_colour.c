/* src/cli/cmd_colour.c - `hovox colour COLOUR...`: the resin fractions a colour prints with through
 * the output profile (hovox/colour.h), and how far what they print lies from it (dE2000). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "core/internal.h"
#include "core/json.h"
#include "hovox/colour.h"

typedef struct colour_cli {
    int json;
} colour_cli;

static const hv_option k_local_opts[] = {
    CLI_JSON(colour_cli, "one JSON object: the profile, the resins and per colour its fractions, Lab and dE2000")};
static const hv_option_set k_local = CLI_LOCAL_SET("colour", k_local_opts, colour_cli);

static int run(const cli_args *args, void *lib, void *local)
{
    const colour_cli *c = local;
    int n = args->npos;
    uint8_t(*rgba)[4] = calloc((size_t)n, sizeof *rgba);
    if (!rgba) return cli_fail(hv_error_set(HV_ERR_NOMEM, "out of memory"));
    for (int i = 0; i < n; ++i) {
        float f[4];
        if (hv_color_parse(args->pos[i], f) != HV_OK) {
            free(rgba);
            return cli_usage_error("colour", "%s", hv_last_error());
        }
        for (int k = 0; k < 4; ++k) rgba[i][k] = (uint8_t)lrintf(f[k] * 255.0f);
    }
    hv_colour_map *map = NULL;
    hv_status s = hv_colour_map_create(lib, &map);
    if (s != HV_OK) {
        free(rgba);
        return cli_fail(s);
    }
    hv_buf out;
    hv_buf_init(&out);
    json_t *doc = NULL, *list = NULL;
    int bad = 0;
    if (c->json) {
        doc = json_object();
        list = json_array();
        json_t *resins = json_array();
        for (int k = 0; k < HV_COLOUR_SLOTS && resins; ++k)
            bad |= json_array_append_new(resins, hv_json_text(hv_colour_map_resin(map, k)));
        bad |= !doc || !list;
        bad |= hv_json_set(doc, "icc", hv_json_text(hv_colour_map_icc(map)));
        bad |= hv_json_set(doc, "description", hv_json_text(hv_colour_map_description(map)));
        bad |= hv_json_set(doc, "intent", hv_json_text(hv_intent_name(hv_colour_map_intent(map))));
        bad |= hv_json_set(doc, "resins", resins);
    } else {
        hv_buf_printf(&out, "profile  %s (%s), intent %s\n", hv_colour_map_icc(map), hv_colour_map_description(map),
                      hv_intent_name(hv_colour_map_intent(map)));
        hv_buf_printf(&out, "%-10s", "colour");
        for (int k = 0; k < HV_COLOUR_SLOTS; ++k) hv_buf_printf(&out, "  %14s", hv_colour_map_resin(map, k));
        hv_buf_puts(&out, "  dE2000\n");
    }
    for (int i = 0; i < n; ++i) {
        float f[HV_COLOUR_SLOTS];
        hv_colour_map_fractions(map, rgba[i], f);
        double want[3], got[3], fr[HV_COLOUR_SLOTS];
        hv_colour_map_lab_of_srgb(map, rgba[i], want);
        hv_colour_map_lab_of_fractions(map, f, got);
        double de = hv_colour_delta_e2000(want, got);
        char hex[10];
        if (rgba[i][3] == 255) snprintf(hex, sizeof hex, "#%02x%02x%02x", rgba[i][0], rgba[i][1], rgba[i][2]);
        else snprintf(hex, sizeof hex, "#%02x%02x%02x%02x", rgba[i][0], rgba[i][1], rgba[i][2], rgba[i][3]);
        if (c->json) {
            for (int k = 0; k < HV_COLOUR_SLOTS; ++k) fr[k] = f[k];
            json_t *o = json_object();
            bad |= !o || json_array_append_new(list, o);
            bad |= hv_json_set(o, "colour", hv_json_text(hex));
            bad |= hv_json_set(o, "fractions", hv_json_numbers(fr, HV_COLOUR_SLOTS));
            bad |= hv_json_set(o, "lab", hv_json_numbers(want, 3));
            bad |= hv_json_set(o, "printed_lab", hv_json_numbers(got, 3));
            bad |= hv_json_set(o, "de2000", hv_json_number(de));
        } else {
            hv_buf_printf(&out, "%-10s", hex);
            for (int k = 0; k < HV_COLOUR_SLOTS; ++k) hv_buf_printf(&out, "  %14.3f", (double)f[k]);
            hv_buf_printf(&out, "  %6.2f\n", de);
        }
    }
    if (c->json) {
        bad |= hv_json_set(doc, "colours", list);
        char *text = bad ? NULL : hv_json_dump(doc);
        if (text) {
            hv_buf_puts(&out, text);
            hv_buf_puts(&out, "\n");
        }
        bad |= !text;
        free(text);
        json_decref(doc);
    }
    hv_colour_map_destroy(map);
    free(rgba);
    if (out.failed || bad) {
        hv_buf_free(&out);
        return cli_fail(hv_error_set(HV_ERR_NOMEM, "out of memory"));
    }
    fputs(out.data, stdout);
    hv_buf_free(&out);
    return EXIT_OK;
}

const cli_spec cmd_colour = {
    "colour", "the resin fractions a colour prints with (C, M, Y, K, white, clear) through an ICC profile",
    "COLOUR [COLOUR ...] [--icc FILE.icc] [--intent INTENT] [--resins C,M,Y,K,W,CLEAR] [--json]",
    "Turn sRGB colours (#rrggbb, #rrggbbaa, or r,g,b[,a] in [0, 1]) into the fractions of the\n"
    "printer's six colour resins, as layers and tray print them: the output profile gives the ink\n"
    "coverages c, m, y, k; white fills the rest of the colour (1 - c - m - y - k; coverage beyond\n"
    "100 % is scaled to fit, white 0); alpha scales the colour and clear takes 1 - alpha. dE2000 is\n"
    "the CIEDE2000 difference between the colour and what the fractions print, both as the profile\n"
    "sees them (relative colorimetric): the cost of the gamut and of the ink limit.\n",
    hv_colour_option_set, &k_local, NULL, 1, -1, "COLOUR argument", 0, run, NULL, NULL};
