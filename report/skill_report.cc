#include "report/skill_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

#include "core/atomic_file.h"
#include "core/check.h"
#include "report/learning_curves.h"
#include "report/skill_figures.h"

namespace flsd {
namespace {

namespace fs = std::filesystem;

// The paper's figures (Tables I and II) that ours are set against.
constexpr double kPaperCoverageFlsd = 0.600, kPaperCoverageDiayn = 0.257;
constexpr double kPaperHighFrequencyFlsd = 199.75, kPaperHighFrequencyDiayn = 448.07;
constexpr double kRateHz = 50.0;
constexpr int kPsdSegment = 100;  // 2 s: 0.5 Hz bins
constexpr int kPsdJoint = 2;      // FR_calf, the joint the paper's Fig. 5 shows is not named
constexpr int kEmbeddingStride = 10;

bool Survived(const SkillSummary& s) { return Survives(s.survival_steps); }

// Skills that survive 500 steps and that skilld's supervisor would not stop for joint speed.
int WithinJointSpeed(const Evaluation& e) {
  int n = 0;
  for (const SkillSummary& s : e.skills) {
    n += Survived(s) && s.longest_overspeed_s <= a1::kJointOverspeedTolerance + 1e-9;
  }
  return n;
}

std::string Fixed(double v, int digits) {
  if (!std::isfinite(v)) return "-";
  char text[48];
  std::snprintf(text, sizeof text, "%.*f", digits, v);
  return text;
}

std::string Escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '&') out += "&amp;";
    else out += c;
  }
  return out;
}

struct Spread {
  double min = NAN, max = NAN, std = NAN;
};
// Of one mean velocity component over the skills that survive 500 steps.
Spread SpreadOf(const Evaluation& e, double (*component)(const SkillSummary&)) {
  std::vector<double> v;
  for (const SkillSummary& s : e.skills) {
    if (Survived(s)) v.push_back(component(s));
  }
  if (v.empty()) return {};
  double mean = 0.0, sq = 0.0;
  for (double x : v) mean += x;
  mean /= v.size();
  for (double x : v) sq += (x - mean) * (x - mean);
  return {*std::min_element(v.begin(), v.end()), *std::max_element(v.begin(), v.end()), std::sqrt(sq / v.size())};
}
double Vx(const SkillSummary& s) { return s.mean_linear_velocity[0]; }
double Vy(const SkillSummary& s) { return s.mean_linear_velocity[1]; }
double Wz(const SkillSummary& s) { return s.mean_angular_velocity[2]; }

nlohmann::json SpreadJson(const Spread& s) { return {{"min", s.min}, {"max", s.max}, {"std", s.std}}; }

nlohmann::json ScaledCoverageJson(const ScaledCoverage& c) {
  nlohmann::json dims;
  for (int d = 0; d < kCoverageDims; ++d) dims[kCoverageRanges[d].name] = c.dim_cells[d];
  return {{"cells_visited", c.cells_visited}, {"dim_cells", dims}};
}

nlohmann::json RunJson(const ReportRun& r, const ScaledCoverage& scaled) {
  const Evaluation& e = r.nominal;
  nlohmann::json dims = nlohmann::json::array();
  for (int d = 0; d < kCoverageDims; ++d) {
    dims.push_back({{"name", kCoverageRanges[d].name}, {"max", e.coverage.max[d]}, {"min", e.coverage.min[d]}});
  }
  const DirectionCounts directions = CountDirections(e);
  return {{"label", r.label},
          {"method", r.method},
          {"seed", r.seed},
          {"iteration", r.iteration},
          {"env_steps", r.env_steps},
          {"num_skills", e.skills.size()},
          {"coverage_rate", e.coverage.rate},
          {"cells_visited", e.coverage.cells_visited},
          {"scaled_coverage", ScaledCoverageJson(scaled)},
          {"table_1", dims},
          {"high_frequency_ratio", e.high_frequency.pooled_ratio},
          {"high_frequency_ratio_per_skill", {{"mean", e.high_frequency.mean_ratio}, {"std", e.high_frequency.std_ratio}}},
          {"survivors", e.survivors},
          {"survivors_randomized", r.randomized.survivors},
          {"survivors_both", RobustSurvivors(r)},
          {"survivors_within_joint_speed_limit", WithinJointSpeed(e)},
          {"mean_velocity_spread",
           {{"vx", SpreadJson(SpreadOf(e, Vx))}, {"vy", SpreadJson(SpreadOf(e, Vy))}, {"wz", SpreadJson(SpreadOf(e, Wz))}}},
          {"directions",
           {{"forward", directions.forward},
            {"backward", directions.backward},
            {"sideways", directions.sideways},
            {"turning", directions.turning}}}};
}

double Mean(const std::vector<double>& v) {
  double sum = 0.0;
  for (double x : v) sum += x;
  return v.empty() ? NAN : sum / v.size();
}

double Median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The sample standard deviation over runs (seeds); null for fewer than two.
nlohmann::json SeedStd(const std::vector<double>& v) {
  if (v.size() < 2) return nullptr;
  const double mean = Mean(v);
  double sq = 0.0;
  for (double x : v) sq += (x - mean) * (x - mean);
  return std::sqrt(sq / (v.size() - 1));
}

// "mean" or, over several runs, "mean ± std".
std::string MeanAndSpread(const nlohmann::json& method, const char* key, double scale, int digits) {
  const nlohmann::json& std = method[std::string(key) + "_std"];
  const std::string mean = Fixed(scale * method[key].get<double>(), digits);
  return std.is_null() ? mean : mean + " &plusmn; " + Fixed(scale * std.get<double>(), digits);
}

// Per method, the mean over its runs of the headline numbers, and their spread over the runs.
nlohmann::json MethodJson(const std::vector<const ReportRun*>& runs,
                          const std::map<const ReportRun*, ScaledCoverage>& scaled) {
  std::vector<double> coverage, scaled_cells, high, survivors, both, steps;
  for (const ReportRun* r : runs) {
    coverage.push_back(r->nominal.coverage.rate);
    scaled_cells.push_back(static_cast<double>(scaled.at(r).cells_visited));
    high.push_back(r->nominal.high_frequency.pooled_ratio);
    survivors.push_back(r->nominal.survivors);
    both.push_back(RobustSurvivors(*r));
    steps.push_back(static_cast<double>(r->env_steps));
  }
  return {{"runs", runs.size()},          {"coverage_rate", Mean(coverage)},   {"high_frequency_ratio", Mean(high)},
          {"survivors", Mean(survivors)}, {"survivors_both", Mean(both)},      {"env_steps", Mean(steps)},
          {"coverage_rate_per_run", coverage}, {"high_frequency_ratio_per_run", high},
          {"coverage_rate_std", SeedStd(coverage)}, {"high_frequency_ratio_std", SeedStd(high)},
          {"scaled_cells", Mean(scaled_cells)}, {"scaled_cells_per_run", scaled_cells},
          {"scaled_cells_std", SeedStd(scaled_cells)}, {"high_frequency_ratio_median", Median(high)}};
}

// Each of the first method's runs over the second method's mean: the spread of a ratio over seeds.
std::vector<double> RatiosPerRun(const nlohmann::json& first, const nlohmann::json& second, const char* per_run,
                                 const char* mean) {
  std::vector<double> ratios;
  for (const nlohmann::json& v : first[per_run]) ratios.push_back(v.get<double>() / second[mean].get<double>());
  return ratios;
}

std::string Svg(const std::string& dir, const std::string& name, const SvgPlot& plot) {
  plot.Save((fs::path(dir) / name).string());
  return "<figure><img src=\"" + name + "\" alt=\"" + name + "\"></figure>\n";
}

std::string Row(const std::vector<std::string>& cells, bool header = false) {
  std::string row = "<tr>";
  for (const std::string& c : cells) row += (header ? "<th>" : "<td>") + c + (header ? "</th>" : "</td>");
  return row + "</tr>\n";
}

std::string AnswersHtml(const nlohmann::json& json) {
  if (!json.contains("comparison")) {
    return "<p>FLSD against DIAYN needs runs of both methods; the numbers per run are below.</p>\n";
  }
  const nlohmann::json& c = json["comparison"];
  const nlohmann::json& f = json["methods"]["flsd"];
  const nlohmann::json& d = json["methods"]["diayn"];
  std::ostringstream h;
  h << "<table>\n"
    << Row({"question", "FLSD", "DIAYN", "FLSD / DIAYN", "paper (FLSD, DIAYN, ratio)"}, true)
    << Row({"state coverage rate (Table I)", MeanAndSpread(f, "coverage_rate", 100, 2) + " %",
            MeanAndSpread(d, "coverage_rate", 100, 2) + " %", Fixed(c["coverage_ratio"].get<double>(), 2),
            "60.0 %, 25.7 %, 2.33"})
    << Row({"state coverage, scaled reading: cells visited", MeanAndSpread(f, "scaled_cells", 1, 0),
            MeanAndSpread(d, "scaled_cells", 1, 0), Fixed(c["scaled_coverage_ratio"].get<double>(), 2), "2.33"})
    << Row({"high-frequency power ratio (Table II)", MeanAndSpread(f, "high_frequency_ratio", 1, 3),
            MeanAndSpread(d, "high_frequency_ratio", 1, 3), Fixed(c["high_frequency_ratio"].get<double>(), 2) +
                " (reduction " + Fixed(100 * c["high_frequency_reduction"].get<double>(), 0) + " %)",
            "199.75, 448.07, 0.45 (reduction 55 %; the text says 73 %)"})
    << Row({"... medians over the runs", Fixed(f["high_frequency_ratio_median"].get<double>(), 3),
            Fixed(d["high_frequency_ratio_median"].get<double>(), 3),
            Fixed(c["high_frequency_ratio_of_medians"].get<double>(), 2), "0.45"})
    << Row({"skills surviving 500 steps", Fixed(f["survivors"].get<double>(), 1), Fixed(d["survivors"].get<double>(), 1),
            "", ""})
    << Row({"... and with the training randomisation on", Fixed(f["survivors_both"].get<double>(), 1),
            Fixed(d["survivors_both"].get<double>(), 1), "", ""})
    << Row({"environment steps per run", Fixed(f["env_steps"].get<double>() / 1e6, 1) + " M",
            Fixed(d["env_steps"].get<double>() / 1e6, 1) + " M", Fixed(c["budget_ratio"].get<double>(), 2), "12 000 M"})
    << "</table>\n"
    << "<p>Each figure is the mean over a method's runs (listed below). The coverage rate is the fraction of the "
       "4<sup>7</sup> = 16384 cells of the normalised grid (step 0.5 over the fixed ranges of <code>metrics.h</code>) "
       "that the skills surviving 500 steps visit. The scaled reading divides each dimension by its standard "
       "deviation over the states of every run in this report and counts cells of 0.5 deviations centred on zero "
       "(<code>ScaledStateCoverage</code>): a still posture that jitters fills one cell per dimension, not two. "
       "The high-frequency ratio is the power of the joint-velocity "
       "spectra above 10 Hz over their total power, all joints and skills pooled; the reduction is "
       "1 &minus; FLSD / DIAYN. The paper's Table II values are the same kind of ratio on a scale it does not state, "
       "so only the ratio of the two compares; 199.75 / 448.07 is a 55 % reduction, not the 73 % its text gives.</p>\n";
  return h.str();
}

std::string RunsHtml(const std::vector<ReportRun>& runs) {
  std::ostringstream h;
  h << "<table>\n" << Row({"run", "method", "seed", "iteration", "env steps"}, true);
  for (const ReportRun& r : runs) {
    h << Row({Escape(r.label), r.method, std::to_string(r.seed), std::to_string(r.iteration),
              Fixed(r.env_steps / 1e6, 2) + " M"});
  }
  return h.str() + "</table>\n";
}

std::string TableOneHtml(const std::vector<ReportRun>& runs) {
  std::ostringstream h;
  std::vector<std::string> header{"run"};
  for (const CoverageRange& r : kCoverageRanges) {
    header.push_back(std::string(r.name) + " max");
    header.push_back(std::string(r.name) + " min");
  }
  header.push_back("cells");
  header.push_back("coverage rate");
  h << "<table>\n" << Row(header, true);
  for (const ReportRun& r : runs) {
    const CoverageResult& c = r.nominal.coverage;
    std::vector<std::string> row{Escape(r.label)};
    for (int d = 0; d < kCoverageDims; ++d) {
      row.push_back(Fixed(c.max[d], 2));
      row.push_back(Fixed(c.min[d], 2));
    }
    row.push_back(std::to_string(c.cells_visited));
    row.push_back(Fixed(100 * c.rate, 2) + " %");
    h << Row(row);
  }
  h << Row({"paper FLSD", "0.94", "-1.47", "1.26", "-1.41", "1.27", "-1.10", "19.97", "-22.53", "8.02", "-7.97", "8.63",
            "-9.55", "0.40", "0.09", "", "60.00 %"})
    << Row({"paper DIAYN", "1.35", "-1.07", "0.79", "-0.88", "0.92", "-0.98", "15.61", "-15.62", "7.72", "-7.53", "5.99",
            "-6.51", "0.31", "0.10", "", "25.70 %"});
  return h.str() + "</table>\n";
}

// Fig. 4 per dimension: the cells each run visits along each dimension alone, on the scaled grid.
std::string ScaledCoverageHtml(const nlohmann::json& json) {
  std::ostringstream h;
  std::vector<std::string> header{"run"};
  for (const CoverageRange& r : kCoverageRanges) header.push_back(r.name);
  header.push_back("7-D cells");
  h << "<p>The scaled reading, per dimension: cells of half a pooled standard deviation visited along each "
       "dimension alone (deviations:";
  for (int d = 0; d < kCoverageDims; ++d) h << " " << kCoverageRanges[d].name << " " << Fixed(json["coverage_scales"][d].get<double>(), 3);
  h << ").</p>\n<table>\n" << Row(header, true);
  for (const nlohmann::json& run : json["runs"]) {
    std::vector<std::string> row{Escape(run["label"].get<std::string>())};
    for (const CoverageRange& r : kCoverageRanges) row.push_back(run["scaled_coverage"]["dim_cells"][r.name].dump());
    row.push_back(run["scaled_coverage"]["cells_visited"].dump());
    h << Row(row);
  }
  return h.str() + "</table>\n";
}

std::string TableTwoHtml(const std::vector<ReportRun>& runs) {
  std::ostringstream h;
  h << "<table>\n"
    << Row({"run", "pooled ratio (> 10 Hz)", "per-skill mean", "per-skill std", "survivors (of skills)",
            "with randomisation (worst of its starts)", "both",
            "survivors skilld runs (" + Fixed(a1::kJointVelocityLimit, 0) + " rad/s for at most " +
                Fixed(a1::kJointOverspeedTolerance, 2) + " s)"},
           true);
  for (const ReportRun& r : runs) {
    const HighFrequencyResult& f = r.nominal.high_frequency;
    h << Row({Escape(r.label), Fixed(f.pooled_ratio, 3), Fixed(f.mean_ratio, 3), Fixed(f.std_ratio, 3),
              std::to_string(r.nominal.survivors) + " / " + std::to_string(r.nominal.skills.size()),
              std::to_string(r.randomized.survivors), std::to_string(RobustSurvivors(r)),
              std::to_string(WithinJointSpeed(r.nominal))});
  }
  return h.str() + "</table>\n";
}

std::string VelocityHtml(const std::vector<ReportRun>& runs) {
  std::ostringstream h;
  h << "<table>\n"
    << Row({"run", "v_x min..max (std)", "v_y min..max (std)", "w_z min..max (std)", "forward", "backward", "sideways",
            "turning"},
           true);
  for (const ReportRun& r : runs) {
    auto cell = [](const Spread& s) { return Fixed(s.min, 2) + " .. " + Fixed(s.max, 2) + " (" + Fixed(s.std, 2) + ")"; };
    const DirectionCounts n = CountDirections(r.nominal);
    h << Row({Escape(r.label), cell(SpreadOf(r.nominal, Vx)), cell(SpreadOf(r.nominal, Vy)), cell(SpreadOf(r.nominal, Wz)),
              std::to_string(n.forward), std::to_string(n.backward), std::to_string(n.sideways),
              std::to_string(n.turning)});
  }
  return h.str() + "</table>\n";
}

std::string SkillsHtml(const ReportRun& r) {
  std::ostringstream h;
  h << "<details><summary>" << Escape(r.label) << ": every skill</summary>\n"
    << "<p>Task columns: legged_gym's velocity-tracking reward per second (A1 scales, unclipped) when the "
       "skill is commanded its own mean velocity; tracking is its two tracking terms, reward the sum of all "
       "terms, penalties included: what a skill selector could at best collect from the skill.</p>\n<table>\n"
    << Row({"skill", "steps", "with randomisation (worst start)", "v_x", "v_y", "w_z", "height", "gait Hz", "> 10 Hz ratio",
            "stance foot speed", "peak joint speed", "task tracking /s", "task reward /s"},
           true);
  for (size_t k = 0; k < r.nominal.skills.size(); ++k) {
    const SkillSummary& s = r.nominal.skills[k];
    const int randomized = k < r.randomized.skills.size() ? r.randomized.skills[k].survival_steps : 0;
    h << Row({std::to_string(s.skill), std::to_string(s.survival_steps) + (s.fell ? " (fell)" : ""),
              std::to_string(randomized), Fixed(Vx(s), 2), Fixed(Vy(s), 2), Fixed(Wz(s), 2),
              Fixed(s.mean_base_height, 3), Fixed(s.gait_frequency_hz, 1), Fixed(s.high_frequency_ratio, 3),
              Fixed(s.mean_stance_foot_speed, 2), Fixed(s.max_joint_speed, 1),
              Fixed(s.task_reward_per_s.tracking_lin_vel + s.task_reward_per_s.tracking_ang_vel, 2),
              Fixed(s.task_reward_per_s.total, 2)});
  }
  return h.str() + "</table></details>\n";
}

std::string FiguresHtml(const std::vector<ReportRun>& runs, const std::string& dir) {
  std::ostringstream h;
  h << "<h2>Fig. 4: state coverage per skill</h2>\n";
  for (const ReportRun& r : runs) h << Svg(dir, "coverage_" + r.label + ".svg", CoverageFigure(r.nominal, r.label));

  h << "<h2>Fig. 5: spectrum of " << a1::kJointNames[kPsdJoint] << "'s velocity</h2>\n"
    << "<p>Each skill that survives 500 steps, cut into " << kPsdSegment / kRateHz
    << " s segments; at each frequency the distribution over the segments' periodograms. A still joint sits "
       "on the -100 dB floor.</p>\n";
  std::vector<PsdBands> bands;
  double lo = INFINITY, hi = -INFINITY;
  for (const ReportRun& r : runs) {
    bands.push_back(JointVelocityPsdBands(r.nominal.trajectories, kPsdJoint, kRateHz, kPsdSegment));
    for (double v : bands.back().p5) lo = std::min(lo, v);
    for (double v : bands.back().p95) hi = std::max(hi, v);
  }
  for (size_t i = 0; i < runs.size(); ++i) {
    if (bands[i].segments == 0) {
      h << "<p>" << Escape(runs[i].label) << ": no skill survived 500 steps.</p>\n";
      continue;
    }
    h << Svg(dir, "psd_" + runs[i].label + ".svg",
             PsdFigure(bands[i], runs[i].label + " (" + std::to_string(bands[i].segments) + " segments)",
                       std::floor(lo / 10) * 10, std::ceil(hi / 10) * 10));
  }

  std::vector<const Evaluation*> evaluations;
  std::vector<std::string> labels;
  int num_skills = 1;
  for (const ReportRun& r : runs) {
    evaluations.push_back(&r.nominal);
    labels.push_back(r.label);
    num_skills = std::max<int>(num_skills, r.nominal.skills.size());
  }
  h << "<h2>Fig. 6: embedding of the skills' states</h2>\n"
    << "<p>Principal components (t-SNE is not available here) of every " << kEmbeddingStride
    << "th state: normalised coverage dimensions and joint angles, standardised. Hue: run; shade: skill.</p>\n"
    << Svg(dir, "embedding.svg",
           EmbeddingFigure(PrincipalComponentEmbedding(evaluations, kEmbeddingStride), labels, num_skills));

  h << "<h2>Mean velocities of the skills that survive 500 steps</h2>\n"
    << Svg(dir, "velocity_lateral.svg", MeanVelocityFigure(evaluations, labels, 1))
    << Svg(dir, "velocity_yaw.svg", MeanVelocityFigure(evaluations, labels, 2));

  std::vector<CurveSpec> curves;
  for (const ReportRun& r : runs) {
    if (!r.progress_csv.empty()) curves.push_back({r.label, {r.progress_csv}});
  }
  if (!curves.empty()) {
    h << "<h2>Learning curves</h2>\n";
    for (const char* column : {"discriminator_accuracy", "intrinsic_reward", "mean_episode_length"}) {
      CurvePlotOptions options;
      options.y = column;
      options.smooth = 25;
      options.title = column;
      options.output = (fs::path(dir) / (std::string("curve_") + column + ".svg")).string();
      PlotCurves(curves, options);
      h << "<figure><img src=\"curve_" << column << ".svg\" alt=\"" << column << "\"></figure>\n";
    }
  }
  return h.str();
}

}  // namespace

DirectionCounts CountDirections(const Evaluation& e) {
  DirectionCounts n;
  for (const SkillSummary& s : e.skills) {
    if (!Survived(s)) continue;
    n.forward += Vx(s) >= kMovingSpeed;
    n.backward += Vx(s) <= -kMovingSpeed;
    n.sideways += std::abs(Vy(s)) >= kMovingSpeed;
    n.turning += std::abs(Wz(s)) >= kTurningRate;
  }
  return n;
}

int RobustSurvivors(const ReportRun& r) {
  int both = 0;
  for (size_t k = 0; k < r.nominal.skills.size() && k < r.randomized.skills.size(); ++k) {
    both += Survived(r.nominal.skills[k]) && Survived(r.randomized.skills[k]);
  }
  return both;
}

nlohmann::json ReportJson(const std::vector<ReportRun>& runs) {
  nlohmann::json json;
  json["runs"] = nlohmann::json::array();
  // The second reading of coverage: every run on the grid of the deviations pooled over all of them.
  std::vector<const std::vector<SkillTrajectory>*> trajectories;
  for (const ReportRun& r : runs) trajectories.push_back(&r.nominal.trajectories);
  const CoverageScales scales = PooledCoverageScales(trajectories);
  json["coverage_scales"] = scales;
  std::map<const ReportRun*, ScaledCoverage> scaled;
  std::map<std::string, std::vector<const ReportRun*>> by_method;
  for (const ReportRun& r : runs) {
    scaled[&r] = ScaledStateCoverage(r.nominal.trajectories, scales);
    json["runs"].push_back(RunJson(r, scaled[&r]));
    by_method[r.method].push_back(&r);
  }
  for (const auto& [method, members] : by_method) json["methods"][method] = MethodJson(members, scaled);
  if (by_method.count("flsd") && by_method.count("diayn")) {
    const nlohmann::json& f = json["methods"]["flsd"];
    const nlohmann::json& d = json["methods"]["diayn"];
    const double high = f["high_frequency_ratio"].get<double>() / d["high_frequency_ratio"].get<double>();
    json["comparison"] = {
        {"coverage_ratio", f["coverage_rate"].get<double>() / d["coverage_rate"].get<double>()},
        {"coverage_ratio_per_flsd_run", RatiosPerRun(f, d, "coverage_rate_per_run", "coverage_rate")},
        {"scaled_coverage_ratio", f["scaled_cells"].get<double>() / d["scaled_cells"].get<double>()},
        {"scaled_coverage_ratio_per_flsd_run", RatiosPerRun(f, d, "scaled_cells_per_run", "scaled_cells")},
        {"high_frequency_ratio", high},
        {"high_frequency_ratio_per_flsd_run",
         RatiosPerRun(f, d, "high_frequency_ratio_per_run", "high_frequency_ratio")},
        {"high_frequency_ratio_of_medians",
         f["high_frequency_ratio_median"].get<double>() / d["high_frequency_ratio_median"].get<double>()},
        {"high_frequency_reduction", 1.0 - high},
        {"budget_ratio", f["env_steps"].get<double>() / d["env_steps"].get<double>()},
        {"paper", {{"coverage_ratio", kPaperCoverageFlsd / kPaperCoverageDiayn},
                   {"high_frequency_ratio", kPaperHighFrequencyFlsd / kPaperHighFrequencyDiayn}}}};
  }
  return json;
}

void WriteSkillReport(const std::vector<ReportRun>& runs, const std::string& dir, const std::string& commit) {
  if (runs.empty()) throw InputError("report: no runs given");
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) throw InputError("report: cannot create " + dir + ": " + error.message());
  const nlohmann::json json = ReportJson(runs);
  WriteFileAtomically((fs::path(dir) / "report.json").string(), json.dump(2) + "\n");

  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>FLSD skill report</title>\n"
       << "<style>body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em}"
          "table{border-collapse:collapse;margin:1em 0;font-size:90%}td,th{border:1px solid #ccc;padding:3px 6px;"
          "text-align:right}th{background:#f4f4f4}img{max-width:100%}</style></head><body>\n"
       << "<h1>FLSD skill report</h1>\n<p>Written by <code>flsd report</code> at commit <code>" << Escape(commit)
       << "</code>. Every skill is rolled out once for " << runs.front().nominal.steps
       << " steps (50 Hz) with its mean action, without randomisation, and once more with the training "
          "randomisation on; numbers are in <a href=\"report.json\">report.json</a>.</p>\n"
       << "<h2>FLSD against DIAYN</h2>\n"
       << AnswersHtml(json) << "<h2>Runs</h2>\n"
       << RunsHtml(runs) << "<h2>Table I: state space coverage</h2>\n"
       << TableOneHtml(runs) << ScaledCoverageHtml(json) << "<h2>Table II: high-frequency power, and survival</h2>\n"
       << TableTwoHtml(runs) << "<h2>Mean velocities of the surviving skills</h2>\n"
       << "<p>Directions: skills surviving 500 steps with v_x &ge; 0.3 m/s (forward), v_x &le; &minus;0.3 (backward), "
          "|v_y| &ge; 0.3 (sideways), |w_z| &ge; 0.5 rad/s (turning).</p>\n"
       << VelocityHtml(runs);
  for (const ReportRun& r : runs) html << SkillsHtml(r);
  html << FiguresHtml(runs, dir) << "</body></html>\n";
  WriteFileAtomically((fs::path(dir) / "index.html").string(), html.str());
}

}  // namespace flsd
