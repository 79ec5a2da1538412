// smokescan: laser range finders and cameras in smoke. A thin CLI over the library.
#include <iostream>
#include <new>

#include "commands.hpp"
#include "smokescan/core/error.hpp"
#include "smokescan/core/version.hpp"

int main(int argc, char** argv)
{
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
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {  // one line, as every other error
        std::cerr << "smokescan: " << smokescan::printable(e.what()) << " (see --help)\n";
        return 2;
    }
    try {
        return run ? run() : 0;
    } catch (const std::bad_alloc&) {
        std::cerr << "smokescan: out of memory (the run needs more than this machine has; see docs/limits.md)\n";
    } catch (const std::exception& e) {
        std::cerr << "smokescan: " << smokescan::printable(e.what()) << '\n';
    }
    return 1;
}
