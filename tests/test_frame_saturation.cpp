// The measurement on recorded frames (camera/frame_saturation.hpp): regions and the encoding of
// linear frames, against values worked out by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "smokescan/camera/frame_saturation.hpp"
#include "smokescan/core/error.hpp"

using namespace smokescan;

namespace {

/// The HSV saturation of a linear colour delivered as an 8-bit sRGB pixel, by hand.
double deliveredSaturation(double r, double g, double b)
{
    auto enc = [](double v) { return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055; };
    const double R = std::round(enc(r) * 255), G = std::round(enc(g) * 255), B = std::round(enc(b) * 255);
    const double mx = std::max({R, G, B}), mn = std::min({R, G, B});
    return (mx - mn) / mx;
}

Image flat(int w, int h, float r, float g, float b)
{
    Image img(w, h, 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            img.at(x, y, 0) = r;
            img.at(x, y, 1) = g;
            img.at(x, y, 2) = b;
        }
    return img;
}

}  // namespace

TEST(FrameSaturation, LinearFramesAreMeasuredAsTheCameraDeliversThem)
{
    // A linear frame of one colour: its saturation is that of the sRGB-encoded 8-bit pixel
    // (124, 89, 63: 0.4919), not of the linear values (0.75) nor of a 1/2.2 gamma (0.4715).
    const Image img = flat(8, 6, 0.2f, 0.1f, 0.05f);
    FrameRegions regions;
    regions.patches.push_back(parseFramePatch("all=0,0,8,6", true, "--rect"));
    const auto m = measureFrame(img, true, nullptr, regions, regions.names());
    EXPECT_EQ(m.all.pixels, 48);
    EXPECT_NEAR(m.all.mean, deliveredSaturation(0.2, 0.1, 0.05), 1e-12);
    EXPECT_NEAR(m.all.mean, 61.0 / 124.0, 1e-12);
    EXPECT_GT(std::abs(m.all.mean - 58.0 / 123.0), 0.01);
    // The same values as delivered (not linear): measured as they are, after 8-bit quantisation.
    const auto d = measureFrame(img, false, nullptr, regions, regions.names());
    EXPECT_NEAR(d.all.mean, (51.0 - 13.0) / 51.0, 1e-12);
}

TEST(FrameSaturation, PolygonsComeFirstThenObjectIds)
{
    // Columns 0–4 blue-ish by a rectangle; columns 4–8 by object id 3 of a scene whose surface 3
    // is target_yellow (yellow-ish, less saturated); column 9 is neither (and very saturated). A
    // pixel in both counts for the polygon only.
    Image img = flat(10, 4, 0.1f, 0.1f, 0.4f);
    for (int y = 0; y < 4; ++y) {
        for (int x = 5; x < 9; ++x) img.at(x, y, 2) = 0.2f, img.at(x, y, 0) = 0.4f, img.at(x, y, 1) = 0.4f;
        img.at(9, y, 0) = 1.0f, img.at(9, y, 1) = 0.0f, img.at(9, y, 2) = 0.0f;
    }
    Image ids(10, 4, 1);
    ids.channel_names = {"object"};
    for (int y = 0; y < 4; ++y)
        for (int x = 4; x < 9; ++x) ids.at(x, y, 0) = 3;
    FrameRegions regions;
    regions.patches.push_back(parseFramePatch("blue=0,0,5,4", true, "--rect"));
    regions.target.names = {"yellow"};
    regions.target.patch_of = {-1, -1, -1, 0};
    regions.by_id = true;
    const auto names = regions.names();
    ASSERT_EQ(names.size(), 2u);
    const auto m = measureFrame(img, false, &ids, regions, names);
    EXPECT_EQ(m.patch[0].pixels, 20);  // columns 0–4: column 4 is in the rectangle and has id 3
    EXPECT_EQ(m.patch[1].pixels, 16);  // columns 5–8
    EXPECT_EQ(m.all.pixels, 36);  // not column 9
    EXPECT_NEAR(m.patch[0].mean, (102.0 - 26.0) / 102.0, 1e-12);
    EXPECT_NEAR(m.patch[1].mean, (102.0 - 51.0) / 102.0, 1e-12);
    EXPECT_NEAR(m.all.mean, (20 * 76.0 / 102.0 + 16 * 51.0 / 102.0) / 36, 1e-12);
}

TEST(FrameSaturation, BadPatchSpecsAndNamesAreOneLineErrors)
{
    EXPECT_THROW(parseFramePatch("a=0,0,-1,4", true, "--rect"), Error);
    EXPECT_THROW(parseFramePatch("=0,0,1,1", true, "--rect"), Error);
    EXPECT_THROW(parseFramePatch("p=0,0,1,1,2", false, "--polygon"), Error);
    EXPECT_THROW(frameTimeFromName("/x/frame.png", 0), Error);
    EXPECT_DOUBLE_EQ(frameTimeFromName("/x/frame_000125.png", 25), 5.0);
}

TEST(FrameSaturation, ASeriesKeepsItsFirstFramesSizeAndItsPatchesInsideIt)
{
    FrameSeries inside(frameRegions({"a=0,0,8,6"}, {}));
    inside.add(flat(8, 6, 0.5f, 0.25f, 0.25f), false, nullptr, 1.0, "f1.png");
    try {
        inside.add(flat(4, 3, 0.5f, 0.25f, 0.25f), false, nullptr, 2.0, "f2.png");
        FAIL() << "a frame of another size was measured";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("f2.png: is 4×3 pixels, the first frame 8×6"), std::string::npos)
            << e.what();
    }
    EXPECT_EQ(inside.take().time_s.size(), 1u);
    // A rect one pixel past the frame's edge, and a polygon vertex before it.
    for (const auto& [rects, polygons] :
         {std::pair<std::vector<std::string>, std::vector<std::string>>{{"a=1,1,8,2"}, {}},
          {{}, {"b=-0.5,1,3,1,3,4"}}}) {
        FrameSeries outside(frameRegions(rects, polygons));
        try {
            outside.add(flat(8, 6, 0.5f, 0.25f, 0.25f), false, nullptr, 1.0, "f1.png");
            FAIL() << "a patch outside the frame was clipped";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("outside the 8×6 frame"), std::string::npos) << e.what();
        }
    }
}
