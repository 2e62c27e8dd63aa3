#include "skills/learning/runners/train_config.h"

#include <algorithm>

namespace flsd {

Method ParseMethod(const std::string& name) {
  if (name == "flsd") return Method::kFlsd;
  if (name == "diayn") return Method::kDiayn;
  throw InputError("method: expected 'flsd' or 'diayn', got '" + name + "'");
}

const char* ToString(Method m) { return m == Method::kFlsd ? "flsd" : "diayn"; }

void ValidateTrainConfig(const TrainConfig& config, const std::string& where) {
  try {
    ParseMethod(config.method);
  } catch (const InputError& e) {
    throw InputError(where + ": " + e.what());
  }
  if (config.pae.kernel_size % 2 == 0) {
    throw InputError(where + ": pae.kernel_size: expected an odd number, got " +
                     std::to_string(config.pae.kernel_size));
  }
  if (config.symmetry.enabled) {
    try {
      mirror::SkillPairing(config.num_skills, config.symmetry.self_paired_skills);
    } catch (const InputError& e) {
      throw InputError(where + ": symmetry." + e.what());
    }
  }
  if (config.travel.enabled()) {
    try {
      const SkillTravelTargets targets = ParseSkillTravelTargets(config.travel, config.num_skills);
      if (config.symmetry.enabled) CheckMirrorImages(targets, SkillPairingOf(config.num_skills, config.symmetry));
    } catch (const InputError& e) {
      throw InputError(where + ": " + e.what());
    }
  }
  if (config.travel.upright) {
    if (!(config.travel.enabled() && config.env.constraints.enabled)) {
      throw InputError(where + ": travel.upright: holds travel skills to a constraint, so it needs travel.weight > 0 "
                       "and env.constraints.enabled");
    }
    const SkillTravelTargets targets = ParseSkillTravelTargets(config.travel, config.num_skills);
    if (std::none_of(targets.begin(), targets.end(), [](const auto& t) { return t && !t->still; })) {
      throw InputError(where + ": travel.upright: no entry of travel.directions is a direction, so it holds no skill");
    }
  }
  if (config.travel.upright_still && !config.travel.upright) {
    throw InputError(where + ": travel.upright_still: holds the still skills as travel.upright holds the others, so it "
                     "needs travel.upright: true");
  }
  if (config.travel.slip_tolerance > 0.0 && !(config.travel.enabled() && config.env.constraints.enabled)) {
    throw InputError(where + ": travel.slip_tolerance: discounts travel pay by the slip constraint's violation, so it "
                     "needs travel.weight > 0 and env.constraints.enabled");
  }
  if (config.skill_switch.enabled() && config.skill_switch.interval_s.lo < a1::kControlDt) {
    throw InputError(where + ": skill_switch.interval_s: expected at least one control step (0.02 s), got " +
                     std::to_string(config.skill_switch.interval_s.lo));
  }
  if (config.window % 2 == 0) {
    throw InputError(where + ": window: expected an odd number of frames (the paper's H = 51), got " +
                     std::to_string(config.window));
  }
}

TrainConfig LoadTrainConfig(const std::string& path, const std::vector<std::string>& overrides) {
  TrainConfig config;
  ReadConfig(LoadConfigFile(path, overrides), path + ":", config);
  ValidateTrainConfig(config, path);
  return config;
}

}  // namespace flsd
