/* src/io/3mf/package.h - the one 3MF package module (package.c): the OPC container every 3MF
 * reader shares (ECMA-376 Part 2 as 3MF Core 1.3 chapter 2 and 6 profile it): the ZIP opened
 * through libzip with budgets against bombs, [Content_Types].xml, the start part named by the
 * root relationship (_rels/.rels, exact part name), and XML parts streamed through libxml2's
 * SAX2 push parser with the line and column of every element. Internal. */
#ifndef HOVOX_3MF_PACKAGE_H
#define HOVOX_3MF_PACKAGE_H

#include <stdarg.h>
#include <stdint.h>
#include <zip.h>

#include "core/internal.h"

#define TMF_MAX_PART_NAME 1024

/* An open package. Bytes inflated from all its parts are counted against `inflate_cap`
 * (the smaller of half the memory budget and what the ZIP declares, with a margin). */
typedef struct tmf_pkg {
    const char *name; /* the file, for messages */
    zip_t *zip;
    zip_source_t *src;
    const uint8_t *data; /* the package in memory (NULL: read from its file) */
    size_t size;
    uint64_t budget;      /* the memory budget the readers charge (hv_memory_budget(0) when opened) */
    uint64_t inflate_cap; /* bytes all parts may inflate to */
    uint64_t inflated;    /* bytes inflated so far */
    char model[TMF_MAX_PART_NAME]; /* the start part (3D model), without the leading '/' */
    char model_type[160];          /* its content type ("" when [Content_Types].xml gives none) */
} tmf_pkg;

/* Open a package from memory (data must outlive it) or, with data NULL, from the file `path`;
 * `name` names it in messages. Checks before any part is inflated: a ZIP that opens, the sizes
 * its directory declares (total within half the memory budget; no part declaring more than 1000
 * times its compressed size beyond 16 MiB, far past what deflate gives XML and PNG), the root
 * relationships and the start part they name, present under exactly that name, and its content
 * type. Errors: HV_ERR_IO (the file cannot be read), HV_ERR_BAD_INPUT ("NAME: ..." naming what
 * is wrong), HV_ERR_LIMIT (a bomb), HV_ERR_NOMEM. On failure nothing stays open. Close with
 * tmf_pkg_close (accepts a package that failed to open). */
hv_status tmf_pkg_open(tmf_pkg *pk, const void *data, size_t size, const char *path, const char *name);
void tmf_pkg_close(tmf_pkg *pk);

/* 1 when the package holds a part of this name (no leading '/'; as OPC, case aside). */
int tmf_pkg_has(const tmf_pkg *pk, const char *part);

/* A part read whole (images; its name as for tmf_pkg_has), at most `limit` bytes inflated; *data freed by the caller with
 * free. Errors: HV_ERR_BAD_INPUT (missing, damaged, inflating past its declared size),
 * HV_ERR_LIMIT (past `limit` or the package's inflate cap), HV_ERR_NOMEM. */
hv_status tmf_pkg_read(tmf_pkg *pk, const char *part, uint64_t limit, uint8_t **data, size_t *size);

/* ---- XML parts, streamed --------------------------------------------------------------------
 * Events come from libxml2's SAX2 parser fed in 64 KiB chunks straight from the inflater; no
 * tree is built. A DOCTYPE (entities: XXE, billion laughs) is refused before its subset is
 * used, and nesting is bounded. */
typedef struct tmf_attr {
    const char *local, *uri; /* uri NULL: no namespace */
    const char *value;       /* not NUL-terminated: `len` bytes */
    size_t len;
} tmf_attr;

typedef struct tmf_xml tmf_xml;
typedef struct tmf_xml_handler {
    /* An element starts (local name, namespace URI or NULL, its attributes). */
    hv_status (*start)(void *ctx, tmf_xml *x, const char *local, const char *uri, const tmf_attr *attrs, int nattrs);
    /* It ends (NULL: no callback). */
    hv_status (*end)(void *ctx, tmf_xml *x, const char *local, const char *uri);
} tmf_xml_handler;

/* Parse the XML part `part` of the package, calling the handler for each element. A callback's
 * status other than HV_OK stops the parse and is returned (its message set by the callback,
 * usually through tmf_xml_bad). XML that is not well-formed: HV_ERR_BAD_INPUT with line and
 * column. `limit`: bytes the part may inflate to. */
hv_status tmf_xml_parse(tmf_pkg *pk, const char *part, uint64_t limit, const tmf_xml_handler *h, void *ctx);

/* Where the parser is: the line and column just past the element's start tag (or end tag). */
void tmf_xml_where(const tmf_xml *x, int *line, int *col);
/* Record "NAME: PART: line L, column C: MESSAGE" and return `code`. */
hv_status tmf_xml_bad(tmf_xml *x, hv_status code, const char *fmt, ...) HV_PRINTF(3, 4);
hv_status tmf_xml_vbad(tmf_xml *x, hv_status code, const char *fmt, va_list ap);
/* The package being parsed. */
tmf_pkg *tmf_xml_pkg(tmf_xml *x);
/* The element being read as written ("v:imagesheet"). */
const char *tmf_xml_qname(tmf_xml *x);
/* The namespace URI a prefix is bound to where the parser is, or NULL. */
const char *tmf_xml_lookup_ns(const tmf_xml *x, const char *prefix);
/* ---- a long run of like children, read ahead on other threads ------------------------------
 * A mesh's <vertices> and <triangles> hold a million children of one form. Asked from the start
 * callback of the element that holds them (tmf_xml_bulk), the rest of its content may be cut at
 * child boundaries into pieces that other threads parse with parsers of their own (issue 26: a
 * 1M-facet model's libxml2 time scales with cores). A piece hands each child (local name
 * `child`, exactly `nattrs` attributes, no children of its own) to `item`, which writes
 * `item_size` bytes or returns 0 to give the piece up; `merge` then receives each whole piece's
 * items on the parser's thread, in document order, where the children's start and end callbacks
 * would have come. Anything else in a piece (another element, a child `item` does not take, XML
 * that is not well-formed, a cut that is not between children) gives it up: that piece and those
 * after it are parsed here as usual, so every message, line and column is the serial parse's.
 * `item` runs on other threads at once: it reads only its arguments and `arg`, which must not
 * change until the element ends. A hint: one thread, a small part, text being collected, no
 * whole part in memory, and it does nothing. */
typedef struct tmf_bulk {
    const char *child;
    int nattrs;
    size_t item_size;
    int (*item)(const void *arg, const tmf_attr *attrs, int nattrs, void *out);
    const void *arg;
    /* 1: merged; 0: nothing changed (no room in the budget, say): the piece is parsed as usual */
    int (*merge)(void *ctx, const void *items, size_t count);
} tmf_bulk;
void tmf_xml_bulk(tmf_xml *x, const tmf_bulk *b);
/* Children read ahead and merged so far, in this process (for the tests). */
uint64_t tmf_xml_bulk_merged(void);

/* Called from a start callback: collect the element's text (at most 64 MiB), which the end
 * callback reads with tmf_xml_text ("" when none). */
void tmf_xml_collect_text(tmf_xml *x);
const char *tmf_xml_text(const tmf_xml *x);

/* The attribute `local` (any namespace when uri is NULL, else that namespace), or NULL. */
const tmf_attr *tmf_attr_find(const tmf_attr *attrs, int n, const char *local, const char *uri);
/* Attribute values: 1 found and valid (*out set), 0 absent, -1 present but not valid. */
int tmf_attr_uint(const tmf_attr *a, uint64_t max, uint64_t *out);
int tmf_attr_double(const tmf_attr *a, double *out); /* finite numbers only */
/* Copy a value into buf (quoted for messages: control characters escaped, cut with "..."). */
const char *tmf_attr_quote(const tmf_attr *a, char *buf, size_t cap);

#endif
