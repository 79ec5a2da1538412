#pragma once
/// @file canvas.hpp
/// @brief A white canvas for the report plots (calibration, fit): lines, boxes, text, then an
/// Image. Drawn with OpenImageIO's ImageBufAlgo (through io/oiio_module.hpp, loaded on first use).
#include <array>
#include <memory>
#include <string>

#include "smokescan/io/image.hpp"

namespace smokescan {

/// Linear RGB in [0, 1].
using Col = std::array<float, 3>;

class Canvas {
public:
    /// @param width_px, height_px the canvas size [px]
    Canvas(int width_px, int height_px);
    ~Canvas();
    Canvas(const Canvas&) = delete;
    Canvas& operator=(const Canvas&) = delete;

    /// @brief A line from (x0, y0) to (x1, y1) [px, y down].
    void line(int x0, int y0, int x1, int y1, const Col& c);
    /// @brief A box with corners (x0, y0), (x1, y1), filled or outlined.
    void box(int x0, int y0, int x1, int y1, const Col& c, bool fill);
    /// @brief Text with its baseline's left end at (x, y), in DejaVu Sans at `size` px. Without
    /// the font the plot has no labels rather than failing; text that would run past the image's
    /// edge is left out (a long legend never aborts a run).
    void text(int x, int y, const std::string& s, int size = 14, const Col& c = {0, 0, 0});
    /// @brief The canvas as an image, clamped to [0, 1].
    Image image() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace smokescan
