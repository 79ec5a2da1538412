// The cloud-profile measure (cloud_profile.hpp) on hand-made scans.
#include <gtest/gtest.h>

#include <cmath>

#include "smokescan/sensors/cloud_profile.hpp"

using namespace smokescan;

namespace {
/// A beam `col` density·m deep in local smoke whose surface is 5 m away; reads `range_m`
/// (NAN: an error value).
BeamResult beam(double col, double range_m)
{
    BeamResult b;
    b.smoke.column_local = col;
    b.hit.hit = true;
    b.hit.t_m = 5.0;
    if (std::isnan(range_m)) {
        b.error = true;
        b.cause = "weak_echo";
    } else {
        b.true_range_m = range_m;
    }
    return b;
}
}  // namespace

TEST(CloudProfile, SplitsEachRunIntoCoreAndEdgeByItsPeakColumn)
{
    Scan s;
    // clear, a cloud (profile 0.002 0.006 0.02 0.012 0.004), clear, a thin cloud (0.003 0.003)
    s.beams = {beam(0, 5.0),     beam(0.002, NAN), beam(0.006, 3.0), beam(0.02, 2.9), beam(0.012, NAN),
               beam(0.004, 4.9), beam(0, 5.0),     beam(0.003, 3.5), beam(0.003, NAN)};
    CloudProfile p;
    p.add(s);
    const CloudProfileResult& r = p.result();
    EXPECT_EQ(r.runs, 2);
    // core: ≥ max(0.5 × 0.02, 0.005) = 0.01 → 0.02 (obstacle) and 0.012 (error); the thin cloud is all edge
    EXPECT_EQ(r.core_beams, 2);
    EXPECT_EQ(r.core_obstacles, 1);
    EXPECT_EQ(r.core_errors, 1);
    EXPECT_EQ(r.edge_beams, 5);
    EXPECT_EQ(r.edge_obstacles, 2);  // 0.006 at 3.0 m and 0.003 at 3.5 m; 4.9 m is the surface
    EXPECT_EQ(r.edge_errors, 2);
    EXPECT_DOUBLE_EQ(r.coreObstacleShare(), 0.5);
    EXPECT_DOUBLE_EQ(r.errorShareAtEdges(), 2.0 / 3.0);
    EXPECT_DOUBLE_EQ(r.edgeShareOfBeams(), 5.0 / 7.0);
    EXPECT_EQ(r.error_causes.at("weak_echo"), std::make_pair(1LL, 2LL));
    EXPECT_NE(r.text().find("weak_echo 1, 2"), std::string::npos);
    // No surface in range: any range reads as an obstacle.
    CloudProfile q;
    Scan open;
    open.beams = {beam(0.02, 7.0)};
    open.beams[0].hit.hit = false;
    q.add(open);
    EXPECT_EQ(q.result().core_obstacles, 1);
}

TEST(CloudProfile, EmptyAndClearScansCountNothing)
{
    CloudProfile p;
    p.add(Scan{});
    Scan s;
    s.beams = {beam(0, 5.0), beam(0.0005, 5.0), beam(NAN, 5.0)};  // a NaN column is no cloud (and no hang)
    p.add(s);
    EXPECT_EQ(p.result().runs, 0);
    EXPECT_DOUBLE_EQ(p.result().coreObstacleShare(), 0.0);
    EXPECT_DOUBLE_EQ(p.result().errorShareAtEdges(), 0.0);
}
