#pragma once
/// @file frame_saturation.hpp
/// @brief The smoke paper's measurement on recorded camera frames: the HSV saturation of the
/// target's pixels, frame by frame, over regions given as pixel polygons or found from a frame's
/// object-id channel (rendered frames). `smokescan saturation` is a thin layer over it.
///
/// | input        | meaning                                                                      |
/// |--------------|------------------------------------------------------------------------------|
/// | frames       | image files (or folders of them, sorted by name), in time order               |
/// | ids          | optional: one id image per frame (channel "object" = scene surface index)    |
/// | patches      | named polygons [px]; a pixel in none of them may still be a target pixel by id |
/// | timestamps   | optional CSV: "file,time_s" rows (or times in frame order); else the last number in each file name ÷ fps |
///
/// Linear frames (EXR) are first encoded as the camera delivers them: the sRGB curve
/// (render/renderer.hpp: srgbEncode), then 8-bit values, as PNG frames are.
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "smokescan/camera/saturation.hpp"
#include "smokescan/camera/saturation_render.hpp"
#include "smokescan/io/recorded.hpp"

namespace smokescan {

/// A named region of a frame: a polygon in pixel coordinates (x right, y down).
struct FramePatch {
    std::string name;
    std::vector<std::pair<double, double>> polygon_px;
};

/// @brief True when (x, y) lies inside the polygon (even–odd rule).
bool insidePolygon(const std::vector<std::pair<double, double>>& polygon, double x, double y);

/// @brief A patch from "NAME=x,y,width,height" (rect) or "NAME=x1,y1,x2,y2,x3,y3,..." (polygon).
/// @throw Error naming `option` for a malformed spec.
FramePatch parseFramePatch(const std::string& spec, bool rect, const std::string& option);

/// @brief Image files of `inputs`: files as given, folders expanded to their images sorted by name.
/// @throw Error for a missing file or a folder without images.
std::vector<std::string> listFrames(const std::vector<std::string>& inputs);

/// @brief Each frame's time [s] from a timestamps CSV: "file,time_s" rows matched by file name,
/// or bare times in frame order. @throw Error naming the file and line.
std::vector<double> readFrameTimestamps(const std::string& timestamps_csv, const std::vector<std::string>& frames);

/// @brief A frame's time [s] from the last number in its file name, divided by fps (fps ≤ 0: the
/// number itself). @throw Error when the name holds no number.
double frameTimeFromName(const std::string& path, double fps);

/// What to measure on each frame.
struct FrameRegions {
    std::vector<FramePatch> patches;  ///< polygons, first match wins
    TargetPatches target;  ///< patches by object id (when id frames are given)
    bool by_id = false;

    /// The patch names, polygons first, then id patches not named by a polygon.
    std::vector<std::string> names() const;
};

/// @brief The patches of "NAME=x,y,width,height" rects and "NAME=x1,y1,…" polygons (parseFramePatch).
/// @throw Error naming --rect/--polygon for a malformed spec or a name given twice.
FrameRegions frameRegions(const std::vector<std::string>& rects, const std::vector<std::string>& polygons);

/// One frame's saturation: over all target pixels and per patch (pixels = 0: none).
struct FrameSaturation {
    SaturationStats all;
    std::vector<SaturationStats> patch;  ///< in FrameRegions::names() order
};

/// @brief Measures one frame. `linear`: the frame holds linear radiance (EXR). `ids`: the frame's
/// id image (required when regions.by_id).
FrameSaturation measureFrame(const Image& frame, bool linear, const Image* ids, const FrameRegions& regions,
                             const std::vector<std::string>& names);

/// A saturation series measured frame by frame, the frames given in time order.
class FrameSeries {
public:
    explicit FrameSeries(const FrameRegions& regions);
    /// @brief Measures one frame (measureFrame) taken at `time_s`.
    /// @throw Error naming `name` when the target region holds no pixels of it, its time does not
    /// follow the previous frame's, its size is not the first frame's, or (on the first frame) a
    /// patch reaches outside it.
    void add(const Image& frame, bool linear, const Image* ids, double time_s, const std::string& name);
    /// @brief The series so far.
    SaturationSeries take() { return std::move(s_); }

private:
    FrameRegions regions_;
    SaturationSeries s_;
    int width_ = 0, height_ = 0;  ///< the first frame's [px]
};

/// @brief The saturation series of a run of frames: whole target and patches (means, with
/// medians, spreads and pixel counts), on the frames' times. Frames are read one at a time.
/// @param id_frames one id image per frame, or empty
/// @param time_of frame k's time [s], asked after the frame has been read
SaturationSeries measureFrames(const std::vector<std::string>& frames, const std::vector<std::string>& id_frames,
                               const std::function<double(size_t)>& time_of, const FrameRegions& regions);

}  // namespace smokescan
