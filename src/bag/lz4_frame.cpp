#include "lz4_frame.hpp"

#include <lz4frame.h>

#include <memory>

#include "smokescan/core/error.hpp"

namespace smokescan::detail {

void unpackLz4Frame(const uint8_t* p, size_t n, std::vector<uint8_t>& out, const std::string& where)
{
    LZ4F_dctx* ctx = nullptr;
    if (LZ4F_isError(LZ4F_createDecompressionContext(&ctx, LZ4F_VERSION))) throw Error(where, "lz4: no context");
    std::unique_ptr<LZ4F_dctx, decltype(&LZ4F_freeDecompressionContext)> guard(ctx, LZ4F_freeDecompressionContext);
    size_t in_at = 0, out_at = 0;
    while (in_at < n) {
        size_t src = n - in_at, dst = out.size() - out_at;
        const size_t r = LZ4F_decompress(ctx, out.data() + out_at, &dst, p + in_at, &src, nullptr);
        if (LZ4F_isError(r))
            throw Error(where, std::string("could not be decompressed (lz4: ") + LZ4F_getErrorName(r) + ")");
        in_at += src;
        out_at += dst;
        if (r == 0) break;
        if (src == 0 && dst == 0) throw Error(where, "could not be decompressed (lz4: no progress)");
    }
    if (out_at != out.size())
        throw Error(where, "decompresses to " + std::to_string(out_at) + " bytes, not " + std::to_string(out.size()));
}

}  // namespace smokescan::detail
