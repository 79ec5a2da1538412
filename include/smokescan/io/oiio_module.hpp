#pragma once
/// @file oiio_module.hpp
/// @brief OpenImageIO, loaded when an image is first read, written or drawn.
///
/// Linking OpenImageIO loads about 260 shared libraries (codecs, DICOM, video) and resolves their
/// symbols before main: 0.2–0.3 s on every start of the CLI, the tests and the Python module, most
/// of which never touch an image. Its calls live instead in a module of their own
/// (libsmokescan_oiio.so, src/io/plugin/oiio_module.cpp), opened with dlopen on first use. Its
/// functions never throw: each returns false and says why. Used by image.hpp and the plot canvas.
#include <string>

#include "smokescan/io/image.hpp"

namespace smokescan::detail {

/// The module's functions (the same compiler and C++ library on both sides: std types pass).
struct OiioApi {
    int version;  ///< kOiioApiVersion of the module's build
    /// Writes `img` to `path` (floats when `as_float`, else 8 bits, sRGB) by the extension's writer.
    bool (*write)(const std::string& path, const Image& img, bool as_float, std::string& why);
    /// Opens `path` (one open: what is checked is what is read), sizes `img` by its header (a
    /// volume or a deep image is refused), asks `admit` whether to read it, then reads its pixels
    /// as floats. `why` is a message for the user (or admit's own).
    bool (*read)(const std::string& path, Image& img, bool (*admit)(const Image& header, std::string& why),
                 std::string& why);
    /// Canvas drawing on an RGB float image in place (OpenImageIO's ImageBufAlgo).
    void (*line)(Image& img, int x0, int y0, int x1, int y1, const float* rgb);
    void (*box)(Image& img, int x0, int y0, int x1, int y1, const float* rgb, bool fill);
    /// The text's extent from its baseline's left end [px]; false without glyphs (or the font).
    bool (*textSize)(const std::string& s, int size, int extent[4]);
    void (*text)(Image& img, int x, int y, const std::string& s, int size, const float* rgb);
};

constexpr int kOiioApiVersion = 2;

/// @brief The module, loaded once (thread-safe). Where from: $SMOKESCAN_OIIO_MODULE alone when
/// set; else beside the shared object holding the library (the Python module), beside the program,
/// its ../lib/smokescan, the build tree, the installed library folder (docs/architecture.md).
/// @throw Error when it cannot be loaded, naming where it looked.
const OiioApi& oiio();

}  // namespace smokescan::detail

/// The module's one entry point.
extern "C" const smokescan::detail::OiioApi* smokescan_oiio_api();
