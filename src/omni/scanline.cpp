#include "smokescan/omni/scanline.hpp"

#include "smokescan/core/error.hpp"

namespace smokescan {

int findHitPoint(const std::vector<bool>& free_in, const ScanlineFilter& f)
{
    if (f.n_behind < 1) throw Error("scanline filter", "N (pixels behind a hit point) must be >= 1");
    if (f.k_free < 1) throw Error("scanline filter", "K (free pixels that break an obstacle) must be >= 1");
    const int n = int(free_in.size());
    std::vector<bool> free = free_in;
    // False negatives: a short free run between non-free pixels is non-free.
    for (int i = 0; i < n;) {
        if (!free_in[size_t(i)]) {
            ++i;
            continue;
        }
        int j = i;
        while (j < n && free_in[size_t(j)]) ++j;
        if (i > 0 && j < n && j - i < f.k_free)
            for (int k = i; k < j; ++k) free[size_t(k)] = false;
        i = j;
    }
    // False positives: the first non-free pixel with n_behind non-free pixels behind it.
    int run = 0;
    for (int i = 0; i < n; ++i) {
        run = free[size_t(i)] ? 0 : run + 1;
        if (run == f.n_behind + 1) return i - f.n_behind;
    }
    return -1;
}

}  // namespace smokescan
