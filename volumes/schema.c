/* volumes/schema.c - the model metadata schema (see schema.h): document keys, versions, and
 * reading and writing documents in a volume's metadata with the version check. */
#include <stdlib.h>
#include <string.h>

#include "schema.h"

static const struct {
    const char *key;
    int version; /* written; read: 1 .. version */
} k_docs[HV_DOC_COUNT] = {
    [HV_DOC_MESH] = {"hovox.mesh.json", 1},
    [HV_DOC_VOXELIZE] = {"hovox.voxelize.json", 1},
    [HV_DOC_MATERIALS] = {"hovox.materials.json", 1},
    [HV_DOC_OBJECT] = {"hovox.object.json", 2}, /* 2: regions with "name" and "base" */
    [HV_DOC_REGIONS] = {"hovox.regions.json", 1},
    [HV_DOC_GEOMETRY] = {"hovox.geometry.json", 1},
};

const char *hv_schema_key(hv_schema_doc d) { return k_docs[d].key; }

int hv_schema_version(hv_schema_doc d) { return k_docs[d].version; }

int hv_schema_is_grading_key(const char *key)
{
    return strcmp(key, k_docs[HV_DOC_MATERIALS].key) == 0 || strcmp(key, k_docs[HV_DOC_OBJECT].key) == 0;
}

static hv_status check(hv_schema_doc d, const json_t *doc)
{
    const char *key = k_docs[d].key;
    int have = k_docs[d].version;
    if (!json_is_object(doc)) return hv_error_set(HV_ERR_BAD_INPUT, "%s: the document is not a JSON object", key);
    const json_t *v = json_object_get(doc, "schema");
    if (!v && d == HV_DOC_OBJECT) v = json_object_get(doc, "version"); /* hovox 0.1.0 */
    if (!v) return HV_OK;                                                /* version 1 */
    if (json_is_integer(v) && json_integer_value(v) >= 1 && json_integer_value(v) <= have) return HV_OK;
    char *found = hv_json_dump(v);
    hv_status s;
    if (json_is_integer(v) && json_integer_value(v) > have)
        s = hv_error_set(HV_ERR_BAD_INPUT, "%s: schema %s is newer than this hovox reads (%d): written by a newer hovox",
                         key, found ? found : "?", have);
    else
        s = hv_error_set(HV_ERR_BAD_INPUT, "%s: schema %s is not a version hovox knows (it reads %s%d)", key,
                         found ? found : "?", have > 1 ? "1 to " : "", have);
    free(found);
    return s;
}

hv_status hv_schema_doc_parse(hv_schema_doc d, const char *text, size_t len, json_t **out)
{
    hv_status s = hv_json_parse(text, len, k_docs[d].key, out);
    if (s == HV_OK && (s = check(d, *out)) != HV_OK) {
        json_decref(*out);
        *out = NULL;
    }
    return s;
}

hv_status hv_schema_doc_read(const hv_volume *vol, hv_schema_doc d, json_t **out)
{
    *out = NULL;
    const char *text = hv_volume_meta_string(vol, k_docs[d].key);
    if (!text) return hv_error_set(HV_ERR_NOT_FOUND, "the model has no %s", k_docs[d].key);
    return hv_schema_doc_parse(d, text, strlen(text), out);
}

static char *doc_dump(hv_schema_doc d, const json_t *doc, int version)
{
    json_t *full = json_pack("{s:i}", "schema", version);
    char *text = NULL;
    /* update copies the members in doc's order, after "schema" */
    if (full && json_object_update(full, (json_t *)doc) == 0) text = hv_json_dump(full);
    else hv_error_set(HV_ERR_NOMEM, "out of memory (writing %s)", k_docs[d].key);
    json_decref(full);
    return text;
}

char *hv_schema_doc_dump(hv_schema_doc d, const json_t *doc) { return doc_dump(d, doc, k_docs[d].version); }

char *hv_schema_doc_dump_version(hv_schema_doc d, const json_t *doc, int version)
{
    if (version < 1 || version > k_docs[d].version) version = k_docs[d].version;
    return doc_dump(d, doc, version);
}

hv_status hv_schema_doc_write(hv_volume *vol, hv_schema_doc d, json_t *doc)
{
    return hv_schema_doc_write_version(vol, d, doc, k_docs[d].version);
}

hv_status hv_schema_doc_write_version(hv_volume *vol, hv_schema_doc d, json_t *doc, int version)
{
    char *text = doc ? hv_schema_doc_dump_version(d, doc, version) : NULL;
    json_decref(doc);
    if (!text) return hv_error_set(HV_ERR_NOMEM, "out of memory (writing %s)", k_docs[d].key);
    hv_status s = hv_volume_meta_set_string(vol, k_docs[d].key, text);
    free(text);
    return s;
}
