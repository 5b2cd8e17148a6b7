// src/core/bridge.hpp - what every C++ bridge plugin shares (STYLE rule 3): hovox's status values,
// the calling thread's last error, and HV_CATCH, which ends every extern "C" entry so that no
// exception crosses into C (std::bad_alloc becomes HV_ERR_NOMEM, any other exception `code` plus
// what()). Header-only: a bridge is a plugin and does not link the library.
#ifndef HOVOX_CORE_BRIDGE_HPP
#define HOVOX_CORE_BRIDGE_HPP

#include "hovox/core.h"

#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <utility>

namespace hv_bridge {

enum {
    OK = HV_OK,
    E_INVALID = HV_ERR_INVALID,
    E_BAD_INPUT = HV_ERR_BAD_INPUT,
    E_IO = HV_ERR_IO,
    E_NOMEM = HV_ERR_NOMEM,
    E_LIMIT = HV_ERR_LIMIT,
    E_CANCELLED = HV_ERR_CANCELLED,
    E_NOT_FOUND = HV_ERR_NOT_FOUND,
    E_UNSUPPORTED = HV_ERR_UNSUPPORTED,
    E_INTERNAL = HV_ERR_INTERNAL
};

// The message of the calling thread's last failure, read by the C side through the plugin's
// last_error entry right after a call returned nonzero.
inline std::string &last_error_text()
{
    static thread_local std::string text;
    return text;
}

inline int fail(int status, std::string msg)
{
    last_error_text() = std::move(msg);
    return status;
}

inline const char *last_error() { return last_error_text().c_str(); }

// A size as the library writes it (hv_size_text): "512 bytes", "9.3 KiB", "4.3 GiB".
inline std::string size_text(double bytes)
{
    static const char *const unit[] = {"bytes", "KiB", "MiB", "GiB", "TiB", "PiB"};
    int u = 0;
    while (bytes >= 1024.0 && u < 5) {
        bytes /= 1024.0;
        ++u;
    }
    char buf[64];
    if (u == 0) std::snprintf(buf, sizeof buf, "%.0f bytes", bytes);
    else std::snprintf(buf, sizeof buf, "%.1f %s", bytes, unit[u]);
    return buf;
}

} // namespace hv_bridge

// The end of an entry's try block: `prefix` starts the message ("" or "VTK: "), `bridge` names
// the bridge for an exception that is not a std::exception.
#define HV_CATCH_PREFIXED(code, prefix, bridge)                                                      \
    catch (const std::bad_alloc &) { return hv_bridge::fail(hv_bridge::E_NOMEM, prefix "out of memory"); } \
    catch (const std::exception &e) { return hv_bridge::fail(code, std::string(prefix) + e.what()); } \
    catch (...) { return hv_bridge::fail(code, "unknown exception in the " bridge " bridge"); }

#endif
