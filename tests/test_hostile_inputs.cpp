// Hostile inputs that got through a review of every subcommand (issue "the house"): each class
// closed where it starts, tested here through the program as a user runs it, and the pieces
// that close them (message text, plot text, numbers as text) as units.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "cli_run.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/format.hpp"
#include "smokescan/io/atomic_folder.hpp"
#include "smokescan/io/recorded.hpp"
#include "smokescan/io/run_files.hpp"
#include "smokescan/plot/canvas.hpp"
#include "smokescan/sensor_config/sensor_file.hpp"

using namespace smokescan;
using namespace smokescan::test;

namespace {

/// A scene file with one URG-04LX and `extra` TOML after it.
std::string sceneWith(const std::string& name, const std::string& sensor_keys, const std::string& extra = "")
{
    return file(
        name,
        "[[sensors]]\nname = \"h\"\ntype = \"urg04lx\"\nposition = [0.0, 0.0, 0.5]\n" + sensor_keys + "\n" + extra);
}

}  // namespace

// ---- crashes ----

TEST(Hardening, ASaturationSeriesTooShortToFitIsNamed)
{
    // One row and --smooth 0: movingAverage ran with a window from a NaN frame time (SIGSEGV).
    const RecordedRun& run = recordedRun();
    const std::string one = file("one_row.csv", "time_s,saturation\n80,0.25\n"), out = file("one.toml");
    expectBad("fit --laser " + run.log + " --saturation " + one + " --scene bocas --smooth 0 --out " + out,
              one + ": holds 1 saturation rows: a fit needs at least 3", out);
}

TEST(Hardening, TheOffsetSearchIsBoundedBeforeWork)
{
    // 1e6 s took minutes and 446 MB; 1e9 overflowed an int and skipped the search.
    const RecordedRun& run = recordedRun();
    const std::string out = file("ow.toml");
    for (const char* w : {"1e6", "1e9"})
        expectBad("fit --laser " + run.log + " --saturation " + run.sat + " --scene bocas --offset-window " + w +
                      " --out " + out,
                  "more than 36000 offsets on each side", out);
}

TEST(Hardening, APlotWithMoreGroupsThanItsKeyHoldsDoesNotAbort)
{
    // 40 one-degree groups: the fit's legend ran off its image and OpenImageIO asserted.
    const RecordedRun& run = recordedRun();
    std::string groups;
    for (int g = 0; g < 40; ++g)
        groups +=
            "g" + std::to_string(g) + " " + std::to_string(-100 + 5 * g) + " " + std::to_string(-99 + 5 * g) + "\n";
    const std::string gfile = file("many_groups.txt", groups), out = file("many.toml");
    const CliRun r = cli("fit --laser " + run.log + " --saturation " + run.sat + " --surfaces " + gfile +
                         " --sensor-type urg04lx --bootstrap 0 --out " + out);
    EXPECT_EQ(r.status, 0) << r.err;  // the fit succeeds, so its plots (and their key) are drawn
    EXPECT_EQ(r.err.find("ssert"), std::string::npos) << r.err;
    for (const char* fig : {"_fig5.png", "_fig9.png"}) EXPECT_TRUE(fs::is_regular_file(file("many") + fig)) << fig;
    // Directly: text past every edge is left out, text inside is drawn.
    Canvas c(60, 40);
    for (auto [x, y] : {std::pair{-50, 20}, {55, 20}, {10, -5}, {10, 80}, {1 << 30, 1 << 30}}) c.text(x, y, "legend");
    const Image blank = c.image();
    for (float v : blank.data) ASSERT_EQ(v, 1.0f);
    c.text(2, 30, "ab", 14);
    const Image drawn = c.image();
    float darkest = 1;
    for (float v : drawn.data) darkest = std::min(darkest, v);
    EXPECT_LT(darkest, 0.5f) << "text inside the image was not drawn (is DejaVu Sans installed?)";
    // Lines and boxes land where asked, in their colour (drawn by the image module in place).
    Canvas d(20, 10);
    d.line(2, 3, 12, 3, {1, 0, 0});
    d.box(14, 1, 18, 8, {0, 0, 1}, true);
    d.box(1, 6, 5, 9, {0, 1, 0}, false);
    const Image p = d.image();
    auto px = [&](int x, int y) { return Col{p.at(x, y, 0), p.at(x, y, 1), p.at(x, y, 2)}; };
    EXPECT_EQ(px(7, 3), (Col{1, 0, 0}));  // on the line
    EXPECT_EQ(px(7, 4), (Col{1, 1, 1}));  // beside it: white
    EXPECT_EQ(px(16, 5), (Col{0, 0, 1}));  // inside the filled box
    EXPECT_EQ(px(1, 7), (Col{0, 1, 0}));  // on the outlined box's edge
    EXPECT_EQ(px(3, 7), (Col{1, 1, 1}));  // inside it: white
}

TEST(Hardening, PositionsBeyondTheSceneReachAreRefusedWhenRead)
{
    // 1.8e18 m reached Embree's assertion.
    const std::string out = file("far_scan.log");
    const std::string far =
        file("far.toml", "[[sensors]]\nname = \"h\"\ntype = \"urg04lx\"\nposition = [2e18, 0.0, 0.5]\n");
    expectBad("scan " + far + " --to 1 --out " + out, "sensors[0].position must lie within 1000 km of the origin", out);
    const std::string robot = file("far_robot.toml",
                                   "[[robots]]\nname = \"r\"\nkeyframes = [{ time_s = 0.0, position = "
                                   "[0.0, -5e18, 0.0] }]\n[[sensors]]\nname = \"h\"\n"
                                   "type = \"urg04lx\"\nrobot = \"r\"\n");
    expectBad("scan " + robot + " --to 1 --out " + out, "must lie within 1000 km of the origin", out);
}

TEST(Hardening, AReaderThatClosesEarlyLeavesNoTemporary)
{
    // stdout closed at once (`| head -c 1`): SIGPIPE ended the run and left its temporary.
    const fs::path d = scratch("sigpipe");
    const std::string log = (d / "p.log").string();
    // TMPDIR: the stream's own temporary (a device's is made in the temp folder) lands here too.
    // The run must die by SIGPIPE (exit 141 in bash's PIPESTATUS): its 33 MB of tau outlast the pipe.
    const std::string cmd = "bash -c 'TMPDIR=" + d.string() + " " + SMOKESCAN_CLI +
        " scan bocas --from 0 --to 120 --rate 5 --out " + log +
        " --tau /dev/stdout | head -c 1 >/dev/null; exit ${PIPESTATUS[0]}'";
    const int rc = std::system(cmd.c_str());
    EXPECT_TRUE(WIFEXITED(rc) && WEXITSTATUS(rc) == 141) << "the scan was not ended by SIGPIPE: " << rc;
    EXPECT_FALSE(fs::exists(log));
    for (const auto& e : fs::directory_iterator(d))
        EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << "left " << e.path();
}

// ---- values accepted that meant nothing ----

TEST(Hardening, SceneValuesBeyondMeaningAreOneLineErrorsNamingTheKey)
{
    const std::string out = file("vals.log");
    struct Case {
        std::string keys, extra, needle;
    };
    const std::string smoke =
        "[[smoke]]\nname = \"s\"\ntype = \"box\"\nmin = [0.5, -1.0, 0.0]\nmax = [1.5, 1.0, 1.0]\n";
    const std::string light = "[[lights]]\nname = \"l\"\n";
    for (const Case& c : std::vector<Case>{
             {"", smoke + "timeline = { kind = \"constant\", value = 1e300 }\n", "value must be in [0, 1e+06]"},
             {"", smoke + "timeline = { kind = \"keyframes\", keys = [[0.0, 1.0], [5.0, 1e300]] }\n",
              "factors must be in [0, 1e6], got 1e+300 at 5 s"},
             {"", light + "kind = \"point\"\nspot_angle_deg = 20.0\n",
              "'lights[0].spot_angle_deg': not a key of a point light"},
             {"", light + "kind = \"spot\"\nspot_angle_deg = 1000.0\n", "spot_angle_deg must be in [0.001, 180]"},
             {"", light + "kind = \"area\"\npower_w = 1e308\n", "power_w must be in [0, 1e+06]"},
             {"", light + "kind = \"point\"\nefficiency = 2.0\n", "efficiency must be in [0, 1]"},
             {"", light + "kind = \"ambient\"\ncolor = [-1.0, 1.0, 1.0]\n", "color must be 3 gains in [0, 100]"},
             {"", light + "kind = \"ambient\"\nradiance = 1e308\n", "radiance must be in [0, 1e+06]"},
             {"", light + "kind = \"ambient\"\nirradiance = 3.0\n",
              "'lights[0].irradiance': not a key of an ambient light"},
             {"", "[[cameras]]\nname = \"c\"\nmirror_radius_px = 100.0\n", "not a key of a pinhole camera"},
             {"", "[[cameras]]\nname = \"c\"\nkind = \"omni\"\nhfov_deg = 60.0\n", "not a key of an omni camera"},
             {"resolution_deg = 0.5", "", "'sensors[0].resolution_deg': not a key of an urg04lx sensor"},
             {"[sensors.physical]\nnoise_floor = 1e308", "", "noise_floor must be in"},
             {"[sensors.physical]\npulse_fwhm_ns = 4.0", "", "not a key of the physical model of an urg04lx"},
             {"penetration_power = 1e308", "", "penetration_power must be in [1e-09, 1000]"},
         }) {
        const std::string scene = sceneWith("vals.toml", c.keys, c.extra);
        expectBad("scan " + scene + " --to 1 --out " + out, c.needle, out);
    }
    // A sensor file's [physical] values are bounded as the scene's are (1e308 loaded, then scan failed).
    const std::string sf =
        file("big.sensor.toml", "type = \"urg04lx\"\nmodel = \"physical\"\n[physical]\nsnr_min = 1e308\n");
    expectBad("scan bocas --to 1 --sensor-file " + sf + " --out " + out, "snr_min must be in [0.001, 1e+06]", out);
}

TEST(Hardening, OptionValuesBeyondMeaningAreOneLineErrors)
{
    const RecordedRun& run = recordedRun();
    const std::string out = file("opt.out"), png = file("opt.png"), dir_out = (dir() / "diag_out").string();
    const std::string diag =
        "diagnose --laser " + run.log + " --saturation " + run.sat + " --scene bocas --out " + dir_out;
    struct Case {
        std::string args, needle, out;
    };
    for (const Case& c : std::vector<Case>{
             {"render bocas --exposure 1e300 --out " + png, "--exposure: must be 'auto' or a number in (0, 1e6]", png},
             {"scan bocas --to 1 --camera-offset 1e20 --saturation-out " + file("co.csv") + " --out " + out,
              "--camera-offset: '1e20' is outside [-100000, 100000]", out},
             {diag + " --alpha nan", "--alpha: 'nan' is not a finite number", dir_out},
             {diag + " --offset nan", "--offset: 'nan' is not a finite number", dir_out},
             {"fit --laser " + run.log + " --saturation " + run.sat + " --surface a=1:2@1e308 --out " + out,
              "range of 'a' must be in (0, 1000] m", out},
             {"saturation " + png + " --rect time_s=0,0,1,1 --out " + out, "is one of the CSV's own columns", out},
             {"volume info volumes/fog_ball_float.vdb --scale 1e300", "--scale: '1e300' is outside [0, 1e+06]", out},
             {"fit --laser " + run.log + " --saturation " + run.sat + " --surface 'a,b=1:2' --out " + out,
              "name 'a,b' must be 1-64 letters", out},
             {"fit --laser " + run.log + " --saturation " + run.sat + " --surface a=2:1 --out " + out,
              "must run from A0 to a larger A1", out},
             {"fit --laser " + run.log + " --saturation " + run.sat + " --surface a=1e308:2 --out " + out,
              "within +/-360 degrees", out},
             {"fit --laser " + run.log + " --saturation " + run.sat + " --scene bocas --offset 1e300 --out " + out,
              "--offset: '1e300' is outside", out},
             {"saturation " + png + " --rect 'a,b=0,0,1,1' --out " + out, "must be 1-64 letters", out},
             // A seed does not wrap around: -1 and 10^23 were 2^64 - 1 both.
             {"scan bocas --to 1 --seed -1 --out " + out, "--seed: '-1' is not a seed", out},
             {"scan plume --sensor vlp16 --to 0.1 --seed 99999999999999999999999 --points " + out,
              "is not a seed (a whole number from 0 to 18446744073709551615)", out},
             {"render bocas --seed 1e3 --out " + png, "--seed: '1e3' is not a seed", png},
             {diag + " --seed ''", "--seed: '' is not a seed", dir_out},
             {"calibrate bocas --densities 0.001,0.002 --spp 1 --width 16 --height 12 --seed +1 --out " + out,
              "--seed: '+1' is not a seed", out},
             {"omnirange bocas --seed ' 5' --out " + out, "--seed: ' 5' is not a seed", out},
             {"scan bocas --to 1 --seed 18446744073709551616 --out " + out, "is not a seed", out},
         })
        expectBad(c.args, c.needle, c.out);
    // A seed is decimal as written (CLI11 alone read 010 as octal 8), up to 2^64 - 1.
    for (const auto& [seed, header] : std::vector<std::pair<std::string, std::string>>{
             {"010", "seed=10\n"}, {"09", "seed=9\n"}, {"18446744073709551615", "seed=18446744073709551615\n"}}) {
        const std::string log = file("seeded.log");
        const CliRun ok = cli("scan bocas --to 0.1 --seed " + seed + " --out " + log);
        ASSERT_EQ(ok.status, 0) << ok.err;
        EXPECT_NE(slurp(log).find(header), std::string::npos) << seed;
    }
    const CliRun r = cli("frobnicate");
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("unknown command 'frobnicate' (scan, "), std::string::npos) << r.err;
    const CliRun v = cli("volume frob");
    EXPECT_EQ(v.status, 2);
    EXPECT_NE(v.err.find("unknown subcommand of volume 'frob' (info, build, export"), std::string::npos) << v.err;
}

// ---- output that reads back ----

TEST(SaturationCsv, EpochTimesAndValuesReadBackExactly)
{
    // 9 significant digits printed every row of an epoch clock as 1.7e+09.
    SaturationSeries s;
    for (int k = 0; k < 5; ++k) {
        s.time_s.push_back(1700000000.25 + 0.1 * k);
        s.saturation.push_back(0.3 - 0.004 * k);
    }
    const std::string path = file("epoch.csv");
    writeSaturationCsv(path, s, {"epoch clock"});
    const SaturationSeries back = readSaturationCsv(path);
    ASSERT_EQ(back.time_s.size(), s.time_s.size());
    for (size_t k = 0; k < s.time_s.size(); ++k) EXPECT_EQ(back.time_s[k], s.time_s[k]) << k;
    EXPECT_EQ(shortest(1700000000.25), "1700000000.25");
    EXPECT_EQ(shortest(0.1), "0.1");
    EXPECT_EQ(std::strtod(shortest(M_PI).c_str(), nullptr), M_PI);
    // A patch name that would break the header is refused before anything is written.
    s.patch_names = {"a,b"};
    s.patch = {s.saturation};
    const std::string bad = file("badname.csv");
    EXPECT_THROW(writeSaturationCsv(bad, s, {}), Error);
    EXPECT_FALSE(fs::exists(bad));
}

TEST(Hardening, DevStdoutIsWrittenIntoWhereverItLeads)
{
    // docs/limits.md names /dev/stdout as an output; it was refused as a link.
    const std::string piped = file("piped.log"), redirected = file("redirected.log");
    const std::string base = std::string(SMOKESCAN_CLI) + " scan bocas --to 1 --quiet --out /dev/stdout";
    ASSERT_EQ(std::system(("sh -c '" + base + " | cat > " + piped + "'").c_str()), 0);
    ASSERT_EQ(std::system(("sh -c '" + base + " > " + redirected + "'").c_str()), 0);
    for (const std::string& f : {piped, redirected}) {
        const std::string got = slurp(f);
        EXPECT_NE(got.find("# smokescan scan builtin:bocas"), std::string::npos) << f << ":\n" << got.substr(0, 300);
        // What the program prints goes to stderr: the file is the log alone, which reads back.
        EXPECT_EQ(got.find("wrote"), std::string::npos) << f << ":\n" << got.substr(0, 300);
    }
    const std::string sat = file("stdout_sat.csv"), diag = (dir() / "stdout_diag").string();
    ASSERT_EQ(std::system(("sh -c '" + std::string(SMOKESCAN_CLI) +
                           " scan bocas --from 90 --to 150 --rate 2 --out /dev/stdout --saturation-out " + sat + " > " +
                           redirected + "'")
                              .c_str()),
              0);
    const CliRun r = cli("diagnose --laser " + redirected + " --saturation " + sat + " --scene bocas --out " + diag);
    EXPECT_EQ(r.err.find("is not a number"), std::string::npos) << r.err;
}

TEST(Messages, ControlsThatMoveOrHideTextAreShownEscaped)
{
    // C1 controls (the CSI U+009B) and bidirectional overrides reached the terminal raw.
    EXPECT_EQ(printable("a\xC2\x9B"
                        "b"),
              "a\\u009Bb");
    EXPECT_EQ(printable("x\xE2\x80\xAEy"), "x\\u202Ey");  // RIGHT-TO-LEFT OVERRIDE
    EXPECT_EQ(printable("x\xE2\x81\xA6y"), "x\\u2066y");  // LEFT-TO-RIGHT ISOLATE
    EXPECT_EQ(printable("d\xC3\xA9j\xC3\xA0"), "d\xC3\xA9j\xC3\xA0");  // ordinary accents stay
    EXPECT_EQ(printable("\x1B[31m"), "\\x1B[31m");
}

// ---- data destroyed ----

TEST(Hardening, EveryCommandProtectsTheFilesItsSceneReads)
{
    // `volume build SCENE --out mesh.obj` overwrote the scene's mesh, and a failing `fit --report
    // mesh.obj` still did: every command that takes a scene now learns its files from the scene.
    const std::string cube =
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n"
        "f 1 3 2\nf 2 3 4\nf 5 6 7\nf 6 8 7\nf 1 2 5\nf 2 6 5\nf 3 7 4\nf 4 7 8\nf 1 5 3\nf 3 5 7\nf 2 4 6\nf 4 8 6\n";
    const std::string mesh = file("kept.obj", cube);
    const std::string scene =
        file("reads_mesh.toml",
             "[[materials]]\nname = \"m\"\n[[surfaces]]\nname = \"target_cube\"\nmaterial = \"m\"\ntype = \"mesh\"\n"
             "file = \"kept.obj\"\nposition = [2.0, -0.5, 0.0]\n"
             "[[sensors]]\nname = \"h\"\ntype = \"urg04lx\"\nposition = [0.0, 0.0, 0.5]\n"
             "[[cameras]]\nname = \"c\"\nlook_at = [2.0, 0.0, 0.5]\nposition = [0.0, 0.0, 0.5]\n"
             "[[smoke]]\nname = \"s\"\ntype = \"box\"\nmin = [0.5, -1.0, 0.0]\nmax = [1.5, 1.0, 1.0]\n");
    const RecordedRun& run = recordedRun();
    const std::string frame = file("frame.png");
    ASSERT_EQ(cli("render " + scene + " --width 16 --height 12 --spp 1 --out " + frame).status, 0);
    for (const std::string& args : {
             "volume build " + scene + " --out " + mesh,
             "calibrate " + scene + " --out " + mesh,
             "fit --laser " + run.log + " --saturation " + run.sat + " --scene " + scene + " --out " + file("f.toml") +
                 " --report " + mesh,
             "fit-plume --laser " + run.log + " --scene " + scene + " --out " + mesh,
             "saturation " + frame + " --scene " + scene + " --rect a=0,0,4,4 --out " + mesh,
         }) {
        const CliRun r = cli(args);
        EXPECT_NE(r.status, 0) << args;
        EXPECT_NE(r.err.find("is the input of a file the scene reads"), std::string::npos) << args << "\n" << r.err;
        EXPECT_EQ(slurp(mesh), cube) << args;
    }
}

TEST(RunFiles, AFolderThatCannotBePlacedTakesTheFilesBack)
{
    // The files are placed, then the run's folder (its last step) fails: the file that replaced
    // the user's is taken back to the old content, the new one removed, the folder left as found.
    const fs::path d = scratch("folder_last");
    const std::string old_file = (d / "range.png").string(), new_file = (d / "top.png").string();
    std::ofstream(old_file) << "the user's picture";
    fs::remove(new_file);
    const std::string dir = (d / "points").string();
    fs::remove_all(dir);
    RunFiles files;
    files.output(old_file, "--range-image");
    files.output(new_file, "--top-view");
    files.outputFolder(dir, "--points");
    AtomicFolder out(dir, "the point-cloud folder", "--points");
    std::ofstream(out.path("000000.pcd")) << "a frame";
    std::ofstream(files.stage(old_file)) << "new range";
    std::ofstream(files.stage(new_file)) << "new top";
    fs::create_directory(dir);
    std::ofstream(dir + "/mine") << "appeared during the run";
    EXPECT_THROW(files.commit([&] { out.commit(); }), Error);
    EXPECT_EQ(slurp(old_file), "the user's picture");
    EXPECT_FALSE(fs::exists(new_file));
    EXPECT_EQ(slurp(dir + "/mine"), "appeared during the run");
    EXPECT_FALSE(fs::exists(dir + "/000000.pcd"));
    // And when the folder can be placed, everything is.
    fs::remove_all(dir);
    RunFiles again;
    again.output(new_file, "--top-view");
    AtomicFolder out2(dir, "the point-cloud folder", "--points");
    std::ofstream(out2.path("000000.pcd")) << "a frame";
    std::ofstream(again.stage(new_file)) << "new top";
    again.commit([&] { out2.commit(); });
    EXPECT_EQ(slurp(new_file), "new top");
    EXPECT_EQ(slurp(dir + "/000000.pcd"), "a frame");
}

TEST(RunFiles, AnOutputThatCannotBePlacedPutsBackWhatTheEarlierOnesReplaced)
{
    // A folder appears at the second output during the run: the first had already replaced the
    // user's file. Now every target is checked before the first rename, and a rename that still
    // fails puts back what was replaced.
    const fs::path d = scratch("all_or_nothing");
    const std::string a = (d / "a.log").string(), b = (d / "b.csv").string();
    // Both files hold their old content; both outputs are staged with new content, `meddle` runs
    // (given b's temporary), then the run commits. True when the commit threw.
    auto run = [&](const std::function<void(const std::string&)>& meddle) {
        std::ofstream(a) << "old a";
        if (!fs::is_directory(b)) std::ofstream(b) << "old b";
        RunFiles files;
        files.output(a, "--out");
        files.output(b, "--tau");
        std::ofstream(files.stage(a)) << "new a";
        const std::string tb = files.stage(b);
        std::ofstream(tb) << "new b";
        meddle(tb);
        try {
            files.commit();
            return false;
        } catch (const Error&) {
            return true;
        }
    };
    EXPECT_TRUE(run([&](const std::string&) {
        fs::remove(b);
        fs::create_directory(b);
    }));
    EXPECT_EQ(slurp(a), "old a");
    EXPECT_TRUE(fs::is_directory(b));
    fs::remove(b);
    // The pre-check passes, then the second rename fails (its temporary is gone): the first
    // output, already in place, is put back.
    EXPECT_TRUE(run([](const std::string& tb) { fs::remove(tb); }));
    EXPECT_EQ(slurp(a), "old a");
    EXPECT_EQ(slurp(b), "old b");
    EXPECT_FALSE(run([](const std::string&) {}));
    EXPECT_EQ(slurp(a), "new a");
    EXPECT_EQ(slurp(b), "new b");
    for (const auto& e : fs::directory_iterator(d)) EXPECT_TRUE(e.path() == a || e.path() == b) << "left " << e.path();
}

TEST(Hardening, AFolderThatAppearsAtDiagnoseOutIsRefusedNotRemoved)
{
    // diagnose --out DIR removed a file that appeared at DIR during the run.
    const fs::path d = scratch("folder_appears");
    const std::string target = (d / "diag").string();
    {
        AtomicFolder out(target, "the diagnosis folder", "--out");
        std::ofstream(out.path("report.md")) << "report";
        std::ofstream(target) << "the user's file";
        EXPECT_THROW(out.commit(), Error);
    }
    EXPECT_EQ(slurp(target), "the user's file");
    for (const auto& e : fs::directory_iterator(d)) EXPECT_EQ(e.path().string(), target) << "left " << e.path();
    // An empty folder given as the target is replaced; one that filled up during the run is not.
    const std::string empty = (d / "empty").string(), filled = (d / "filled").string();
    fs::create_directory(empty);
    fs::create_directory(filled);
    {
        AtomicFolder out(empty, "the diagnosis folder", "--out");
        std::ofstream(out.path("report.md")) << "report";
        out.commit();
    }
    EXPECT_EQ(slurp(fs::path(empty) / "report.md"), "report");
    {
        AtomicFolder out(filled, "the diagnosis folder", "--out");
        std::ofstream(fs::path(filled) / "mine.txt") << "kept";
        EXPECT_THROW(out.commit(), Error);
    }
    EXPECT_EQ(slurp(fs::path(filled) / "mine.txt"), "kept");
}

TEST(Hardening, AScenesPlumesAreBoundedTogether)
{
    // Twelve plumes each under the bound peaked at 3.3 GB: the bound is now the scene's. Three
    // plumes of about 1.8e8 voxels each pass one by one and fail together.
    std::string plumes;
    for (int i = 0; i < 3; ++i)
        plumes += "[[smoke]]\nname = \"p" + std::to_string(i) +
            "\"\ntype = \"plume\"\nsource = [0.0, 0.0, 0.5]\nrate_per_s = 10.0\nlifetime_s = 10.0\nradius_m = 1.0\n"
            "growth_m_s = 0.0\nvoxel = 0.05\n";
    const std::string one = file("one_plume.toml", plumes.substr(0, plumes.find("[[smoke]]", 1)));
    const std::string three = file("three_plumes.toml", plumes), out = file("plumes.vdb");
    const CliRun r = cli("volume info " + one);
    EXPECT_EQ(r.status, 0) << r.err;
    expectBad("volume build " + three + " --out " + out, "the scene's plumes would cover about", out);
}

TEST(Hardening, TimestampsWithTrailingJunkAndLongOutputNames)
{
    // A --timestamps line "12.5abc" was read as 12.5; an output name of 239-245 bytes failed on
    // its temporary's longer name.
    const std::string frame = file("ts_frame.png");
    ASSERT_EQ(cli("render bocas --width 16 --height 12 --spp 1 --out " + frame).status, 0);
    const std::string ts = file("ts.csv", "frame,time_s\nts_frame.png,12.5abc\n"), out = file("ts_out.csv");
    expectBad("saturation " + frame + " --rect a=0,0,4,4 --timestamps " + ts + " --out " + out,
              "ts.csv:2: time is not a finite number: '12.5abc'", out);
    const std::string long_name = file(std::string(241, 'n') + ".log");
    const CliRun r = cli("scan bocas --to 1 --quiet --out " + long_name);
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(fs::is_regular_file(long_name));
}

TEST(Hardening, SmokeGridsAreBoundedByTheMemoryTheyTakeTogether)
{
    // A box within 4000 voxels a side (3960, soft edge 0.5 m) exhausted memory and aborted.
    const std::string out = file("bigbox.log");
    const std::string big = file("bigbox.toml",
                                 "[[smoke]]\nname = \"room\"\ntype = \"box\"\nmin = [-99.0, -99.0, -99.0]\n"
                                 "max = [98.9, 98.9, 98.9]\nvoxel = 0.05\nedge_m = 0.5\n");
    expectBad("volume build " + big + " --out " + out, "GB of grid (at most 2.0 over all of them)", out);
    // Two boxes of about 1.0 GB each (each under the bound alone) fail together, before the
    // first grid is made... of the second: the first is built, the second refused.
    const std::string box =
        "[[smoke]]\nname = \"b\"\ntype = \"box\"\nmin = [-55.0, -55.0, -55.0]\n"
        "max = [55.0, 55.0, 55.0]\nvoxel = 0.05\n";
    const std::string two = file("box2.toml", box + box);
    expectBad("volume build " + two + " --out " + out,
              "smoke[1].voxel makes the scene's box and mesh smoke take about 2.1 GB", out);
}

TEST(SensorFile, WrittenValuesReadBackExactly)
{
    // Ten significant digits made 1e6 and 1.00000000001e6 Hz one frequency: fit wrote a sensor
    // file that scan then refused.
    SensorConfig c = SensorConfig::defaults(SensorType::Urg04lx);
    c.physical.mod_freq_lo_hz = 1e6;
    c.physical.mod_freq_hi_hz = 1.00000000001e6;
    c.physical.noise_floor = 1.0 / 3.0;
    const std::string path = file("exact.sensor.toml");
    writeSensorFile(path, c, "round trip");
    SensorConfig back = SensorConfig::defaults(SensorType::Urg04lx);
    applySensorFile(path, back);
    EXPECT_EQ(back.physical.mod_freq_hi_hz, c.physical.mod_freq_hi_hz);
    EXPECT_EQ(back.physical.noise_floor, c.physical.noise_floor);
}

TEST(Hardening, WhatTheProgramPrintsIsEscapedAsItsErrorsAre)
{
    // An output named with a right-to-left override (U+202E) was printed raw in "wrote ...", and a
    // group name with an escape sequence reached the terminal from fit's table.
    const std::string bidi = file("o\xE2\x80\xAEgol.log");
    const CliRun r = cli("scan bocas --to 1 --quiet --out '" + bidi + "'");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("o\\u202Egol.log"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("\xE2\x80\xAE"), std::string::npos) << r.out;
}
