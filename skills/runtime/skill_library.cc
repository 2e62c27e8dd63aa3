#include "skills/runtime/skill_library.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <type_traits>

#include "core/check.h"
#include "robot/a1.h"
#include "robot/observation.h"
#include "skills/runtime/selector_memory.h"
#include "robot/target_filter.h"
#include "skills/runtime/library_format.h"
#include "skills/runtime/safetensors.h"

namespace flsd {
namespace {

constexpr double kTolerance = 1e-9;

// Checks fields of the metadata JSON, each failure naming the file and the field's path.
class MetadataChecker {
 public:
  MetadataChecker(const std::string& path, const nlohmann::json& root) : path_(path), root_(root) {}

  const nlohmann::json& At(const std::string& pointer) const {
    const nlohmann::json::json_pointer p(pointer);
    if (!root_.contains(p)) Fail(pointer, "is missing");
    return root_.at(p);
  }
  template <class T>
  T Get(const std::string& pointer) const {
    const nlohmann::json& value = At(pointer);
    if constexpr (std::is_same_v<T, int>) {
      // nlohmann would turn 1.7 or true into 1; an id or a count must be written as an integer.
      if (!value.is_number_integer() || value.get<int64_t>() < std::numeric_limits<int>::min() ||
          value.get<int64_t>() > std::numeric_limits<int>::max()) {
        Fail(pointer, "must be an integer (it is " + value.dump() + ")");
      }
    }
    try {
      return value.get<T>();
    } catch (const nlohmann::json::exception&) {
      Fail(pointer, "has the wrong type (" + value.dump() + ")");
    }
  }
  void ExpectNumber(const std::string& pointer, double expected) const {
    const double got = Get<double>(pointer);
    if (std::abs(got - expected) > kTolerance * std::max(1.0, std::abs(expected))) {
      Fail(pointer, "is " + Show(got) + " but this robot uses " + Show(expected));
    }
  }
  void ExpectNumbers(const std::string& pointer, const std::vector<double>& expected) const {
    const std::vector<double> got = Get<std::vector<double>>(pointer);
    if (got.size() != expected.size()) {
      Fail(pointer, "has " + std::to_string(got.size()) + " entries; expected " + std::to_string(expected.size()));
    }
    for (size_t i = 0; i < got.size(); ++i) {
      if (std::abs(got[i] - expected[i]) > kTolerance * std::max(1.0, std::abs(expected[i]))) {
        Fail(pointer + "/" + std::to_string(i), "is " + Show(got[i]) + " but this robot uses " + Show(expected[i]));
      }
    }
  }
  void ExpectString(const std::string& pointer, const std::string& expected) const {
    const std::string got = Get<std::string>(pointer);
    if (got != expected) Fail(pointer, "is '" + got + "' but this build expects '" + expected + "'");
  }
  void Expect(const std::string& pointer, int expected) const { ExpectNumber(pointer, expected); }
  void Expect(const std::string& pointer, double expected) const { ExpectNumber(pointer, expected); }
  void Expect(const std::string& pointer, const std::vector<double>& expected) const { ExpectNumbers(pointer, expected); }
  void Expect(const std::string& pointer, const std::string& expected) const { ExpectString(pointer, expected); }
  void Expect(const std::string& pointer, const std::vector<std::string>& expected) const {
    const std::vector<std::string> got = Get<std::vector<std::string>>(pointer);
    if (got.size() != expected.size()) {
      Fail(pointer, "has " + std::to_string(got.size()) + " entries; expected " + std::to_string(expected.size()));
    }
    for (size_t i = 0; i < got.size(); ++i) {
      if (got[i] != expected[i]) Fail(pointer + "/" + std::to_string(i), "is '" + got[i] + "' but this build expects '" + expected[i] + "'");
    }
  }
  bool Has(const std::string& pointer) const { return root_.contains(nlohmann::json::json_pointer(pointer)); }
  const std::string& path() const { return path_; }
  [[noreturn]] void Fail(const std::string& pointer, const std::string& what) const {
    throw InputError(path_ + ": skill library field " + pointer + " " + what);
  }

 private:
  static std::string Show(double v) {
    std::ostringstream s;
    s.precision(10);
    s << v;
    return s.str();
  }
  const std::string& path_;
  const nlohmann::json& root_;
};

const FloatTensor& Tensor(const SafeTensors& file, const std::string& path, const std::string& name,
                          const std::vector<int64_t>& shape) {
  const auto it = file.tensors.find(name);
  if (it == file.tensors.end()) throw InputError(path + ": skill library has no tensor '" + name + "'");
  if (it->second.shape != shape) {
    auto show = [](const std::vector<int64_t>& s) {
      std::string t = "[";
      for (size_t i = 0; i < s.size(); ++i) t += (i ? ", " : "") + std::to_string(s[i]);
      return t + "]";
    };
    throw InputError(path + ": tensor '" + name + "' has shape " + show(it->second.shape) + "; expected " +
                     show(shape));
  }
  for (float v : it->second.values) {
    if (!std::isfinite(v)) throw InputError(path + ": tensor '" + name + "' holds a NaN or infinite value");
  }
  return it->second;
}

std::string FileFingerprint(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  uint64_t hash = 1469598103934665603ULL;
  for (char c; in.get(c);) hash = (hash ^ static_cast<unsigned char>(c)) * 1099511628211ULL;
  char text[17];
  std::snprintf(text, sizeof(text), "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

// The network stored under tensors `layer_prefix`layer<l>.{weight,bias} and
// `normalizer_prefix`{mean,std}, described by metadata at `at` (hidden, layers, activation).
DenseNetwork ReadNetwork(const SafeTensors& file, const MetadataChecker& m, const std::string& at,
                         const std::string& layer_prefix, const std::string& normalizer_prefix, int inputs,
                         int outputs, int normalized) {
  const std::string& path = m.path();
  m.ExpectString(at + "/activation", "elu");
  const std::vector<int> hidden = m.Get<std::vector<int>>(at + "/hidden");
  m.ExpectNumber(at + "/layers", static_cast<double>(hidden.size() + 1));
  DenseNetwork net;
  int width = inputs;
  for (size_t l = 0; l <= hidden.size(); ++l) {
    const int out = l < hidden.size() ? hidden[l] : outputs;
    const std::string name = layer_prefix + "layer" + std::to_string(l);
    const FloatTensor& w = Tensor(file, path, name + ".weight", {out, width});
    const FloatTensor& b = Tensor(file, path, name + ".bias", {out});
    DenseLayer layer;
    layer.weight = Eigen::Map<const RowMatrixXf>(w.values.data(), out, width);
    layer.bias = Eigen::Map<const Eigen::VectorXf>(b.values.data(), out);
    net.layers.push_back(std::move(layer));
    width = out;
  }
  const std::string mean = normalizer_prefix + "mean", std = normalizer_prefix + "std";
  net.normalizer_mean = Eigen::Map<const Eigen::VectorXf>(Tensor(file, path, mean, {normalized}).values.data(), normalized);
  net.normalizer_std = Eigen::Map<const Eigen::VectorXf>(Tensor(file, path, std, {normalized}).values.data(), normalized);
  if ((net.normalizer_std.array() <= 0.0f).any()) {
    throw InputError(path + ": tensor '" + std + "' has a value that is not positive");
  }
  return net;
}

// Reads a SkillDescriptor's fields (SkillDescriptor::Visit) from the metadata at `at`; a missing
// field that is not required keeps its value.
struct DescriptorReader {
  const MetadataChecker& m;
  std::string at;
  template <class T>
  void operator()(const char* key, T& field, bool required) {
    const std::string pointer = at + "/" + key;
    if (!required && !m.Has(pointer)) return;
    if constexpr (std::is_same_v<T, Eigen::Vector3d>) {
      const auto v = m.Get<std::vector<double>>(pointer);
      if (v.size() != 3) m.Fail(pointer, "must have 3 entries");
      field = Eigen::Vector3d(v[0], v[1], v[2]);
    } else if constexpr (std::is_same_v<T, std::optional<int>> || std::is_same_v<T, std::optional<double>>) {
      field = m.Get<typename T::value_type>(pointer);
    } else {
      field = m.Get<T>(pointer);
    }
  }
};

// Writes them.
struct DescriptorWriter {
  nlohmann::json& out;
  template <class T>
  void operator()(const char* key, const T& field, bool) {
    if constexpr (std::is_same_v<T, Eigen::Vector3d>) {
      out[key] = {field.x(), field.y(), field.z()};
    } else if constexpr (std::is_same_v<T, std::optional<int>> || std::is_same_v<T, std::optional<double>>) {
      if (field) out[key] = *field;
    } else {
      out[key] = field;
    }
  }
};

std::vector<double> CommandScale() {
  return {kMotionObsLayout[0].scale, kMotionObsLayout[0].scale, kMotionObsLayout[1].scale};
}

}  // namespace

nlohmann::json DescriptorJson(const SkillDescriptor& descriptor) {
  nlohmann::json out = nlohmann::json::object();
  DescriptorWriter writer{out};
  SkillDescriptor copy = descriptor;  // Visit is one list for reading and writing, so not const
  copy.Visit(writer);
  return out;
}

std::optional<SkillFall> EarliestFall(const SkillDescriptor& d) {
  std::optional<SkillFall> fall;
  if (d.fell) fall = SkillFall{d.survival_steps, false};
  if (d.randomized_fell) {
    const int steps = d.randomized_survival_steps.value_or(0);
    if (!fall || steps < fall->steps) fall = SkillFall{steps, true};
  }
  return fall;
}

std::string WhyUndependable(const SkillDescriptor& d, int min_fall_steps) {
  if (const std::optional<SkillFall> fall = EarliestFall(d); fall && fall->steps < min_fall_steps) {
    return "fell after " + std::to_string(fall->steps) + " steps in the library's " +
           (fall->randomized ? "randomised evaluation" : "evaluation");
  }
  const auto short_of_bar = [](int steps, const char* evaluation) {
    return "survived " + std::to_string(steps) + " steps in the library's " + evaluation + ", not more than " +
           std::to_string(kSurvivalSteps);
  };
  if (!Survives(d.survival_steps)) return short_of_bar(d.survival_steps, "evaluation");
  if (d.randomized_survival_steps && !Survives(*d.randomized_survival_steps)) {
    return short_of_bar(*d.randomized_survival_steps, "randomised evaluation");
  }
  return "";
}

SkillLibrary SkillLibrary::Load(const std::string& path) {
  const SafeTensors file = ReadSafeTensors(path);
  SkillLibrary lib;
  lib.path_ = path;
  lib.fingerprint_ = FileFingerprint(path);
  const auto format = file.metadata.find("format");
  if (format == file.metadata.end() || format->second != kSkillLibraryFormat || file.metadata.count("flsd") == 0) {
    throw InputError(path + ": a safetensors file, but not an FLSD skill library (no '" + std::string(kSkillLibraryFormat) +
                     "' metadata)");
  }
  try {
    lib.metadata_ = nlohmann::json::parse(file.metadata.at("flsd"));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path + ": skill library metadata is not JSON: " + e.what());
  }
  const MetadataChecker m(path, lib.metadata_);

  // The version first: what else a library holds, and where, depends on it.
  const int version = m.Get<int>("/format_version");
  if (version != 1 && version != kSkillLibraryVersion) {
    m.Fail("/format_version", "is " + std::to_string(version) + " but this build reads versions 1 to " +
                                  std::to_string(kSkillLibraryVersion));
  }
  LibraryValues values;
  values.Visit([&](const char* pointer, auto& field, bool required, double min, double max) {
    if (!required && !m.Has(pointer)) return;
    field = m.Get<std::decay_t<decltype(field)>>(pointer);
    if (!(field >= min && field <= max)) {
      char range[64];
      std::snprintf(range, sizeof(range), "must be within [%g, %g]", min, max);
      m.Fail(pointer, range);
    }
  });
  lib.num_skills_ = values.num_skills;
  lib.action_filter_hz_ = values.action_filter_hz;
  lib.action_filter_order_ = values.action_filter_order;
  VisitLibraryFacts([&](const std::string& pointer, const auto& expected) {
    if (pointer != "/format_version") m.Expect(pointer, expected);
  });

  const int normalized = kMotionObsSize + kActionSize;
  if (version == 1) {
    // One policy over all the skills, described at /policy and /training.
    SkillPolicy policy;
    policy.num_skills = lib.num_skills_;
    policy.network = ReadNetwork(file, m, "/policy", "policy.", "normalizer.", PolicyObservationSize(lib.num_skills_),
                                 kActionSize, normalized);
    m.Get<std::string>("/training/config");
    policy.training = m.At("/training");
    lib.policies_.push_back(std::move(policy));
  } else {
    const nlohmann::json& policies = m.At("/policies");
    if (!policies.is_array() || policies.empty()) m.Fail("/policies", "must list at least one policy");
    for (size_t p = 0; p < policies.size(); ++p) {
      const std::string at = "/policies/" + std::to_string(p);
      SkillPolicy policy;
      policy.num_skills = m.Get<int>(at + "/num_skills");
      if (policy.num_skills < 1 || policy.num_skills > kMaxSkills) {
        m.Fail(at + "/num_skills", "must be within [1, " + std::to_string(kMaxSkills) + "]");
      }
      VisitPolicyFacts([&](const std::string& pointer, const auto& expected) { m.Expect(pointer, expected); },
                       static_cast<int>(p), policy.num_skills);
      const std::string tensors = PolicyTensorPrefix(static_cast<int>(p));
      policy.network = ReadNetwork(file, m, at, tensors, tensors + "normalizer.",
                                   PolicyObservationSize(policy.num_skills), kActionSize, normalized);
      m.Get<std::string>(at + "/training/config");  // what evaluations of the library rebuild its env from
      policy.training = m.At(at + "/training");
      lib.policies_.push_back(std::move(policy));
    }
  }
  if (m.Has("/selector")) {
    SelectorNetwork selector;
    m.ExpectNumber("/selector/observation/motion", kMotionObsSize);
    m.ExpectNumber("/selector/observation/command", kCommandSize);
    m.ExpectNumbers("/selector/observation/command_scale", CommandScale());
    if (m.Has("/selector/memory_window_steps")) {
      selector.memory_window_steps = m.Get<int>("/selector/memory_window_steps");
      if (selector.memory_window_steps < 0) m.Fail("/selector/memory_window_steps", "must be at least 0 (0: no memory)");
    }
    selector.network = ReadNetwork(file, m, "/selector", "selector.", "selector.normalizer.",
                                   selector.inputs(lib.num_skills_), lib.num_skills_, selector.normalized_inputs());
    const char* axes[3] = {"vx", "vy", "wz"};
    for (int a = 0; a < 3; ++a) {
      const std::string at = std::string("/selector/commands/") + axes[a];
      const auto range = m.Get<std::vector<double>>(at);
      if (range.size() != 2 || !(range[0] <= range[1])) m.Fail(at, "must be [min, max] with min <= max");
      selector.command_min[a] = range[0];
      selector.command_max[a] = range[1];
    }
    selector.min_planar_speed = m.Get<double>("/selector/commands/min_planar_speed");
    if (!(selector.min_planar_speed >= 0.0)) m.Fail("/selector/commands/min_planar_speed", "must be at least 0");
    selector.decision_interval = m.Get<int>("/selector/decision_interval");
    if (selector.decision_interval < 1) m.Fail("/selector/decision_interval", "must be at least 1");
    if (m.Has("/selector/nearest_prior_temperature")) {
      selector.nearest_prior_temperature = m.Get<double>("/selector/nearest_prior_temperature");
      if (!(selector.nearest_prior_temperature >= 0.0)) {
        m.Fail("/selector/nearest_prior_temperature", "must be at least 0 (0: no prior)");
      }
    }
    if (m.Has("/selector/time_sharing_prior")) {
      selector.time_sharing_prior = m.Get<double>("/selector/time_sharing_prior");
      if (!(selector.time_sharing_prior >= 0.0)) m.Fail("/selector/time_sharing_prior", "must be at least 0 (0: no prior)");
      if (selector.time_sharing_prior > 0.0 && selector.nearest_prior_temperature > 0.0) {
        m.Fail("/selector/time_sharing_prior", "a selector has one prior, but nearest_prior_temperature is set too");
      }
    }
    lib.selector_ = std::move(selector);
  }

  const nlohmann::json& skills = m.At("/skills");
  if (!skills.is_array() || static_cast<int>(skills.size()) != lib.num_skills_) {
    m.Fail("/skills", "must describe each of the " + std::to_string(lib.num_skills_) + " skills");
  }
  std::map<std::pair<int, int>, int> runs;  // (policy, policy_skill) -> the skill it runs
  for (int k = 0; k < lib.num_skills_; ++k) {
    const std::string at = "/skills/" + std::to_string(k);
    SkillDescriptor d;
    d.mirror_skill = k;
    d.policy_skill = k;
    DescriptorReader reader{m, at};
    d.Visit(reader);
    if (version >= 2) {  // only version 1's skills all belong to one policy
      m.At(at + "/policy");
      m.At(at + "/policy_skill");
    }
    if (d.id != k) m.Fail(at + "/id", "is " + std::to_string(d.id) + "; expected " + std::to_string(k));
    if (d.mirror_skill < 0 || d.mirror_skill >= lib.num_skills_) {
      m.Fail(at + "/mirror_skill", "must be a skill id, 0 to " + std::to_string(lib.num_skills_ - 1));
    }
    const int num_policies = static_cast<int>(lib.policies_.size());
    if (d.policy < 0 || d.policy >= num_policies) {
      m.Fail(at + "/policy", "must be a policy index, 0 to " + std::to_string(num_policies - 1));
    }
    const int policy_skills = lib.policies_[d.policy].num_skills;
    if (d.policy_skill < 0 || d.policy_skill >= policy_skills) {
      m.Fail(at + "/policy_skill", "must be 0 to " + std::to_string(policy_skills - 1) + " (policy " +
                                       std::to_string(d.policy) + "'s skills)");
    }
    if (const auto [it, fresh] = runs.emplace(std::make_pair(d.policy, d.policy_skill), k); !fresh) {
      m.Fail(at + "/policy_skill", "is skill " + std::to_string(it->second) + "'s too");
    }
    lib.skills_.push_back(d);
  }
  // Mirror images pair both ways.
  for (const SkillDescriptor& d : lib.skills_) {
    if (lib.skills_[d.mirror_skill].mirror_skill != d.id) {
      m.Fail("/skills/" + std::to_string(d.id) + "/mirror_skill",
             "is " + std::to_string(d.mirror_skill) + ", but skill " + std::to_string(d.mirror_skill) +
                 "'s is not " + std::to_string(d.id));
    }
  }
  if (m.Has("/transitions/falls")) {
    const nlohmann::json& falls = m.At("/transitions/falls");
    if (!falls.is_array()) m.Fail("/transitions/falls", "must be a list of [from, to] skill id pairs");
    for (size_t i = 0; i < falls.size(); ++i) {
      const std::string at = "/transitions/falls/" + std::to_string(i);
      if (!falls[i].is_array() || falls[i].size() != 2) m.Fail(at, "must be a [from, to] pair of skill ids");
      const int from = m.Get<int>(at + "/0"), to = m.Get<int>(at + "/1");
      for (int id : {from, to}) {
        if (id < 0 || id >= lib.num_skills_) {
          m.Fail(at, "names skill " + std::to_string(id) + "; expected 0 to " + std::to_string(lib.num_skills_ - 1));
        }
      }
      if (from == to) m.Fail(at, "switches skill " + std::to_string(from) + " to itself");
      lib.falling_switches_.emplace(from, to);
    }
  }
  if (m.Has("/cycles/falls")) {
    const nlohmann::json& falls = m.At("/cycles/falls");
    constexpr int kMax = FallingCycles::kMaxLength;
    const std::string what = "must be a list of cycles, each 2 to " + std::to_string(kMax) + " skill ids";
    if (!falls.is_array()) m.Fail("/cycles/falls", what);
    for (size_t i = 0; i < falls.size(); ++i) {
      const std::string at = "/cycles/falls/" + std::to_string(i);
      if (!falls[i].is_array() || falls[i].size() < 2 || falls[i].size() > kMax) {
        m.Fail(at, "must be a cycle of 2 to " + std::to_string(kMax) + " skill ids");
      }
      std::array<int, kMax> cycle{};
      const int length = static_cast<int>(falls[i].size());
      for (int h = 0; h < length; ++h) {
        cycle[h] = m.Get<int>(at + "/" + std::to_string(h));
        if (cycle[h] < 0 || cycle[h] >= lib.num_skills_) {
          m.Fail(at, "names skill " + std::to_string(cycle[h]) + "; expected 0 to " + std::to_string(lib.num_skills_ - 1));
        }
      }
      if (std::all_of(cycle.begin(), cycle.begin() + length, [&](int k) { return k == cycle[0]; })) {
        m.Fail(at, "holds skill " + std::to_string(cycle[0]) + " throughout: a cycle switches");
      }
      lib.falling_cycles_.Add(cycle.data(), length);
    }
  }
  return lib;
}

void WriteCheckedLibrary(const std::string& output, const SafeTensors& file) {
  const std::string unchecked = output + ".unchecked";
  WriteSafeTensors(unchecked, file);
  try {
    SkillLibrary::Load(unchecked);
  } catch (...) {
    std::filesystem::remove(unchecked);
    throw;
  }
  std::filesystem::rename(unchecked, output);
}

NetworkRunner::NetworkRunner(const DenseNetwork& network) : network_(network) {
  activations_.emplace_back(Eigen::VectorXf::Zero(network.inputs()));
  for (const DenseLayer& layer : network.layers) activations_.emplace_back(Eigen::VectorXf::Zero(layer.bias.size()));
}

void NetworkRunner::Run(const float* input, float* output) {
  Eigen::VectorXf& x = activations_[0];
  const int normalized = static_cast<int>(network_.normalizer_mean.size());
  const Eigen::Map<const Eigen::VectorXf> in(input, x.size());
  x.head(normalized) = (in.head(normalized) - network_.normalizer_mean).cwiseQuotient(network_.normalizer_std);
  x.tail(x.size() - normalized) = in.tail(x.size() - normalized);
  const std::vector<DenseLayer>& layers = network_.layers;
  for (size_t l = 0; l < layers.size(); ++l) {
    Eigen::VectorXf& y = activations_[l + 1];
    y.noalias() = layers[l].weight * activations_[l];
    y += layers[l].bias;
    if (l + 1 < layers.size()) {
      // ELU: x for x > 0, exp(x) - 1 otherwise.
      y = y.unaryExpr([](float v) { return v > 0.0f ? v : std::expm1(v); });
    }
  }
  Eigen::Map<Eigen::VectorXf>(output, activations_.back().size()) = activations_.back();
}

PolicyRunner::PolicyRunner(const SkillLibrary& library) : library_(library) {
  int largest = 0;
  for (const SkillPolicy& policy : library.policies()) {
    runners_.emplace_back(policy.network);
    largest = std::max(largest, PolicyObservationSize(policy.num_skills));
  }
  policy_obs_.resize(largest);
}

void PolicyRunner::Act(const float* motion_obs, const float* previous_action, int skill, float* action) {
  if (skill < 0 || skill >= library_.num_skills()) {
    throw InputError("skill " + std::to_string(skill) + " is not in " + library_.path() + " (0 to " +
                     std::to_string(library_.num_skills() - 1) + ")");
  }
  const SkillDescriptor& d = library_.skills()[skill];
  BuildPolicyObservation(motion_obs, previous_action, d.policy_skill, library_.policies()[d.policy].num_skills,
                         policy_obs_.data());
  runners_[d.policy].Run(policy_obs_.data(), action);
}

int SelectorNetwork::inputs(int num_skills) const {
  return kTaskObsSize + (memory_window_steps > 0 ? SelectorMemory::FeatureSize(num_skills) : 0);
}

int SelectorNetwork::normalized_inputs() const {
  return kTaskObsSize + (memory_window_steps > 0 ? SelectorMemory::kScalarFeatures : 0);
}

std::array<double, 3> ClipCommand(const SelectorNetwork& s, const double* command) {
  std::array<double, 3> clipped;
  for (int a = 0; a < 3; ++a) clipped[a] = std::clamp(command[a], s.command_min[a], s.command_max[a]);
  if (std::hypot(clipped[0], clipped[1]) < s.min_planar_speed) clipped[0] = clipped[1] = 0.0;
  return clipped;
}

}  // namespace flsd
