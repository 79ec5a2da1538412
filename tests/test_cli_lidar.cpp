// `smokescan scan --sensor PRESET`: a 3D lidar's frames as point-cloud files, and the bad input a
// user can give it (one line, exit != 0, no folder left behind).
#include <gtest/gtest.h>

#include <algorithm>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_run.hpp"
#include "smokescan/io/image.hpp"

namespace fs = std::filesystem;

using namespace smokescan::test;

namespace {

/// The PCD header's value of `key` ("POINTS", "FIELDS", ...).
std::string pcdHeader(const fs::path& p, const std::string& key)
{
    std::ifstream in(p, std::ios::binary);
    for (std::string line; std::getline(in, line) && line.rfind("DATA", 0) != 0;)
        if (line.rfind(key + " ", 0) == 0) return line.substr(key.size() + 1);
    return "";
}

}  // namespace

TEST(LidarCli, ScanWritesOnePointCloudPerFrameAtTheSensorsRate)
{
    const fs::path pts = dir() / "os1_points";
    fs::remove_all(pts);
    const CliRun r = cli("scan plume --sensor os1-128 --returns dual --from 20 --to 20.25 --points " + pts.string());
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("3 pcd frames of the os1-128 (128 channels x 1024 columns, 10 Hz, dual returns)"),
              std::string::npos)
        << r.out;
    for (const char* f : {"000000.pcd", "000001.pcd", "000002.pcd"}) {
        ASSERT_TRUE(fs::exists(pts / f)) << f;
        EXPECT_EQ(pcdHeader(pts / f, "FIELDS"), "x y z intensity ring return_index time source");
        const long long n = std::stoll(pcdHeader(pts / f, "POINTS"));
        EXPECT_GT(n, 10000);  // the plume scene's walls and floor
        // Binary data after the header: 24 bytes a point (4+4+4+4+2+1+4+1).
        const std::string text = slurp(pts / f);
        const size_t data = text.find("DATA binary\n");
        ASSERT_NE(data, std::string::npos);
        EXPECT_EQ(text.size(), data + 12 + size_t(n) * 24);
    }
    EXPECT_FALSE(fs::exists(pts / "000003.pcd"));
    // frames.csv: a line a frame, its file and start time (--from + k / 10 Hz), the sensor's pose;
    // each PCD's VIEWPOINT is that start pose (the plume's LMS200 stands still at z = 0.5 m).
    std::istringstream index(slurp(pts / "frames.csv"));
    std::string line;
    ASSERT_TRUE(std::getline(index, line));
    EXPECT_EQ(line.substr(0, 24), "frame,file,start_s,end_s");
    for (int k = 0; k < 3; ++k) {
        ASSERT_TRUE(std::getline(index, line)) << k;
        std::vector<std::string> cell;
        std::istringstream row(line);
        for (std::string c; std::getline(row, c, ',');) cell.push_back(c);
        ASSERT_EQ(cell.size(), 18u) << line;
        EXPECT_EQ(cell[1], "00000" + std::to_string(k) + ".pcd");
        EXPECT_NEAR(std::stod(cell[2]), 20 + 0.1 * k, 1e-9);
        EXPECT_NEAR(std::stod(cell[3]) - std::stod(cell[2]), 0.1 * 1023 / 1024, 1e-6);  // the last column's firing
        std::string viewpoint = cell[4];
        for (int i = 5; i < 11; ++i) viewpoint += " " + cell[size_t(i)];
        EXPECT_EQ(pcdHeader(pts / cell[1], "VIEWPOINT"), viewpoint);
        EXPECT_EQ(std::stod(cell[6]), 0.5);
    }
    EXPECT_FALSE(std::getline(index, line));
    // Each frame is its own turn of the head: the clouds drift between them.
    EXPECT_NE(slurp(pts / "000000.pcd"), slurp(pts / "000001.pcd"));
    const fs::path ply = dir() / "vlp_points";
    fs::remove_all(ply);
    const std::string range = file("vlp_range.png"), top = file("vlp_top.png");
    const CliRun v = cli("scan plume --sensor vlp16 --rate 20 --points-format ply --points " + ply.string() +
                         " --range-image " + range + " --top-view " + top);
    ASSERT_EQ(v.status, 0) << v.err;
    EXPECT_NE(v.out.find("1 ply frames of the vlp16 (16 channels x 904 columns, 20 Hz, strongest returns)"),
              std::string::npos)
        << v.out;
    EXPECT_TRUE(fs::exists(ply / "000000.ply"));
    const smokescan::Image r_im = smokescan::readImage(range), t_im = smokescan::readImage(top);
    EXPECT_EQ(r_im.width, 904);  // a column per firing cycle
    EXPECT_EQ(r_im.height, 16 * 14);  // 16 channels, each row 14 times
    EXPECT_EQ(t_im.width, 800);
}

TEST(LidarCli, BadLidarOptionsAreOneLineErrorsAndLeaveNoFolder)
{
    const std::string pts = (dir() / "bad_points").string();
    fs::remove_all(pts);
    const std::string scan = "scan plume --points " + pts + " --sensor ";
    expectBad(scan + "os1-128 --returns both", "unknown return mode 'both' (first, last, strongest or dual)", pts);
    expectBad(scan + "os1-128 --returns last", "the os1-128 offers strongest, dual, not last", pts);
    expectBad(scan + "os1-128 --rate 20 --columns 2048",
              "--rate and --columns: the os1-128 fires at most 20480 columns a second", pts);
    expectBad(scan + "vlp16 --rate 7", "--rate: the vlp16 spins at 5, 10, 15, 20 Hz, not 7", pts);
    expectBad(
        scan + "vlp16 --columns 1024",
        "--columns: the vlp16's columns follow from its rate (a column each firing cycle): 1808 at 10 Hz, not 1024",
        pts);
    expectBad(scan + "os1-128 --columns 8192", "--columns: the os1-128 offers 512, 1024, 2048 columns, not 8192", pts);
    expectBad(scan + "vlp16 --points-format las", "--points-format: must be pcd or ply", pts);
    expectBad(scan + "vlp16 --out x.log", "--out: is for the 2D lasers", pts);
    expectBad(scan + "vlp16 --top-view " + (dir() / "t.bmpx").string(), "t.bmpx: unknown image format", pts);
    {
        // The bound on frames, in the plume made to last 30,000 s.
        std::string longer = slurp("scenes/plume.toml");
        longer.replace(longer.find("t_end_s = 150\n"), 14, "t_end_s = 30000\n");
        expectBad(
            "scan " + file("plume_long.toml", longer) + " --points " + pts + " --sensor vlp16 --from 0 --to 20000",
            "would make 200001 lidar frames (at most 100000)", pts);
    }
    // Frames within the scene's time (plume: 0 to 150 s), the last ending by its end; the option
    // that set the time at fault named.
    expectBad(scan + "vlp16 --from -1", "--from: -1 s is before the scene's start, 0 s", pts);
    expectBad(scan + "vlp16 --from -1e-9", "--from: -1e-09 s is before the scene's start, 0 s", pts);
    expectBad(scan + "vlp16 --from 151", "--from: 151 s is after the scene's end, 150 s", pts);
    expectBad(scan + "vlp16 --from 20 --to -1", "--to: -1 s is before the scene's start, 0 s", pts);
    expectBad(scan + "vlp16 --from 149.95", "--from: the last frame, from 149.95 s, ends at 150.0", pts);
    expectBad(scan + "vlp16 --from 149 --to 150", "--to: the last frame, from 150 s, ends at 150.0", pts);
    expectBad(scan + (dir() / "nosuch.toml").string(), "nosuch.toml", pts);
    expectBad("scan plume --sensor vlp16", "--points: a lidar's frames need a folder", pts);
    expectBad("scan bocas --sensor urg04lx --out " + file("u.log") + " --returns dual", "--returns: is for a 3D lidar",
              file("u.log"));
    expectBad("scan bocas --sensor urg04lx", "--out: a 2D laser's scans need a log", pts);
    expectBad(scan + "vlp16 --target wall", "--target: is for the 2D lasers", pts);
    expectBad(scan + "vlp16 --camera-offset 2", "--camera-offset: is for the 2D lasers", pts);
    expectBad(scan + "vlp16 --top-view-width 5", "--top-view-width: needs --top-view", pts);
    expectBad("scan bocas --sensor urg04lx --out " + file("u2.log") + " --top-view-width 5",
              "--top-view-width: is for a 3D lidar", file("u2.log"));
    expectBad("scan plume --sensor vlp32 --points " + pts, "no sensor named or of type 'vlp32'", pts);
    // Folder names refused before the work, not after it: a name too long for the file system,
    // a folder named by '.', and a picture inside the points folder.
    expectBad("scan plume --sensor vlp16 --points " + (dir() / std::string(300, 'a')).string(),
              "has a name of 300 bytes (at most 255)", pts);
    fs::create_directories(dir() / "dotted");
    expectBad("scan plume --sensor vlp16 --points " + (dir() / "dotted" / ".").string(), "names its folder by '.'",
              (dir() / "dotted" / "000000.pcd").string());
    fs::create_directories(dir() / "inside");
    expectBad("scan plume --sensor vlp16 --points " + (dir() / "inside").string() + " --range-image " +
                  (dir() / "inside" / "r.png").string(),
              "--range-image: '" + (dir() / "inside" / "r.png").string() + "' lies inside the --points folder",
              (dir() / "inside" / "r.png").string());
    // A preset's pattern file is an input: no output may replace it, and a pattern has no range image.
    const fs::path pat = dir() / "pat";
    fs::create_directories(pat);
    std::ofstream(pat / "beams.png") << "0, 0, 0\n10, 0, 0.01\n";
    std::ofstream(pat / "p.toml") << "name = \"p\"\npattern = \"file\"\npattern_file = \"beams.png\"\n";
    expectBad(scan + (pat / "p.toml").string() + " --top-view " + (pat / "beams.png").string(), "pattern file", pts);
    EXPECT_EQ(slurp(pat / "beams.png"), "0, 0, 0\n10, 0, 0.01\n");
    expectBad(scan + (pat / "p.toml").string() + " --range-image " + (dir() / "r.png").string(),
              "--range-image: the p fires a pattern file", pts);
    // An existing folder with files in it is never replaced.
    fs::create_directories(pts);
    std::ofstream(fs::path(pts) / "keep.txt") << "mine";
    const CliRun r = cli(scan + "vlp16");
    EXPECT_NE(r.status, 0);
    EXPECT_TRUE(fs::exists(fs::path(pts) / "keep.txt"));
    EXPECT_FALSE(fs::exists(fs::path(pts) / "000000.pcd"));
}

TEST(LidarCli, DiagnosePointsWritesItsFolderAndRefusesOtherRunsOptions)
{
    const fs::path pts = dir() / "diag_points", out = dir() / "diag_points_out";
    fs::remove_all(pts);
    fs::remove_all(out);
    ASSERT_EQ(cli("scan factory_smoke --sensor vlp16 --from 38 --to 38.15 --points " + pts.string()).status, 0);
    const std::string base = "diagnose --scene factory_smoke --points " + pts.string() + " --sensor vlp16 ";
    // Another run's options, the lidar's without --points, no --sensor, --out inside the frames:
    // one line each, nothing written.
    for (const auto& [args, says] : std::vector<std::pair<std::string, std::string>>{
             {base + "--unit m --out " + out.string(), "--unit: is not an option of a 3D lidar's diagnosis"},
             {base + "--seed 3 --out " + out.string(), "--seed: is not an option of a 3D lidar's diagnosis"},
             {"diagnose --scene bocas --laser x.log --returns dual --out " + out.string(),
              "--returns: is a 3D lidar's option"},
             {"diagnose --scene factory_smoke --points " + pts.string() + " --out " + out.string(),
              "--sensor: names the lidar"},
             {base + "--out " + (pts / "diag").string(), "lies in the frames' folder"},
             {base + "--returns dual --out " + out.string(), "--returns: dual, but the frames"}}) {
        const CliRun r = cli(args);
        EXPECT_NE(r.status, 0) << args;
        EXPECT_NE(r.err.find(says), std::string::npos) << args << "\n" << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_FALSE(fs::exists(out)) << args;
        EXPECT_FALSE(fs::exists(pts / "diag")) << args;
    }
    const CliRun r = cli(base + "--out " + out.string());
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("verdict: none"), std::string::npos) << r.out;
    // Nearly every certain beam answered (a rare beam differs between compilers' floating point).
    const size_t at = r.out.find(" % of them unanswered; 0 points matched no beam");
    ASSERT_NE(at, std::string::npos) << r.out;
    EXPECT_LT(std::stod(r.out.substr(r.out.rfind(' ', at - 1) + 1)), 0.1) << r.out;
    const nlohmann::json j = nlohmann::json::parse(slurp(out / "diagnosis.json"));
    EXPECT_EQ(j["verdict"], "none");
    EXPECT_EQ(j["sensor"], "vlp16");
    EXPECT_EQ(j["returns"], "strongest");
    EXPECT_EQ(j["frames"], 2);
    EXPECT_EQ(j["tried"].size(), 5u);
    EXPECT_EQ(j["rings"].size(), 16u);
    EXPECT_NE(slurp(out / "report.md").find("Verdict: **none**"), std::string::npos);
}

TEST(LidarCli, FitPointsWritesThePresetExtendedByTheSurfacesAndRefusesOtherRunsOptions)
{
    const fs::path pts = dir() / "fit_points", out = dir() / "fit_points.toml",
                   report = dir() / "fit_points_report.json", again = dir() / "fit_points_again";
    for (const fs::path& p : {pts, out, report, again}) fs::remove_all(p);
    ASSERT_EQ(cli("scan factory_smoke --sensor vlp16 --from 20 --to 20.05 --points " + pts.string()).status, 0);
    const std::string base = "fit --scene factory_smoke --points " + pts.string() + " --sensor vlp16 ";
    // A whole preset (the VLP-16's) and one extending it.
    const fs::path whole = dir() / "fit_whole.toml", ext = dir() / "fit_ext.toml";
    fs::copy_file(std::string(SMOKESCAN_SOURCE_DIR) + "/presets/lidar/vlp16.toml", whole,
                  fs::copy_options::overwrite_existing);
    std::ofstream(ext) << "name = \"mine\"\nbase = \"fit_whole.toml\"\n";
    const std::string whole_text = slurp(whole);
    // Another run's options, the lidar's without --points, no --scene or --sensor, an output in
    // the frames' folder, a return mode the frames do not hold: one line each, nothing written.
    for (const auto& [args, says] : std::vector<std::pair<std::string, std::string>>{
             {base + "--saturation s.csv --out " + out.string(), "--saturation: is not an option of a 3D lidar's fit"},
             {base + "--offset 2 --out " + out.string(), "--offset: is not an option of a 3D lidar's fit"},
             {"fit --laser x.log --saturation s.csv --returns dual --out " + out.string(),
              "--returns: is a 3D lidar's option"},
             {"fit --laser x.log --out " + out.string(), "--saturation: is required"},
             {"fit --points " + pts.string() + " --sensor vlp16 --out " + out.string(), "--scene: names the scene"},
             {"fit --scene factory_smoke --points " + pts.string() + " --out " + out.string(),
              "--sensor: names the lidar"},
             {base + "--out " + (pts / "x.toml").string(), "lies in the frames' folder"},
             {base + "--out " + out.string() + " --report " + (pts / "r.json").string(), "lies in the frames' folder"},
             {base + "--returns dual --out " + out.string(), "--returns: dual, but the frames"},
             {base + "--rate 20 --out " + out.string(), "another rate or column count"},
             {base + "--out " + (dir() / "fit_points_noext").string(), "must name a .toml file"},
             {base + "--out ''", "--out: '' must name a .toml file"},
             {base + "--out " + out.string() + " --report ''", "--report: must not be empty"},
             {"fit --scene factory_smoke --points '' --sensor vlp16 --out " + out.string(),
              "--points: names no folder"},
             // The preset's base is an input too: never written over.
             {"fit --scene factory_smoke --points " + pts.string() + " --sensor " + ext.string() + " --out " +
                  whole.string(),
              "--out would destroy it"}}) {
        const CliRun r = cli(args);
        EXPECT_NE(r.status, 0) << args;
        EXPECT_NE(r.err.find(says), std::string::npos) << args << "\n" << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_FALSE(fs::exists(out)) << args;
        EXPECT_FALSE(fs::exists(report)) << args;
        EXPECT_FALSE(fs::exists(pts / "x.toml") || fs::exists(pts / "r.json")) << args;
        EXPECT_EQ(slurp(whole), whole_text) << args;
    }
    // One frame is enough (the fit holds nothing out).
    const CliRun r = cli(base + "--out " + out.string());
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("wrote " + out.string()), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("warning"), std::string::npos) << r.out;  // the room is the recording's
    const nlohmann::json j = nlohmann::json::parse(slurp(report));
    EXPECT_EQ(j["frames"], 1);
    EXPECT_EQ(j["sensor"], "vlp16");
    // The room as the scene says it: every fitted surface's factor 1 within its errors and a
    // thousandth, the receiver's noise the preset's.
    int fitted = 0;
    for (const auto& s : j["surfaces"]) {
        if (!s["fitted"].get<bool>()) continue;
        ++fitted;
        EXPECT_FALSE(s["misfit"].get<bool>()) << s.dump();
        EXPECT_NEAR(s["reflectance_factor"].get<double>(), 1,
                    4 * std::hypot(s["reflectance_factor_se"].get<double>(), s["reflectance_factor_sys"].get<double>()))
            << s.dump();
    }
    EXPECT_GE(fitted, 6);
    EXPECT_NEAR(j["intensity_scatter"].get<double>(), 1, 0.1);
    EXPECT_NEAR(j["range_sd_m"].get<double>(), j["preset_range_sd_m"].get<double>(), 0.1 * 0.015);
    // The preset it wrote is a lidar a scan takes, extended by those surfaces.
    const std::string preset = slurp(out);
    EXPECT_EQ(preset, j["extended_preset"].get<std::string>());
    EXPECT_NE(preset.find("name = \"vlp16-extended\"\nbase = \"vlp16\"\n"), std::string::npos) << preset;
    EXPECT_EQ(size_t(std::count(preset.begin(), preset.end(), '[') / 2), size_t(fitted)) << preset;
    const CliRun s =
        cli("scan factory_smoke --sensor " + out.string() + " --from 20 --to 20.05 --points " + again.string());
    EXPECT_EQ(s.status, 0) << s.err;
    EXPECT_NE(s.out.find("of the vlp16-extended"), std::string::npos) << s.out;
}
