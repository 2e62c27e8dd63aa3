#pragma once
// A skill library loaded for serving: the policy's weights and the metadata that says how to run
// it, each field checked against this robot and this build (robot/a1.h, robot/observation.h).
// Eigen only: the robot computer needs no libtorch.

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

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
};

using RowMatrixXf = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

struct DenseLayer {
  RowMatrixXf weight;  // outputs x inputs
  Eigen::VectorXf bias;
};

class SkillLibrary {
 public:
  // Reads and validates `path`. Throws InputError naming the file and the first field that is
  // missing, malformed or different from what this robot and build expect.
  static SkillLibrary Load(const std::string& path);

  int num_skills() const { return num_skills_; }
  int policy_obs_size() const { return policy_obs_size_; }
  const std::vector<DenseLayer>& policy_layers() const { return layers_; }
  const Eigen::VectorXf& normalizer_mean() const { return normalizer_mean_; }
  const Eigen::VectorXf& normalizer_std() const { return normalizer_std_; }
  const std::vector<SkillDescriptor>& skills() const { return skills_; }
  const nlohmann::json& metadata() const { return metadata_; }
  const std::string& path() const { return path_; }
  // A hash of the file's bytes (FNV-1a, 64 bits, hex): what a selector records of the library it
  // was trained over, so that it is never run over different skills.
  const std::string& fingerprint() const { return fingerprint_; }

 private:
  std::string path_, fingerprint_;
  nlohmann::json metadata_;
  int num_skills_ = 0;
  int policy_obs_size_ = 0;
  std::vector<DenseLayer> layers_;
  Eigen::VectorXf normalizer_mean_, normalizer_std_;
  std::vector<SkillDescriptor> skills_;
};

// Runs a library's policy, one observation at a time, into buffers allocated at construction:
// Act() does no heap allocation. Holds a reference to `library`, which must outlive it.
class PolicyRunner {
 public:
  explicit PolicyRunner(const SkillLibrary& library);

  // policy_obs: the raw o^p (PolicyObservationSize floats, robot/observation.h); action: 12.
  void Act(const float* policy_obs, float* action);

 private:
  const SkillLibrary& library_;
  std::vector<Eigen::VectorXf> activations_;  // one per layer output, plus the normalised input
};

}  // namespace flsd
