#include "image/oidn_library.h"

#include <dlfcn.h>

#include <cstdlib>
#include <stdexcept>
#include <vector>

#ifndef RT_OIDN_LIBRARY
#define RT_OIDN_LIBRARY ""
#endif

namespace rt::oidn {
namespace {

struct Loaded {
    Api api{};
    std::string path;
    std::string error;  // why nothing loaded, when nothing did
};

template <class F>
bool resolve(void* handle, const char* name, F& function, std::string& missing) {
    function = reinterpret_cast<F>(dlsym(handle, name));
    if (!function) missing += std::string(missing.empty() ? "" : ", ") + name;
    return function != nullptr;
}

// Resolves every function of Api from `handle`; "" or the names missing.
std::string resolve_all(void* handle, Api& api) {
    std::string missing;
    resolve(handle, "oidnNewDevice", api.new_device, missing);
    resolve(handle, "oidnSetDeviceInt", api.set_device_int, missing);
    resolve(handle, "oidnSetDeviceBool", api.set_device_bool, missing);
    resolve(handle, "oidnCommitDevice", api.commit_device, missing);
    resolve(handle, "oidnReleaseDevice", api.release_device, missing);
    resolve(handle, "oidnGetDeviceError", api.get_device_error, missing);
    resolve(handle, "oidnNewFilter", api.new_filter, missing);
    resolve(handle, "oidnSetSharedFilterImage", api.set_shared_filter_image, missing);
    resolve(handle, "oidnSetFilterBool", api.set_filter_bool, missing);
    resolve(handle, "oidnCommitFilter", api.commit_filter, missing);
    resolve(handle, "oidnExecuteFilter", api.execute_filter, missing);
    resolve(handle, "oidnReleaseFilter", api.release_filter, missing);
    return missing;
}

Loaded load() {
    std::vector<std::string> candidates;
    if (const char* given = std::getenv("RT_OIDN_LIBRARY"); given && *given) candidates.emplace_back(given);
    if (*RT_OIDN_LIBRARY) candidates.emplace_back(RT_OIDN_LIBRARY);
    candidates.emplace_back("libOpenImageDenoise.so.2");
    Loaded loaded;
    std::string tried;
    for (const std::string& path : candidates) {
        // RTLD_LOCAL: OIDN's bundled TBB stays out of everyone else's way.
        void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle) {
            const char* why = dlerror();
            tried += "\n  " + path + ": " + (why ? why : "not loadable");
            continue;
        }
        if (const std::string missing = resolve_all(handle, loaded.api); !missing.empty()) {
            tried += "\n  " + path + ": not OIDN 2 (no " + missing + ")";
            dlclose(handle);
            continue;
        }
        loaded.path = path;
        return loaded;
    }
    loaded.error = "Open Image Denoise could not be loaded (pip install pyoidn, or set RT_OIDN_LIBRARY to "
                   "libOpenImageDenoise.so.2); tried:" + tried;
    return loaded;
}

const Loaded& library() {
    static const Loaded loaded = load();
    return loaded;
}

}  // namespace

const Api& api() {
    const Loaded& loaded = library();
    if (!loaded.error.empty()) throw std::runtime_error(loaded.error);
    return loaded.api;
}

std::string loaded_library() { return library().path; }

}  // namespace rt::oidn
