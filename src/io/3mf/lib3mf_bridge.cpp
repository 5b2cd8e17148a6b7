// src/mesh/threemf_bridge.cpp - the one file that includes lib3mf (1.8, its C interface): reads
// a 3MF package from memory and hands the build items and their flattened mesh objects to the
// C side (threemf_bridge.h). Built as plugins/hovox-3mf.so. Every entry catches exceptions and
// turns them into a status and a message.
#include "lib3mf_bridge.h"

#include "hovox/core.h"

#include <Model/COM/NMR_DLLInterfaces.h>

#include <cstdio>
#include <cstring>
#include <map>
#include <new>
#include <string>
#include <utility>
#include <vector>

using namespace NMR;

namespace {

thread_local std::string g_error;

int fail(int status, std::string msg)
{
    g_error = std::move(msg);
    return status;
}

// A lib3mf object released when it goes out of scope.
struct Handle {
    PLib3MFBase *p = nullptr;
    Handle() = default;
    Handle(const Handle &) = delete;
    Handle &operator=(const Handle &) = delete;
    Handle(Handle &&o) noexcept : p(o.p) { o.p = nullptr; }
    ~Handle()
    {
        if (p) lib3mf_release(p);
    }
};

// lib3mf's last error on `obj`: "message (lib3mf error 0x8028)"; its code in *code.
std::string last_error(PLib3MFBase *obj, uint32_t *code)
{
    DWORD c = 0;
    LPCSTR msg = nullptr;
    if (obj) lib3mf_getlasterror(obj, &c, &msg);
    if (code) *code = c;
    char buf[64];
    std::snprintf(buf, sizeof buf, " (lib3mf error 0x%X)", unsigned(c));
    return std::string(msg && *msg ? msg : "unknown error") + buf;
}

struct Lib3mfError {
    std::string what;
};

void check(LIB3MFRESULT r, PLib3MFBase *obj, const char *call)
{
    if (r != LIB3MF_OK) throw Lib3mfError{std::string(call) + ": " + last_error(obj, nullptr)};
}

std::string object_name(PLib3MFModelObjectResource *o)
{
    ULONG need = 0;
    if (lib3mf_object_getnameutf8(o, nullptr, 0, &need) != LIB3MF_OK || need == 0) return "";
    std::vector<char> buf(size_t(need) + 1, '\0');
    check(lib3mf_object_getnameutf8(o, buf.data(), ULONG(buf.size()), &need), o, "object name");
    return std::string(buf.data());
}

typedef double Affine[12];

void compose(const double *a, const double *b, double *out)
{
    double c[12];
    for (int r = 0; r < 3; ++r) {
        for (int k = 0; k < 4; ++k)
            c[4 * r + k] = a[4 * r] * b[k] + a[4 * r + 1] * b[4 + k] + a[4 * r + 2] * b[8 + k];
        c[4 * r + 3] += a[4 * r + 3];
    }
    std::memcpy(out, c, sizeof c);
}

void to_affine(const MODELTRANSFORM &t, double *out)
{
    for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 4; ++k) out[4 * r + k] = t.m_fFields[r][k];
}

const int kMaxDepth = 256;

struct Reader {
    PLib3MFModel *model;
    const hv_3mf_sink *sink;
    hv_3mf_info *info;
    uint64_t max_triangles;
    std::map<DWORD, uint64_t> triangles; // per object resource: flattened triangle count
    std::map<DWORD, size_t> ordinal;     // per object resource: its position among the objects
    int status = HV_OK;                  // the sink's, when it stopped the read

    static DWORD id_of(PLib3MFModelObjectResource *o)
    {
        DWORD id = 0;
        check(lib3mf_resource_getresourceid(o, &id), o, "resource id");
        return id;
    }

    size_t ordinal_of(PLib3MFModelObjectResource *o)
    {
        auto it = ordinal.find(id_of(o));
        if (it == ordinal.end()) throw Lib3mfError{"an object lib3mf does not list among the model's objects"};
        return it->second;
    }

    // Triangles of an object with its components flattened, plus one per object placed (so
    // that a tree of empty objects costs its size too), saturating above max_triangles.
    uint64_t count(PLib3MFModelObjectResource *o, int depth)
    {
        if (depth > kMaxDepth)
            throw Lib3mfError{"components nested deeper than " + std::to_string(kMaxDepth) + " levels"};
        DWORD id = id_of(o);
        auto it = triangles.find(id);
        if (it != triangles.end()) return it->second;
        uint64_t n = 1;
        BOOL mesh = 0, comps = 0;
        check(lib3mf_object_ismeshobject(o, &mesh), o, "object type");
        check(lib3mf_object_iscomponentsobject(o, &comps), o, "object type");
        if (mesh) {
            DWORD nt = 0;
            check(lib3mf_meshobject_gettrianglecount(o, &nt), o, "triangle count");
            n += nt;
        } else if (comps) {
            DWORD nc = 0;
            check(lib3mf_componentsobject_getcomponentcount(o, &nc), o, "component count");
            for (DWORD k = 0; k < nc && n <= max_triangles; ++k) {
                Handle c, child;
                check(lib3mf_componentsobject_getcomponent(o, k, &c.p), o, "component");
                check(lib3mf_component_getobjectresource(c.p, &child.p), c.p, "component object");
                n += count(child.p, depth + 1);
            }
        }
        if (n > max_triangles) n = max_triangles + 1;
        triangles[id] = n;
        return n;
    }

    void deliver_mesh(PLib3MFModelMeshObject *o, size_t item, const double *t)
    {
        std::string name = object_name(o);
        DWORD nv = 0, nt = 0;
        check(lib3mf_meshobject_getvertexcount(o, &nv), o, "vertex count");
        check(lib3mf_meshobject_gettrianglecount(o, &nt), o, "triangle count");
        std::vector<MODELMESHVERTEX> v(nv);
        std::vector<MODELMESHTRIANGLE> tri(nt);
        DWORD got = 0;
        if (nv) check(lib3mf_meshobject_getvertices(o, v.data(), nv, &got), o, "vertices");
        if (nt) check(lib3mf_meshobject_gettriangleindices(o, tri.data(), nt, &got), o, "triangles");
        static_assert(sizeof(MODELMESHVERTEX) == 3 * sizeof(float), "vertex layout");
        static_assert(sizeof(MODELMESHTRIANGLE) == 3 * sizeof(uint32_t), "triangle layout");
        hv_3mf_instance in{};
        in.item = item;
        in.object = ordinal_of(o);
        in.object_name = name.c_str();
        in.nv = nv;
        in.nt = nt;
        in.xyz = nv ? &v[0].m_fPosition[0] : nullptr;
        in.tri = nt ? reinterpret_cast<const uint32_t *>(&tri[0].m_nIndices[0]) : nullptr;
        std::memcpy(in.transform, t, sizeof in.transform);
        int s = sink->instance(sink->ctx, &in);
        if (s != HV_OK) {
            status = s;
            throw Lib3mfError{""};
        }
    }

    void deliver(PLib3MFModelObjectResource *o, size_t item, const double *t, int depth)
    {
        BOOL mesh = 0, comps = 0;
        check(lib3mf_object_ismeshobject(o, &mesh), o, "object type");
        check(lib3mf_object_iscomponentsobject(o, &comps), o, "object type");
        if (mesh) return deliver_mesh(o, item, t);
        if (!comps) return;
        DWORD nc = 0;
        check(lib3mf_componentsobject_getcomponentcount(o, &nc), o, "component count");
        for (DWORD k = 0; k < nc; ++k) {
            Handle c, child;
            check(lib3mf_componentsobject_getcomponent(o, k, &c.p), o, "component");
            check(lib3mf_component_getobjectresource(c.p, &child.p), c.p, "component object");
            Affine ct = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}, world;
            BOOL has = 0;
            check(lib3mf_component_hastransform(c.p, &has), c.p, "component transform");
            if (has) {
                MODELTRANSFORM m{};
                check(lib3mf_component_gettransform(c.p, &m), c.p, "component transform");
                to_affine(m, ct);
            }
            compose(t, ct, world);
            deliver(child.p, item, world, depth + 1);
        }
    }

    int run(const void *data, size_t size)
    {
        Handle reader;
        check(lib3mf_model_queryreader(model, "3mf", &reader.p), model, "reader");
        if (lib3mf_reader_readfrombuffer(reader.p, static_cast<BYTE *>(const_cast<void *>(data)), ULONG64(size)) !=
            LIB3MF_OK)
            return fail(HV_ERR_BAD_INPUT, last_error(reader.p, &info->error_code));
        DWORD unit = 1;
        check(lib3mf_model_getunit(model, &unit), model, "unit");
        info->unit = int(unit);
        Handle objects;
        check(lib3mf_model_getobjects(model, &objects.p), model, "objects");
        for (;;) {
            BOOL has = 0;
            check(lib3mf_resourceiterator_movenext(objects.p, &has), objects.p, "objects");
            if (!has) break;
            Handle o;
            check(lib3mf_resourceiterator_getcurrent(objects.p, &o.p), objects.p, "object");
            size_t n = ordinal.size();
            ordinal[id_of(o.p)] = n;
        }
        if (int s = sink->begin(sink->ctx, info->unit, ordinal.size())) return status = s;

        // the build items, with their triangle counts checked before anything is delivered
        struct Item {
            Handle object;
            Affine t;
            bool skip;
        };
        std::vector<Item> items;
        Handle it;
        check(lib3mf_model_getbuilditems(model, &it.p), model, "build items");
        uint64_t total = 0;
        for (;;) {
            BOOL has = 0;
            check(lib3mf_builditemiterator_movenext(it.p, &has), it.p, "build items");
            if (!has) break;
            Handle bi;
            check(lib3mf_builditemiterator_getcurrent(it.p, &bi.p), it.p, "build item");
            items.emplace_back();
            Item &i = items.back();
            check(lib3mf_builditem_getobjectresource(bi.p, &i.object.p), bi.p, "build item object");
            Affine id = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
            std::memcpy(i.t, id, sizeof id);
            BOOL ht = 0;
            check(lib3mf_builditem_hasobjecttransform(bi.p, &ht), bi.p, "build item transform");
            if (ht) {
                MODELTRANSFORM m{};
                check(lib3mf_builditem_getobjecttransform(bi.p, &m), bi.p, "build item transform");
                to_affine(m, i.t);
            }
            DWORD type = MODELOBJECTTYPE_MODEL;
            check(lib3mf_object_gettype(i.object.p, &type), i.object.p, "object type");
            i.skip = type == MODELOBJECTTYPE_SUPPORT || type == MODELOBJECTTYPE_OTHER;
            if (i.skip) {
                info->skipped_items++;
                continue;
            }
            total += count(i.object.p, 0);
            if (total > max_triangles)
                return fail(HV_ERR_LIMIT, "the build items hold more than " + std::to_string(max_triangles) +
                                              " triangles once their components are placed");
        }
        info->items = items.size();
        for (size_t k = 0; k < items.size(); ++k) {
            if (items[k].skip) continue;
            std::string name = object_name(items[k].object.p);
            int s = sink->item(sink->ctx, k, ordinal_of(items[k].object.p), name.c_str());
            if (s != HV_OK) return status = s;
            deliver(items[k].object.p, k, items[k].t, 0);
        }
        return HV_OK;
    }
};

int read_3mf(const void *data, size_t size, uint64_t max_triangles, const hv_3mf_sink *sink, hv_3mf_info *info)
{
    std::memset(info, 0, sizeof *info);
    info->unit = 1;
    Handle model;
    Reader r{nullptr, sink, info, max_triangles, {}, {}, HV_OK};
    try {
        if (lib3mf_createmodel(&model.p) != LIB3MF_OK) return fail(HV_ERR_INTERNAL, "lib3mf cannot create a model");
        r.model = model.p;
        return r.run(data, size);
    } catch (const Lib3mfError &e) {
        if (r.status != HV_OK) return r.status;
        return fail(HV_ERR_BAD_INPUT, e.what);
    } catch (const std::bad_alloc &) {
        return fail(HV_ERR_NOMEM, "out of memory");
    } catch (const std::exception &e) {
        return fail(HV_ERR_INTERNAL, std::string("lib3mf bridge: ") + e.what());
    } catch (...) {
        return fail(HV_ERR_INTERNAL, "lib3mf bridge: unknown exception");
    }
}

const char *get_last_error() { return g_error.c_str(); }

const hv_3mf_api k_api = {HV_3MF_ABI, get_last_error, read_3mf};

} // namespace

extern "C" __attribute__((visibility("default"))) const hv_3mf_api *hv_3mf_plugin_v1(void)
{
    return &k_api;
}
