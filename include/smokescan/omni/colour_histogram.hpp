#pragma once
/// @file colour_histogram.hpp
/// @brief The omnicam rangefinder's free-space model (Nguyen and Visser, Eqs. 4–5): a histogram
/// of the RGB values of pixels known to be free floor; a pixel is free space when its bin holds at
/// least a share Θ of all the counts.
///
/// | parameter        | default | unit | meaning                                             |
/// |------------------|---------|------|-----------------------------------------------------|
/// | bins_per_channel | 13      | –    | the paper's 13 bins, on each of R, G and B (13³ bins) |
/// | threshold        | –       | –    | Θ ∈ (0, 1]: 0.05 in the maze, 0.075 in the factory   |
///
/// Values are display-encoded (8-bit sRGB as a camera delivers, mapped to [0, 1]); channel value v
/// falls in bin min(⌊v·bins⌋, bins − 1). The colours mean something only at the exposure of the
/// frames they were counted in: the histogram keeps it (0: unknown) and its file records it.
#include <cstdint>
#include <string>
#include <vector>

namespace smokescan {

class ColourHistogram {
public:
    /// @throw Error for bins_per_channel outside 1…64.
    explicit ColourHistogram(int bins_per_channel = 13);

    /// @brief Counts one pixel (values outside [0, 1] are clamped).
    void add(float r, float g, float b);
    /// @brief The share c[rgb]/T_c of all counts in the pixel's bin (0 for an empty histogram).
    double share(float r, float g, float b) const;
    /// @brief Free space: share ≥ threshold.
    bool isFree(float r, float g, float b, double threshold) const { return share(r, g, b) >= threshold; }

    int binsPerChannel() const { return bins_; }
    uint64_t total() const { return total_; }
    uint64_t count(int bin_r, int bin_g, int bin_b) const;

    /// The radiance scale of the frames it was trained on; 0 = unknown.
    double exposure() const { return exposure_; }
    /// @throw Error for a scale outside [1e-6, 1e6] (0 = unknown is allowed).
    void setExposure(double scale);

    /// @brief Writes the histogram as text (atomically): a header line, "# exposure x" when
    /// known, then one line per non-empty bin "r g b count". @throw Error naming the file.
    void save(const std::string& path) const;
    /// @brief Reads what save wrote. @throw Error naming the file and line: a bad header, a bin
    /// outside the histogram, a repeated bin, a count that is not a positive integer, no counts,
    /// an exposure outside [1e-6, 1e6] or given twice.
    static ColourHistogram load(const std::string& path);

private:
    int bin(float v) const;
    size_t index(int r, int g, int b) const { return (size_t(r) * bins_ + g) * bins_ + b; }

    int bins_;
    std::vector<uint64_t> counts_;
    uint64_t total_ = 0;
    double exposure_ = 0;
};

}  // namespace smokescan
