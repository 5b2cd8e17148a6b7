/* src/material/profile_options.c - the options of material profiles along a line (hovox/profile.h,
 * hovox/options.h): the line, the samples and how the plot looks, for the library, CLI and Lua. */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "core/internal.h"
#include "hovox/profile.h"

/* mark: T or T=LABEL, repeatable */
static hv_status parse_mark(const hv_option *o, void *opts, const hv_opt_value *v)
{
    hv_profile_options *p = opts;
    if (p->marks == HV_PROFILE_MAX_MARKS)
        return hv_error_option(HV_ERR_INVALID, "at most %d {%s}s", HV_PROFILE_MAX_MARKS, o->key);
    hv_profile_mark *m = &p->mark[p->marks];
    m->label = NULL;
    if (v->type == HV_VALUE_NUMBERS && v->n == 1 && isfinite(v->numbers[0])) {
        m->t = v->numbers[0];
    } else {
        static const hv_option t = {.key = "mark", .kind = HV_OPT_NUMBER};
        const char *eq = v->type == HV_VALUE_TEXT ? strchr(v->text, '=') : NULL;
        char num[64];
        size_t n = eq ? (size_t)(eq - v->text) : v->type == HV_VALUE_TEXT ? strlen(v->text) : 0;
        if (v->type != HV_VALUE_TEXT || n == 0 || n >= sizeof num)
            return hv_error_option(HV_ERR_INVALID, "{%s} must be T or T=LABEL, got '%s'", o->key,
                                   v->type == HV_VALUE_TEXT ? v->text : "?");
        memcpy(num, v->text, n);
        num[n] = '\0';
        if (hv_option_set_text(&t, &m->t, num) != HV_OK)
            return hv_error_option(HV_ERR_INVALID, "{%s} must be T or T=LABEL with T a number, got '%s'", o->key,
                                   v->text);
        m->label = eq && eq[1] ? eq + 1 : NULL;
    }
    p->marks++;
    return HV_OK;
}

/* y_range: LO,HI with LO < HI, or auto */
static hv_status parse_y_range(const hv_option *o, void *opts, const hv_opt_value *v)
{
    hv_profile_options *p = opts;
    if (v->type == HV_VALUE_TEXT && strcmp(v->text, "auto") == 0) {
        p->y_range[0] = p->y_range[1] = NAN;
        return HV_OK;
    }
    static const hv_option two = {.key = "y_range", .kind = HV_OPT_NUMBER, .count = 2, .meta = "LO,HI"};
    double r[2];
    if (hv_option_set_value(&two, r, v) != HV_OK || !(r[0] < r[1]))
        return hv_error_option(HV_ERR_INVALID, "{%s} must be LO,HI with LO < HI, or auto", o->key);
    p->y_range[0] = r[0];
    p->y_range[1] = r[1];
    return HV_OK;
}

#define OFF(f) offsetof(hv_profile_options, f)
static const hv_option k_opts[] = {
    {.key = "from", .kind = HV_OPT_NUMBER, .count = 3, .flags = HV_OPT_REQUIRED, .offset = OFF(from),
     .meta = "X,Y,Z", .unit = "mm", .help = "start of the line (world coordinates, mm)", .section = "The line"},
    {.key = "to", .kind = HV_OPT_NUMBER, .count = 3, .flags = HV_OPT_REQUIRED, .offset = OFF(to), .meta = "X,Y,Z",
     .unit = "mm", .help = "end of the line"},
    {.key = "samples", .kind = HV_OPT_NUMBER, .elem = HV_ELEM_INT, .lo = 2, .hi = 10000000, .offset = OFF(samples),
     .meta = "N", .help = "samples along the line, both ends included"},
    {.key = "property", .kind = HV_OPT_STRING, .offset = OFF(property), .meta = "NAME",
     .help = "also this property along the line, from the calibration table stored with the model's grading "
             "source (a column NAME[UNIT] in the CSV, a curve on a right-hand axis of the plot)"},
    {.key = "title", .kind = HV_OPT_STRING, .offset = OFF(title), .meta = "TEXT",
     .help = "plot title (default 'Material fractions along a line')", .section = "The plot"},
    {.key = "size", .kind = HV_OPT_NUMBER, .elem = HV_ELEM_INT, .count = 2, .flags = HV_OPT_XSEP, .lo = 100,
     .hi = 8192, .offset = OFF(size), .meta = "W,H", .unit = "pixels", .help = "plot size in pixels"},
    {.key = "mark", .kind = HV_OPT_CUSTOM, .flags = HV_OPT_REPEAT, .meta = "T[=LABEL]", .parse = parse_mark,
     .help = "a dashed vertical line at distance T along the line, e.g. a grading source's d- and d- + dg "
             "(repeatable, up to 64)"},
    {.key = "y_range", .kind = HV_OPT_CUSTOM, .meta = "LO,HI", .parse = parse_y_range,
     .help = "y axis range of the plot (default 0,1); 'auto': the data range"},
};
#undef OFF

static hv_status finish(const hv_optargs *args)
{
    const hv_profile_options *p = args->opts;
    if (p->from[0] == p->to[0] && p->from[1] == p->to[1] && p->from[2] == p->to[2])
        return hv_error_option(HV_ERR_INVALID, "{from} and {to} are the same point");
    if (p->property && !*p->property) return hv_error_option(HV_ERR_INVALID, "{property} is empty");
    return HV_OK;
}

void hv_profile_options_init(hv_profile_options *o)
{
    memset(o, 0, sizeof *o);
    o->samples = 200;
    o->size[0] = 900;
    o->size[1] = 560;
    o->y_range[0] = 0;
    o->y_range[1] = 1;
}

static void init(void *o) { hv_profile_options_init(o); }

static const hv_option_set k_set = {"profile", k_opts, (int)HV_COUNT(k_opts), sizeof(hv_profile_options), init,
                                    NULL, 0, finish, NULL, NULL, 0};

const hv_option_set *hv_profile_option_set(void) { return &k_set; }

hv_status hv_profile_options_check(const hv_profile_options *o) { return hv_options_check(&k_set, o); }
