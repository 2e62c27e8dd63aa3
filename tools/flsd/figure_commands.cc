// flsd render and flsd plot.

#include <cstdio>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "core/check.h"
#include "render/skill_render.h"
#include "report/learning_curves.h"
#include "tools/flsd/subcommands.h"

namespace flsd::cli {

void AddFigures(CLI::App& app, Subcommands& out) {
  auto render = std::make_shared<RenderOptions>();
  CLI::App* render_cmd = app.add_subcommand(
      "render", "Film a skill in the simulator (.gif, .mp4, .png), or every skill as one contact sheet (.png)");
  render_cmd->add_option("--library", render->library, "Skill library (.safetensors)")->required();
  render_cmd->add_option("-o,--output", render->output, "File to write: .gif, .mp4 (needs ffmpeg) or .png")->required();
  render_cmd->add_option("--skill", render->skill, "Skill to film (from 0)");
  render_cmd->add_flag("--contact-sheet", render->contact_sheet, "One still of every skill, 4 across (.png)");
  render_cmd->add_option("--seconds", render->seconds, "Length of the rollout (a contact sheet's stills are its last frames)");
  render_cmd->add_option("--fps", render->fps, "Frames per second (1 to 50)");
  render_cmd->add_option("--width", render->width, "Frame width in pixels");
  render_cmd->add_option("--height", render->height, "Frame height in pixels");
  render_cmd->add_option("--seed", render->seed, "Seed of the initial pose");
  out.push_back({render_cmd, [render] { return RunRender(*render); }});

  struct PlotArgs {
    std::vector<std::string> curves;
    CurvePlotOptions options;
  };
  auto plot = std::make_shared<PlotArgs>();
  CLI::App* plot_cmd = app.add_subcommand("plot", "Draw learning curves of runs as one SVG chart");
  plot_cmd->add_option("curves", plot->curves,
                       "LABEL=RUN_DIR/progress.csv[,RUN_DIR/progress.csv...] ... (several: one per seed, drawn as "
                       "their mean and the band between the lowest and the highest)")
      ->required();
  plot_cmd->add_option("--x", plot->options.x, "Column for the x axis (default env_steps)");
  plot_cmd->add_option("--y", plot->options.y, "Column for the y axis (default mean_reward)");
  plot_cmd->add_option("--smooth", plot->options.smooth, "Moving average over this many iterations")
      ->check(CLI::Range(1, 100000));
  plot_cmd->add_option("--title", plot->options.title, "Chart title");
  plot_cmd->add_option("-o,--output", plot->options.output, "SVG file to write")->required();
  out.push_back({plot_cmd, [plot] {
                   std::vector<CurveSpec> specs;
                   for (const std::string& arg : plot->curves) {
                     const size_t eq = arg.find('=');
                     if (eq == std::string::npos) throw InputError("plot: expected LABEL=FILE, got '" + arg + "'");
                     CurveSpec spec{arg.substr(0, eq), {}};
                     std::stringstream files(arg.substr(eq + 1));
                     for (std::string file; std::getline(files, file, ',');) spec.csvs.push_back(file);
                     specs.push_back(spec);
                   }
                   PlotCurves(specs, plot->options);
                   std::printf("%s\n", plot->options.output.c_str());
                   return 0;
                 }});
}

}  // namespace flsd::cli
