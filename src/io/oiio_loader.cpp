// Finds and opens libsmokescan_oiio.so once (smokescan/io/oiio_module.hpp).
#include <dlfcn.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <vector>

#include "smokescan/core/error.hpp"
#include "smokescan/io/oiio_module.hpp"

namespace smokescan::detail {
namespace {

constexpr const char* kModuleName = "libsmokescan_oiio.so";

/// Where to look, in order: $SMOKESCAN_OIIO_MODULE alone when set; else beside the object holding
/// this code (the installed Python module has one beside it), beside the program, in the library
/// folder beside its bin/ (an installed tree moved elsewhere), the build tree's module, the
/// installed one.
std::vector<std::string> candidates()
{
    if (const char* env = std::getenv("SMOKESCAN_OIIO_MODULE"); env && *env) return {env};
    std::vector<std::string> out;
    std::error_code ec;
    if (Dl_info info{}; ::dladdr(reinterpret_cast<void*>(&candidates), &info) && info.dli_fname && *info.dli_fname) {
        const std::filesystem::path holder = std::filesystem::absolute(info.dli_fname, ec);
        if (!ec) out.push_back((holder.parent_path() / kModuleName).string());
    }
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        out.push_back((self.parent_path() / kModuleName).string());
#ifdef SMOKESCAN_OIIO_INSTALL_DIR
        out.push_back((self.parent_path().parent_path() / SMOKESCAN_OIIO_INSTALL_DIR / kModuleName).string());
#endif
    }
#ifdef SMOKESCAN_OIIO_BUILD_PATH
    out.emplace_back(SMOKESCAN_OIIO_BUILD_PATH);
#endif
#ifdef SMOKESCAN_OIIO_INSTALL_PATH
    out.emplace_back(SMOKESCAN_OIIO_INSTALL_PATH);
#endif
    return out;
}

const OiioApi* load()
{
    std::string tried;
    for (const std::string& path : candidates()) {
        if (::access(path.c_str(), R_OK) != 0) {
            tried += (tried.empty() ? "" : ", ") + path;
            continue;
        }
        void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle) throw Error(path, std::string("cannot load smokescan's image module: ") + ::dlerror());
        using Entry = const OiioApi* (*)();
        const auto entry = reinterpret_cast<Entry>(::dlsym(handle, "smokescan_oiio_api"));
        const OiioApi* api = entry ? entry() : nullptr;
        if (!api || api->version != kOiioApiVersion)
            throw Error(path, "is not this smokescan's image module (rebuild it, or set SMOKESCAN_OIIO_MODULE)");
        return api;  // never closed: it lives as long as the program
    }
    throw Error(kModuleName,
                "smokescan's image module (OpenImageIO) was not found; looked at " + printableWhole(tried) +
                    " (set SMOKESCAN_OIIO_MODULE to its path)");
}

}  // namespace

const OiioApi& oiio()
{
    static const OiioApi* api = load();
    return *api;
}

}  // namespace smokescan::detail
