// flsd: the learning side's command line: simulator demo, training, evaluation, export, figures,
// benchmarks. Each group of subcommands lives in its own file (tools/flsd/subcommands.h).

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <string>

#include "core/check.h"
#include "skills/learning/runners/communicator.h"
#include "tools/flsd/subcommands.h"

namespace {

// In an MPI job a failing rank ends the whole job, naming itself, so that no other rank waits for
// it in a collective for ever; alone, the error is logged and the exit code returned.
int Fail(int code, const std::string& message) {
  const flsd::Communicator& comm = flsd::Communicator::World();
  if (comm.size() > 1) comm.Abort(message);
  spdlog::error("{}", message);
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"FLSD: Fourier Latent Skill Discovery for the Unitree A1"};
  app.require_subcommand(1);
  flsd::cli::Subcommands subcommands;
  flsd::cli::AddDemo(app, subcommands);
  flsd::cli::AddTraining(app, subcommands);
  flsd::cli::AddEvaluation(app, subcommands);
  flsd::cli::AddFigures(app, subcommands);
  flsd::cli::AddReport(app, subcommands);
  flsd::cli::AddBenchmarks(app, subcommands);
  CLI11_PARSE(app, argc, argv);
  try {
    for (const flsd::cli::Subcommand& subcommand : subcommands) {
      if (*subcommand.app) return subcommand.run();
    }
  } catch (const flsd::InputError& e) {
    return Fail(2, e.what());
  } catch (const std::exception& e) {
    return Fail(1, std::string("internal error: ") + e.what());
  }
  return 0;
}
