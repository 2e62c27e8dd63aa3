#pragma once
// A skill library loaded for serving: its policies' weights and the metadata that says how to run
// them, each field checked against this robot and this build (robot/a1.h, robot/observation.h).
// Eigen only: the robot computer needs no libtorch.

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <array>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "skills/runtime/library_format.h"
#include "skills/runtime/falling_cycles.h"
#include "skills/runtime/safetensors.h"

namespace flsd {

// What evaluation measured of one skill (the library's per-skill descriptor).
struct SkillDescriptor {
  int id = 0;
  Eigen::Vector3d mean_linear_velocity = Eigen::Vector3d::Zero();   // body frame, m/s
  Eigen::Vector3d mean_angular_velocity = Eigen::Vector3d::Zero();  // body frame, rad/s
  double mean_base_height = 0.0;
  double gait_frequency_hz = 0.0;
  int survival_steps = 0;
  bool fell = false;
  // Absent from libraries exported before they were recorded:
  int mirror_skill = 0;  // the skill trained as this one's left-right mirror image (itself if none)
  // Which of the library's policies runs it, and its index in that policy's skill one-hot.
  // Absent from version 1 libraries: one policy, in which skill k is k.
  int policy = 0;
  int policy_skill = 0;
  std::optional<double> mean_stance_foot_speed;  // m/s: how fast its stance feet slide
  std::optional<int> randomized_survival_steps;  // under the training randomisation, the worst start
  std::optional<double> randomized_stance_foot_speed;  // m/s, the mean over those starts
  bool randomized_fell = false;

  // The fields as the library's metadata names them, listed once: `flsd export` writes them
  // (DescriptorJson) and SkillLibrary::Load reads them. v(key, field, required); a field that is
  // not required may be absent from older libraries.
  template <class V>
  void Visit(V& v) {
    v("id", id, true);
    v("mirror_skill", mirror_skill, false);  // absent: the skill is its own mirror image
    v("policy", policy, false);
    v("policy_skill", policy_skill, false);
    v("mean_linear_velocity", mean_linear_velocity, true);
    v("mean_angular_velocity", mean_angular_velocity, true);
    v("mean_base_height", mean_base_height, true);
    v("mean_stance_foot_speed", mean_stance_foot_speed, false);
    v("gait_frequency_hz", gait_frequency_hz, true);
    v("survival_steps", survival_steps, true);
    v("fell", fell, true);
    v("randomized_survival_steps", randomized_survival_steps, false);
    v("randomized_fell", randomized_fell, false);
    v("randomized_stance_foot_speed", randomized_stance_foot_speed, false);
  }
};

// A descriptor as the library's metadata stores it (its /skills/K entry).
nlohmann::json DescriptorJson(const SkillDescriptor& descriptor);

// A skill's earliest fall in the library's evaluations: after how many control steps, and whether
// under randomisation. A randomised fall without a recorded count is at step 0.
struct SkillFall {
  int steps = 0;
  bool randomized = false;
};
// std::nullopt if the skill fell in neither evaluation. skilld lists it.
std::optional<SkillFall> EarliestFall(const SkillDescriptor& descriptor);

// A dependable skill is one every evaluation the library records of it (nominal and, where
// measured, randomised) saw survive past the paper's bar of kSurvivalSteps without a fall. The one
// rule: the selectors choose only dependable skills, the shipping bar counts only them, the
// navigation benchmark's top speed is theirs, and skilld runs no other skill on request (its
// safety.min_skill_survival, passed as `min_fall_steps`, may allow a skill whose earliest fall
// comes at least that late). Empty if dependable; else why not, for a person: "fell after 212
// steps in the library's randomised evaluation".
std::string WhyUndependable(const SkillDescriptor& descriptor, int min_fall_steps = kAnyFall);
inline bool Dependable(const SkillDescriptor& descriptor) { return WhyUndependable(descriptor).empty(); }

using RowMatrixXf = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

struct DenseLayer {
  RowMatrixXf weight;  // outputs x inputs
  Eigen::VectorXf bias;
};

// A network as the library stores it: the first normalizer_mean.size() inputs are normalised
// ((x - mean) / std), the rest pass as they are; ELU between layers, a linear output.
struct DenseNetwork {
  std::vector<DenseLayer> layers;
  Eigen::VectorXf normalizer_mean, normalizer_std;
  int inputs() const { return static_cast<int>(layers.front().weight.cols()); }
  int outputs() const { return static_cast<int>(layers.back().bias.size()); }
};

// The velocity-tracking skill selector (optional in a library): a categorical policy over the
// skills whose input is o^c (robot/observation.h) and, for a semi-MDP selector, what it remembers
// (selector_memory.h), and the command ranges it was trained on.
struct SelectorNetwork {
  DenseNetwork network;
  std::array<double, 3> command_min{}, command_max{};  // vx, vy, wz
  double min_planar_speed = 0.0;  // slower (vx, vy) commands were zeroed in training, and are here
  int decision_interval = 1;  // control steps each chosen skill is held, as in training
  // > 0: the network's logits are added to NearestSkillSelector::Prior at this temperature, as in
  // training (absent from the file: 0, no prior).
  double nearest_prior_temperature = 0.0;
  // > 0: they are added to this logit on the time-sharing selector's choice (absent: 0, none).
  double time_sharing_prior = 0.0;
  // > 0: the input is o^c and then SelectorMemory's features over a window of this many control
  // steps (selector_memory.h: a semi-MDP selector); 0 (absent): o^c alone.
  int memory_window_steps = 0;
  // Of a library of num_skills skills.
  int inputs(int num_skills) const;
  // How many leading inputs are normalised: o^c and the memory's scalar features.
  int normalized_inputs() const;
};

// A command (vx, vy, wz) as the selector sees it: clipped to the ranges it was trained on, its
// planar part zeroed below the trained min_planar_speed.
std::array<double, 3> ClipCommand(const SelectorNetwork& selector, const double* command);

// One skill-conditioned policy of a library: its network reads o^p with a one-hot over its own
// num_skills skills (robot/observation.h). `training` is what the library records of the run that
// trained it (method, iteration, config, provenance).
struct SkillPolicy {
  DenseNetwork network;
  int num_skills = 0;
  nlohmann::json training;
};

class SkillLibrary {
 public:
  // Reads and validates `path`. Throws InputError naming the file and the first field that is
  // missing, malformed or different from what this robot and build expect.
  static SkillLibrary Load(const std::string& path);

  int num_skills() const { return num_skills_; }
  // The policies that run the skills (SkillDescriptor::policy); most libraries hold one.
  const std::vector<SkillPolicy>& policies() const { return policies_; }
  // The skill selector, if the library carries one (flsd export-selector).
  const std::optional<SelectorNetwork>& selector() const { return selector_; }
  const std::vector<SkillDescriptor>& skills() const { return skills_; }
  // Whether the robot fell when skill `from` handed over straight to skill `to` in the switches the
  // library records (`flsd transitions --record`, /transitions/falls): a selector does not make
  // that switch. False for a library that records none.
  bool SwitchFell(int from, int to) const { return falling_switches_.count({from, to}) > 0; }
  const std::set<std::pair<int, int>>& falling_switches() const { return falling_switches_; }
  // The cycles of holds the library records a fall for (`flsd cycles --record`, /cycles/falls):
  // a selector plays none of them. Empty for a library that records none.
  const FallingCycles& falling_cycles() const { return falling_cycles_; }
  // The cutoff (0: none) and order of the target filter the skills were trained behind; whoever
  // runs the policy runs a TargetFilter with them.
  double action_filter_hz() const { return action_filter_hz_; }
  int action_filter_order() const { return action_filter_order_; }
  const nlohmann::json& metadata() const { return metadata_; }
  const std::string& path() const { return path_; }
  // A hash of the file's bytes (FNV-1a, 64 bits, hex): what a selector records of the library it
  // was trained over, so that it is never run over different skills.
  const std::string& fingerprint() const { return fingerprint_; }

 private:
  std::string path_, fingerprint_;
  nlohmann::json metadata_;
  int num_skills_ = 0;
  double action_filter_hz_ = 0.0;
  int action_filter_order_ = 1;
  std::vector<SkillPolicy> policies_;
  std::optional<SelectorNetwork> selector_;
  std::vector<SkillDescriptor> skills_;
  std::set<std::pair<int, int>> falling_switches_;
  FallingCycles falling_cycles_;
};

// Writes a library file as `output` (atomically), after loading it as skilld will: a file that
// would not load never takes the name. Throws InputError naming what is wrong.
void WriteCheckedLibrary(const std::string& output, const SafeTensors& file);

// Runs a DenseNetwork on one input at a time, into buffers allocated at construction: Run()
// does no heap allocation. Holds a reference to `network`, which must outlive it.
class NetworkRunner {
 public:
  explicit NetworkRunner(const DenseNetwork& network);
  // input: network.inputs() floats (raw, before normalisation); output: network.outputs().
  void Run(const float* input, float* output);

 private:
  const DenseNetwork& network_;
  std::vector<Eigen::VectorXf> activations_;  // one per layer output, plus the normalised input
};

// Runs the library's skills, each on its own policy. Holds a reference to `library`, which must
// outlive it. Act() does no heap allocation.
class PolicyRunner {
 public:
  explicit PolicyRunner(const SkillLibrary& library);
  // motion_obs: o^m (kMotionObsSize floats); previous_action: the last action (12); skill: the
  // library's skill id. Writes the 12 action values. Throws InputError for an unknown skill.
  void Act(const float* motion_obs, const float* previous_action, int skill, float* action);

 private:
  const SkillLibrary& library_;
  std::vector<NetworkRunner> runners_;  // one per policy
  std::vector<float> policy_obs_;       // sized for the largest policy
};

}  // namespace flsd
