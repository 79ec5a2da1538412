// `smokescan diagnose` end to end: a simulated run diagnosed into a new folder; bad input is a
// one-line error naming the file and the problem, with no folder left.
#include <gtest/gtest.h>

#include <fstream>

#include "cli_run.hpp"

using namespace smokescan::test;
namespace fs = std::filesystem;

TEST(Cli, DiagnoseWritesItsFolderAndRefusesBadRuns)
{
    const std::string log = file("d_rec.log"), sat = file("d_sat.csv"), out = file("diag");
    CliRun r = cli("scan bocas --rate 1 --seed 3 --quiet --out " + log + " --saturation-out " + sat +
                   " --saturation-sigma 0.01 --saturation-rate 5");
    ASSERT_EQ(r.status, 0) << r.err;
    r = cli("diagnose --laser " + log + " --saturation " + sat + " --scene bocas --out " + out + "/");  // a folder/
    ASSERT_EQ(r.status, 0) << r.err << r.out;
    EXPECT_NE(r.out.find("verdict: none"), std::string::npos) << r.out;
    EXPECT_NE(slurp(fs::path(out) / "diagnosis.json").find("\"verdict\": \"none\""), std::string::npos);
    const std::string report = slurp(fs::path(out) / "report.md");
    EXPECT_NE(report.find("### smoke_trend"), std::string::npos);
    // A bin whose beams all failed has no range residual: "–", not "nan".
    EXPECT_EQ(report.find("nan"), std::string::npos) << report;
    EXPECT_NE(report.find("| –"), std::string::npos) << "the dense bins have no ranges";
    EXPECT_TRUE(fs::is_regular_file(fs::path(out) / "worst_1.png"));  // the worst covariates, plotted
    // The extended sensor file (nothing learned: the paper model) scans.
    const std::string toml = (fs::path(out) / "sensor.toml").string();
    EXPECT_NE(slurp(toml).find("model = \"paper\""), std::string::npos);
    r = cli("scan bocas --from 0 --to 5 --quiet --sensor-file " + toml + " --out " + file("d_rescan.log"));
    EXPECT_EQ(r.status, 0) << r.err;
    // A sensor file with extensions scans them (a dropout sector over the beams ahead), and its
    // clock offset is the diagnosis' default --offset.
    const std::string ext = file("d_ext.toml",
                                 "type = \"urg04lx\"\nmodel = \"paper\"\n[extensions]\nclock_offset_s = 0.75\n"
                                 "[[extensions.sector]]\nfrom_deg = -10\nto_deg = 10\ndropout = 1\n");
    r = cli("scan bocas --from 0 --to 2 --quiet --sensor-file " + ext + " --out " + file("d_ext.log") + " --tau " +
            file("d_ext.csv"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(slurp(file("d_ext.csv")).find("sector_dropout"), std::string::npos);
    r = cli("diagnose --laser " + log + " --saturation " + sat + " --scene bocas --sensor-file " + ext + " --out " +
            file("diag_ext"));
    ASSERT_EQ(r.status, 0) << r.err << r.out;
    EXPECT_NE(slurp(fs::path(file("diag_ext")) / "diagnosis.json").find("\"offset_s\": 0.75"), std::string::npos);
    // Without a saturation series the scene's own time line is replayed. The log is read through
    // a name with a byte that is not UTF-8: named escaped in the JSON and the report (raw, the
    // JSON writer refused it after all the work).
    const std::string odd = file("d_rec_\xff.log");
    fs::copy_file(log, odd);
    r = cli("diagnose --laser '" + odd + "' --scene bocas --out " + file("diag_traced"));
    ASSERT_EQ(r.status, 0) << r.err << r.out;
    EXPECT_NE(r.out.find("verdict: none"), std::string::npos) << r.out;
    EXPECT_NE(slurp(fs::path(file("diag_traced")) / "diagnosis.json").find("d_rec_\\\\xFF.log\""), std::string::npos);
    EXPECT_NE(slurp(fs::path(file("diag_traced")) / "report.md").find("# Diagnosis of " + file("d_rec_\\xFF.log")),
              std::string::npos);
    // The folder exists now: a second run is refused and leaves it as it was.
    expectBad("diagnose --laser " + log + " --saturation " + sat + " --scene bocas --out " + out, "not an empty folder",
              file("none"));

    // A Sick's log on the BOCAS URG; a saturation on another day; a run too short to hold out.
    const std::string sick = file("d_sick.log"),
                      late = file("d_late.csv", "time_s,saturation\n10000,0.3\n10001,0.6\n10002,0.2\n10003,0.5\n");
    ASSERT_EQ(cli("scan plume --sensor lms200 --from 0 --to 3 --quiet --out " + sick).status, 0);
    expectBad("diagnose --laser " + sick + " --saturation " + sat + " --scene bocas --out " + file("d1"),
              "d_sick.log: has 361 beams a scan", file("d1"));
    expectBad("diagnose --laser " + log + " --saturation " + late + " --scene bocas --out " + file("d2"),
              "d_late.csv: does not overlap the laser log", file("d2"));
    // An empty target prefix would make every surface the camera's target.
    expectBad(
        "diagnose --laser " + log + " --saturation " + sat + " --scene bocas --target-prefix '' --out " + file("d0"),
        "--target-prefix: must not be empty", file("d0"));
    const std::string shortlog = file("d_short.log");
    // 1 s: at most three blocks even while the smoke changes (a block lasts at least 0.5 s).
    ASSERT_EQ(cli("scan bocas --from 100 --to 101 --quiet --out " + shortlog).status, 0);
    expectBad("diagnose --laser " + shortlog + " --saturation " + sat + " --scene bocas --out " + file("d3"),
              "at least 4 are needed", file("d3"));
    const std::string badsensor = file("d_bad.toml", "type = \"urg04lx\"\n[extensions]\nx = 1\n");
    expectBad("diagnose --laser " + log + " --saturation " + sat + " --scene bocas --sensor-file " + badsensor +
                  " --out " + file("d4"),
              "d_bad.toml", file("d4"));
    // A camera that saw no smoke vary; a log in cm read as mm.
    const std::string flat = file("d_flat.csv", "time_s,saturation\n0,0.5\n100,0.5\n200,0.5\n300,0.5\n400,0.5\n");
    expectBad("diagnose --laser " + log + " --saturation " + flat + " --scene bocas --out " + file("d7"),
              "d_flat.csv: holds a saturation from 0.5 to 0.5", file("d7"));
    expectBad("diagnose --laser " + log + " --saturation " + sat + " --scene bocas --unit cm --out " + file("d8"),
              "is --unit right?", file("d8"));
    expectBad("diagnose --laser " + log + " --scene bocas --model physical --out " + file("d5"),
              "replayed from a saturation series only", file("d5"));
    // A smoke shape that is not one; the timeline with the physical model (its tables are the
    // reference state's).
    expectBad(
        "diagnose --laser " + log + " --saturation " + sat + " --scene bocas --smoke-shape bogus --out " + file("d9"),
        "--smoke-shape: 'bogus' is not a smoke shape (reference, timeline)", file("d9"));
    expectBad("diagnose --laser " + log + " --saturation " + sat +
                  " --scene bocas --model physical --smoke-shape timeline --out " + file("d10"),
              "--smoke-shape: timeline is replayed with the paper model only", file("d10"));
    // Extensions on a surface the scene does not have.
    const std::string alien =
        file("d_alien.toml", "type = \"urg04lx\"\n[extensions]\n[[extensions.surface]]\nname = \"nowhere\"\n");
    expectBad("diagnose --laser " + log + " --saturation " + sat + " --scene bocas --sensor-file " + alien + " --out " +
                  file("d6"),
              "d_alien.toml: [extensions] name surface 'nowhere'", file("d6"));
    expectBad("scan bocas --from 0 --to 2 --sensor-file " + alien + " --out " + file("d_alien.log"), "'nowhere'",
              file("d_alien.log"));
}
