// smokescan: laser range finders and cameras in smoke. A thin CLI over the library.
#include <glog/logging.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <new>
#include <string>

#include "commands.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/version.hpp"
#include "smokescan/io/atomic_file.hpp"

namespace {

/// Ceres logs through glog (rank-deficient covariances, line-search notes); the fits report what
/// matters in their results and an error is one line, so the program lets glog say nothing
/// below FATAL.
void quietGlog(const char* argv0)
{
    google::InitGoogleLogging(argv0);
    FLAGS_minloglevel = google::GLOG_FATAL;
    FLAGS_stderrthreshold = google::GLOG_FATAL;
    FLAGS_logtostderr = false;
}

/// True when an argument (or an `--option=value`'s value) names the program's standard output as
/// a file (`--out /dev/stdout`), as the writers read such names (smokescan::ownStreamFd).
bool writesToStdout(int argc, char** argv)
{
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const size_t eq = a.rfind('=');
        if (smokescan::ownStreamFd(a) == 1 ||
            (eq != std::string::npos && smokescan::ownStreamFd(a.substr(eq + 1)) == 1))
            return true;
    }
    return false;
}

}  // namespace

int main(int argc, char** argv)
{
    quietGlog(argc > 0 ? argv[0] : "smokescan");
    // A file written to standard output holds only the file: what the program prints goes to
    // standard error instead (docs/limits.md).
    if (writesToStdout(argc, argv)) smokescan::divertStdout();
    CLI::App app{"smokescan: laser range finders and cameras in smoke, simulated physically"};
    app.set_version_flag("--version", std::string("smokescan ") + smokescan::version());
    app.require_subcommand(1);
    smokescan::cli::Runner run;
    smokescan::cli::addScan(app, run);
    smokescan::cli::addVolume(app, run);
    smokescan::cli::addScene(app, run);
    smokescan::cli::addRender(app, run);
    smokescan::cli::addCalibration(app, run);
    smokescan::cli::addFit(app, run);
    smokescan::cli::addFitPlume(app, run);
    smokescan::cli::addDiagnose(app, run);
    smokescan::cli::addOmnirange(app, run);
    // CLI11 would say only that an argument was not expected, or that a subcommand is required:
    // an unknown command (or a command's unknown subcommand, `volume frob`) is named.
    CLI::App* level = &app;
    for (int i = 1; i < argc && argv[i][0] != '-'; ++i) {
        const auto subs = level->get_subcommands([](CLI::App*) { return true; });
        if (subs.empty()) break;
        CLI::App* next = nullptr;
        std::string names;
        for (CLI::App* sub : subs) {
            if (sub->get_name() == argv[i]) next = sub;
            names += (names.empty() ? "" : ", ") + sub->get_name();
        }
        if (!next) {
            std::cerr << "smokescan: unknown " << (level == &app ? "command" : "subcommand of " + level->get_name())
                      << " '" << smokescan::printable(argv[i]) << "' (" << names << "; see --help)\n";
            return 2;
        }
        level = next;
    }
    // A report or help text that could not be written (a full disk, a closed pipe's reader gone)
    // is a failure the user must see, not a silent 0.
    auto written = [](int rc) {
        errno = 0;
        std::cout.flush();
        if (std::fflush(stdout) != 0 || std::ferror(stdout) || !std::cout) {
            const int e = errno;
            std::cerr << "smokescan: standard output: cannot write the report"
                      << (e ? " (" + std::string(std::strerror(e)) + ")" : std::string()) << '\n';
            return rc ? rc : 1;
        }
        return rc;
    };
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return written(app.exit(e));
    } catch (const CLI::CallForAllHelp& e) {
        return written(app.exit(e));
    } catch (const CLI::CallForVersion& e) {
        return written(app.exit(e));
    } catch (const CLI::ParseError& e) {  // one line, as every other error
        std::cerr << "smokescan: " << smokescan::printable(e.what()) << " (see --help)\n";
        return 2;
    }
    try {
        return written(run ? run() : 0);
    } catch (const std::bad_alloc&) {
        std::cerr << "smokescan: out of memory (the run needs more than this machine has; see docs/limits.md)\n";
    } catch (const std::exception& e) {
        std::cerr << "smokescan: " << smokescan::printable(e.what()) << '\n';
    }
    return 1;
}
