#pragma once
/// @file image.hpp
/// @brief Float images and their files, through OpenImageIO.
#include <string>
#include <vector>

namespace smokescan {

struct Image {
    int width = 0, height = 0, channels = 0;
    std::vector<std::string> channel_names;  ///< e.g. {"R","G","B"}; empty = the format's default
    std::vector<float> data;  ///< row-major, interleaved channels, row 0 at the top

    Image() = default;
    Image(int w, int h, int c) : width(w), height(h), channels(c), data(size_t(w) * h * c, 0.0f) {}
    float& at(int x, int y, int c) { return data[(size_t(y) * width + x) * channels + c]; }
    /// Index of the channel named `name` (files may reorder channels: EXR sorts them by name), or
    /// `fallback` when there is no such name.
    int channel(const std::string& name, int fallback) const
    {
        for (size_t i = 0; i < channel_names.size(); ++i)
            if (channel_names[i] == name) return int(i);
        return fallback;
    }
    float at(int x, int y, int c) const { return data[(size_t(y) * width + x) * channels + c]; }
};

/// @brief Writes an image atomically (temporary file, then rename). The format follows the
/// extension: .exr keeps 32-bit floats (linear data); .png, .jpg, .tif store 8 bits, from
/// values in [0, 1] already encoded for display (clamped, rounded).
/// @throw Error naming the file: unknown extension, unwritable path, writer failure.
void writeImage(const std::string& path, const Image& img);

/// @brief Reads any image OpenImageIO reads, as floats (8-bit files map to [0, 1]).
/// @throw Error naming the file.
Image readImage(const std::string& path);

/// True for extensions writeImage accepts.
bool isImageExtension(const std::string& path);

}  // namespace smokescan
