// Finds and opens libsmokescan_oiio.so once (smokescan/io/oiio_module.hpp).
#include <dlfcn.h>
#include <link.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <vector>

#include "smokescan/core/error.hpp"
#include "smokescan/io/oiio_module.hpp"

namespace smokescan::detail {
namespace {

namespace fs = std::filesystem;
constexpr const char* kModuleName = "libsmokescan_oiio.so";

/// The shared object holding this code, by its absolute path; empty when it is the program itself
/// (whose name as the loader knows it is argv[0], which says nothing of where the program lies).
std::string holdingSharedObject()
{
    struct Search {
        uintptr_t address;
        std::string name;
    } s{reinterpret_cast<uintptr_t>(&holdingSharedObject), {}};
    dl_iterate_phdr(
        [](dl_phdr_info* info, size_t, void* data) {
            auto* s = static_cast<Search*>(data);
            for (int i = 0; i < info->dlpi_phnum; ++i) {
                const ElfW(Phdr)& p = info->dlpi_phdr[i];
                const uintptr_t lo = info->dlpi_addr + p.p_vaddr;
                if (p.p_type == PT_LOAD && s->address >= lo && s->address < lo + p.p_memsz) {
                    s->name = info->dlpi_name ? info->dlpi_name : "";
                    return 1;
                }
            }
            return 0;
        },
        &s);
    return !s.name.empty() && s.name.front() == '/' ? s.name : std::string();
}

/// Whether `p` lies in the build tree this code was compiled in (false when it was not).
bool inBuildTree([[maybe_unused]] const fs::path& p)
{
#ifdef SMOKESCAN_BUILD_DIR
    const std::string dir = fs::path(SMOKESCAN_BUILD_DIR).lexically_normal().string() + "/";
    return p.lexically_normal().string().compare(0, dir.size(), dir) == 0;
#else
    return false;
#endif
}

/// Where to look, in order: $SMOKESCAN_OIIO_MODULE alone when set (made absolute); else beside the
/// shared object holding this code (the installed Python module has one beside it), beside the
/// program, in the library folder beside its bin/ (an installed tree moved elsewhere); then the
/// build tree's module and the installed one, the build tree's first only for a program (or shared
/// object) inside the build tree: an installed program never prefers a build tree's module. Never
/// the working folder.
std::vector<std::string> candidates()
{
    if (const char* env = std::getenv("SMOKESCAN_OIIO_MODULE"); env && *env) {
        std::error_code ec;
        const fs::path p = fs::absolute(env, ec);
        return {ec ? std::string(env) : p.string()};
    }
    std::vector<std::string> out;
    const std::string holder = holdingSharedObject();
    if (!holder.empty()) out.push_back((fs::path(holder).parent_path() / kModuleName).string());
    std::error_code ec;
    const fs::path self = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        out.push_back((self.parent_path() / kModuleName).string());
#ifdef SMOKESCAN_OIIO_INSTALL_DIR
        out.push_back((self.parent_path().parent_path() / SMOKESCAN_OIIO_INSTALL_DIR / kModuleName).string());
#endif
    }
    std::vector<std::string> tail;
#ifdef SMOKESCAN_OIIO_BUILD_PATH
    tail.emplace_back(SMOKESCAN_OIIO_BUILD_PATH);
#endif
#ifdef SMOKESCAN_OIIO_INSTALL_PATH
    tail.emplace_back(SMOKESCAN_OIIO_INSTALL_PATH);
#endif
    const bool built_here = (!ec && inBuildTree(self)) || (!holder.empty() && inBuildTree(holder));
    if (!built_here) std::reverse(tail.begin(), tail.end());
    out.insert(out.end(), tail.begin(), tail.end());
    return out;
}

const OiioApi* load()
{
    std::string tried;
    for (const std::string& path : candidates()) {
        struct stat st {};
        if (::stat(path.c_str(), &st) != 0) {
            tried += (tried.empty() ? "" : ", ") + path;
            continue;
        }
        // A FIFO or a device would block dlopen; a folder or an unreadable file is no module.
        if (!S_ISREG(st.st_mode)) throw Error(path, "smokescan's image module is not a regular file");
        if (::access(path.c_str(), R_OK) != 0)
            throw Error(path, std::string("cannot read smokescan's image module (") + std::strerror(errno) + ")");
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
