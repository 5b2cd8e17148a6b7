/* hovox/options.h - option domains: every option of every operation is described once, in the
 * library (key, type, domain, default, help), and the library parses and checks its values.
 * The front ends (the CLI, Lua, job files) only translate syntax: a CLI argument, a Lua value or
 * a JSON value becomes an hv_opt_value, and a refusal comes back as one message that each front
 * end spells its own way ("--step must be in (0, 4] voxels, got 5" on the command line, "step
 * must be in (0, 4] voxels, got 5" in Lua). */
#ifndef HOVOX_OPTIONS_H
#define HOVOX_OPTIONS_H

#include <stddef.h>
#include <stdint.h>

#include "hovox/core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ==== enumerations =========================================================================
 *
 * The names of an enum, indexed by value (or with an explicit values[] array). Parsing is exact
 * (case-sensitive); aliases map other accepted spellings onto a name. Every enum hovox reads,
 * from an option or from a file, goes through these, so an unknown name is refused the same way
 * everywhere. */
typedef struct hv_enum_def {
    const char *what;             /* "render mode": for messages without an option key */
    const char *const *names;     /* NULL-terminated */
    const int *values;            /* NULL: names[i] has value i */
    const char *const *aliases;   /* NULL or NULL-terminated pairs {alias, name, ...} */
} hv_enum_def;

/* Value of `name`. Errors: HV_ERR_INVALID "<what> must be one of a, b, c, got 'x'". */
HV_API hv_status hv_enum_parse(const hv_enum_def *e, const char *name, int *out);
/* Name of `value`, or NULL when it has none. */
HV_API const char *hv_enum_name(const hv_enum_def *e, int value);
/* "a, b or c" into buf (truncated to size); returns buf. */
HV_API const char *hv_enum_list(const hv_enum_def *e, char *buf, size_t size);

/* ==== colours ================================================================================ */

/* Parse "#rrggbb", "#rrggbbaa" or "r,g,b[,a]" (components in [0,1]) into straight RGBA (alpha 1
 * unless given). Errors: HV_ERR_INVALID naming the text. */
HV_API hv_status hv_color_parse(const char *s, float rgba[4]);

/* ==== option descriptors ===================================================================== */

typedef enum hv_opt_kind {
    HV_OPT_FLAG = 0, /* int: 1 when given; CLI --name (no value), Lua/JSON true or false; with
                        `parse` set, parse receives the (BOOL) value instead */
    HV_OPT_NUMBER,   /* `count` numbers of type `elem`: text "1,2,3", a list of numbers, or
                        one number (count 1, or HV_OPT_SCALAR) */
    HV_OPT_BYTES,    /* uint64_t: text "512M", "8G" (K/M/G/T = powers of 1024), or a number */
    HV_OPT_ENUM,     /* int: one of enumdef's names */
    HV_OPT_STRING,   /* const char *: the front end keeps the text alive until the call ends */
    HV_OPT_COLOR,    /* elem FLOAT: float[4] straight RGBA; elem UINT8: uint8_t[3] RGB. Text
                        as hv_color_parse, or a list {r, g, b[, a]} in [0, 1]; with
                        HV_OPT_ALPHA "transparent" (or "none") is alpha 0 */
    HV_OPT_RANGE,    /* size_t[2]: [first, last) of a sequence: text "A:B" (A: or :B), or a
                        list {A, B}; last 0 means "to the end" */
    HV_OPT_CUSTOM    /* set by `parse` */
} hv_opt_kind;

typedef enum hv_opt_elem {
    HV_ELEM_DOUBLE = 0, HV_ELEM_FLOAT, HV_ELEM_INT, HV_ELEM_INT64, HV_ELEM_UINT64, HV_ELEM_UINT8
} hv_opt_elem;

/* flags */
#define HV_OPT_LO_OPEN 0x01u  /* the domain excludes lo */
#define HV_OPT_HI_OPEN 0x02u  /* the domain excludes hi */
#define HV_OPT_SCALAR 0x04u   /* NUMBER with count > 1: one number fills every component */
#define HV_OPT_FIRST 0x08u    /* NUMBER with count > 1: one number sets the first component and
                                 zeroes the others (dims = N) */
#define HV_OPT_ALPHA 0x10u    /* COLOR: alpha allowed, and "transparent" */
#define HV_OPT_REPEAT 0x20u   /* may be given several times (CUSTOM: each value is added) */
#define HV_OPT_REQUIRED 0x40u /* must be given (checked by hv_optargs_finish) */
#define HV_OPT_XSEP 0x80u     /* NUMBER with count 2: text "WxH" is accepted too (documented
                                 before "W,H" was the one syntax) */
#define HV_OPT_ZERO_OK 0x100u /* NUMBER: 0 is accepted besides the domain ("automatic") */
#define HV_OPT_UNSET0 0x800u  /* NUMBER: 0 in a struct means "not given" (a user's 0 is still
                                 checked against the domain); implied for SCALAR and FIRST */
#define HV_OPT_OUT_PATH 0x200u /* STRING: a file the operation writes (a sandbox checks it) */
#define HV_OPT_IN_PATH 0x1000u /* STRING: a file the operation reads */
#define HV_OPT_PAIRS 0x400u   /* CUSTOM text "KEY=VALUE" (repeatable): a Lua or JSON map
                                 {KEY = VALUE, ...} gives one value per entry */

/* A value as a front end delivers it. */
typedef enum hv_opt_value_type { HV_VALUE_TEXT = 0, HV_VALUE_NUMBERS, HV_VALUE_BOOL } hv_opt_value_type;
typedef struct hv_opt_value {
    hv_opt_value_type type;
    const char *text;      /* TEXT: the text as typed */
    const double *numbers; /* NUMBERS: n numbers (a Lua number is n = 1, a list n = #list) */
    int n;
    int boolean;           /* BOOL */
} hv_opt_value;

typedef struct hv_option hv_option;
/* CUSTOM: store `value` into the options struct `opts`; errors set with hv_error_option. */
typedef hv_status (*hv_opt_parse_fn)(const hv_option *opt, void *opts, const hv_opt_value *value);
/* Extra check of a parsed value (STRING: a printer profile that exists, ...). */
typedef hv_status (*hv_opt_check_fn)(const hv_option *opt, const void *opts);

struct hv_option {
    const char *key;          /* "layer_height": Lua and JSON key; CLI --layer-height */
    hv_opt_kind kind;
    hv_opt_elem elem;         /* NUMBER and COLOR */
    int count;                /* NUMBER: components (0 means 1) */
    unsigned flags;
    double lo, hi;            /* NUMBER and BYTES: domain of each component (lo == hi == 0: any
                                 finite value) */
    size_t offset;            /* of the value in the options struct */
    const hv_enum_def *enumdef;
    const char *meta;         /* placeholder in help: "X,Y,Z", "SIZE", "NAME" */
    const char *unit;         /* in messages: "voxels", "mm", "degrees" (may be NULL) */
    const char *help;         /* help text (wrapped by the front end) */
    const char *section;      /* help heading this option starts (NULL: same as before) */
    hv_opt_parse_fn parse;    /* CUSTOM */
    hv_opt_check_fn check;    /* optional */
};

/* Rules between options, checked by hv_optargs_finish. `value` names an enum value of b. */
typedef enum hv_opt_rule_kind {
    HV_RULE_EXCLUDES = 0,   /* a and b are not both given */
    HV_RULE_NEEDS,          /* a given: b given too */
    HV_RULE_NEEDS_VALUE     /* a given: b has one of the values in `value` ("halftone|mask") */
} hv_opt_rule_kind;
typedef struct hv_opt_rule {
    hv_opt_rule_kind kind;
    const char *a, *b;
    const char *value;
    const char *why;        /* optional reason appended to the message */
} hv_opt_rule;

typedef struct hv_optargs hv_optargs;

/* A shorthand: giving `name` (CLI --name, Lua name = true) sets option `key` to `value`
 * (text), e.g. "surface" for mode = surface. */
typedef struct hv_opt_alias {
    const char *name;
    const char *key;
    const char *value;
} hv_opt_alias;

/* The options of one operation. */
typedef struct hv_option_set {
    const char *name;            /* "render" */
    const hv_option *options;
    int count;
    size_t size;                 /* sizeof the options struct */
    void (*init)(void *opts);    /* defaults */
    const hv_opt_rule *rules;
    int rule_count;
    /* Cross-option checks and derived values once every value is in (hv_optargs_given tells
     * what was given). May be NULL. Errors set with hv_error_option. */
    hv_status (*finish)(const hv_optargs *args);
    /* Value checks of the whole struct that need no "given" information (also run by the
     * library's own entry points on structs filled in C). May be NULL. */
    hv_status (*validate)(const void *opts);
    const hv_opt_alias *aliases;
    int alias_count;
} hv_option_set;

/* The option of that key, or NULL. */
HV_API const hv_option *hv_option_find(const hv_option_set *set, const char *key);
/* HV_OK when `key` is an option of the set, one of its aliases, or listed in `extra` (NULL or
 * NULL-terminated: keys a front end reads itself, such as an output path); else HV_ERR_NOT_FOUND
 * with the message the front ends give: "unknown option 'k' (options: a, b, ..., extra, ...)". */
HV_API hv_status hv_option_known(const hv_option_set *set, const char *const *extra, const char *key);

/* Store a value into opts (parsing text, checking the domain). Errors: HV_ERR_INVALID with a
 * message naming the option ("{step} must be in (0, 4] voxels, got 5", see hv_error_option). */
HV_API hv_status hv_option_set_value(const hv_option *opt, void *opts, const hv_opt_value *value);
HV_API hv_status hv_option_set_text(const hv_option *opt, void *opts, const char *text);

/* Check the value an option holds in opts against its domain (used on structs filled in C). */
HV_API hv_status hv_option_check(const hv_option *opt, const void *opts);
/* Copy option `key`'s value from struct src to struct dst (both of `set`): a later source of
 * options overriding an earlier one only where it gave a value (a job file, then the command
 * line). Strings are copied as pointers. Errors: HV_ERR_NOT_FOUND (no such key), HV_ERR_INVALID
 * (a custom option, whose storage the set does not describe). */
HV_API hv_status hv_option_copy(const hv_option_set *set, const char *key, void *dst, const void *src);
/* Every option's domain, then set->validate. */
HV_API hv_status hv_options_check(const hv_option_set *set, const void *opts);

/* The option's current value in opts as text, in the syntax hv_option_set_text reads
 * ("0.5", "1,2,3", "#ff0000", "512M", "halftone", "3:10"); "" for an unset string. */
HV_API const char *hv_option_format(const hv_option *opt, const void *opts, char *buf, size_t size);

/* ==== collecting values from a front end ====================================================== */

struct hv_optargs {
    const hv_option_set *set;
    void *opts;
    uint64_t given;   /* bit i: set->options[i] was given (a set has at most 64 options) */
};

/* Start: opts initialised with set->init. */
HV_API void hv_optargs_begin(hv_optargs *args, const hv_option_set *set, void *opts);
/* Set the option `key` (or an alias: a BOOL true applies it, false does nothing). Errors:
 * HV_ERR_NOT_FOUND for an unknown key ("unknown option 'x' (options of render: ...)"),
 * HV_ERR_INVALID for a value out of its domain, or an option given twice that may not be
 * repeated. */
HV_API hv_status hv_optargs_set(hv_optargs *args, const char *key, const hv_opt_value *value);
/* 1 when `key` was given. */
HV_API int hv_optargs_given(const hv_optargs *args, const char *key);
/* The rules, required options, set->finish and hv_options_check. */
HV_API hv_status hv_optargs_finish(hv_optargs *args);

/* ==== messages naming options ==================================================================
 *
 * A message about options names them as {key}; hv_last_error() shows the key itself
 * ("step must be in ..."), hv_error_spell renders the braces the caller's way ("--step must be
 * in ..."). */

/* Record a failure whose format names options as {key}, or as {%s} with the key an argument
 * (only identifiers [a-z0-9_] in braces, and {%s}, are option names; values are formatted after
 * the names are marked, so braces in values are text). Returns status. */
HV_API hv_status hv_error_option(hv_status status, const char *fmt, ...) HV_PRINTF(2, 3);

/* 1 when the calling thread's last message begins with an option's name (recorded by
 * hv_error_option as "{key} ..."): a refusal of a value someone gave, not a failure that only
 * mentions an option in passing. */
HV_API int hv_last_error_names_option(void);

/* The calling thread's last message with each option name passed through spell(key, user) (a
 * NULL result keeps the key); into buf of size bytes. Returns buf. */
typedef const char *(*hv_spell_fn)(const char *key, void *user);
HV_API const char *hv_error_spell(hv_spell_fn spell, void *user, char *buf, size_t size);

#ifdef __cplusplus
}
#endif
#endif
