#pragma once
// flsd's subcommands. Each file registers its own with the command line (its options, bound to
// storage it owns) and says how it runs; main.cc parses and runs the one chosen.

#include <CLI/CLI.hpp>

#include <atomic>
#include <functional>
#include <vector>

namespace flsd::cli {

struct Subcommand {
  CLI::App* app;
  std::function<int()> run;  // the process's exit code
};
using Subcommands = std::vector<Subcommand>;

void AddDemo(CLI::App& app, Subcommands& out);            // sim_demo.cc
void AddTraining(CLI::App& app, Subcommands& out);        // train, train-selector
void AddEvaluation(CLI::App& app, Subcommands& out);      // eval, export, export-selector, track
void AddFigures(CLI::App& app, Subcommands& out);         // render, plot
void AddReport(CLI::App& app, Subcommands& out);          // report_command.cc
void AddBenchmarks(CLI::App& app, Subcommands& out);      // bench sim|train|mpi|policy|hw|plan|nav

// Set by Ctrl-C or a scheduler's SIGTERM once StopOnSignals() ran: training ends the iteration in
// progress, then checkpoints.
void StopOnSignals();
const std::atomic<bool>& StopRequested();

// An option that names a checkpoint a run kept, as eval and export take it.
inline constexpr const char* kKeptIterationHelp =
    "Load the checkpoint the run kept at this iteration (checkpoints/ITER.pt; default: the latest)";

}  // namespace flsd::cli
