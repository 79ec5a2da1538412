// Hostile and careless input, item by item: outputs never destroy inputs, devices or links; sizes
// are bounded before work; bad values are one-line errors; a failed run leaves nothing behind.
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <fstream>
#include <sstream>
#include <tuple>

#include <chrono>
#include <cmath>
#include <thread>

#include "smokescan/calib/saturation_curve.hpp"
#include "smokescan/core/error.hpp"

#include "cli_run.hpp"

using namespace smokescan::test;

namespace {

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAsan = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kAsan = true;
#else
constexpr bool kAsan = false;
#endif
#else
constexpr bool kAsan = false;
#endif

bool isCharDevice(const std::string& p)
{
    struct stat st {};
    return ::stat(p.c_str(), &st) == 0 && S_ISCHR(st.st_mode);
}

}  // namespace

// ---- outputs never destroy ----

TEST(Hardening, DevicesAndFifosAreWrittenIntoNeverReplaced)
{
    const CliRun r = cli("scan bocas --to 1 --quiet --out /dev/null --tau /dev/null");
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(isCharDevice("/dev/null"));
    if (isCharDevice("/dev/full")) {
        expectBad("scan bocas --to 1 --quiet --out /dev/full", "/dev/full: write failed (No space left on device)",
                  file("nothing"));
        EXPECT_TRUE(isCharDevice("/dev/full"));
    }
    // A FIFO gets the log through it, and stays a FIFO.
    const std::string fifo = (dir() / "pipe.log").string(), got = file("from_pipe.log");
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    const std::string cmd = "sh -c 'timeout 60 cat " + fifo + " > " + got + " & p=$!; " + SMOKESCAN_CLI +
        " scan bocas --to 1 --quiet --out " + fifo + " >/dev/null; s=$?; wait $p; exit $s'";
    EXPECT_EQ(std::system(cmd.c_str()), 0);
    struct stat st {};
    ASSERT_EQ(::lstat(fifo.c_str(), &st), 0);
    EXPECT_TRUE(S_ISFIFO(st.st_mode));
    EXPECT_NE(slurp(got).find("# format: time_s then pairs"), std::string::npos);
    fs::remove(fifo);
}

TEST(Hardening, LinksAndPlantedTemporariesAreNeverFollowed)
{
    const std::string victim = file("victim.txt", "precious\n");
    const std::string link = (dir() / "link.log").string();
    fs::create_symlink(victim, link);
    expectBad("scan bocas --to 1 --quiet --out " + link, "is a symbolic link", file("never.log"));
    EXPECT_TRUE(fs::is_symlink(link));
    // Links planted where a predictable temporary would have been: the run writes its output and
    // touches none of them (temporaries are created exclusively, with random names).
    const std::string out = (dir() / "o.vdb").string();
    for (const std::string& t :
         {out + ".tmp", out + ".tmp." + std::to_string(::getpid() + 1), (dir() / "o.tmp.vdb").string()})
        fs::create_symlink(victim, t);
    const CliRun r = cli("volume build bocas --time 100 --out " + out);
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(fs::is_regular_file(out));
    EXPECT_EQ(slurp(victim), "precious\n");
    fs::remove(link);
    for (const auto& e : fs::directory_iterator(dir()))
        if (fs::is_symlink(e.path())) fs::remove(e.path());
}

TEST(Hardening, AnOutputThatIsAnInputIsRefusedByIdentity)
{
    const RecordedRun& run = recordedRun();
    const std::string scene = file("s.toml", slurp(std::string(SMOKESCAN_SOURCE_DIR) + "/scenes/bocas.toml"));
    const std::string hard = (dir() / "hardlink.log").string();
    fs::create_hard_link(run.log, hard);
    const std::string vdb = file("in.vdb", slurp(std::string(SMOKESCAN_SOURCE_DIR) + "/volumes/ramp_block_double.vdb"));
    const std::string log0 = slurp(run.log), sat0 = slurp(run.sat), scene0 = slurp(scene), vdb0 = slurp(vdb);
    const std::string dot_log = (dir() / "." / fs::path(run.log).filename()).string();
    struct Case {
        std::string args, needle;
    };
    const std::string fit = "fit --laser " + run.log + " --saturation " + run.sat + " --scene bocas ";
    for (const Case& c : std::vector<Case>{
             {"scan " + scene + " --to 1 --out " + scene, "is the input of the scene"},
             {fit + "--out " + dot_log, "is the input of --laser"},
             {fit + "--out " + hard, "is the input of --laser"},
             {fit + "--out " + file("f.toml") + " --report " + run.sat, "is the input of --saturation"},
             {fit + "--out " + file("f.toml") + " --aligned " + run.log, "is the input of --laser"},
             {"volume export " + vdb + " --out " + vdb, "is the input of the input"},
             {"scan bocas --to 1 --out " + file("x.log") + " --tau " + (dir() / "." / "x.log").string(),
              "named by both --out and --tau"},
             {"scan bocas --to 1 --out " + file("x.png") + " --image " + file("x.png"),
              "named by both --out and --image"},
             {"render bocas --spp 1 --out " + file("f.exr") + " --exr " + file("f.exr"),
              "named by both --out and --exr"},
             {"scan bocas --to 1 --out " + file("x.log") + " --saturation-out " + file("x.csv") +
                  " --saturation-render --saturation-frames " + file("x.log"),
              "named by both --out and --saturation-frames"},
         }) {
        const CliRun r = cli(c.args);
        EXPECT_NE(r.status, 0) << c.args;
        EXPECT_NE(r.err.find(c.needle), std::string::npos) << c.args << "\n" << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    }
    EXPECT_EQ(slurp(run.log), log0);
    EXPECT_EQ(slurp(run.sat), sat0);
    EXPECT_EQ(slurp(scene), scene0);
    EXPECT_EQ(slurp(vdb), vdb0);
    EXPECT_FALSE(fs::exists(file("x.log")));
    EXPECT_FALSE(fs::exists(file("f.toml")));
    fs::remove(hard);
}

// ---- crashes ----

TEST(Hardening, InputsThatCrashedAreOneLineErrors)
{
    const RecordedRun& run = recordedRun();
    const std::string out = file("crash.toml");
    for (const char* smooth : {"3e9", "1e10", "inf"})
        expectBad("fit --laser " + run.log + " --saturation " + run.sat + " --scene bocas --out " + out + " --smooth " +
                      smooth,
                  "--smooth", out);
    expectBad("calibrate bocas --densities 0,0.001,0.002,10 --spp 1 --width 16 --height 12 --out " + file("c.json"),
              "--densities: density 10", file("c.json"));
    // A sweep whose curve is not identified went through Ceres' covariance, which logged its
    // rank deficiency on stderr; a frame too small for the target's radiance field: one line each,
    // and no calibration.
    expectBad("calibrate bocas --densities 0,0.5,0.8,1 --spp 1 --width 16 --height 12 --out " + file("c.json"),
              "too few for its radiance field", file("c.json"));
    // A sweep too short to reach the threshold: the curve would be extrapolated (it was written,
    // exit 0, with a threshold far outside the sweep); a sweep that keeps too many frames.
    expectBad("calibrate bocas --densities 0,0.0004,0.0008,0.0012,0.0016 --spp 4 --width 64 --height 48 --out " +
                  file("c.json"),
              "an extrapolation", file("c.json"));
    expectBad("calibrate bocas --max-batches 2048 --spp 1 --out " + file("c.json"),
              "--max-batches: a converged measurement", file("c.json"));
    // A mesh smoke area at 0.1 mm voxels (15.6 GB before): refused before any voxel is made.
    file(
        "cube.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n"
        "f 1 3 2\nf 2 3 4\nf 5 6 7\nf 6 8 7\nf 1 2 5\nf 2 6 5\nf 3 7 4\nf 4 7 8\nf 1 5 3\nf 3 5 7\nf 2 4 6\nf 4 8 6\n");
    const std::string mesh_scene =
        file("mesh.toml",
             "[[sensors]]\nname = \"h\"\ntype = \"urg04lx\"\nposition = [0.0, 0.0, 0.5]\n"
             "[[smoke]]\nname = \"m\"\ntype = \"mesh\"\nfile = \"cube.obj\"\nvoxel = 0.0001\n");
    expectBad("scan " + mesh_scene + " --to 1 --out " + file("m.log"), "makes this mesh over 4000 voxels a side",
              file("m.log"));
}

TEST(Hardening, ACalibrationWhoseCurveMeansNothingIsRefused)
{
    // Edited calibration files gave penetration powers of NaN, inf or 1e300 with exit 0: the reader
    // bounds each parameter and refuses a bad covariance or a fit that did not converge.
    std::ifstream in(std::string(SMOKESCAN_SOURCE_DIR) + "/calib/bocas.json");
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string text = ss.str(), combined = "\"combined\": {";
    const size_t at = text.find(combined);
    ASSERT_NE(at, std::string::npos);
    auto edited = [&](const std::string& key, const std::string& value) {
        const size_t k = text.find("\"" + key + "\": ", at);
        const size_t e = text.find_first_of(",\n", k);
        return text.substr(0, k) + "\"" + key + "\": " + value + text.substr(e);
    };
    const std::string out = file("cal.csv");
    for (const auto& [key, value, needle] :
         std::vector<std::tuple<std::string, std::string, std::string>>{{"S0", "0.1", "never reached"},
                                                                        {"gamma", "1e300", "out of range"},
                                                                        {"b", "1e-300", "out of range"},
                                                                        {"converged", "false", "did not converge"}}) {
        const std::string cal = file("cal_" + key + ".json", edited(key, value));
        expectBad(
            "scan bocas --to 1 --quiet --out " + file("cal.log") + " --saturation-out " + out + " --calibration " + cal,
            needle, out);
    }
}

TEST(Hardening, TheCalibrationFitSurvivesDensitiesFarBeyondItsRange)
{
    // The curve underflows at density 10: the covariance must not run an SVD on a NaN Jacobian
    // (it crashed), and the fit must say it is not identified instead of reporting numbers.
    std::vector<smokescan::SaturationPoint> pts = {
        {0, 0.8, 0.01}, {0.001, 0.6, 0.01}, {0.002, 0.45, 0.01}, {10, 0.0, 0.01}};
    const smokescan::CurveFitResult r = smokescan::fitSaturationCurve(pts);
    if (r.converged)
        for (double se : r.std_error) EXPECT_TRUE(std::isfinite(se) && se > 0);
    pts.push_back({20, 0.0, 0.01});
    pts.push_back({30, 0.0, 0.01});
    (void)smokescan::fitSaturationCurve(pts);  // must return
}

// ---- hangs and unbounded work ----

TEST(Hardening, UnboundedRequestsAreRefusedBeforeWork)
{
    const std::string out = file("u.out.log"), png = file("u.png");
    const auto plume = [](const std::string& extra) {
        return file("plume.toml",
                    "[[sensors]]\nname = \"s\"\ntype = \"lms200\"\nposition = [0.0, 0.0, 0.5]\n"
                    "[[smoke]]\nname = \"p\"\ntype = \"plume\"\nsource = [3.0, 0.0, 0.0]\n" +
                        extra);
    };
    expectBad("scan " + plume("radius_m = 1e6\n") + " --to 1 --out " + out, "plume puffs would cover", out);
    expectBad("scan " + plume("voxel = 0.001\n") + " --to 1 --out " + out, "plume puffs would cover", out);
    expectBad("scan bocas --to 10 --bin 1e-9 --out " + out, "--bin: would print", out);
    expectBad("scan bocas --from 0 --to 360 --rate 99999 --out " + out, "million scans", out);
    expectBad("scan bocas --from -1 --to 3 --out " + out, "--from: -1 s is before the scene's start, 0 s", out);
    expectBad("scan bocas --from 1 --to 361 --out " + out, "--to: 361 s is after the scene's end, 360 s", out);
    expectBad("scan bocas --from 1 --to 360.0000001 --out " + out,
              "--to: 360.0000001 s is after the scene's end, 360 s", out);
    expectBad("scan bocas --from 400 --out " + out, "--from: 400 s is after the scene's end, 360 s", out);
    // An empty path is not an absent one: named, not taken as no bag (the error named --out).
    expectBad("scan bocas --bag '' --out " + out, "--bag: must not be empty", out);
    expectBad("render bocas --bag '' --out " + png, "--bag: must not be empty", png);
    expectBad("fit --laser '' --saturation x.csv --scene bocas --out " + out, "--laser: must not be empty", out);
    expectBad("scan bocas --from 0 --to 360 --rate 200 --out " + out + " --image " + png, "--image: would draw", out);
    expectBad("render bocas --spp 2147483647 --out " + png, "--spp", png);
    expectBad("render bocas --from 0 --to 10 --every 1e-9 --out " + file("f{i}.png"), "--every: would render", png);
    expectBad("render bocas --width 100000 --out " + png, "--width", png);
    expectBad("render bocas --spp 65536 --width 8000 --height 8000 --out " + png, "samples a frame", png);
    // Endless or binary text inputs.
    expectBad("scan /dev/zero --out " + out, "is not text", out);
    const RecordedRun& run = recordedRun();
    expectBad("fit --laser /dev/zero --saturation " + run.sat + " --scene bocas --out " + file("z.toml"), "is not text",
              file("z.toml"));
    expectBad("fit --laser " + run.log + " --saturation /dev/zero --scene bocas --out " + file("z.toml"), "is not text",
              file("z.toml"));
    // A NUL deep in a text file: named at its byte, not at the start of the block read.
    std::string nul(100000, 'a');
    nul[70001] = '\0';
    const std::string binary = file("nul_inside.toml");
    std::ofstream(binary, std::ios::binary) << nul;
    expectBad("scan " + binary + " --out " + out, "is not text (a NUL byte at byte 70001)", out);
}

TEST(Hardening, ScanMemoryDoesNotGrowWithTheRunsLength)
{
    if (kAsan) GTEST_SKIP() << "AddressSanitizer's quarantine holds freed memory: peak RSS says nothing there";
    // Scans stream to the output: 40× the scans may not cost more than a few MB (each kept scan
    // held ~124 kB before: 4000 scans would have added ~500 MB).
    auto peak_kb = [] {
        rusage u{};
        ::getrusage(RUSAGE_CHILDREN, &u);
        return long(u.ru_maxrss);
    };
    ASSERT_EQ(cli("scan bocas --from 0 --to 10 --rate 10 --quiet --out /dev/null").status, 0);
    const long small = peak_kb();
    ASSERT_EQ(cli("scan bocas --from 0 --to 360 --rate 10 --quiet --out /dev/null").status, 0);
    const long large = peak_kb();
    EXPECT_LT(large - small, 40 * 1024) << "peak RSS " << small << " kB for 101 scans, " << large << " kB for 3601";
}

// ---- bad values ----

TEST(Hardening, BadOptionValuesAreOneLineErrors)
{
    const RecordedRun& run = recordedRun();
    const std::string out = file("b.log"), png = file("b.png");
    const std::string fit = "fit --laser " + run.log + " --saturation " + run.sat + " --scene bocas --out " + out;
    struct Case {
        std::string args, needle;
    };
    for (const Case& c : std::vector<Case>{
             {"scan bocas --to 1 --penetration-power nan --out " + out,
              "--penetration-power: 'nan' is not a finite number"},
             {"scan bocas --to 1 --penetration-power -1 --out " + out, "--penetration-power: '-1' must be > 0"},
             {"scan bocas --from nan --out " + out, "--from: 'nan'"},
             {"scan bocas --to inf --out " + out, "--to: 'inf'"},
             {"scan bocas --to 1 --bin 0 --out " + out, "--bin: '0' must be > 0"},
             {"scan bocas --to 1 --image-range nan --out " + out, "--image-range: 'nan'"},
             {"scan bocas --to 1 --camera-offset nan --saturation-out " + file("c.csv") + " --out " + out,
              "--camera-offset: 'nan'"},
             {"render bocas --from 0 --to 1 --every 0 --out " + png, "--every: '0' must be > 0"},
             {"render bocas --from 0 --to 1 --every -1 --out " + png, "--every: '-1' must be > 0"},
             {"render bocas --max-depth -1 --out " + png, "--max-depth: '-1' is outside"},
             {"fit-plume --laser " + run.log + " --scene plume --bins 0 --out " + out, "--bins: '0' is outside"},
             {"saturation " + png + " --rect a=0,0,1,1 --fps 0 --out " + out, "--fps: '0' must be > 0"},
             {fit + " --offset nan", "--offset: 'nan'"},
         })
        expectBad(c.args, c.needle, c.args.rfind("render", 0) == 0 ? png : out);
}

TEST(Hardening, BadSceneAndMeshValuesAreOneLineErrorsNamingFileAndKey)
{
    const std::string out = file("v.log"), vdb = file("v.vdb");
    const std::string fill =
        file("fill.toml",
             "[[sensors]]\nname = \"h\"\ntype = \"urg04lx\"\nposition = [0.0, 0.0, 0.5]\n"
             "[[smoke]]\nname = \"room\"\ntype = \"box\"\nmin = [-1.0, -1.0, 0.0]\nmax = [3.0, 1.0, 2.0]\n"
             "timeline = { kind = \"machine\", on = [[0.0, 10.0]], fill_per_s = 1e308 }\n");
    expectBad("scan " + fill + " --to 5 --out " + out, fill + ":", out);
    expectBad("volume build " + fill + " --time 5 --out " + vdb, fill + ":", vdb);
    EXPECT_NE(cli("volume build " + fill + " --time 5 --out " + vdb).err.find("fill_per_s"), std::string::npos);
    // A soft edge of 1000 km (it hung), and a box at 1e300 m with voxels to match.
    const auto box = [](const std::string& keys) {
        return file("box.toml", "[[smoke]]\nname = \"b\"\ntype = \"box\"\n" + keys);
    };
    expectBad("volume build " + box("min = [0.0, 0.0, 0.0]\nmax = [1.0, 1.0, 1.0]\nedge_m = 1e6\n") + " --out " + vdb,
              "smoke[0].edge_m makes this box over 4000 voxels a side", vdb);
    expectBad(
        "volume build " + box("min = [-1e300, 0.0, 0.0]\nmax = [1e300, 1.0, 1.0]\nvoxel = 1e298\n") + " --out " + vdb,
        "smoke[0].max the box must lie within 1000 km of the origin", vdb);
    file("nan.obj", "v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n");
    const std::string nan_scene =
        file("nanmesh.toml", "[[smoke]]\nname = \"m\"\ntype = \"mesh\"\nfile = \"nan.obj\"\n");
    expectBad("volume build " + nan_scene + " --out " + vdb,
              "nan.obj:2: vertex coordinate 'nan' is not a finite number", vdb);
    file("open.obj",
         "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\n");  // a tetrahedron without its fourth face
    const std::string open_scene =
        file("openmesh.toml", "[[smoke]]\nname = \"m\"\ntype = \"mesh\"\nfile = \"open.obj\"\n");
    expectBad("volume build " + open_scene + " --out " + vdb, "is not a closed mesh (3 edges", vdb);
}

TEST(Hardening, ImplausibleLaserLogsAreRefused)
{
    const RecordedRun& run = recordedRun();
    const std::string out = file("l.toml");
    const std::string fit = " --saturation " + run.sat + " --scene bocas --out " + out;
    expectBad("fit --laser " + file("neg.log", "0 0.1 2500 0.2 -5000\n") + fit, "neg.log:1: beam 1: range -5000", out);
    expectBad("fit --laser " + file("far.log", "0 0.1 2500 0.2 1e300\n") + fit, "far.log:1: beam 1: range", out);
    expectBad("fit --laser " + file("ang.log", "0 1e10 2500 0.2 2500\n") + fit, "ang.log:1: beam 0: angle", out);
    expectBad("fit --laser " + file("dup.log", "0 0.1 2500\n0 0.1 2501\n") + fit, "dup.log:2: time repeats", out);
    // A URG-04LX log is not an LMS200's.
    expectBad("fit-plume --laser " + run.log + " --scene plume --out " + file("p.json"), "has 682 beams a scan",
              file("p.json"));
    // A patch name given twice would duplicate CSV columns.
    expectBad("saturation volumes --rect a=0,0,1,1 --rect a=1,1,1,1 --out " + file("r.csv"), "patch 'a' is named twice",
              file("r.csv"));
}

// ---- messages and partial output ----

TEST(Hardening, AFailedRunLeavesNoneOfItsOutputs)
{
    const std::string log = file("p.log"), png = file("p.png"), folder = (dir() / "a_folder").string();
    fs::create_directories(folder);
    expectBad("scan bocas --to 1 --out " + log + " --image " + folder, "is a directory", log);
    // A device that refuses the content (a full disk) fails the run before any file lands.
    if (fs::exists("/dev/full")) expectBad("scan bocas --to 1 --out " + log + " --tau /dev/full", "/dev/full", log);
    fs::create_directories(folder + ".exr");
    expectBad("render bocas --spp 1 --width 8 --height 6 --out " + png + " --exr " + folder + ".exr", "is a directory",
              png);
    // A fit that fails writes its report (the diagnosis) and nothing else.
    std::string flat;  // three scans of the URG's 682 beams, all reading 2.5 m: no smoke event
    for (int t = 0; t < 3; ++t) {
        flat += std::to_string(t);
        for (int i = 0; i < 682; ++i) flat += " " + std::to_string((44 + i - 384) * 2 * M_PI / 1024) + " 2500";
        flat += "\n";
    }
    const std::string flat_log = file("flat.log", flat);
    const std::string flat_sat = file("flat.csv", "time_s,saturation\n0,0.3\n1,0.3\n2,0.3\n");
    const CliRun r =
        cli("fit --laser " + flat_log + " --saturation " + flat_sat + " --surface t=0:10 --out " + file("ff.toml"));
    EXPECT_NE(r.status, 0);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(file("ff.toml")));
    EXPECT_FALSE(fs::exists(file("ff_fig5.png")));
    EXPECT_FALSE(fs::exists(file("ff_fig9.png")));
    EXPECT_TRUE(fs::exists(file("ff_report.json")));
}

TEST(Hardening, InterruptedRunsRemoveTheirTemporaries)
{
    // A long scan is stopped while it streams into its temporaries; it must die by the signal
    // and leave nothing in its folder. Spawned directly, with SIGINT at its default (a shell's
    // background job would start with SIGINT ignored, which smokescan respects, as nohup wants).
    for (int sig : {SIGINT, SIGTERM}) {
        const fs::path d = scratch("interrupt_" + std::to_string(sig));
        const std::string log = (d / "long.log").string(), csv = (d / "long.csv").string();
        std::vector<std::string> args = {SMOKESCAN_CLI, "scan", "bocas",   "--from", "0", "--to",  "360",
                                         "--rate",      "20",   "--quiet", "--out",  log, "--tau", csv};
        std::vector<char*> argv;
        for (auto& a : args) argv.push_back(a.data());
        argv.push_back(nullptr);
        posix_spawnattr_t attr;
        posix_spawnattr_init(&attr);
        sigset_t def;
        sigemptyset(&def);
        sigaddset(&def, SIGINT);
        sigaddset(&def, SIGTERM);
        posix_spawnattr_setsigdefault(&attr, &def);
        posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGDEF);
        pid_t pid = 0;
        ASSERT_EQ(posix_spawn(&pid, argv[0], nullptr, &attr, argv.data(), environ), 0);
        posix_spawnattr_destroy(&attr);
        std::this_thread::sleep_for(std::chrono::milliseconds(1500));
        ::kill(pid, sig);
        int status = 0;
        ASSERT_EQ(::waitpid(pid, &status, 0), pid);
        EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == sig) << "the scan was not stopped by signal " << sig;
        for (const auto& e : fs::directory_iterator(d)) ADD_FAILURE() << "left " << e.path() << " after signal " << sig;
    }
}

TEST(Hardening, MessagesAreOneReadableLine)
{
    const RecordedRun& run = recordedRun();
    // Raw bytes are escaped; the message is valid UTF-8 on one line.
    const std::string bin = file("bin.log", std::string("0 0.1 \x01\xff\n"));
    const CliRun r = cli("fit --laser " + bin + " --saturation " + run.sat + " --scene bocas --out " + file("m.toml"));
    EXPECT_NE(r.err.find("'\\x01\\xFF'"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    // --lenient skips a non-UTF-8 line and still writes a valid JSON report.
    const std::string bad_utf8 = file("utf8.log", slurp(run.log) + "999.0 \xff\xfe 1\n");
    const CliRun l = cli("fit --lenient --laser " + bad_utf8 + " --saturation " + run.sat + " --scene bocas --out " +
                         file("u.toml"));
    EXPECT_EQ(l.err.find("json"), std::string::npos) << l.err;
    EXPECT_NE(slurp(file("u_report.json")).find("\"skipped\""), std::string::npos);
    // A folder as a scene, a truncated PNG, an unparseable option.
    expectBad("scan " + dir().string() + " --out " + file("t.log"), "is a folder, not a scene file", file("t.log"));
    const std::string png = file("whole.png");
    ASSERT_EQ(cli("render bocas --spp 1 --width 32 --height 24 --out " + png).status, 0);
    const std::string cut = file("cut.png", slurp(png).substr(0, 300));
    expectBad("saturation " + cut + " --rect a=0,0,4,4 --out " + file("cut.csv"), "cut.png: cannot read pixels",
              file("cut.csv"));
    expectBad("scan bocas --rate abc --out " + file("t.log"), "--rate: 'abc' is not a number", file("t.log"));
    // Out of memory is a sentence, not "std::bad_alloc" (AddressSanitizer cannot start under a
    // small address-space limit, so the sanitizer build leaves this to the Release build).
    if (kAsan) return;
    const std::string oom = "sh -c 'ulimit -v 2500000; " + std::string(SMOKESCAN_CLI) +
        " render bocas --spp 1 --width 8192 --height 8192 --out " + file("oom.png") + " 2>" + file("oom.err") + "'";
    EXPECT_NE(std::system(oom.c_str()), 0);
    EXPECT_NE(slurp(file("oom.err")).find("smokescan: out of memory"), std::string::npos) << slurp(file("oom.err"));
}

// OpenImageIO is opened on first use (include/smokescan/io/oiio_module.hpp): a module that is
// missing or is not smokescan's is a one-line error naming it, and no image is left.
TEST(Hardening, AnImageModuleMissingOrNotSmokescansIsOneLineAndNoImage)
{
    const std::string frame = file("module.png"), args = "render bocas --width 16 --height 12 --spp 1 --out ";
    for (const auto& [module, needle] : {std::pair<std::string, std::string>{"/nonexistent/libsmokescan_oiio.so",
                                                                             "was not found; looked at /nonexistent"},
                                         {file("not_a_module.so", "text\n"), "cannot load smokescan's image module"}}) {
        ::setenv("SMOKESCAN_OIIO_MODULE", module.c_str(), 1);
        expectBad(args + frame, needle, frame);
        ::unsetenv("SMOKESCAN_OIIO_MODULE");
    }
    // A FIFO would block dlopen: refused before it is opened.
    const std::string fifo = (dir() / "module_fifo.so").string();
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    ::setenv("SMOKESCAN_OIIO_MODULE", fifo.c_str(), 1);
    expectBad(args + frame, "is not a regular file", frame);
    ::unsetenv("SMOKESCAN_OIIO_MODULE");
    const CliRun r = cli(args + frame);  // the module beside the program
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(fs::exists(frame));
    // Run by its bare name through PATH from a folder holding a stray module: never the working
    // folder's (the loader knows the program by argv[0], which would have put it there).
    const fs::path stray = smokescan::test::scratch("stray_module");
    std::ofstream(stray / "libsmokescan_oiio.so") << "not a module\n";
    const fs::path cli_dir = fs::path(SMOKESCAN_CLI).parent_path(), frame2 = stray / "frame.png";
    const std::string cmd = "cd '" + stray.string() + "' && PATH='" + cli_dir.string() + "':\"$PATH\" " +
        fs::path(SMOKESCAN_CLI).filename().string() + " " + args + frame2.string() + " > /dev/null 2>&1";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
    EXPECT_TRUE(fs::exists(frame2));
}

// A volume (an OpenVDB grid named .png: OpenImageIO reads it as a W×H×D image) is not a picture:
// a one-line error, where its pixels overran the reader's buffer (a crash).
TEST(Hardening, AVolumeGivenAsAFrameIsRefused)
{
    const std::string png = file("volume_000.png"), csv = file("volume.csv");
    fs::copy_file("volumes/fog_ball_float.vdb", png, fs::copy_options::overwrite_existing);
    expectBad("saturation " + png + " --rect a=0,0,4,4 --out " + csv, "volume, not a picture", csv);
}
