#pragma once
/// @file scanline.hpp
/// @brief The omnicam rangefinder's two filters along one scanline (Nguyen and Visser, Fig. 3),
/// from the image centre outwards: which pixel is the first obstacle.
///
/// | parameter | default | unit | meaning                                                        |
/// |-----------|---------|------|----------------------------------------------------------------|
/// | n_behind  | 20      | px   | N, false positives: a non-free pixel is a hit point only when the N pixels behind it are non-free too |
/// | k_free    | 2       | px   | K, false negatives: a run of fewer than K free pixels between non-free ones does not break a non-free run |
#include <vector>

namespace smokescan {

struct ScanlineFilter {
    int n_behind = 20;
    int k_free = 2;
};

/// @brief The index of the hit point on a scanline of free (true) and non-free (false) pixels,
/// ordered outwards: runs of fewer than k_free free pixels with non-free pixels on both sides
/// count as non-free; then the first non-free pixel followed by n_behind more non-free pixels.
/// −1 when there is none (a candidate too near the line's end to have n_behind pixels behind it
/// is not a hit).
/// @throw Error for n_behind or k_free below 1.
int findHitPoint(const std::vector<bool>& free, const ScanlineFilter& f);

}  // namespace smokescan
