#pragma once
// Subcommands of the shvol program; each registers its options on the CLI11 app.
#include <CLI/CLI.hpp>
#include <functional>

namespace shvol::app {

/// Registers a subcommand; `run` is set to its action when it is selected.
void addRenderCommand(CLI::App& app, std::function<int()>& run);
void addMakeMediumCommand(CLI::App& app, std::function<int()>& run);
void addMakeSkyCommand(CLI::App& app, std::function<int()>& run);
void addBenchCommand(CLI::App& app, std::function<int()>& run);
void addPhaseCommand(CLI::App& app, std::function<int()>& run);
void addDiffCommand(CLI::App& app, std::function<int()>& run);
void addTonemapCommand(CLI::App& app, std::function<int()>& run);

/// Peak resident memory of this process in MiB.
double peakMemoryMiB();

}  // namespace shvol::app
