// shvol: a participating-media simulator. See README.md for the command-line reference.
#include <cstdio>
#include <string>

#include "commands.h"
#include "shvol/core/error.h"

int main(int argc, char** argv) {
    CLI::App app{"shvol " SHVOL_VERSION " - volumetric path tracing of participating media"};
    app.set_version_flag("--version", "shvol " SHVOL_VERSION);
    app.require_subcommand(1);
    // --help shows every option's default (inherited by the subcommands added below).
    app.option_defaults()->always_capture_default();
    std::function<int()> run;
    shvol::app::addRenderCommand(app, run);
    shvol::app::addMakeMediumCommand(app, run);
    shvol::app::addMakeSkyCommand(app, run);
    shvol::app::addBenchCommand(app, run);
    shvol::app::addPhaseCommand(app, run);
    shvol::app::addDiffCommand(app, run);
    shvol::app::addTonemapCommand(app, run);
    shvol::app::addBatchCommand(app, run);
    shvol::app::addReportCommand(app, run);
    // An unknown first word is a wrong subcommand, not a missing one (CLI11 would say "A
    // subcommand is required", and print the main help with exit 0 for `shvol typo --help`).
    if (argc >= 2 && argv[1][0] != '-') {
        std::string names;
        bool known = false;
        for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
            known |= sub->get_name() == argv[1];
            names += (names.empty() ? "" : ", ") + sub->get_name();
        }
        if (!known) {
            std::fprintf(stderr, "shvol: error: unknown subcommand \"%s\"; expected one of %s\n",
                         argv[1], names.c_str());
            return 1;
        }
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        // Like every other error: one line and exit code 1 (CLI11 would print two lines and use
        // its own codes).
        std::fprintf(stderr, "shvol: error: %s (see --help)\n", e.what());
        return 1;
    }
    try {
        return run();
    } catch (const shvol::Error& e) {
        std::fprintf(stderr, "shvol: error: %s\n", e.what());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "shvol: internal error: %s\n", e.what());
    }
    return 1;
}
