/* src/io/3mf/package.c - the one 3MF package module: the OPC container (ECMA-376 Part 2, as 3MF
 * Core 1.3 chapters 2 "Parts and Relationships" and 6 profile it) opened through libzip with
 * budgets against ZIP bombs, [Content_Types].xml and the root relationships read for the start
 * part, and XML parts streamed through libxml2's SAX2 push parser (no tree) with the line and
 * column of every element. The mesh reader, the Volumetric reader and the writer's checks use it. */
#include <errno.h>
#include <limits.h>
#include <libdeflate.h>
#include <libxml/parser.h>
#include <libxml/parserInternals.h>
#include <libxml/SAX2.h>
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <zlib.h>

#include "package.h"
#include "threemf_internal.h"

#define PKG_MAX_SMALL_PART ((uint64_t)1 << 20) /* _rels/.rels and [Content_Types].xml */
#define PKG_MAX_RATIO 1000                     /* declared size per compressed byte, past 16 MiB */
#define PKG_RATIO_FLOOR ((uint64_t)16 << 20)
#define PKG_MAX_ATTRS 64
#define PKG_MAX_DEPTH 256
#define PKG_CHUNK 65536
#define PKG_RING 4                       /* chunks the inflater thread may run ahead */
#ifndef PKG_THREAD_FLOOR /* (defined otherwise only by the differential check: every part the whole path) */
#define PKG_THREAD_FLOOR ((uint64_t)1 << 20) /* parts smaller than this inflate on the parser's thread */
#endif

/* ---- opening ------------------------------------------------------------------------------ */

void tmf_pkg_close(tmf_pkg *pk)
{
    if (pk->zip) zip_discard(pk->zip);
    else if (pk->src) zip_source_free(pk->src);
    pk->zip = NULL;
    pk->src = NULL;
}

static hv_status open_fail(const char *name, zip_error_t *e)
{
    int code = zip_error_code_zip(e);
    if (code == ZIP_ER_MEMORY) return HV_ERR_NOMEM;
    if (code == ZIP_ER_OPEN || code == ZIP_ER_READ || code == ZIP_ER_NOENT)
        return hv_error_set(HV_ERR_IO, "%s: cannot read: %s", name, zip_error_strerror(e));
    return hv_error_set(HV_ERR_BAD_INPUT, "%s: not a 3MF package: not a readable ZIP archive (libzip: %s; truncated?)",
                        name, zip_error_strerror(e));
}

/* The sizes the ZIP's directory declares: a bomb is refused here, before anything inflates
 * (issue 32 item 12). Parts inflating past what they declare are stopped while inflating. */
static hv_status check_declared(tmf_pkg *pk)
{
    zip_int64_t ne = zip_get_num_entries(pk->zip, 0);
    uint64_t total = 0, limit = pk->budget / 2;
    for (zip_int64_t i = 0; i < ne; ++i) {
        zip_stat_t st;
        if (zip_stat_index(pk->zip, (zip_uint64_t)i, 0, &st) != 0 || !(st.valid & ZIP_STAT_SIZE)) continue;
        uint64_t comp = (st.valid & ZIP_STAT_COMP_SIZE) ? st.comp_size : st.size;
        char q[96];
        const char *en = (st.valid & ZIP_STAT_NAME) && st.name ? st.name : "?";
        if (st.size > PKG_RATIO_FLOOR && st.size / PKG_MAX_RATIO > comp)
            return hv_error_set(HV_ERR_LIMIT,
                                "%s: part '/%s' declares %llu bytes from %llu compressed, more than %d times: a ZIP bomb",
                                pk->name, hv_quote(q, sizeof q, en, strlen(en)), (unsigned long long)st.size,
                                (unsigned long long)comp, PKG_MAX_RATIO);
        total += HV_MIN(st.size, UINT64_MAX / 2);
        if (total > limit) {
            char b1[32], b2[32];
            return hv_error_set(HV_ERR_LIMIT, "%s: the package expands to more than %s, half of the memory budget (%s)",
                                pk->name, hv_size_text(b1, sizeof b1, (double)limit),
                                hv_size_text(b2, sizeof b2, (double)pk->budget));
        }
    }
    pk->inflate_cap = limit;
    return HV_OK;
}

/* The entry of a part: exactly that name; `nocase` also accepts another spelling (OPC compares
 * part names without case; the start part alone is only read under the name its relationship
 * gives, so no look-alike can stand in for it). */
static zip_int64_t locate(const tmf_pkg *pk, const char *part, int nocase)
{
    zip_int64_t i = zip_name_locate(pk->zip, part, 0);
    if (i < 0 && nocase) i = zip_name_locate(pk->zip, part, ZIP_FL_NOCASE);
    return i;
}

/* A deflated part is inflated here, not by libzip: libzip checks its CRC with zlib's crc32,
 * a sixth of a 1M-facet model's inflate; libdeflate's takes a fifth of that (issue 26 item 2).
 * The raw stream is read and inflated as libzip 1.7's layers do (8 KiB of input at a time,
 * inflate with Z_SYNC_FLUSH, the output of a failing call dropped, the CRC checked at the end), so
 * a damaged part gives the same bytes, then the same error with libzip's own words. */
#define PKG_RAW_IN 8192

typedef struct raw_inflate {
    z_stream z;
    uint8_t in[PKG_RAW_IN];
    zip_error_t err; /* the first error, as libzip's layers would have set it */
    uint32_t crc, want_crc;
    int check_crc, failed, end_of_input, end_of_stream, eof;
} raw_inflate;

typedef struct inflater {
    tmf_pkg *pk;
    const char *part;
    zip_file_t *f;
    uint64_t declared, bytes, limit;
    raw_inflate *raw; /* NULL: libzip inflates */
    zip_int64_t index;
    uint64_t comp_size;
} inflater;

int tmf_pkg_has(const tmf_pkg *pk, const char *part) { return locate(pk, part, 1) >= 0; }

static void inflate_close(inflater *in);

static hv_status inflate_open(tmf_pkg *pk, zip_int64_t i, const char *part, uint64_t limit, inflater *in)
{
    memset(in, 0, sizeof *in);
    in->pk = pk;
    in->part = part;
    in->limit = limit;
    in->index = i;
    zip_stat_t st;
    in->declared = UINT64_MAX;
    int ok = zip_stat_index(pk->zip, (zip_uint64_t)i, 0, &st) == 0;
    if (ok && (st.valid & ZIP_STAT_SIZE)) in->declared = st.size;
    /* deflated, not encrypted: inflated here (anything else: libzip) */
    if (ok && (st.valid & ZIP_STAT_COMP_METHOD) && st.comp_method == ZIP_CM_DEFLATE &&
        (st.valid & ZIP_STAT_ENCRYPTION_METHOD) && st.encryption_method == ZIP_EM_NONE) {
        raw_inflate *r = hv_calloc(1, sizeof *r);
        if (!r) return HV_ERR_NOMEM;
        if (inflateInit2(&r->z, -MAX_WBITS) != Z_OK) {
            free(r);
            return HV_ERR_NOMEM;
        }
        zip_error_init(&r->err);
        r->check_crc = (st.valid & ZIP_STAT_CRC) != 0;
        r->want_crc = st.crc;
        in->raw = r;
        in->comp_size = (st.valid & ZIP_STAT_COMP_SIZE) ? st.comp_size : 0;
        in->f = zip_fopen_index(pk->zip, (zip_uint64_t)i, ZIP_FL_COMPRESSED);
    } else
        in->f = zip_fopen_index(pk->zip, (zip_uint64_t)i, 0);
    if (!in->f) {
        char q[96];
        hv_status s = hv_error_set(HV_ERR_BAD_INPUT, "%s: part '/%s' cannot be read (libzip: %s)", pk->name,
                                   hv_quote(q, sizeof q, part, strlen(part)), zip_strerror(pk->zip));
        inflate_close(in);
        return s;
    }
    return HV_OK;
}

/* Up to cap bytes; 0 at the end. Counts against the part's limit, its declared size and the
 * package's inflate cap. */
/* libzip's decompression layer (compress_read): inflate into data until len bytes, the stream's
 * end, or an error (the failing call's output dropped); the input read PKG_RAW_IN bytes at a time.
 * Bytes, 0 at the end, -1 on an error (in r->err). */
static zip_int64_t raw_process(raw_inflate *r, zip_file_t *f, uint8_t *data, size_t len)
{
    if (r->failed) return -1;
    if (len == 0 || r->end_of_stream) return 0;
    size_t out = 0;
    int end = 0;
    while (!end && out < len) {
        r->z.next_out = data + out;
        r->z.avail_out = (uInt)HV_MIN(len - out, (size_t)UINT_MAX);
        uInt avail = r->z.avail_out;
        int ret = inflate(&r->z, Z_SYNC_FLUSH);
        size_t made = avail - r->z.avail_out;
        if (ret == Z_OK || ret == Z_STREAM_END || (ret == Z_BUF_ERROR && r->z.avail_in == 0)) out += made;
        if (ret == Z_STREAM_END) {
            r->end_of_stream = 1;
            end = 1;
        } else if (ret == Z_BUF_ERROR && r->z.avail_in == 0) { /* needs input */
            if (r->end_of_input) {
                end = 1; /* the stream stops short: the CRC tells */
                continue;
            }
            zip_int64_t n = zip_fread(f, r->in, sizeof r->in);
            if (n < 0) {
                zip_error_set(&r->err, zip_error_code_zip(zip_file_get_error(f)), zip_error_code_system(zip_file_get_error(f)));
                r->failed = 1;
                end = 1;
            } else if (n == 0)
                r->end_of_input = 1;
            else {
                r->z.next_in = r->in;
                r->z.avail_in = (uInt)n;
            }
        } else if (ret != Z_OK) {
            zip_error_set(&r->err, ZIP_ER_ZLIB, ret);
            r->failed = 1;
            end = 1;
        }
    }
    if (out > 0) return (zip_int64_t)out;
    return r->failed ? -1 : 0;
}

/* zip_fread over libzip's decompression and CRC layers: the buffer filled from raw_process, its
 * CRC kept, checked against the directory's at the end. */
static zip_int64_t raw_read(raw_inflate *r, zip_file_t *f, void *buf, size_t cap)
{
    if (r->failed) return -1;
    if (r->eof || cap == 0) return 0;
    size_t got = 0;
    while (got < cap) {
        zip_int64_t n = raw_process(r, f, (uint8_t *)buf + got, cap - got);
        if (n < 0) return got ? (zip_int64_t)got : -1;
        if (n == 0) {
            if (r->check_crc && r->crc != r->want_crc) {
                zip_error_set(&r->err, ZIP_ER_CRC, 0);
                r->failed = 1;
                return got ? (zip_int64_t)got : -1;
            }
            r->eof = 1;
            break;
        }
        r->crc = (uint32_t)libdeflate_crc32(r->crc, (const uint8_t *)buf + got, (size_t)n);
        got += (size_t)n;
    }
    return (zip_int64_t)got;
}

static hv_status inflate_count(inflater *in, size_t n);

static hv_status inflate_read(inflater *in, void *buf, size_t cap, size_t *got)
{
    *got = 0;
    zip_int64_t n = in->raw ? raw_read(in->raw, in->f, buf, cap) : zip_fread(in->f, buf, cap);
    char q[96];
    if (n < 0)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: part '/%s' is damaged (libzip: %s)", in->pk->name,
                            hv_quote(q, sizeof q, in->part, strlen(in->part)),
                            in->raw ? zip_error_strerror(&in->raw->err) : zip_file_strerror(in->f));
    *got = (size_t)n;
    return inflate_count(in, (size_t)n);
}

/* n more bytes inflated: counted against the part's limit, its declared size and the package's
 * inflate cap. */
static hv_status inflate_count(inflater *in, size_t n)
{
    char q[96];
    in->bytes += (uint64_t)n;
    in->pk->inflated += (uint64_t)n;
    if (in->bytes > in->declared)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: part '/%s' inflates past the %llu bytes the ZIP declares", in->pk->name,
                            hv_quote(q, sizeof q, in->part, strlen(in->part)), (unsigned long long)in->declared);
    if (in->bytes > in->limit || in->pk->inflated > in->pk->inflate_cap) {
        char b[32];
        return hv_error_set(HV_ERR_LIMIT, "%s: part '/%s' expands to more than %s", in->pk->name,
                            hv_quote(q, sizeof q, in->part, strlen(in->part)),
                            hv_size_text(b, sizeof b, (double)HV_MIN(in->limit, in->pk->inflate_cap)));
    }
    return HV_OK;
}

static void inflate_close(inflater *in)
{
    if (in->f) zip_fclose(in->f);
    in->f = NULL;
    if (in->raw) {
        inflateEnd(&in->raw->z);
        zip_error_fini(&in->raw->err);
        free(in->raw);
        in->raw = NULL;
    }
}

hv_status tmf_pkg_read(tmf_pkg *pk, const char *part, uint64_t limit, uint8_t **data, size_t *size)
{
    *data = NULL;
    *size = 0;
    zip_int64_t i = locate(pk, part, 1);
    char q[96];
    if (i < 0)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: part '/%s' is missing from the package", pk->name,
                            hv_quote(q, sizeof q, part, strlen(part)));
    inflater in;
    hv_status s = inflate_open(pk, i, part, limit, &in);
    if (s != HV_OK) return s;
    size_t cap = (size_t)HV_MIN(in.declared, (uint64_t)HV_MIN(limit, (uint64_t)SIZE_MAX / 2));
    uint8_t *buf = hv_malloc(cap + 1);
    if (!buf) s = HV_ERR_NOMEM;
    size_t len = 0, got = 0;
    while (s == HV_OK) {
        if (len == cap) { /* at the declared size: one more byte means it lied */
            uint8_t one;
            if ((s = inflate_read(&in, &one, 1, &got)) == HV_OK && got) s = HV_ERR_BAD_INPUT; /* unreachable: counted */
            break;
        }
        if ((s = inflate_read(&in, buf + len, cap - len, &got)) != HV_OK || got == 0) break;
        len += got;
    }
    inflate_close(&in);
    if (s != HV_OK) {
        free(buf);
        return s;
    }
    *data = buf;
    *size = len;
    return HV_OK;
}

/* ---- chunks for the parser: a large part inflates on a thread of its own ---------------------
 * Inflating took a quarter of a 1M-facet model's read, parsing the rest: the inflater thread
 * fills a ring of PKG_RING chunks while the parser reads the one before (issue 26 item 2). The
 * parser sees the same chunks, and an error of the inflater (its message carried over from its
 * thread) at the same place, as when it inflates them itself. */
typedef struct feed {
    inflater *in;
    uint8_t *whole; /* the part inflated in one call (one thread), handed out a chunk at a time */
    size_t whole_len, whole_at;
    int counted; /* the whole part is counted against its limits already (pull_parse) */
    char *buf[PKG_RING];
    size_t len[PKG_RING];
    size_t head, tail; /* chunks filled and not yet parsed: [head, tail) */
    int threaded, started, stop, end; /* end: no chunk will follow tail */
    hv_status status;                 /* the inflater's, at the end */
    char msg[1024];
    pthread_t thread;
    pthread_mutex_t mu;
    pthread_cond_t cv;
} feed;

static void *feed_main(void *arg)
{
    feed *f = arg;
    for (;;) {
        pthread_mutex_lock(&f->mu);
        while (f->tail - f->head == PKG_RING && !f->stop) pthread_cond_wait(&f->cv, &f->mu);
        int stop = f->stop;
        size_t slot = f->tail % PKG_RING;
        pthread_mutex_unlock(&f->mu);
        if (stop) return NULL;
        size_t got = 0;
        hv_status s = inflate_read(f->in, f->buf[slot], PKG_CHUNK, &got);
        pthread_mutex_lock(&f->mu);
        if (s != HV_OK) {
            f->status = s;
            snprintf(f->msg, sizeof f->msg, "%s", hv_last_error());
            f->end = 1;
        } else {
            f->len[slot] = got;
            f->tail++;
            f->end = got == 0;
        }
        pthread_cond_signal(&f->cv);
        pthread_mutex_unlock(&f->mu);
        if (f->end) return NULL;
    }
}

/* The part's raw stream opened again at its start. 0: it cannot be (feed_open says so). */
static int reread(inflater *in)
{
    zip_fclose(in->f);
    in->f = zip_fopen_index(in->pk->zip, (zip_uint64_t)in->index, ZIP_FL_COMPRESSED);
    return in->f != NULL;
}

/* The compressed bytes of a part of a package in memory, where they lie (a 1M-facet model's 16 MB
 * not copied: issue 26). libzip reads a compressed part through a window on the package's source,
 * so once it has handed out the first bytes the source's position says where they start; used
 * only when those bytes are there, and libdeflate and the CRC check the rest (or the part
 * streams). NULL: read them (reread first). */
static const uint8_t *in_place(inflater *in, zip_int64_t *n)
{
    tmf_pkg *pk = in->pk;
    uint8_t head[64];
    zip_int64_t k = (zip_int64_t)HV_MIN(in->comp_size, (uint64_t)sizeof head);
    if (!pk->data || zip_fread(in->f, head, (zip_uint64_t)k) != k) return NULL;
    zip_int64_t at = zip_source_tell(pk->src) - k;
    if (at < 0 || (uint64_t)at + in->comp_size > pk->size || memcmp(pk->data + at, head, (size_t)k) != 0) return NULL;
    *n = (zip_int64_t)in->comp_size;
    return pk->data + at;
}

/* One thread: a deflated part of PKG_THREAD_FLOOR bytes or more, within its limits, inflates in one
 * libdeflate call (two to three times zlib's speed: issue 26 item 2) into a buffer the parser then
 * reads. The whole part must be good: the stream inflates to at most its declared size and its
 * CRC is the directory's. Anything else (a damaged part, no memory) and the part streams from its
 * start through zlib as before, so the parser sees the same bytes and the same error. 1: done. */
static int feed_whole(feed *f)
{
    inflater *in = f->in;
    tmf_pkg *pk = in->pk;
    if (!in->raw || in->declared < PKG_THREAD_FLOOR || in->declared == UINT64_MAX || in->declared > in->limit ||
        in->declared > pk->inflate_cap - HV_MIN(pk->inflated, pk->inflate_cap) || in->comp_size == 0 ||
        in->comp_size > in->declared + 1024)
        return 0;
    uint8_t *out = hv_malloc_big((size_t)in->declared + 1, 1); /* + the NUL libxml2 reads at the end */
    struct libdeflate_decompressor *d = out ? libdeflate_alloc_decompressor() : NULL;
    uint8_t *comp = NULL;
    zip_int64_t n = -1;
    const uint8_t *src = d ? in_place(in, &n) : NULL;
    if (d && !src && reread(in) && (comp = hv_malloc_big((size_t)in->comp_size, 1)) != NULL)
        n = zip_fread(in->f, comp, in->comp_size), src = comp;
    int ok = src != NULL;
    size_t used = 0, made = 0;
    ok = ok && n > 0 &&
         libdeflate_deflate_decompress_ex(d, src, (size_t)n, out, (size_t)in->declared, &used, &made) == LIBDEFLATE_SUCCESS &&
         (!in->raw->check_crc || (uint32_t)libdeflate_crc32(0, out, made) == in->raw->want_crc);
    libdeflate_free_decompressor(d);
    free(comp);
    if (ok) {
        out[made] = 0;
        f->whole = out;
        f->whole_len = made;
        return 1;
    }
    free(out);
    reread(in); /* from the start: the raw stream again */
    return 0;
}

/* A thread only for a part of PKG_THREAD_FLOOR bytes or more, when hovox may use two threads. */
static hv_status feed_open(feed *f, inflater *in)
{
    memset(f, 0, sizeof *f);
    f->in = in;
    if (feed_whole(f)) return HV_OK; /* one thread: pulled; several: pushed, its bulk elements read ahead */
    if (!in->f) {
        char q[96];
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: part '/%s' cannot be read (libzip: %s)", in->pk->name,
                            hv_quote(q, sizeof q, in->part, strlen(in->part)), zip_strerror(in->pk->zip));
    }
    int n = in->declared >= PKG_THREAD_FLOOR && in->declared != UINT64_MAX && hv_threads() > 1 ? PKG_RING : 1;
    for (int i = 0; i < n; ++i)
        if (!(f->buf[i] = hv_malloc(PKG_CHUNK))) return HV_ERR_NOMEM;
    if (n == 1 || pthread_mutex_init(&f->mu, NULL) != 0) return HV_OK;
    if (pthread_cond_init(&f->cv, NULL) != 0) {
        pthread_mutex_destroy(&f->mu);
        return HV_OK;
    }
    f->threaded = 1;
    f->started = pthread_create(&f->thread, NULL, feed_main, f) == 0;
    if (!f->started) { /* inflate on this thread, then */
        pthread_cond_destroy(&f->cv);
        pthread_mutex_destroy(&f->mu);
        f->threaded = 0;
    }
    return HV_OK;
}

/* The next chunk (*len 0: the part's end); feed_done once it is parsed. */
static hv_status feed_next(feed *f, const char **data, size_t *len)
{
    if (f->whole) {
        *len = HV_MIN(f->whole_len - f->whole_at, (size_t)PKG_CHUNK);
        *data = (const char *)f->whole + f->whole_at;
        f->whole_at += *len;
        return f->counted ? HV_OK : inflate_count(f->in, *len);
    }
    if (!f->threaded) {
        *data = f->buf[0];
        return inflate_read(f->in, f->buf[0], PKG_CHUNK, len);
    }
    pthread_mutex_lock(&f->mu);
    while (f->head == f->tail && !f->end) pthread_cond_wait(&f->cv, &f->mu);
    hv_status s = HV_OK;
    if (f->head == f->tail) s = hv_error_set(f->status, "%s", f->msg);
    else {
        *data = f->buf[f->head % PKG_RING];
        *len = f->len[f->head % PKG_RING];
    }
    pthread_mutex_unlock(&f->mu);
    return s;
}

static void feed_done(feed *f)
{
    if (!f->threaded) return;
    pthread_mutex_lock(&f->mu);
    f->head++;
    pthread_cond_signal(&f->cv);
    pthread_mutex_unlock(&f->mu);
}

static void feed_close(feed *f)
{
    if (f->threaded) {
        pthread_mutex_lock(&f->mu);
        f->stop = 1;
        pthread_cond_signal(&f->cv);
        pthread_mutex_unlock(&f->mu);
        pthread_join(f->thread, NULL);
        pthread_cond_destroy(&f->cv);
        pthread_mutex_destroy(&f->mu);
    }
    for (int i = 0; i < PKG_RING; ++i) free(f->buf[i]);
    free(f->whole);
}

/* ---- XML ---------------------------------------------------------------------------------- */

struct tmf_xml {
    tmf_pkg *pk;
    const char *part;
    xmlParserCtxtPtr ctxt;
    const tmf_xml_handler *h;
    void *ctx;
    hv_status status;
    int depth;
    const xmlChar *prefix, *local; /* the element being read (the parser's dictionary holds them) */
    int qname_stale; /* qname is not yet theirs */
    char qname[160]; /* the element being read, as written (prefix:local), made when asked */
    int collect;     /* its text is wanted (tmf_xml_collect_text) */
    hv_buf text;
    char xml_error[400];
    int err_line, err_col;
    /* a whole part parsed by pull_parse, then again by push (its replay): */
    uint64_t seen;       /* elements' starts and ends so far */
    uint64_t failed_at;  /* the one whose start or end failed (0: none) */
    uint64_t replay;     /* the replay hands the first `replay` of them to no one */
    int collect_after;   /* `collect` after the last one handled well */
    int restart;         /* not UTF-8: parsed by push from its start, as if pull_parse had not been */
    int pulling;         /* pull_parse is parsing */
    hv_status fail;      /* the replay raises this at failed_at, with fail_msg */
    char fail_msg[2048];
    /* tmf_xml_bulk: the element whose children may be read ahead, while it is open */
    feed *whole;         /* the part, lying whole in memory and pushed from there (else NULL) */
    tmf_bulk bulk;
    int bulk_depth;      /* its depth (0: none) */
    int bulk_asked;      /* asked and not yet tried */
    char bulk_qname[160];
};

tmf_pkg *tmf_xml_pkg(tmf_xml *x) { return x->pk; }


const char *tmf_xml_lookup_ns(const tmf_xml *x, const char *prefix)
{
    /* the parser's namespace stack: (prefix, URI) pairs, innermost last */
    for (int i = x->ctxt ? x->ctxt->nsNr - 2 : -2; i >= 0; i -= 2) {
        const char *p = (const char *)x->ctxt->nsTab[i];
        if (p && strcmp(p, prefix) == 0) return (const char *)x->ctxt->nsTab[i + 1];
    }
    return NULL;
}

static void on_text(void *ctx, const xmlChar *ch, int len);

/* Text is handed to on_text only while an element's text is wanted: the blanks between a
 * million elements otherwise cost a call each (issue 26 item 2). */
static void want_text(tmf_xml *x, int on)
{
    x->collect = on;
    if (x->ctxt && x->ctxt->sax) x->ctxt->sax->characters = x->ctxt->sax->cdataBlock = on ? on_text : NULL;
}

void tmf_xml_collect_text(tmf_xml *x)
{
    want_text(x, 1);
    x->text.len = 0;
}

const char *tmf_xml_text(const tmf_xml *x) { return x->text.data && x->text.len ? x->text.data : ""; }

void tmf_xml_where(const tmf_xml *x, int *line, int *col)
{
    *line = x->ctxt ? xmlSAX2GetLineNumber(x->ctxt) : 0;
    *col = x->ctxt ? xmlSAX2GetColumnNumber(x->ctxt) : 0;
}

hv_status tmf_xml_vbad(tmf_xml *x, hv_status code, const char *fmt, va_list ap)
{
    char msg[1024];
    vsnprintf(msg, sizeof msg, fmt, ap);
    int line, col;
    tmf_xml_where(x, &line, &col);
    return hv_error_set(code, "%s: %s: line %d, column %d: %s", x->pk->name, x->part, line, col, msg);
}

hv_status tmf_xml_bad(tmf_xml *x, hv_status code, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    hv_status s = tmf_xml_vbad(x, code, fmt, ap);
    va_end(ap);
    return s;
}

static void stop(tmf_xml *x, hv_status s)
{
    if (x->status == HV_OK) x->status = s;
    xmlStopParser(x->ctxt);
}

/* The element's qualified name, [prefix:]local, cut to the buffer, made only when asked (for a
 * message): made for every element, copies took 5-8% of a 1M-facet model's read (issue 26 item 2). */
static void set_qname(tmf_xml *x, const xmlChar *prefix, const xmlChar *local)
{
    x->prefix = prefix;
    x->local = local;
    x->qname_stale = 1;
}

const char *tmf_xml_qname(tmf_xml *x)
{
    if (!x->qname_stale) return x->qname;
    x->qname_stale = 0;
    const xmlChar *prefix = x->prefix, *local = x->local ? x->local : (const xmlChar *)"";
    size_t cap = sizeof x->qname - 1, at = 0;
    if (prefix) {
        size_t n = strlen((const char *)prefix);
        n = n < cap ? n : cap;
        memcpy(x->qname, prefix, n);
        at = n;
        if (at < cap) x->qname[at++] = ':';
    }
    size_t n = strlen((const char *)local);
    n = n < cap - at ? n : cap - at;
    memcpy(x->qname + at, local, n);
    x->qname[at + n] = 0;
    return x->qname;
}

/* An element's start or end failed: where, then the parse stops. */
static void fail(tmf_xml *x, hv_status s)
{
    if (x->status == HV_OK) x->failed_at = x->seen;
    stop(x, s);
}

/* pull_parse's replay: 1 when this start or end goes to no handler, being one the handler had
 * (after the last of them its element's text is collected again if the handler asked for it)
 * or the one it failed at (the error raised again). */
static int replayed(tmf_xml *x)
{
    if (x->seen <= x->replay) {
        if (x->seen == x->replay && x->collect_after) {
            want_text(x, 1);
            x->text.len = 0;
        }
        return 1;
    }
    if (x->fail == HV_OK || x->seen != x->failed_at) return 0;
    stop(x, hv_error_set(x->fail, "%s", x->fail_msg));
    return 1;
}

/* SAX2 with these callbacks and no other. */
static void sax_init(xmlSAXHandler *sax, startElementNsSAX2Func start, endElementNsSAX2Func end, xmlStructuredErrorFunc error)
{
    memset(sax, 0, sizeof *sax);
    sax->initialized = XML_SAX2_MAGIC;
    sax->startElementNs = start;
    sax->endElementNs = end;
    sax->serror = error;
}

/* libxml2's attributes (local, prefix, URI, value, end: five pointers each) as tmf_attr. */
static void attrs_of(const xmlChar **attrs, int n, tmf_attr *a)
{
    for (int i = 0; i < n; ++i) {
        const xmlChar **t = attrs + 5 * i;
        a[i].local = (const char *)t[0];
        a[i].uri = (const char *)t[2];
        a[i].value = (const char *)t[3];
        a[i].len = (size_t)(t[4] - t[3]);
    }
}

static void on_start(void *ctx, const xmlChar *local, const xmlChar *prefix, const xmlChar *uri, int nns,
                     const xmlChar **ns, int nattrs, int ndefaulted, const xmlChar **attrs)
{
    (void)prefix, (void)nns, (void)ns, (void)ndefaulted;
    tmf_xml *x = ctx;
    if (x->status != HV_OK) return;
    x->seen++;
    if (++x->depth > PKG_MAX_DEPTH) {
        fail(x, tmf_xml_bad(x, HV_ERR_BAD_INPUT, "elements nested more than %d deep", PKG_MAX_DEPTH));
        return;
    }
    if (nattrs > PKG_MAX_ATTRS) {
        fail(x, tmf_xml_bad(x, HV_ERR_BAD_INPUT, "<%s> has %d attributes, more than %d", (const char *)local, nattrs,
                            PKG_MAX_ATTRS));
        return;
    }
    set_qname(x, prefix, local);
    if (x->collect) want_text(x, 0);
    if (replayed(x)) return;
    tmf_attr a[PKG_MAX_ATTRS];
    attrs_of(attrs, nattrs, a);
    hv_status s = x->h->start ? x->h->start(x->ctx, x, (const char *)local, (const char *)uri, a, nattrs) : HV_OK;
    if (s == HV_OK) x->collect_after = x->collect;
    else fail(x, s);
}

static void on_end(void *ctx, const xmlChar *local, const xmlChar *prefix, const xmlChar *uri)
{
    tmf_xml *x = ctx;
    if (x->status != HV_OK) return;
    x->seen++;
    if (x->depth == x->bulk_depth) x->bulk_depth = x->bulk_asked = 0;
    x->depth--;
    set_qname(x, prefix, local);
    if (replayed(x)) return;
    hv_status s = x->h->end ? x->h->end(x->ctx, x, (const char *)local, (const char *)uri) : HV_OK;
    if (x->collect) want_text(x, 0);
    if (s == HV_OK) x->collect_after = x->collect;
    else fail(x, s);
}

#define PKG_MAX_TEXT ((size_t)64 << 20)

static void on_text(void *ctx, const xmlChar *ch, int len)
{
    tmf_xml *x = ctx;
    if (x->status != HV_OK || !x->collect || len <= 0) return;
    if (x->text.len + (size_t)len > PKG_MAX_TEXT) {
        stop(x, tmf_xml_bad(x, HV_ERR_LIMIT, "<%s> holds more than 64 MiB of text", tmf_xml_qname(x)));
        return;
    }
    hv_buf_append(&x->text, (const char *)ch, (size_t)len);
    if (x->text.failed) stop(x, HV_ERR_NOMEM);
}

/* A DOCTYPE is where entities are declared (XXE, billion laughs): refused before its subset. */
static void on_doctype(void *ctx, const xmlChar *name, const xmlChar *ext, const xmlChar *sys)
{
    (void)name, (void)ext, (void)sys;
    tmf_xml *x = ctx;
    if (x->status == HV_OK) stop(x, tmf_xml_bad(x, HV_ERR_BAD_INPUT, "a DOCTYPE is not allowed in a 3MF part"));
}

static void on_error(void *ctx, xmlErrorPtr e)
{
    tmf_xml *x = ctx;
    if (x->xml_error[0] || !e || e->level < XML_ERR_ERROR) return;
    snprintf(x->xml_error, sizeof x->xml_error, "%s", e->message ? e->message : "malformed XML");
    size_t n = strlen(x->xml_error);
    while (n > 0 && (x->xml_error[n - 1] == '\n' || x->xml_error[n - 1] == ' ')) x->xml_error[--n] = '\0';
    x->err_line = e->line;
    x->err_col = e->int2;
    /* pull_parse: the push parser takes the part from its start; the pull parser would go on
     * past a fatal error without SAX (a DOCTYPE's entities declared, the rest read for nothing) */
    if (x->pulling) xmlStopParser(x->ctxt);
}

static pthread_once_t g_xml_once = PTHREAD_ONCE_INIT;
static void xml_init(void) { xmlInitParser(); }

static void xml_silent(void *ctx, const char *fmt, ...)
{
    (void)ctx;
    (void)fmt;
}

void tmf_xml_quiet_begin(tmf_xml_quiet *q)
{
    pthread_once(&g_xml_once, xml_init);
    q->ctx = xmlGenericErrorContext;
    q->fn = xmlGenericError;
    xmlSetGenericErrorFunc(NULL, xml_silent);
}

void tmf_xml_quiet_end(const tmf_xml_quiet *q) { xmlSetGenericErrorFunc(q->ctx, q->fn); }

#define PKG_XML_OPTIONS (XML_PARSE_NONET | XML_PARSE_BIG_LINES | XML_PARSE_NOCDATA)

/* One chunk to the push parser (terminate: the last): the handler's status, else the XML error. */
static hv_status push_chunk(tmf_xml *x, const char *data, size_t len, int terminate)
{
    int rc = xmlParseChunk(x->ctxt, data, (int)len, terminate);
    if (x->status != HV_OK) return x->status;
    if (rc != 0 || x->xml_error[0] || x->ctxt->disableSAX)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: %s: line %d, column %d: malformed XML: %s", x->pk->name, x->part,
                            x->err_line, x->err_col, x->xml_error[0] ? x->xml_error : "the parser stopped");
    return HV_OK;
}

/* ---- bulk: a run of like children read ahead on other threads (tmf_xml_bulk) ----------------
 * The element's content from where the parser has been fed to about its end (bulk_reach) is cut at '<'
 * into one share per thread. The parser goes on through the first share itself; every other is
 * parsed by a push parser of its own, inside a copy of the element's start tag that declares the
 * namespaces in scope (nsTab), handing each child to the bulk's item function. The cuts are
 * checked, not trusted: the parser must stand in the element's content at the first cut with
 * nothing but blanks unparsed (not in a comment, a CDATA section or a child), and each piece must
 * be well-formed content made only of children taken, which it cannot be if its cut fell inside
 * markup. The pieces taken are merged in order, the parser's line and column set where the bytes
 * skipped would have left them, and it goes on from the first piece not taken, or from the
 * element's end tag where a piece met it. */
#ifndef PKG_BULK_SHARE /* (defined otherwise only by the differential check: every bulk element cut) */
#define PKG_BULK_SHARE ((size_t)1 << 20) /* bytes of children worth a thread */
#endif
#define PKG_BULK_MAX 64                  /* pieces */
#define PKG_PIECE_CHUNK 262144

static _Atomic uint64_t g_bulk_merged;
uint64_t tmf_xml_bulk_merged(void) { return g_bulk_merged; }

void tmf_xml_bulk(tmf_xml *x, const tmf_bulk *b)
{
    const xmlParserCtxtPtr c = x->ctxt;
    if (!x->whole || x->pulling || x->collect || x->status != HV_OK || hv_threads() < 2 || !c->input || !c->input->buf ||
        c->input->buf->encoder) /* the bytes the parser reads are not the part's */
        return;
    x->bulk = *b;
    x->bulk_depth = x->depth;
    x->bulk_asked = 1;
    snprintf(x->bulk_qname, sizeof x->bulk_qname, "%s", tmf_xml_qname(x));
}

typedef struct piece {
    const tmf_bulk *b;
    const uint8_t *from, *to;
    const char *open; /* the element's start tag, namespaces declared */
    size_t open_len;
    const char *close;
    size_t close_len;
    xmlParserCtxtPtr ctxt;
    const xmlChar *child; /* the children's name in this parser's dictionary, once seen */
    int depth, ok, started;
    const uint8_t *end;  /* where the element's own end tag closed the piece (NULL: our copy did) */
    const uint8_t *stop; /* the children taken end here: `to`, `end`, or a child not taken */
    uint8_t *items;
    size_t count, cap;
    uint64_t lines, tail; /* newlines in [from, to), characters after the last (or all) */
    pthread_t thread;
} piece;

static void piece_bail(piece *p)
{
    p->ok = 0;
    xmlStopParser(p->ctxt);
}

/* The piece's byte where its parser stands (the copy of the start tag before it aside); NULL
 * outside the piece's own bytes. */
static const uint8_t *piece_here(const piece *p)
{
    const xmlParserInputPtr in = p->ctxt->input;
    size_t past = (size_t)in->consumed + (size_t)(in->cur - in->base);
    if (past <= p->open_len || past - p->open_len > (size_t)(p->to - p->from)) return NULL;
    return p->from + (past - p->open_len);
}

/* A child the piece does not take, just read: the piece ends before it, where it starts (found
 * back from the parser's place within its start tag: no '<' in names and attribute values). */
static void piece_stop(piece *p)
{
    const uint8_t *q = piece_here(p);
    while (q && q > p->from && q[-1] != '<') --q;
    if (!q || q == p->from) {
        piece_bail(p);
        return;
    }
    p->stop = q - 1;
    xmlStopParser(p->ctxt);
}

static void piece_start(void *ctx, const xmlChar *local, const xmlChar *prefix, const xmlChar *uri, int nns,
                        const xmlChar **ns, int nattrs, int ndefaulted, const xmlChar **attrs)
{
    (void)prefix, (void)ns;
    piece *p = ctx;
    if (!p->ok || p->depth++ == 0) return; /* the copy of the element's start tag */
    if (p->depth > 2) { /* inside a child: where that child starts is not known */
        piece_bail(p);
        return;
    }
    const tmf_bulk *b = p->b;
    if (local != p->child && !p->child && strcmp((const char *)local, b->child) == 0) p->child = local;
    if (local != p->child || nns || ndefaulted || nattrs != b->nattrs || nattrs > PKG_MAX_ATTRS) {
        piece_stop(p);
        return;
    }
    if (p->count == p->cap) {
        size_t cap = p->cap ? 2 * p->cap : 4096;
        uint8_t *q = hv_realloc_big(p->items, cap * b->item_size);
        if (!q) {
            piece_bail(p);
            return;
        }
        p->items = q;
        p->cap = cap;
    }
    tmf_attr a[PKG_MAX_ATTRS];
    attrs_of(attrs, nattrs, a);
    (void)uri;
    if (b->item(b->arg, a, nattrs, p->items + p->count * b->item_size)) p->count++;
    else piece_stop(p);
}

/* The element's own end tag within the piece closes it there: the children before it are the
 * piece's, the parser goes on from that tag (found back from just past it: it holds no '<'). */
static void piece_end(void *ctx, const xmlChar *local, const xmlChar *prefix, const xmlChar *uri)
{
    (void)local, (void)prefix, (void)uri;
    piece *p = ctx;
    if (--p->depth > 0 || !p->ok) return;
    const uint8_t *q = piece_here(p);
    if (!q) return; /* our copy's end tag */
    while (q > p->from && q[-1] != '<') --q;
    if (q == p->from || q[0] != '/') {
        piece_bail(p);
        return;
    }
    p->end = p->stop = q - 1;
    xmlStopParser(p->ctxt);
}

static void piece_error(void *ctx, xmlErrorPtr e)
{
    piece *p = ctx;
    if (e && e->level >= XML_ERR_ERROR && p->ok) piece_bail(p);
}

/* Newlines in [from, stop) and the characters (UTF-8 sequences) after the last, as libxml2 counts
 * lines and columns. */
static void piece_lines(piece *p)
{
    const uint8_t *at = p->from, *last = NULL;
    for (const uint8_t *q; (q = memchr(at, '\n', (size_t)(p->stop - at))) != NULL; at = q + 1) {
        p->lines++;
        last = q;
    }
    for (const uint8_t *c = last ? last + 1 : p->from; c < p->stop; ++c) p->tail += (*c & 0xC0) != 0x80;
}

static void *piece_main(void *arg)
{
    piece *p = arg;
    tmf_xml_quiet quiet;
    tmf_xml_quiet_begin(&quiet); /* libxml2's generic error function is the thread's own */
    xmlSAXHandler sax;
    sax_init(&sax, piece_start, piece_end, piece_error);
    p->ctxt = xmlCreatePushParserCtxt(&sax, p, NULL, 0, NULL);
    if (p->ctxt) {
        xmlCtxtUseOptions(p->ctxt, PKG_XML_OPTIONS);
        p->ok = 1;
        int rc = xmlParseChunk(p->ctxt, p->open, (int)p->open_len, 0);
        for (const uint8_t *at = p->from; rc == 0 && p->ok && !p->stop && at < p->to;) {
            size_t n = HV_MIN((size_t)(p->to - at), (size_t)PKG_PIECE_CHUNK);
            rc = xmlParseChunk(p->ctxt, (const char *)at, (int)n, 0);
            at += n;
        }
        if (rc == 0 && p->ok && !p->stop) rc = xmlParseChunk(p->ctxt, p->close, (int)p->close_len, 1);
        /* whole: to its end, well-formed; stopped: at a child not taken or the element's end */
        p->ok = p->ok && (p->stop ? 1 : rc == 0 && p->ctxt->wellFormed && !p->ctxt->disableSAX && p->depth == 0);
        if (p->ctxt->myDoc) xmlFreeDoc(p->ctxt->myDoc);
        xmlFreeParserCtxt(p->ctxt);
        p->ctxt = NULL;
    }
    if (!p->stop) p->stop = p->to;
    if (p->ok) piece_lines(p);
    tmf_xml_quiet_end(&quiet);
    return NULL;
}

/* The element's start tag again, with every namespace in scope declared (the last binding of
 * each prefix), for a piece's parser; NULL when it cannot be written plainly. */
static char *bulk_open_tag(const tmf_xml *x, size_t *len)
{
    hv_buf b;
    hv_buf_init(&b);
    hv_buf_printf(&b, "<%s", x->bulk_qname);
    const xmlParserCtxtPtr c = x->ctxt;
    for (int i = c->nsNr - 2; i >= 0; i -= 2) {
        const xmlChar *prefix = c->nsTab[i], *url = c->nsTab[i + 1];
        int shadowed = 0;
        for (int j = i + 2; j < c->nsNr && !shadowed; j += 2) shadowed = c->nsTab[j] == prefix;
        if (shadowed || !url) continue;
        if (strpbrk((const char *)url, "&<\"") != NULL) {
            hv_buf_free(&b);
            return NULL;
        }
        if (prefix) hv_buf_printf(&b, " xmlns:%s=\"%s\"", (const char *)prefix, (const char *)url);
        else hv_buf_printf(&b, " xmlns=\"%s\"", (const char *)url);
    }
    hv_buf_puts(&b, ">");
    if (b.failed) {
        hv_buf_free(&b);
        return NULL;
    }
    *len = b.len;
    return b.data;
}

/* 1 when the first tag at or after `at` starts a child: '<', a prefix maybe, the child's name. */
static int child_next(const uint8_t *data, size_t at, size_t len, const char *child)
{
    const uint8_t *q = memchr(data + at, '<', len - at);
    if (!q) return 0;
    size_t k = strlen(child), i = 1, left = (size_t)(data + len - q);
    for (size_t j = 1; j < left && j < 64 && q[j] != ' ' && q[j] != '/' && q[j] != '>'; ++j)
        if (q[j] == ':') i = j + 1;
    return i + k < left && memcmp(q + i, child, k) == 0 &&
           (q[i + k] == ' ' || q[i + k] == '\t' || q[i + k] == '\n' || q[i + k] == '\r' || q[i + k] == '/' || q[i + k] == '>');
}

/* Where the element's run of children ends, about: halving the rest of the part while a child
 * follows the middle, then the next '<' (0: no child follows `from`). A guess, not trusted:
 * pieces past the true end are not taken, and the piece holding it ends there (piece_end). */
static size_t bulk_reach(const uint8_t *data, size_t from, size_t len, const char *child)
{
    if (!child_next(data, from, len, child)) return 0;
    size_t lo = from, hi = len;
    while (hi - lo > 4096) {
        size_t mid = lo + (hi - lo) / 2;
        if (child_next(data, mid, len, child)) lo = mid;
        else hi = mid;
    }
    const uint8_t *q = memchr(data + hi, '<', len - hi);
    return q ? (size_t)(q - data) : len;
}

static int blanks_only(const xmlChar *p, const xmlChar *e)
{
    for (; p < e; ++p)
        if (*p != ' ' && *p != '\t' && *p != '\r' && *p != '\n') return 0;
    return 1;
}

/* The parser where the bytes skipped would have left it. The blanks it holds unparsed (before
 * the first cut) are parsed first, ended by an empty comment (no handler sees comments); then
 * its line and column are set past the skipped newlines and the characters after the last. */
static hv_status skip_lines(tmf_xml *x, uint64_t lines, uint64_t tail)
{
    static const char mark[] = "<!---->";
    hv_status s = push_chunk(x, mark, sizeof mark - 1, 0);
    if (s != HV_OK) return s;
    xmlParserInputPtr in = x->ctxt->input;
    if (lines > 0) {
        in->line += (int)lines;
        in->col = (int)tail + 1;
    } else
        in->col += (int)tail - (int)(sizeof mark - 1);
    return HV_OK;
}

/* The parser stands in the bulk element's content, nothing but blanks unparsed, fit to skip. */
static int bulk_standing(const tmf_xml *x)
{
    const xmlParserCtxtPtr c = x->ctxt;
    return x->status == HV_OK && !x->xml_error[0] && !c->disableSAX && c->instate == XML_PARSER_CONTENT &&
           x->bulk_depth != 0 && x->depth == x->bulk_depth && c->input && c->input->buf && !c->input->buf->encoder &&
           blanks_only(c->input->cur, c->input->end);
}

static hv_status bulk_run(tmf_xml *x, feed *f)
{
    const uint8_t *data = f->whole;
    size_t len = f->whole_len, from = f->whole_at;
    size_t e = bulk_reach(data, from, len, x->bulk.child);
    size_t span = e > from ? e - from : 0;
    int n = (int)HV_MIN((size_t)HV_MIN(hv_threads(), PKG_BULK_MAX), span / PKG_BULK_SHARE);
    if (n < 2) return HV_OK;
    size_t cut[PKG_BULK_MAX + 1];
    int m = 0; /* cuts: cut[0] ends the parser's share, cut[m] = e */
    for (int i = 1; i < n; ++i) {
        size_t at = from + span / (size_t)n * (size_t)i;
        const uint8_t *q = memchr(data + at, '<', e - at);
        at = q ? (size_t)(q - data) : e;
        if (at < e && (m == 0 || at > cut[m - 1])) cut[m++] = at;
    }
    if (m == 0) return HV_OK;
    cut[m] = e;
    size_t open_len = 0;
    char *open = bulk_open_tag(x, &open_len);
    char close[168];
    size_t close_len = (size_t)snprintf(close, sizeof close, "</%s>", x->bulk_qname);
    piece *pc = open ? hv_calloc((size_t)m, sizeof *pc) : NULL;
    if (!pc) {
        free(open);
        return HV_OK; /* parsed here as usual */
    }
    for (int i = 0; i < m; ++i) {
        piece *p = &pc[i];
        p->b = &x->bulk;
        p->from = data + cut[i];
        p->to = data + cut[i + 1];
        p->open = open;
        p->open_len = open_len;
        p->close = close;
        p->close_len = close_len;
        p->started = pthread_create(&p->thread, NULL, piece_main, p) == 0;
    }
    /* the parser's own share, to the first cut */
    hv_status s = HV_OK;
    size_t at = f->whole_at;
    while (s == HV_OK && at < cut[0]) {
        size_t k = HV_MIN(cut[0] - at, (size_t)PKG_CHUNK);
        s = push_chunk(x, (const char *)data + at, k, 0);
        at += k;
    }
    for (int i = 0; i < m; ++i)
        if (pc[i].started) pthread_join(pc[i].thread, NULL);
    /* each piece, at its cut: merged and skipped where the parser stands in the element's content
     * and the piece took children, then the rest to the next cut parsed here */
    for (int i = 0; s == HV_OK && i < m && x->bulk_depth; ++i) {
        const piece *p = &pc[i];
        if (p->started && p->ok && p->count && p->tail < (uint64_t)INT_MAX / 2 && p->lines < (uint64_t)INT_MAX / 2 &&
            bulk_standing(x) && x->bulk.merge(x->ctx, p->items, p->count)) {
            x->seen += 2 * (uint64_t)p->count;
            g_bulk_merged += p->count;
            s = skip_lines(x, p->lines, p->tail);
            at = (size_t)(p->stop - data);
            if (p->end) break; /* the element ends in it: the parser goes on from its end tag */
        }
        while (s == HV_OK && at < cut[i + 1]) {
            size_t k = HV_MIN(cut[i + 1] - at, (size_t)PKG_CHUNK);
            s = push_chunk(x, (const char *)data + at, k, 0);
            at += k;
        }
    }
    f->whole_at = at;
    for (int i = 0; i < m; ++i) free(pc[i].items);
    free(pc);
    free(open);
    return s;
}

/* The push parser fed chunk by chunk: the streamed path, a whole part on several threads (its
 * bulk elements read ahead), and a whole part pull_parse leaves to it. */
static hv_status push_parse(tmf_xml *x, feed *f, xmlSAXHandler *sax)
{
    hv_status s = HV_OK;
    x->ctxt = xmlCreatePushParserCtxt(sax, x, NULL, 0, x->part);
    if (!x->ctxt) s = HV_ERR_NOMEM;
    else xmlCtxtUseOptions(x->ctxt, PKG_XML_OPTIONS);
    if (s == HV_OK && f->whole && !f->counted && (s = inflate_count(f->in, f->whole_len)) == HV_OK) f->counted = 1;
    x->whole = f->whole && x->replay == 0 ? f : NULL;
    size_t got = 0;
    int done = 0;
    while (s == HV_OK && !done) {
        if (x->bulk_asked) {
            x->bulk_asked = 0;
            if ((s = bulk_run(x, f)) != HV_OK) break;
        }
        const char *chunk = NULL;
        if ((s = feed_next(f, &chunk, &got)) != HV_OK) break;
        done = got == 0;
        s = push_chunk(x, chunk, got, done);
        feed_done(f);
    }
    x->whole = NULL;
    if (x->ctxt) {
        if (x->ctxt->myDoc) xmlFreeDoc(x->ctxt->myDoc);
        xmlFreeParserCtxt(x->ctxt);
        x->ctxt = NULL;
    }
    return s;
}

/* pull_parse: the document's declared encoding, once its XML declaration is read. */
static void on_document(void *ctx)
{
    tmf_xml *x = ctx;
    const char *enc = (const char *)x->ctxt->encoding;
    if (x->ctxt->input->encoding || (enc && strcasecmp(enc, "UTF-8") != 0 && strcasecmp(enc, "UTF8") != 0)) {
        x->restart = 1;
        xmlStopParser(x->ctxt);
    }
}

/* A part inflated whole (one thread) parsed where it lies by libxml2's pull parser: not copied
 * into the push parser's buffer nor each tag looked ahead for (8% of libxml2's time on a 1M-facet
 * model: issue 26). The handler must get what the push parser gives it, so a part in another
 * encoding than UTF-8 (by BOM or declaration: the string input has no decoder) is parsed by push
 * from its start, before any element, and one not well-formed to its last byte (the parsers'
 * messages, lines and columns differ, at a truncated end above all) by push from its start too,
 * which hands the handler none of the starts and ends it had and raises again the error of the
 * one it failed at (after an XML error the parse went on past). 1: parsed (*s). */
static int pull_parse(tmf_xml *x, feed *f, const xmlSAXHandler *sax, hv_status *s)
{
    if (f->whole_len < 4 || f->whole_len > INT_MAX) return 0;
    xmlCharEncoding enc = xmlDetectCharEncoding(f->whole, 4);
    if (enc != XML_CHAR_ENCODING_NONE && enc != XML_CHAR_ENCODING_UTF8) return 0;
    if ((*s = inflate_count(f->in, f->whole_len)) != HV_OK) return 1;
    f->counted = 1;
    xmlParserCtxtPtr c = xmlNewParserCtxt();
    xmlSAXHandler *own = c ? xmlMalloc(sizeof *own) : NULL;
    xmlParserInputPtr in = own ? xmlNewInputStream(c) : NULL;
    if (in) {
        in->base = in->cur = f->whole;
        in->end = f->whole + f->whole_len; /* a NUL before it ends the parse early: checked below */
        in->length = (int)f->whole_len;
    }
    if (!in || inputPush(c, in) < 0) {
        if (in) xmlFreeInputStream(in);
        xmlFree(own);
        xmlFreeParserCtxt(c);
        *s = HV_ERR_NOMEM;
        return 1;
    }
    memcpy(own, sax, sizeof *own);
    own->startDocument = on_document;
    xmlFree(c->sax);
    c->sax = own;
    c->userData = x;
    xmlCtxtUseOptions(c, PKG_XML_OPTIONS);
    x->ctxt = c;
    x->pulling = 1;
    int rc = xmlParseDocument(c);
    x->pulling = 0;
    int whole = rc == 0 && c->wellFormed && !c->disableSAX && c->input == in && in->cur == in->end;
    if (c->myDoc) xmlFreeDoc(c->myDoc);
    xmlFreeParserCtxt(c);
    x->ctxt = NULL;
    if (!x->xml_error[0] && !x->restart && (x->status != HV_OK || whole)) {
        *s = x->status; /* a handler's error with no XML error before it is the push parser's too */
        return 1;
    }
    /* by push from the start: the starts and ends handled skipped, the failing one failing again */
    x->replay = x->restart ? 0 : x->seen;
    if (!x->restart && x->status != HV_OK) {
        x->fail = x->status;
        snprintf(x->fail_msg, sizeof x->fail_msg, "%s", hv_last_error());
        if (x->failed_at) x->replay = x->failed_at - 1; /* else it failed between them (text, DOCTYPE): again there */
    }
    x->status = HV_OK;
    x->seen = 0;
    x->depth = 0;
    x->collect = 0;
    x->text.len = 0;
    x->xml_error[0] = '\0';
    x->err_line = x->err_col = 0;
    return 0;
}

hv_status tmf_xml_parse(tmf_pkg *pk, const char *part, uint64_t limit, const tmf_xml_handler *h, void *ctx)
{
    zip_int64_t i = locate(pk, part, 0);
    char q[96];
    if (i < 0)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: part '/%s' is missing from the package", pk->name,
                            hv_quote(q, sizeof q, part, strlen(part)));
    inflater in;
    hv_status s = inflate_open(pk, i, part, limit, &in);
    if (s != HV_OK) return s;
    xmlSAXHandler sax;
    sax_init(&sax, on_start, on_end, on_error);
    sax.internalSubset = on_doctype; /* characters and cdataBlock: want_text sets them */
    tmf_xml x;
    memset(&x, 0, sizeof x);
    x.pk = pk;
    x.part = part;
    x.h = h;
    x.ctx = ctx;
    hv_buf_init(&x.text);
    feed f;
    if ((s = feed_open(&f, &in)) != HV_OK) {
        feed_close(&f);
        inflate_close(&in);
        return s;
    }
    tmf_xml_quiet quiet;
    tmf_xml_quiet_begin(&quiet);
    if (!f.whole || hv_threads() > 1 || !pull_parse(&x, &f, &sax, &s)) s = push_parse(&x, &f, &sax);
    tmf_xml_quiet_end(&quiet);
    hv_buf_free(&x.text);
    feed_close(&f);
    inflate_close(&in);
    return s;
}

/* ---- attributes ----------------------------------------------------------------------------- */

const tmf_attr *tmf_attr_find(const tmf_attr *attrs, int n, const char *local, const char *uri)
{
    for (int i = 0; i < n; ++i)
        if (strcmp(attrs[i].local, local) == 0 && (!uri || (attrs[i].uri && strcmp(attrs[i].uri, uri) == 0)))
            return &attrs[i];
    return NULL;
}

static void trim(const tmf_attr *a, const char **s, const char **e)
{
    *s = a->value;
    *e = a->value + a->len;
    while (*s < *e && (**s == ' ' || **s == '\t' || **s == '\n' || **s == '\r')) ++*s;
    while (*e > *s && ((*e)[-1] == ' ' || (*e)[-1] == '\t' || (*e)[-1] == '\n' || (*e)[-1] == '\r')) --*e;
}

int tmf_attr_uint(const tmf_attr *a, uint64_t max, uint64_t *out)
{
    if (!a) return 0;
    if (a->len - 1 < 19) { /* 1 to 19 digits and nothing else, as every index is written: no overflow, no
                            * division a digit, one compare at the end (a million triangles: issue 26) */
        uint64_t v = 0;
        size_t k = 0;
        for (unsigned d; k < a->len && (d = (unsigned)(unsigned char)a->value[k] - '0') < 10; ++k) v = v * 10 + d;
        if (k == a->len) {
            if (v > max) return -1;
            *out = v;
            return 1;
        }
    }
    const char *s, *e;
    trim(a, &s, &e);
    if (s == e) return -1;
    uint64_t v = 0;
    for (; s < e; ++s) {
        if (*s < '0' || *s > '9') return -1;
        uint64_t d = (uint64_t)(*s - '0');
        if (v > (max - d) / 10) return -1;
        v = v * 10 + d;
    }
    *out = v;
    return 1;
}

int tmf_attr_double(const tmf_attr *a, double *out)
{
    if (!a) return 0;
    const char *s, *e;
    trim(a, &s, &e);
    char buf[80];
    size_t n = (size_t)(e - s);
    if (n == 0 || n >= sizeof buf) return -1;
    memcpy(buf, s, n);
    buf[n] = '\0';
    char *end;
    double v = strtod(buf, &end);
    if (end != buf + n || !isfinite(v)) return -1;
    *out = v;
    return 1;
}

const char *tmf_attr_quote(const tmf_attr *a, char *buf, size_t cap) { return hv_quote(buf, cap, a->value, a->len); }

/* ---- the root relationships and content types -------------------------------------------- */

typedef struct rels_scan {
    char target[TMF_MAX_PART_NAME];
    int found, bad;
} rels_scan;

static hv_status rels_start(void *ctx, tmf_xml *x, const char *local, const char *uri, const tmf_attr *a, int n)
{
    (void)x, (void)uri;
    rels_scan *r = ctx;
    if (r->found || strcmp(local, "Relationship") != 0) return HV_OK;
    const tmf_attr *type = tmf_attr_find(a, n, "Type", NULL), *target = tmf_attr_find(a, n, "Target", NULL);
    if (!type || !target || type->len != strlen(TMF_REL_MODEL) || memcmp(type->value, TMF_REL_MODEL, type->len) != 0)
        return HV_OK;
    r->found = 1;
    const char *t = target->value;
    size_t len = target->len;
    if (len && t[0] == '/') ++t, --len; /* the root relationships' source is the package root */
    if (len == 0 || len >= sizeof r->target || memchr(t, '\0', len)) {
        r->bad = 1;
        snprintf(r->target, sizeof r->target, "%.*s", (int)HV_MIN(len, (size_t)200), t);
        return HV_OK;
    }
    memcpy(r->target, t, len);
    r->target[len] = '\0';
    return HV_OK;
}

typedef struct types_scan {
    const char *part; /* the start part, no leading '/' */
    char over[160], dflt[160];
} types_scan;

static void copy_value(char *dst, size_t cap, const tmf_attr *a)
{
    size_t n = HV_MIN(a->len, cap - 1);
    memcpy(dst, a->value, n);
    dst[n] = '\0';
}

static hv_status types_start(void *ctx, tmf_xml *x, const char *local, const char *uri, const tmf_attr *a, int n)
{
    (void)x, (void)uri;
    types_scan *t = ctx;
    const tmf_attr *ct = tmf_attr_find(a, n, "ContentType", NULL);
    if (!ct) return HV_OK;
    if (strcmp(local, "Override") == 0) {
        const tmf_attr *pn = tmf_attr_find(a, n, "PartName", NULL);
        /* part names compare without case (ECMA-376 Part 2, 9.1.1.1) */
        if (pn && pn->len == strlen(t->part) + 1 && pn->value[0] == '/' &&
            strncasecmp(pn->value + 1, t->part, pn->len - 1) == 0)
            copy_value(t->over, sizeof t->over, ct);
    } else if (strcmp(local, "Default") == 0) {
        const tmf_attr *ext = tmf_attr_find(a, n, "Extension", NULL);
        const char *dot = strrchr(t->part, '.');
        if (ext && dot && !strchr(dot, '/') && ext->len == strlen(dot + 1) && strncasecmp(ext->value, dot + 1, ext->len) == 0)
            copy_value(t->dflt, sizeof t->dflt, ct);
    }
    return HV_OK;
}

static hv_status find_start_part(tmf_pkg *pk)
{
    zip_int64_t i = locate(pk, "_rels/.rels", 1);
    if (i < 0) return hv_error_set(HV_ERR_BAD_INPUT, "%s: missing model part: the package has no _rels/.rels naming one", pk->name);
    const char *rels_name = zip_get_name(pk->zip, (zip_uint64_t)i, 0);
    rels_scan r;
    memset(&r, 0, sizeof r);
    tmf_xml_handler h = {rels_start, NULL};
    hv_status s = tmf_xml_parse(pk, rels_name ? rels_name : "_rels/.rels", PKG_MAX_SMALL_PART, &h, &r);
    if (s != HV_OK) return s;
    char q[96];
    if (!r.found) return hv_error_set(HV_ERR_BAD_INPUT, "%s: missing model part: _rels/.rels names no 3D model", pk->name);
    if (r.bad)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: _rels/.rels names the model part '%s', not a part name", pk->name,
                            hv_quote(q, sizeof q, r.target, strlen(r.target)));
    snprintf(pk->model, sizeof pk->model, "%s", r.target);
    /* part names compare without case (ECMA-376 Part 2, 9.1.1.1.2): the part named is the entry
     * spelt so in any case, and a package holding two such is not one OPC allows (issue 32 item
     * 5: the part read is never one of two look-alikes) */
    zip_int64_t at = locate(pk, pk->model, 1), ne = zip_get_num_entries(pk->zip, 0);
    if (at < 0)
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: missing model part '/%s' (named by _rels/.rels)", pk->name,
                            hv_quote(q, sizeof q, pk->model, strlen(pk->model)));
    const char *spelt = zip_get_name(pk->zip, (zip_uint64_t)at, 0);
    for (zip_int64_t k = 0; k < ne && spelt; ++k) {
        const char *other = zip_get_name(pk->zip, (zip_uint64_t)k, 0);
        if (k == at || !other || strcasecmp(other, spelt) != 0) continue;
        char q2[96], q3[96];
        return hv_error_set(HV_ERR_BAD_INPUT,
                            "%s: the model part '/%s' is held twice, as '/%s' and '/%s' (OPC part names compare "
                            "without case, so a package may not hold both)",
                            pk->name, hv_quote(q, sizeof q, pk->model, strlen(pk->model)),
                            hv_quote(q2, sizeof q2, spelt, strlen(spelt)), hv_quote(q3, sizeof q3, other, strlen(other)));
    }
    if (spelt) snprintf(pk->model, sizeof pk->model, "%s", spelt);
    /* its content type */
    i = locate(pk, "[Content_Types].xml", 1);
    if (i < 0) return hv_error_set(HV_ERR_BAD_INPUT, "%s: not a 3MF package: no [Content_Types].xml", pk->name);
    const char *types_name = zip_get_name(pk->zip, (zip_uint64_t)i, 0);
    types_scan t;
    memset(&t, 0, sizeof t);
    t.part = pk->model;
    h.start = types_start;
    if ((s = tmf_xml_parse(pk, types_name ? types_name : "[Content_Types].xml", PKG_MAX_SMALL_PART, &h, &t)) != HV_OK)
        return s;
    snprintf(pk->model_type, sizeof pk->model_type, "%s", t.over[0] ? t.over : t.dflt);
    if (!pk->model_type[0])
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: [Content_Types].xml gives the model part '/%s' no content type", pk->name,
                            hv_quote(q, sizeof q, pk->model, strlen(pk->model)));
    if (strcasecmp(pk->model_type, TMF_CT_MODEL) != 0) { /* media types compare without case (RFC 7231 3.1.1.1) */
        char q2[96];
        return hv_error_set(HV_ERR_BAD_INPUT, "%s: the model part '/%s' has content type '%s', not %s", pk->name,
                            hv_quote(q, sizeof q, pk->model, strlen(pk->model)),
                            hv_quote(q2, sizeof q2, pk->model_type, strlen(pk->model_type)), TMF_CT_MODEL);
    }
    return HV_OK;
}

hv_status tmf_pkg_open(tmf_pkg *pk, const void *data, size_t size, const char *path, const char *name)
{
    memset(pk, 0, sizeof *pk);
    pk->name = name;
    pk->budget = hv_memory_budget(0);
    zip_error_t ze;
    zip_error_init(&ze);
    if (data || !path) {
        if (size == 0) {
            zip_error_fini(&ze);
            return hv_error_set(HV_ERR_BAD_INPUT, "%s: empty file (0 bytes)", name);
        }
        pk->data = data;
        pk->size = size;
        pk->src = zip_source_buffer_create(data, size, 0, &ze);
        if (!pk->src) {
            zip_error_fini(&ze);
            return HV_ERR_NOMEM;
        }
        pk->zip = zip_open_from_source(pk->src, ZIP_RDONLY, &ze);
    } else {
        struct stat st;
        if (stat(path, &st) != 0) return hv_error_set(HV_ERR_IO, "%s: cannot open: %s", name, strerror(errno));
        if (S_ISDIR(st.st_mode)) return hv_error_set(HV_ERR_IO, "%s: is a directory, not a file", name);
        if (st.st_size == 0) return hv_error_set(HV_ERR_BAD_INPUT, "%s: empty file (0 bytes)", name);
        int zerr = 0;
        pk->zip = zip_open(path, ZIP_RDONLY, &zerr);
        if (!pk->zip) zip_error_init_with_code(&ze, zerr);
    }
    if (!pk->zip) {
        hv_status s = open_fail(name, &ze);
        zip_error_fini(&ze);
        tmf_pkg_close(pk);
        return s;
    }
    zip_error_fini(&ze);
    hv_status s = check_declared(pk);
    if (s == HV_OK) s = find_start_part(pk);
    if (s != HV_OK) tmf_pkg_close(pk);
    return s;
}
