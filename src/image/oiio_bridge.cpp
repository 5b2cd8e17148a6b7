// src/image/oiio_bridge.cpp - the only code that includes OpenImageIO: writes float RGBA images
// as EXR or TIFF. Built as plugins/hovox-oiio.so and loaded by image.c only when one of those
// formats is requested. Every entry catches all exceptions (HV_CATCH) and turns them into a
// status plus what(); nothing propagates into C.
#include "oiio_bridge.h"

#include "core/bridge.hpp"

#include <OpenImageIO/imageio.h>

#include <exception>
#include <memory>
#include <new>
#include <string>

namespace {

using namespace hv_bridge;

#define HV_CATCH(code) HV_CATCH_PREFIXED(code, "", "OpenImageIO")

const char *b_last_error(void) { return last_error(); }

// OpenImageIO keeps a per-thread pending error; fetch it so the message is ours to report
// (and OIIO does not complain about unretrieved errors at exit).
std::string pending(const std::string &fallback)
{
    std::string e = OIIO::geterror();
    return e.empty() ? fallback : e;
}

int b_write(const char *path, const char *format, int width, int height, int channels,
            const float *pixels, int type, int unassociated_alpha)
{
    try {
        if (width < 1 || height < 1 || channels < 1 || channels > 4 || !pixels)
            return fail(E_INVALID, "bad image arguments");
        std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(format);
        if (!out)
            return fail(E_UNSUPPORTED, pending(std::string("no OpenImageIO writer for ") + format));
        OIIO::TypeDesc td = type == HV_OIIO_UINT8  ? OIIO::TypeDesc::UINT8
                            : type == HV_OIIO_HALF ? OIIO::TypeDesc::HALF
                                                   : OIIO::TypeDesc::FLOAT;
        OIIO::ImageSpec spec(width, height, channels, td);
        if (channels == 4) spec.alpha_channel = 3;
        if (unassociated_alpha) spec.attribute("oiio:UnassociatedAlpha", 1);
        spec.attribute("compression", td == OIIO::TypeDesc::UINT8 ? "lzw" : "zip");
        spec.attribute("Software", "hovox");
        if (!out->open(path, spec)) {
            std::string e = out->geterror();
            OIIO::geterror();
            return fail(E_IO, e.empty() ? pending("cannot open for writing") : e);
        }
        if (!out->write_image(OIIO::TypeDesc::FLOAT, pixels)) {
            std::string e = out->geterror();
            out->close();
            return fail(E_IO, e.empty() ? pending("write failed") : e);
        }
        if (!out->close()) {
            std::string e = out->geterror();
            return fail(E_IO, e.empty() ? pending("close failed") : e);
        }
        return OK;
    }
    HV_CATCH(E_INTERNAL)
}

const hv_oiio_api g_api = {HV_OIIO_ABI, b_last_error, b_write};

} // namespace

extern "C" __attribute__((visibility("default"))) const hv_oiio_api *hv_oiio_plugin_v1(void)
{
    return &g_api;
}
