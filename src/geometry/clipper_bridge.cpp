// src/geometry/clipper_bridge.cpp - the Clipper bridge plugin (plugins/hovox-clipper.so; table in
// clipper_bridge.h): 2D polygon Booleans by Clipper 6 (Vatti's sweep with Johnson's extensions,
// Debian libpolyclipping) for the outlines of a model's Boolean tree. Every entry catches all
// exceptions (HV_CATCH) and turns them into a status plus what().
#include <polyclipping/clipper.hpp>
#include <stdexcept>
#include <vector>

#include "core/bridge.hpp"
#include "clipper_bridge.h"

#define HV_CATCH(code) HV_CATCH_PREFIXED(code, "Clipper: ", "Clipper")

using namespace hv_bridge;

static ClipperLib::Paths to_paths(const hv_clip_paths *p)
{
    ClipperLib::Paths out;
    if (!p) return out;
    out.resize(p->n);
    for (size_t i = 0; i < p->n; ++i) {
        out[i].resize(p->count[i]);
        for (size_t k = 0; k < p->count[i]; ++k) out[i][k] = ClipperLib::IntPoint(p->xy[i][2 * k], p->xy[i][2 * k + 1]);
    }
    return out;
}

static int clip_boolean(int op, const hv_clip_paths *subject, const hv_clip_paths *clip, hv_clip_out_fn out, void *user)
{
    try {
        ClipperLib::ClipType type = op == HV_CLIP_INTERSECTION ? ClipperLib::ctIntersection
                                    : op == HV_CLIP_UNION      ? ClipperLib::ctUnion
                                    : op == HV_CLIP_DIFFERENCE ? ClipperLib::ctDifference
                                                               : throw std::invalid_argument("unknown operation");
        ClipperLib::Clipper c;
        c.AddPaths(to_paths(subject), ClipperLib::ptSubject, true);
        c.AddPaths(to_paths(clip), ClipperLib::ptClip, true);
        ClipperLib::Paths result;
        if (!c.Execute(type, result, ClipperLib::pftNonZero, ClipperLib::pftNonZero))
            return fail(E_INTERNAL, "Clipper: the Boolean failed");
        std::vector<int64_t> xy;
        for (const ClipperLib::Path &p : result) {
            xy.resize(2 * p.size());
            for (size_t k = 0; k < p.size(); ++k) {
                xy[2 * k] = p[k].X;
                xy[2 * k + 1] = p[k].Y;
            }
            int r = out(user, p.size(), xy.data());
            if (r) return r;
        }
        return OK;
    }
    HV_CATCH(E_INTERNAL)
}

static const char *clip_last_error() { return last_error(); }

extern "C" __attribute__((visibility("default"))) const hv_clipper_api *hv_clipper_plugin_v1(void)
{
    static const hv_clipper_api api = {HV_CLIPPER_ABI, clip_last_error, clip_boolean};
    return &api;
}
