// Intel Open Image Denoise, loaded at run time. OIDN ships on PyPI (pyoidn)
// as shared libraries without their C headers, and in no Debian package, so
// the renderer builds without it and declares the few C API functions it
// calls itself (OIDN 2.x's ABI, oidn.h). A machine without the library still
// renders everything else; asking it to denoise says where it looked.
#pragma once

#include <cstddef>
#include <string>

namespace rt::oidn {

// The handles and enum values of oidn.h that the renderer passes.
using Device = struct DeviceImpl*;
using Filter = struct FilterImpl*;
enum DeviceType : int { kDeviceCpu = 1 };
enum Format : int { kFormatFloat3 = 3 };
enum Error : int { kErrorNone = 0 };

// The C API, resolved from the library once.
struct Api {
    Device (*new_device)(DeviceType);
    void (*set_device_int)(Device, const char*, int);
    void (*set_device_bool)(Device, const char*, bool);
    void (*commit_device)(Device);
    void (*release_device)(Device);
    Error (*get_device_error)(Device, const char**);
    Filter (*new_filter)(Device, const char*);
    void (*set_shared_filter_image)(Filter, const char*, void*, Format, size_t width, size_t height,
                                    size_t byte_offset, size_t pixel_byte_stride, size_t row_byte_stride);
    void (*set_filter_bool)(Filter, const char*, bool);
    void (*commit_filter)(Filter);
    void (*execute_filter)(Filter);
    void (*release_filter)(Filter);
};

// The API of the first library that loads: $RT_OIDN_LIBRARY, else the one the
// build found in the venv's pyoidn package, else libOpenImageDenoise.so.2 on
// the loader's path. Throws std::runtime_error naming every place tried and
// why each failed; thread-safe, loads once.
const Api& api();

// The file api() loaded, or "" when none loaded (never throws): for
// `rtrender --help`, /api/health and error messages.
std::string loaded_library();

}  // namespace rt::oidn
