/* volumes/schema.h - the model metadata schema, in one place: the JSON documents a model (.vdb)
 * carries as string metadata, their keys and schema versions, and reading and writing them with
 * the version check. Each document's (de)serialisers live with the module that owns it (mesh
 * report: mesh_internal.h; voxelize record and regions: voxel_internal.h; material table and
 * grading definition: material_internal.h; geometry record: src/geometry/record.c). Not public API: the public readers are
 * hv_voxelize_record_read, hv_material_table_load / _from_json and hv_object_from_model.
 *
 * Every document is an object whose first member is "schema": its version. Version 1 is the
 * layout hovox 0.1.0 wrote without that member (the object document had "version": 1), so a
 * document without "schema" reads as version 1. A reader refuses versions it does not know
 * (newer, zero, negative, not an integer) with HV_ERR_BAD_INPUT naming the key, the version
 * found and the versions it reads. Bump a document's version when its meaning changes in a way
 * older readers would get wrong, and keep reading the older versions. */
#ifndef HOVOX_SCHEMA_H
#define HOVOX_SCHEMA_H

#include "core/json.h"
#include "hovox/volume.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum hv_schema_doc {
    HV_DOC_MESH,      /* "hovox.mesh.json": the report of the voxelized mesh (hv_voxelize) */
    HV_DOC_VOXELIZE,  /* "hovox.voxelize.json": adjacency, fill, index box, voxel size */
    HV_DOC_MATERIALS, /* "hovox.materials.json": the material table (graded models) */
    HV_DOC_OBJECT,    /* "hovox.object.json": the grading definition (graded models) */
    HV_DOC_REGIONS,   /* "hovox.regions.json": the regions of an assembly (hv_voxelize) */
    HV_DOC_GEOMETRY,  /* "hovox.geometry.json": the leaves and the Boolean tree (hovox/geometry.h) */
    HV_DOC_COUNT
} hv_schema_doc;

/* The metadata key holding the hovox version that voxelized the model (a plain string). */
#define HV_META_HOVOX_VERSION "hovox.version"

/* Metadata key of a document ("hovox.object.json"), and the version this hovox writes. */
const char *hv_schema_key(hv_schema_doc d);
int hv_schema_version(hv_schema_doc d);
/* 1 when `key` names a document grading writes (materials, object): a graded model's own, the
 * rest of a model's metadata describes its geometry and carries over into graded models. */
int hv_schema_is_grading_key(const char *key);

/* Parse document d from text (len bytes) and check its version. Errors: HV_ERR_BAD_INPUT
 * "hovox.object.json: line L, column C: ...", "<key>: schema 3 is newer than this hovox reads
 * (1)", a document that is not an object; HV_ERR_NOMEM. *out: json_decref. */
hv_status hv_schema_doc_parse(hv_schema_doc d, const char *text, size_t len, json_t **out);
/* The same from vol's metadata. Errors: as parse, HV_ERR_NOT_FOUND (no such key: "the model has
 * no hovox.object.json"). */
hv_status hv_schema_doc_read(const hv_volume *vol, hv_schema_doc d, json_t **out);
/* Serialise doc (its members after "schema": version; hv_json_dump). Returns malloc'd text, or
 * NULL with HV_ERR_NOMEM recorded. */
char *hv_schema_doc_dump(hv_schema_doc d, const json_t *doc);
/* The same under an older version (see hv_schema_doc_write_version). */
char *hv_schema_doc_dump_version(hv_schema_doc d, const json_t *doc, int version);
/* Store doc (reference stolen, NULL allowed: then HV_ERR_NOMEM) in vol's metadata. */
hv_status hv_schema_doc_write(hv_volume *vol, hv_schema_doc d, json_t *doc);
/* The same under an older version, 1 <= version <= hv_schema_version(d): a writer whose document
 * needs no newer member writes the version older hovox reads (the object document is version 1
 * unless its regions carry names or bases of their own). */
hv_status hv_schema_doc_write_version(hv_volume *vol, hv_schema_doc d, json_t *doc, int version);

#ifdef __cplusplus
}
#endif
#endif
