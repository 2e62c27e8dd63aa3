#include "skills/runtime/compose_library.h"

#include <algorithm>
#include <map>
#include <set>
#include <utility>

#include "core/check.h"
#include "skills/runtime/library_format.h"
#include "skills/runtime/safetensors.h"
#include "skills/runtime/skill_library.h"

namespace flsd {
namespace {

// A policy's metadata object and its tensors' name prefixes, in either version of the format.
struct StoredPolicy {
  nlohmann::json metadata;
  std::string layer_prefix, normalizer_prefix;
};

StoredPolicy StoredPolicyOf(const SkillLibrary& library, int policy) {
  const nlohmann::json& m = library.metadata();
  if (m.at("format_version").get<int>() == 1) {
    // One policy, its description spread over the top level.
    StoredPolicy stored{m.at("policy"), "policy.", "normalizer."};
    for (const char* key : {"training", "evaluation", "randomized_evaluation"}) {
      if (m.contains(key)) stored.metadata[key] = m.at(key);
    }
    return stored;
  }
  const std::string prefix = "policies." + std::to_string(policy) + ".";
  return {m.at("policies").at(policy), prefix, prefix + "normalizer."};
}

std::vector<int> ChosenSkills(const LibraryPart& part, const SkillLibrary& library) {
  std::vector<int> chosen = part.skills;
  if (chosen.empty()) {
    for (int k = 0; k < library.num_skills(); ++k) chosen.push_back(k);
  }
  std::set<int> seen;
  for (int k : chosen) {
    if (k < 0 || k >= library.num_skills()) {
      throw InputError(part.path + ": has no skill " + std::to_string(k) + " (it has 0 to " +
                       std::to_string(library.num_skills() - 1) + ")");
    }
    if (!seen.insert(k).second) throw InputError(part.path + ": skill " + std::to_string(k) + " is chosen twice");
  }
  for (int k : chosen) {
    const int mirror = library.skills()[k].mirror_skill;
    if (!seen.count(mirror)) {
      throw InputError(part.path + ": skill " + std::to_string(k) + " is chosen but its mirror image, skill " +
                       std::to_string(mirror) + ", is not; choose both, or neither");
    }
  }
  return chosen;
}

}  // namespace

LibraryPart ParseLibraryPart(const std::string& text) {
  const size_t colon = text.rfind(':');
  if (colon == std::string::npos) return {text, {}};
  LibraryPart part{text.substr(0, colon), {}};
  const std::string list = text.substr(colon + 1);
  size_t begin = 0;
  while (begin <= list.size()) {
    const size_t end = std::min(list.find(',', begin), list.size());
    const std::string item = list.substr(begin, end - begin);
    size_t used = 0;
    int k = -1;
    try {
      k = std::stoi(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (item.empty() || used != item.size() || k < 0) {
      throw InputError("'" + text + "': after ':' expected skill ids separated by commas, but found '" + item + "'");
    }
    part.skills.push_back(k);
    begin = end + 1;
  }
  return part;
}

nlohmann::json ComposeLibraries(const std::vector<LibraryPart>& parts, const std::string& output) {
  if (parts.empty()) throw InputError("compose: give at least one library");
  std::vector<SkillLibrary> libraries;
  for (const LibraryPart& part : parts) libraries.push_back(SkillLibrary::Load(part.path));
  const SkillLibrary& first = libraries.front();
  for (size_t i = 1; i < libraries.size(); ++i) {
    const SkillLibrary& l = libraries[i];
    if (l.action_filter_hz() != first.action_filter_hz() || l.action_filter_order() != first.action_filter_order()) {
      throw InputError(parts[i].path + ": its skills run behind a " + std::to_string(l.action_filter_hz()) +
                       " Hz target filter of order " + std::to_string(l.action_filter_order()) + ", but " +
                       parts[0].path + "'s behind " + std::to_string(first.action_filter_hz()) + " Hz, order " +
                       std::to_string(first.action_filter_order()) + "; one library runs one filter");
    }
  }

  // New skill ids in the order chosen; new policy ids in the order first used.
  struct Source {
    int part, skill;
  };
  std::vector<Source> sources;
  std::vector<std::map<int, int>> new_id(parts.size());
  for (size_t i = 0; i < parts.size(); ++i) {
    for (int k : ChosenSkills(parts[i], libraries[i])) {
      new_id[i][k] = static_cast<int>(sources.size());
      sources.push_back({static_cast<int>(i), k});
    }
  }
  std::map<std::pair<int, int>, int> new_policy;  // (part, policy) -> index
  std::vector<std::pair<int, int>> policy_sources;
  for (const Source& s : sources) {
    const std::pair<int, int> key{s.part, libraries[s.part].skills()[s.skill].policy};
    if (new_policy.emplace(key, static_cast<int>(policy_sources.size())).second) policy_sources.push_back(key);
  }

  nlohmann::json metadata;
  auto write = [&](const std::string& pointer, const auto& value) {
    metadata[nlohmann::json::json_pointer(pointer)] = value;
  };
  VisitLibraryFacts(write);
  LibraryValues values{static_cast<int>(sources.size()), first.action_filter_hz(), first.action_filter_order()};
  values.Visit([&](const char* pointer, const auto& field, bool, double, double) { write(pointer, field); });

  SafeTensors file;
  file.metadata["format"] = kSkillLibraryFormat;
  const nlohmann::json::array_t no_policies;
  metadata["policies"] = no_policies;
  for (size_t p = 0; p < policy_sources.size(); ++p) {
    const auto [part, policy] = policy_sources[p];
    const SkillLibrary& library = libraries[part];
    const StoredPolicy stored = StoredPolicyOf(library, policy);
    metadata["policies"].push_back(stored.metadata);
    VisitPolicyFacts(write, static_cast<int>(p), library.policies()[policy].num_skills);
    metadata["policies"][p]["source"] = {
        {"library", parts[part].path}, {"fingerprint", library.fingerprint()}, {"policy", policy}};
    // Its tensors, renamed; the library loaded above has checked each of them.
    const std::string prefix = "policies." + std::to_string(p) + ".";
    for (const auto& [name, tensor] : ReadSafeTensors(parts[part].path).tensors) {
      if (name.rfind(stored.normalizer_prefix, 0) == 0) {
        file.tensors[prefix + "normalizer." + name.substr(stored.normalizer_prefix.size())] = tensor;
      } else if (name.rfind(stored.layer_prefix + "layer", 0) == 0) {
        file.tensors[prefix + name.substr(stored.layer_prefix.size())] = tensor;
      }
    }
  }

  nlohmann::json skills = nlohmann::json::array();
  nlohmann::json origins = nlohmann::json::array();
  for (size_t id = 0; id < sources.size(); ++id) {
    const Source& s = sources[id];
    SkillDescriptor d = libraries[s.part].skills()[s.skill];
    d.id = static_cast<int>(id);
    d.mirror_skill = new_id[s.part].at(d.mirror_skill);
    d.policy = new_policy.at({s.part, d.policy});
    skills.push_back(DescriptorJson(d));
    origins.push_back({{"library", parts[s.part].path}, {"skill", s.skill}});
  }
  metadata["skills"] = skills;
  metadata["composed_from"] = origins;
  file.metadata["flsd"] = metadata.dump();
  WriteSafeTensors(output, file);

  nlohmann::json dropped = nlohmann::json::array();
  for (size_t i = 0; i < parts.size(); ++i) {
    if (libraries[i].selector()) dropped.push_back(parts[i].path);
  }
  const SkillLibrary written = SkillLibrary::Load(output);  // what skilld will read
  return {{"library", output},
          {"num_skills", written.num_skills()},
          {"policies", written.policies().size()},
          {"skills_from", origins},
          {"selectors_not_carried_over", dropped}};
}

}  // namespace flsd
