// smokescan: laser range finders and cameras in smoke. A thin CLI over the library.
#include <iostream>

#include "commands.hpp"
#include "smokescan/core/error.hpp"

int main(int argc, char** argv)
{
    CLI::App app{"smokescan: laser range finders and cameras in smoke, simulated physically"};
    app.require_subcommand(1);
    smokescan::cli::Runner run;
    smokescan::cli::addScan(app, run);
    smokescan::cli::addVolume(app, run);
    smokescan::cli::addScene(app, run);
    smokescan::cli::addRender(app, run);
    smokescan::cli::addCalibration(app, run);
    smokescan::cli::addFit(app, run);
    smokescan::cli::addFitPlume(app, run);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    try {
        return run ? run() : 0;
    } catch (const smokescan::Error& e) {
        std::cerr << "smokescan: " << e.what() << '\n';
    } catch (const std::exception& e) {
        std::cerr << "smokescan: " << e.what() << '\n';
    }
    return 1;
}
