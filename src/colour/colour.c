/* src/colour/colour.c - colour maps (hovox/colour.h): LittleCMS 2 transforms from sRGB (or an input
 * profile) to the output profile's CMYK (ICC.1:2010; the intent's B2A table), the ink coverages
 * mixed with white and clear into six resin fractions, cached per distinct colour; Lab of what the
 * fractions print (the profile's A2B, relative colorimetric) and CIEDE2000 (Sharma, Wu, Dalal
 * 2005, as LittleCMS implements it). */
#include <inttypes.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <lcms2.h>

#include "core/internal.h"
#include "hovox/colour.h"

#define MAX_INPUTS 256
#define ICC_MAX_BYTES ((size_t)64 << 20)

static const char *const k_j750[HV_COLOUR_SLOTS] = {"VeroCyan-V",    "VeroMagenta-V", "VeroYellow-V",
                                                     "VeroBlackPlus", "VeroPureWhite", "VeroClear"};

const char *hv_colour_default_icc(void) { return "/usr/share/color/icc/ghostscript/default_cmyk.icc"; }

const char *hv_colour_j750_resin(int slot)
{
    return slot >= 0 && slot < HV_COLOUR_SLOTS ? k_j750[slot] : NULL;
}

/* Six names from "C,M,Y,K,W,CLEAR" (blanks around names trimmed), or the J750's. */
static hv_status split_resins(const char *text, char *out[HV_COLOUR_SLOTS])
{
    const char *p = text;
    for (int k = 0; k < HV_COLOUR_SLOTS; ++k) {
        const char *src = k_j750[k];
        size_t n = strlen(src);
        if (text) {
            const char *e = strchr(p, ',');
            if (!e) e = p + strlen(p);
            while (p < e && (*p == ' ' || *p == '\t')) ++p;
            const char *q = e;
            while (q > p && (q[-1] == ' ' || q[-1] == '\t')) --q;
            if (q == p || (k < HV_COLOUR_SLOTS - 1 && !*e) || (k == HV_COLOUR_SLOTS - 1 && *e)) {
                for (int j = 0; j < k; ++j) free(out[j]);
                return hv_error_option(HV_ERR_INVALID,
                                       "{resins} must be six names, C,M,Y,K,W,CLEAR (for example %s,%s,%s,%s,%s,%s), "
                                       "got '%s'",
                                       k_j750[0], k_j750[1], k_j750[2], k_j750[3], k_j750[4], k_j750[5], text);
            }
            src = p;
            n = (size_t)(q - p);
            p = *e ? e + 1 : e;
        }
        out[k] = hv_malloc(n + 1);
        if (!out[k]) {
            for (int j = 0; j < k; ++j) free(out[j]);
            return HV_ERR_NOMEM;
        }
        memcpy(out[k], src, n);
        out[k][n] = '\0';
    }
    return HV_OK;
}

/* ---- LittleCMS's messages ------------------------------------------------------------------- */

static _Thread_local char t_lcms_msg[256];

static void lcms_log(cmsContext ctx, cmsUInt32Number code, const char *text)
{
    (void)ctx;
    (void)code;
    if (!t_lcms_msg[0]) snprintf(t_lcms_msg, sizeof t_lcms_msg, "%s", text);
}

static pthread_once_t g_lcms_once = PTHREAD_ONCE_INIT;
static void lcms_init(void) { cmsSetLogErrorHandler(lcms_log); }

/* ---- the map -------------------------------------------------------------------------------- */

/* Refuses what is no ICC profile before LittleCMS reads it, with one message that says what and
 * which value (ICC.1:2022 7.2: a 128-byte header, its size at byte 0, "acsp" at byte 36): `name`
 * the file, `is` "" or "its embedded colour profile is " (a texture's). LittleCMS's own messages
 * ("not an ICC profile, invalid signature", "Read from memory error. Got 13 bytes, ...") said
 * the same twice or in its terms. */
static hv_status icc_header_check(const char *name, const char *is, const unsigned char *d, size_t size)
{
    if (size < 128)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: %snot an ICC profile (%zu bytes, shorter than the 128-byte header)",
                            name, is, size);
    if (memcmp(d + 36, "acsp", 4) != 0) {
        char sig[20], *p = sig;
        for (int i = 36; i < 40; ++i)
            p += d[i] >= 0x20 && d[i] < 0x7f && d[i] != '"' && d[i] != '\\' ? sprintf(p, "%c", d[i])
                                                                            : sprintf(p, "\\x%02x", d[i]);
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: %snot an ICC profile (bytes 36-39 are \"%s\", not the signature \"acsp\")",
                            name, is, sig);
    }
    uint32_t declared = (uint32_t)d[0] << 24 | (uint32_t)d[1] << 16 | (uint32_t)d[2] << 8 | d[3];
    if (declared > size)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: %sa truncated ICC profile (its header gives %" PRIu32 " bytes, %s %zu)",
                            name, is, declared, *is ? "there are" : "the file has", size);
    return HV_OK;
}

typedef struct cache_slot {
    uint64_t key; /* input id << 32 | rgba, plus 1 (0: empty) */
    float f[HV_COLOUR_SLOTS];
} cache_slot;

struct hv_colour_map {
    char *icc, *description;
    char *resins[HV_COLOUR_SLOTS];
    hv_intent intent;
    cmsHPROFILE out, lab;
    cmsHTRANSFORM to_cmyk[MAX_INPUTS]; /* per input profile: RGBA 8 -> CMYK 16 */
    cmsHTRANSFORM to_srgb[MAX_INPUTS]; /* per input profile but sRGB's: RGBA 8 -> sRGB 8 */
    int ninputs;
    cmsHTRANSFORM cmyk_to_lab, srgb_to_lab;
    pthread_mutex_t lock;
    cache_slot *cache;
    size_t cap, used; /* cap a power of two */
};

void hv_colour_map_destroy(hv_colour_map *m)
{
    if (!m) return;
    for (int i = 0; i < m->ninputs; ++i)
        if (m->to_cmyk[i]) cmsDeleteTransform(m->to_cmyk[i]);
    for (int i = 0; i < m->ninputs; ++i)
        if (m->to_srgb[i]) cmsDeleteTransform(m->to_srgb[i]);
    if (m->cmyk_to_lab) cmsDeleteTransform(m->cmyk_to_lab);
    if (m->srgb_to_lab) cmsDeleteTransform(m->srgb_to_lab);
    if (m->out) cmsCloseProfile(m->out);
    if (m->lab) cmsCloseProfile(m->lab);
    free(m->icc);
    free(m->description);
    for (int k = 0; k < HV_COLOUR_SLOTS; ++k) free(m->resins[k]);
    free(m->cache);
    pthread_mutex_destroy(&m->lock);
    free(m);
}

static const char *space_name(cmsColorSpaceSignature s)
{
    switch (s) {
    case cmsSigRgbData: return "RGB";
    case cmsSigGrayData: return "grey";
    case cmsSigLabData: return "Lab";
    case cmsSigXYZData: return "XYZ";
    case cmsSigCmyData: return "CMY";
    case cmsSigCmykData: return "CMYK";
    default: return "non-RGB, non-CMYK";
    }
}

/* A transform from input profile `in` (RGB or grey) to the output CMYK, with alpha dropped. */
static cmsHTRANSFORM to_cmyk(hv_colour_map *m, cmsHPROFILE in)
{
    cmsUInt32Number fmt = cmsGetColorSpace(in) == cmsSigGrayData ? TYPE_GRAYA_8 : TYPE_RGBA_8;
    return cmsCreateTransform(in, fmt, m->out, TYPE_CMYK_16, (cmsUInt32Number)m->intent, cmsFLAGS_NOCACHE);
}

hv_status hv_colour_map_create(const hv_colour_options *opt, hv_colour_map **out)
{
    *out = NULL;
    hv_colour_options defaults;
    if (!opt) {
        hv_colour_options_init(&defaults);
        opt = &defaults;
    }
    if ((unsigned)opt->intent > HV_INTENT_ABSOLUTE)
        return hv_error_set(HV_ERR_INVALID, "rendering intent %d out of range (0 to 3)", (int)opt->intent);
    char *resins[HV_COLOUR_SLOTS] = {NULL};
    hv_status s = split_resins(opt->resins, resins);
    if (s != HV_OK) return s;
    pthread_once(&g_lcms_once, lcms_init);
    const char *path = opt->icc ? opt->icc : hv_colour_default_icc();
    char *data = NULL;
    size_t size = 0;
    s = hv_read_file(path, ICC_MAX_BYTES, &data, &size);
    if (s == HV_ERR_LIMIT) s = hv_error_set(HV_ERR_BAD_INPUT, "%s: not an ICC profile (larger than 64 MiB)", path);
    hv_colour_map *m = s == HV_OK ? hv_calloc(1, sizeof *m) : NULL;
    if (!m) {
        free(data);
        for (int k = 0; k < HV_COLOUR_SLOTS; ++k) free(resins[k]);
        return s != HV_OK ? s : HV_ERR_NOMEM;
    }
    memcpy(m->resins, resins, sizeof resins);
    pthread_mutex_init(&m->lock, NULL);
    m->intent = opt->intent;
    m->icc = hv_strdup(path);
    t_lcms_msg[0] = '\0';
    s = icc_header_check(path, "", (const unsigned char *)data, size);
    if (s == HV_OK) m->out = cmsOpenProfileFromMem(data, (cmsUInt32Number)size);
    free(data);
    if (s != HV_OK) goto fail;
    if (!m->icc) {
        s = HV_ERR_NOMEM;
        goto fail;
    }
    if (!m->out) {
        s = hv_error_set(HV_ERR_BAD_INPUT, "%s: a damaged ICC profile (LittleCMS: %s)", path,
                         t_lcms_msg[0] ? t_lcms_msg : "no reason given");
        goto fail;
    }
    cmsColorSpaceSignature cs = cmsGetColorSpace(m->out);
    cmsProfileClassSignature cls = cmsGetDeviceClass(m->out);
    if (cls == cmsSigLinkClass || cls == cmsSigAbstractClass || cls == cmsSigNamedColorClass) {
        s = hv_error_set(HV_ERR_BAD_INPUT, "%s: a %s profile, not an output profile", path,
                         cls == cmsSigLinkClass ? "device link" : cls == cmsSigAbstractClass ? "abstract" : "named colour");
        goto fail;
    }
    if (cs != cmsSigCmykData) {
        s = hv_error_set(HV_ERR_BAD_INPUT, "%s: %s %s profile where a CMYK output profile is needed", path,
                         cs == cmsSigRgbData || cs == cmsSigXYZData ? "an" : "a", space_name(cs));
        goto fail;
    }
    if (!cmsIsIntentSupported(m->out, (cmsUInt32Number)m->intent, LCMS_USED_AS_OUTPUT)) {
        s = hv_error_set(HV_ERR_BAD_INPUT, "%s: the profile has no %s intent for output", path,
                         hv_intent_name(m->intent));
        goto fail;
    }
    char desc[256] = "";
    cmsGetProfileInfoASCII(m->out, cmsInfoDescription, "en", "US", desc, sizeof desc);
    m->description = hv_strdup(desc);
    m->lab = cmsCreateLab4Profile(NULL); /* D50 */
    cmsHPROFILE srgb = cmsCreate_sRGBProfile();
    t_lcms_msg[0] = '\0';
    if (srgb && m->out) m->to_cmyk[0] = to_cmyk(m, srgb);
    m->ninputs = 1;
    if (srgb && m->lab)
        m->srgb_to_lab = cmsCreateTransform(srgb, TYPE_RGB_8, m->lab, TYPE_Lab_DBL, INTENT_RELATIVE_COLORIMETRIC,
                                            cmsFLAGS_NOCACHE);
    if (m->lab)
        m->cmyk_to_lab = cmsCreateTransform(m->out, TYPE_CMYK_DBL, m->lab, TYPE_Lab_DBL,
                                            INTENT_RELATIVE_COLORIMETRIC, cmsFLAGS_NOCACHE);
    if (srgb) cmsCloseProfile(srgb);
    m->cap = 4096;
    m->cache = hv_calloc(m->cap, sizeof *m->cache);
    if (!m->description || !m->cache) {
        s = HV_ERR_NOMEM;
        goto fail;
    }
    for (int k = 0; k < HV_COLOUR_SLOTS; ++k)
        if (!m->resins[k]) {
            s = HV_ERR_NOMEM;
            goto fail;
        }
    if (!m->to_cmyk[0] || !m->srgb_to_lab || !m->cmyk_to_lab) {
        s = hv_error_set(HV_ERR_BAD_INPUT, "%s: LittleCMS cannot build a transform with it%s%s", path,
                         t_lcms_msg[0] ? ": " : "", t_lcms_msg);
        goto fail;
    }
    *out = m;
    return HV_OK;
fail:
    hv_colour_map_destroy(m);
    return s;
}

const char *hv_colour_map_icc(const hv_colour_map *m) { return m->icc; }
const char *hv_colour_map_description(const hv_colour_map *m) { return m->description; }
hv_intent hv_colour_map_intent(const hv_colour_map *m) { return m->intent; }
const char *hv_colour_map_resin(const hv_colour_map *m, int slot)
{
    return slot >= 0 && slot < HV_COLOUR_SLOTS ? m->resins[slot] : NULL;
}

hv_status hv_colour_map_add_input(hv_colour_map *m, const void *icc, size_t size, const char *name, int *id)
{
    if (m->ninputs >= MAX_INPUTS)
        return hv_error_set(HV_ERR_LIMIT, "%s: more than %d input colour profiles", name, MAX_INPUTS - 1);
    pthread_once(&g_lcms_once, lcms_init);
    t_lcms_msg[0] = '\0';
    static const char is[] = "its embedded colour profile is ";
    if (size > ICC_MAX_BYTES)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: %snot an ICC profile (larger than 64 MiB)", name, is);
    hv_status s = icc_header_check(name, is, icc, size);
    if (s != HV_OK) return s;
    cmsHPROFILE in = cmsOpenProfileFromMem(icc, (cmsUInt32Number)size);
    if (!in)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: %sa damaged ICC profile (LittleCMS: %s)", name, is,
                            t_lcms_msg[0] ? t_lcms_msg : "no reason given");
    cmsColorSpaceSignature cs = cmsGetColorSpace(in);
    if (cs != cmsSigRgbData && cs != cmsSigGrayData) {
        cmsCloseProfile(in);
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: its embedded colour profile is %s, not RGB or grey", name,
                            space_name(cs));
    }
    cmsHTRANSFORM t = to_cmyk(m, in);
    /* the colour asked for, as sRGB for the render and the dE2000 (relative colorimetric) */
    cmsHPROFILE srgb = t ? cmsCreate_sRGBProfile() : NULL;
    cmsHTRANSFORM ts = srgb ? cmsCreateTransform(in, cs == cmsSigGrayData ? TYPE_GRAYA_8 : TYPE_RGBA_8, srgb, TYPE_RGB_8,
                                                 INTENT_RELATIVE_COLORIMETRIC, cmsFLAGS_NOCACHE)
                            : NULL;
    if (srgb) cmsCloseProfile(srgb);
    cmsCloseProfile(in);
    if (t && !ts) {
        cmsDeleteTransform(t);
        t = NULL;
    }
    if (!t)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: its embedded colour profile cannot be used%s%s", name,
                            t_lcms_msg[0] ? ": " : "", t_lcms_msg);
    m->to_cmyk[m->ninputs] = t;
    m->to_srgb[m->ninputs] = ts;
    *id = m->ninputs++;
    return HV_OK;
}

/* The mixing rule of hovox/colour.h. */
static void mix(const uint16_t cmyk[4], double alpha, float f[HV_COLOUR_SLOTS])
{
    double ink[4], t = 0;
    for (int k = 0; k < 4; ++k) t += ink[k] = cmyk[k] / 65535.0;
    double white = t < 1 ? 1 - t : 0, scale = t > 1 ? 1 / t : 1;
    for (int k = 0; k < 4; ++k) f[k] = (float)(alpha * ink[k] * scale);
    f[HV_COLOUR_W] = (float)(alpha * white);
    f[HV_COLOUR_CLEAR] = (float)(1 - alpha);
}

static void compute(hv_colour_map *m, int id, const uint8_t rgba[4], float out[HV_COLOUR_SLOTS])
{
    uint16_t cmyk[4];
    uint8_t px[4] = {rgba[0], rgba[1], rgba[2], 255};
    cmsDoTransform(m->to_cmyk[id], px, cmyk, 1); /* a grey input reads the first two bytes */
    mix(cmyk, rgba[3] / 255.0, out);
}

/* Insert into the table (locked; grows at half full). */
static void cache_put(hv_colour_map *m, uint64_t key, const float f[HV_COLOUR_SLOTS])
{
    if (2 * (m->used + 1) > m->cap) {
        size_t cap = 2 * m->cap;
        cache_slot *t = calloc(cap, sizeof *t);
        if (!t) return; /* the colour is still right; only not cached */
        for (size_t i = 0; i < m->cap; ++i) {
            if (!m->cache[i].key) continue;
            size_t j = (size_t)((m->cache[i].key * 0x9E3779B97F4A7C15ull) >> 20) & (cap - 1);
            while (t[j].key) j = (j + 1) & (cap - 1);
            t[j] = m->cache[i];
        }
        free(m->cache);
        m->cache = t;
        m->cap = cap;
    }
    size_t j = (size_t)((key * 0x9E3779B97F4A7C15ull) >> 20) & (m->cap - 1);
    while (m->cache[j].key && m->cache[j].key != key) j = (j + 1) & (m->cap - 1);
    if (!m->cache[j].key) m->used++;
    m->cache[j].key = key;
    memcpy(m->cache[j].f, f, sizeof m->cache[j].f);
}

void hv_colour_map_fractions_in(hv_colour_map *m, int id, const uint8_t rgba[4], float out[HV_COLOUR_SLOTS])
{
    if (id < 0 || id >= m->ninputs) id = 0;
    uint64_t key = ((uint64_t)id << 32 | (uint64_t)rgba[0] << 24 | (uint64_t)rgba[1] << 16 |
                    (uint64_t)rgba[2] << 8 | rgba[3]) + 1;
    pthread_mutex_lock(&m->lock);
    size_t j = (size_t)((key * 0x9E3779B97F4A7C15ull) >> 20) & (m->cap - 1);
    while (m->cache[j].key && m->cache[j].key != key) j = (j + 1) & (m->cap - 1);
    if (m->cache[j].key == key) {
        memcpy(out, m->cache[j].f, sizeof m->cache[j].f);
        pthread_mutex_unlock(&m->lock);
        return;
    }
    pthread_mutex_unlock(&m->lock);
    compute(m, id, rgba, out);
    pthread_mutex_lock(&m->lock);
    cache_put(m, key, out);
    pthread_mutex_unlock(&m->lock);
}

void hv_colour_map_srgb_in(const hv_colour_map *m, int id, const uint8_t rgba[4], uint8_t srgb[3])
{
    if (id <= 0 || id >= m->ninputs || !m->to_srgb[id]) {
        memcpy(srgb, rgba, 3);
        return;
    }
    uint8_t px[4] = {rgba[0], rgba[1], rgba[2], 255};
    cmsDoTransform(m->to_srgb[id], px, srgb, 1);
}

void hv_colour_map_fractions(hv_colour_map *m, const uint8_t rgba[4], float out[HV_COLOUR_SLOTS])
{
    hv_colour_map_fractions_in(m, 0, rgba, out);
}

void hv_colour_map_lab_of_srgb(const hv_colour_map *m, const uint8_t rgb[3], double lab[3])
{
    cmsCIELab l;
    cmsDoTransform(m->srgb_to_lab, rgb, &l, 1);
    lab[0] = l.L;
    lab[1] = l.a;
    lab[2] = l.b;
}

void hv_colour_map_lab_of_fractions(const hv_colour_map *m, const float f[HV_COLOUR_SLOTS], double lab[3])
{
    double part = 0;
    for (int k = 0; k < HV_COLOUR_CLEAR; ++k) part += f[k];
    double cmyk[4] = {0, 0, 0, 0}; /* LittleCMS's CMYK doubles are percentages */
    for (int k = 0; k < 4 && part > 0; ++k) cmyk[k] = 100.0 * f[k] / part;
    cmsCIELab l;
    cmsDoTransform(m->cmyk_to_lab, cmyk, &l, 1);
    lab[0] = l.L;
    lab[1] = l.a;
    lab[2] = l.b;
}

double hv_colour_delta_e2000(const double a[3], const double b[3])
{
    cmsCIELab x = {a[0], a[1], a[2]}, y = {b[0], b[1], b[2]};
    return cmsCIE2000DeltaE(&x, &y, 1, 1, 1);
}
