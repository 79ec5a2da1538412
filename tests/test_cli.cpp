// The CLI end to end: the main job works, and bad input gives one line, exit != 0, no output file.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "smokescan/io/image.hpp"
#include "smokescan/io/recorded.hpp"

#include "cli_run.hpp"

namespace fs = std::filesystem;

using namespace smokescan::test;

TEST(Cli, ScanWritesThePapersLogAndSummary)
{
    const std::string log = file("bocas.log"), tau = file("tau.csv");
    const CliRun r = cli("scan bocas --sensor urg04lx --from 90 --to 110 --rate 1 --out " + log + " --tau " + tau);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("error codes on the target"), std::string::npos);
    std::ifstream in(log);
    std::string line;
    int scans = 0;
    while (std::getline(in, line))
        if (!line.empty() && line[0] != '#') {
            std::istringstream ss(line);
            double t;
            ss >> t;
            int fields = 0;
            double x;
            while (ss >> x) ++fields;
            EXPECT_EQ(fields, 2 * 682);
            ++scans;
        }
    EXPECT_EQ(scans, 21);
    EXPECT_EQ(slurp(tau).substr(0, 22), "time_s,beam,angle_rad,");
}

TEST(Cli, AReportThatCannotBeWrittenIsAnErrorNotASilentZero)
{
    // Standard output on a full disk: the run's files are written, but the report is lost, and
    // the exit status says so (as coreutils' tools do).
    if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full on this machine";
    const std::string log = file("full.log"), err = file("full.err");
    const std::string cmd =
        std::string(SMOKESCAN_CLI) + " scan bocas --from 0 --to 1 --out " + log + " >/dev/full 2>" + err;
    const int rc = std::system(cmd.c_str());
    ASSERT_TRUE(WIFEXITED(rc));
    EXPECT_EQ(WEXITSTATUS(rc), 1);
    EXPECT_NE(slurp(err).find("smokescan: standard output: cannot write the report (No space left on device)"),
              std::string::npos)
        << slurp(err);
    EXPECT_TRUE(fs::exists(log));  // So is the help text.
    const int help = std::system((std::string(SMOKESCAN_CLI) + " --help >/dev/full 2>" + err).c_str());
    ASSERT_TRUE(WIFEXITED(help));
    EXPECT_EQ(WEXITSTATUS(help), 1);
}

TEST(Cli, ScanImageDrawsTheSeriesLikeFig10)
{
    const std::string log = file("plume.log"), png = file("plume.png");
    const CliRun r = cli("scan plume --sensor lms200 --from 0 --to 9 --rate 1 --out " + log + " --image " + png);
    ASSERT_EQ(r.status, 0) << r.err;
    const smokescan::Image img = smokescan::readImage(png);
    EXPECT_EQ(img.width, 361 * 2);
    EXPECT_EQ(img.height, 10 * 2);
    expectBad("scan plume --from 0 --to 1 --out " + file("x.log") + " --image " + file("x.bmpx"),
              "unknown image format", file("x.log"));
}

TEST(Cli, ScanPhysicalModelAndSensorFiles)
{
    const std::string log = file("phys.log");
    const std::string sf =
        file("hokuyo.toml", "type = \"urg04lx\"\nmodel = \"physical\"\n[physical]\nnoise_floor = 5.4e-4\n");
    CliRun r = cli("scan bocas --from 0 --to 2 --rate 1 --sensor-file " + sf + " --out " + log);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("model physical"), std::string::npos) << r.out;
    EXPECT_NE(slurp(log).find("model=physical noise_floor=0.00054 "), std::string::npos) << slurp(log).substr(0, 300);
    r = cli("scan bocas --from 0 --to 2 --rate 1 --model physical --out " + log);
    ASSERT_EQ(r.status, 0) << r.err;
    // In the densest smoke the --tau table names each error's cause and the received power.
    r = cli("scan bocas --from 125 --to 126 --rate 1 --model physical --quiet --out " + log + " --tau " +
            file("phys_tau.csv"));
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string tau = slurp(file("phys_tau.csv"));
    EXPECT_EQ(tau.substr(0, tau.find('\n')),
              "time_s,beam,angle_rad,value,error,cause,surface,hit_m,column_regional,column_local,tau,power");
    EXPECT_NE(tau.find(",1,low_intensity,target_blue,"), std::string::npos);
    expectBad("scan bocas --from 0 --to 1 --model magic --out " + file("m.log"), "unknown sensor model", file("m.log"));
    const std::string bad = file("bad_sensor.toml", "type = \"urg04lx\"\n[physical]\nnoise_floor = \"loud\"\n");
    expectBad("scan bocas --from 0 --to 1 --sensor-file " + bad + " --out " + file("b.log"), "bad_sensor.toml:3",
              file("b.log"));
    expectBad("scan bocas --from 0 --to 1 --sensor-file " + file("none.toml") + " --out " + file("n.log"),
              "no such sensor file", file("n.log"));
}

TEST(Cli, VolumeBuildInfoExport)
{
    const std::string vdb = file("bocas.vdb");
    ASSERT_EQ(cli("volume build bocas --time 120 --out " + vdb).status, 0);
    const CliRun info = cli("volume info " + vdb + " --grid room");
    ASSERT_EQ(info.status, 0) << info.err;
    EXPECT_NE(info.out.find("grid 'room'"), std::string::npos);
    const std::string exp = file("export.vdb");
    const CliRun e = cli("volume export volumes/ramp_block_double.vdb --scale 0.01 --out " + exp);
    ASSERT_EQ(e.status, 0) << e.err;
    EXPECT_NE(cli("volume info " + exp).out.find("stored as float"), std::string::npos);
    EXPECT_EQ(cli("volume info bocas --time 120").status, 0);
}

TEST(Cli, RenderWritesFrameAndAovs)
{
    const std::string png = file("f.png"), exr = file("f.exr"), ids = file("ids.exr");
    const CliRun r =
        cli("render bocas --time 100 --spp 2 --width 32 --height 24 --out " + png + " --exr " + exr + " --ids " + ids);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(fs::exists(png) && fs::exists(exr) && fs::exists(ids));
    const CliRun s = cli("render bocas --from 0 --to 20 --every 10 --spp 1 --width 8 --height 6 --out " +
                         (dir() / "series_{i}.png").string());
    ASSERT_EQ(s.status, 0) << s.err;
    for (int i = 0; i < 3; ++i) EXPECT_TRUE(fs::exists(dir() / ("series_000" + std::to_string(i) + ".png")));
}

TEST(Cli, BadInputGivesOneLineAndNoOutput)
{
    const std::string out = file("never.log");
    expectBad("scan bocass --out " + out, "bocass: no such scene file", out);
    expectBad("scan bocas --sensor velodyne --out " + out, "no sensor named or of type 'velodyne'", out);
    expectBad("scan bocas --rate 0 --out " + out, "--rate", out);
    expectBad("scan bocas --from 10 --to 5 --out " + out, "--to", out);
    expectBad("scan bocas --model magic --out " + out, "unknown sensor model", out);
    const std::string bad_key = file("bad_key.toml", "[[materials]]\nname = \"a\"\nshine = 2\n");
    expectBad("scan " + bad_key + " --out " + out, bad_key + ":3: unknown key 'materials[0].shine'", out);
    const std::string bad_type = file("bad_type.toml", "[scene]\nt_end_s = \"late\"\n");
    expectBad("scan " + bad_type + " --out " + out, bad_type + ":2: scene.t_end_s must be a number", out);
    const std::string no_field = file("no_field.toml", "[[sensors]]\nname = \"x\"\n");
    expectBad("scan " + no_field + " --out " + out, "missing field 'sensors[0].type'", out);
    const std::string bad_vdb = file("bad_vdb.toml", "[[smoke]]\nname = \"s\"\ntype = \"vdb\"\nfile = \"nope.vdb\"\n");
    expectBad("scan " + bad_vdb + " --out " + out, "nope.vdb: no such file", out);
    expectBad("scan bocas --from 0 --to 1 --out /nonexistent/dir/x.log", "/nonexistent/dir/x.log: cannot write",
              "/nonexistent/dir/x.log");
    const std::string png = file("never.png");
    const std::string no_cam = file("no_cam.toml", "[[materials]]\nname = \"a\"\n");
    expectBad("render " + no_cam + " --out " + png, "has no camera", png);
    const std::string zero = file("zero.toml", "[[cameras]]\nname = \"c\"\nwidth = 0\n");
    expectBad("render " + zero + " --out " + png, zero + ":3: cameras[0].width must lie in 1…16384 px", png);
    expectBad("render bocas --width 0 --out " + png, "--width: '0' is outside", png);
    const std::string nan_pose = file("nan.toml", "[[cameras]]\nname = \"c\"\nposition = [nan, 0.0, 0.0]\n");
    expectBad("render " + nan_pose + " --out " + png, "cameras[0].position must be an array of 3 finite numbers", png);
    expectBad("render bocas --spp 1 --width 8 --height 6 --out /nonexistent/dir/f.png",
              "/nonexistent/dir/f.png: cannot write", "/nonexistent/dir/f.png");
    expectBad("render bocas --out " + file("f.bmpx"), "unknown image format", file("f.bmpx"));
    expectBad("render bocas --out " + png + " --exr " + file("lin.png"), "must be an .exr", png);
    expectBad("render bocas --camera nope --spp 1 --out " + png, "no camera named 'nope'", png);
    const std::string vdb_out = file("never.vdb");
    expectBad("volume info volumes/fog_ball_float.vdb --grid smoke", "no grid named 'smoke'", vdb_out);
    expectBad("volume export nothere.vdb --out " + vdb_out, "nothere.vdb: no such file", vdb_out);
    expectBad("volume export volumes/fog_ball_float.vdb --scale -1 --out " + vdb_out, "--scale: '-1' must be > 0",
              vdb_out);
}

// A simulated recorded run (the laser's log and the camera's saturation 3 s ahead) goes through
// `fit`; its sensor file drives `scan` again; bad recorded data is a one-line error naming the
// file and line, or, with --lenient, skipped and counted.
TEST(Cli, FitRecoversTheSensorFromASimulatedRun)
{
    const std::string log = file("rec.log"), sat = file("rec_sat.csv"), toml = file("fitted.toml");
    CliRun r = cli("scan bocas --rate 2 --seed 4 --quiet --out " + log + " --saturation-out " + sat +
                   " --saturation-sigma 0.01 --saturation-rate 10 --camera-offset 3");
    ASSERT_EQ(r.status, 0) << r.err;
    r = cli("fit --laser " + log + " --saturation " + sat + " --scene bocas --out " + toml + " --aligned " +
            file("aligned.csv"));
    ASSERT_EQ(r.status, 0) << r.err << r.out;
    EXPECT_NE(r.out.find("clock offset"), std::string::npos);
    for (const auto& f :
         {toml, file("fitted_report.json"), file("fitted_fig5.png"), file("fitted_fig9.png"), file("aligned.csv")})
        EXPECT_TRUE(fs::exists(f)) << f;
    EXPECT_NE(slurp(toml).find("penetration_power = 0.00"), std::string::npos);
    r = cli("scan bocas --from 95 --to 100 --quiet --sensor-file " + toml + " --out " + file("again.log"));
    EXPECT_EQ(r.status, 0) << r.err;

    // The physical model's sensor file: its noise floor fitted in the scene, and used as it is.
    r = cli("fit --model physical --reference target_blue --laser " + log + " --saturation " + sat +
            " --scene bocas --out " + file("phys.toml"));
    ASSERT_EQ(r.status, 0) << r.err << r.out;
    EXPECT_NE(slurp(file("phys.toml")).find("model = \"physical\""), std::string::npos);
    EXPECT_NE(slurp(file("phys_report.json")).find("\"noise_floor\""), std::string::npos);
    r = cli("scan bocas --from 95 --to 96 --quiet --sensor-file " + file("phys.toml") + " --out " +
            file("again_phys.log"));
    EXPECT_EQ(r.status, 0) << r.err;
    expectBad("fit --model physical --laser " + log + " --saturation " + sat + " --surface 'yellow=-3:3@2.5' --out " +
                  file("nophys.toml"),
              "needs --scene", file("nophys.toml"));
    expectBad(
        "fit --model fancy --laser " + log + " --saturation " + sat + " --scene bocas --out " + file("nophys.toml"),
        "unknown sensor model", file("nophys.toml"));

    // Groups by angle instead of a scene; the offset held.
    r = cli("fit --laser " + log + " --saturation " + sat +
            " --surface 'yellow=-3:3@2.5' --fixed-offset --offset 3 --out " + file("f2.toml"));
    EXPECT_EQ(r.status, 0) << r.err << r.out;

    // Bad recorded data.
    std::string text = slurp(log);
    const std::string bad_log = file("bad.log", text + "400.0 0.1 2500 0.2\n");
    expectBad("fit --laser " + bad_log + " --saturation " + sat + " --scene bocas --out " + file("bad.toml"),
              "bad.log:", file("bad.toml"));
    r = cli("fit --lenient --laser " + bad_log + " --saturation " + sat + " --scene bocas --out " + file("len.toml"));
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("skipped 1 bad lines"), std::string::npos) << r.out;
    expectBad("fit --laser " + log + " --saturation " + file("bad_sat.csv", "time_s,saturation\n0,0.5\n1,1.5\n") +
                  " --scene bocas --out " + file("bad.toml"),
              "bad_sat.csv:3: saturation 1.5 is outside [0, 1]", file("bad.toml"));
    expectBad("fit --laser " + log + " --saturation " + file("nan_sat.csv", "0,0.5\n1,nan\n") +
                  " --scene bocas --out " + file("bad.toml"),
              "nan_sat.csv:2", file("bad.toml"));
    expectBad("fit --laser " + log + " --saturation " + file("back_sat.csv", "0,0.5\n2,0.5\n1,0.5\n") +
                  " --scene bocas --out " + file("bad.toml"),
              "time goes backwards", file("bad.toml"));
    expectBad("fit --unit furlong --laser " + log + " --saturation " + sat + " --scene bocas --out " + file("bad.toml"),
              "unknown unit", file("bad.toml"));
    expectBad("fit --laser " + file("odd.log", "0.0 0.1 2500 0.2\n") + " --saturation " + sat +
                  " --scene bocas --out " + file("bad.toml"),
              "odd.log:1: expected a time and (angle, range) pairs", file("bad.toml"));
    expectBad("fit --laser " + file("word.log", "0.0 0.1 abc\n") + " --saturation " + sat + " --scene bocas --out " +
                  file("bad.toml"),
              "word.log:1: field 3 is not a number", file("bad.toml"));
    // Degenerate: the camera's clock a day off: a diagnosis, no sensor file.
    const std::string far_sat = file("far_sat.csv", "86400,0.6\n86401,0.6\n86402,0.1\n86403,0.6\n");
    r = cli("fit --laser " + log + " --saturation " + far_sat + " --scene bocas --out " + file("far.toml"));
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.err.find("do not overlap"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(file("far.toml")));
}

// `fit-plume` on a short simulated Sick run in the plume scene: a table and a JSON report; a log
// that does not exist and a sensor that is not a Sick are one-line errors with no report.
TEST(Cli, FitPlumeReportsTheSickPenetration)
{
    const std::string log = file("sick.log"), out = file("sick_plume.json"), bag = (dir() / "sick_bag").string();
    fs::remove_all(bag);
    CliRun r = cli("scan plume --sensor lms200 --model physical --from 20 --to 80 --rate 0.5 --quiet --out " + log +
                   " --bag " + bag);
    ASSERT_EQ(r.status, 0) << r.err;
    r = cli("fit-plume --laser " + log + " --scene plume --out " + out);
    ASSERT_EQ(r.status, 0) << r.err << r.out;
    EXPECT_NE(r.out.find("penetration depth"), std::string::npos) << r.out;
    EXPECT_NE(slurp(out).find("\"D_m\""), std::string::npos);
    // The same run's bag gives the same fit (its scans read back in the Sick's own units), up to the
    // log's angles written to 1e-6 rad: a few of 6,600 beams graze a plume's edge differently.
    const std::string from_bag = file("sick_plume_bag.json");
    r = cli("fit-plume --bag " + bag + " --scene plume --out " + from_bag);
    ASSERT_EQ(r.status, 0) << r.err << r.out;
    nlohmann::json ja = nlohmann::json::parse(slurp(out)), jb = nlohmann::json::parse(slurp(from_bag));
    EXPECT_EQ(jb["sources"]["laser"], bag + " /scan") << jb.dump().substr(0, 300);
    EXPECT_NEAR(ja["observations"].get<double>(), jb["observations"].get<double>(),
                0.002 * ja["observations"].get<double>());
    for (const auto& [fit, key] : {std::pair{"depth", "D_m"}, {"depth", "k"}, {"echo_share", "rho_50"}})
        EXPECT_NEAR(ja[fit][key]["value"].get<double>(), jb[fit][key]["value"].get<double>(),
                    0.1 * ja[fit][key]["std_error"].get<double>())
            << fit << " " << key;
    expectBad("fit-plume --laser " + file("none.log") + " --scene plume --out " + file("np.json"), "none.log",
              file("np.json"));
    expectBad("fit-plume --laser " + log + " --scene plume --sensor hokuyo --out " + file("np.json"),
              "for the Sick LMS200", file("np.json"));
}

// `scan --saturation-out --saturation-render`: the camera's stream measured in rendered frames,
// with the target's patches as extra columns, close to the cheap prediction; the kept frames
// re-measured by `smokescan saturation` give the same stream; asking for frames without a stream,
// or from a camera the scene lacks, is a one-line error with no log.
TEST(Cli, ScanSaturationFromRenderedFrames)
{
    const std::string rs = file("rendered_sat.csv"), ps = file("predicted_sat.csv");
    const std::string common = "scan bocas --from 98 --to 102 --rate 1 --quiet --saturation-rate 0.5 ";
    const std::string frames = file("rendered_frames");
    CliRun r =
        cli(common + "--out " + file("rs.log") + " --saturation-out " + rs +
            " --saturation-render --saturation-width 120 --saturation-height 90 --saturation-spp 4 --camera-offset 0.5"
            " --saturation-frames " +
            frames);
    ASSERT_EQ(r.status, 0) << r.err;
    // Predicted through the built-in calibration (calib/bocas.json), measured the same way: the
    // target's converged radiance through the scene camera.
    r = cli(common + "--out " + file("ps.log") + " --saturation-out " + ps);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(slurp(rs).find("rendered target saturation"), std::string::npos);
    const smokescan::SaturationSeries R = smokescan::readSaturationCsv(rs), P = smokescan::readSaturationCsv(ps);
    ASSERT_EQ(R.time_s, (std::vector<double>{98.5, 100.5, 102.5}));
    ASSERT_EQ(P.time_s, (std::vector<double>{98, 100, 102}));
    EXPECT_EQ(R.patch_names, (std::vector<std::string>{"blue", "gold", "yellow"}));
    for (size_t k = 0; k < R.time_s.size(); ++k) EXPECT_NEAR(R.saturation[k], P.saturation[k], 0.03) << R.time_s[k];
    EXPECT_GT(R.saturation.front(), R.saturation.back());  // the 40 s run thickens the smoke

    // The kept frames, measured by `smokescan saturation` as a user's recorded frames would be,
    // give the same stream: same 8-bit pixels, same id mask, same camera-clock times.
    ASSERT_TRUE(fs::exists(frames + "/frame_000002.png"));
    r = cli("saturation " + frames + " --ids " + frames + "/ids --scene bocas --timestamps " + frames +
            "/timestamps.csv --out " + file("remeasured.csv"));
    ASSERT_EQ(r.status, 0) << r.err;
    const smokescan::SaturationSeries M = smokescan::readSaturationCsv(file("remeasured.csv"));
    ASSERT_EQ(M.time_s, R.time_s);
    ASSERT_EQ(M.patch_names.size(), R.patch_names.size());
    for (size_t k = 0; k < R.time_s.size(); ++k) EXPECT_NEAR(M.saturation[k], R.saturation[k], 1e-6);
    for (size_t p = 0; p < R.patch.size(); ++p) {  // columns by name (`saturation` keeps the scene's order)
        const size_t q =
            size_t(std::find(M.patch_names.begin(), M.patch_names.end(), R.patch_names[p]) - M.patch_names.begin());
        ASSERT_LT(q, M.patch_names.size()) << R.patch_names[p];
        for (size_t k = 0; k < R.time_s.size(); ++k)
            EXPECT_NEAR(M.patch[q][k], R.patch[p][k], 1e-6) << R.patch_names[p];
    }
    expectBad(common + "--out " + file("h.log") + " --saturation-out " + file("h.csv") +
                  " --saturation-render --saturation-frames " + frames,
              "not an empty folder", file("h.log"));
    expectBad(common + "--out " + file("h.log") + " --saturation-out " + file("h.csv") + " --saturation-frames " +
                  file("new_frames"),
              "needs --saturation-render", file("h.log"));

    expectBad("scan bocas --from 0 --to 1 --out " + file("g.log") + " --saturation-render", "needs --saturation-out",
              file("g.log"));
    expectBad("scan bocas --from 0 --to 1 --out " + file("g.log") + " --saturation-out " + file("g.csv") +
                  " --saturation-render --camera nobody",
              "nobody", file("g.log"));
    EXPECT_FALSE(fs::exists(file("g.csv")));
}
