#include "skills/learning/export/compose_library.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <utility>

#include "core/check.h"
#include "skills/runtime/library_format.h"
#include "skills/runtime/safetensors.h"
#include "skills/runtime/skill_library.h"

namespace flsd {
namespace {

// Policy P's metadata object, in either version of the format.
nlohmann::json PolicyMetadata(const SkillLibrary& library, int policy) {
  const nlohmann::json& m = library.metadata();
  if (m.at("format_version").get<int>() == 1) {
    // One policy, its description spread over the top level.
    nlohmann::json stored = m.at("policy");
    for (const char* key : {"training", "evaluation", "randomized_evaluation"}) {
      if (m.contains(key)) stored[key] = m.at(key);
    }
    return stored;
  }
  return m.at("policies").at(policy);
}

FloatTensor ToTensor(const float* data, std::vector<int64_t> shape) {
  int64_t size = 1;
  for (int64_t d : shape) size *= d;
  return {std::move(shape), std::vector<float>(data, data + size)};
}

// The network as SkillLibrary reads it back, under `prefix` (library_format.h).
void AddNetwork(SafeTensors& file, const DenseNetwork& network, const std::string& prefix) {
  for (size_t l = 0; l < network.layers.size(); ++l) {
    const DenseLayer& layer = network.layers[l];
    const std::string name = prefix + "layer" + std::to_string(l);
    file.tensors[name + ".weight"] = ToTensor(layer.weight.data(), {layer.weight.rows(), layer.weight.cols()});
    file.tensors[name + ".bias"] = ToTensor(layer.bias.data(), {layer.bias.size()});
  }
  file.tensors[prefix + "normalizer.mean"] = ToTensor(network.normalizer_mean.data(), {network.normalizer_mean.size()});
  file.tensors[prefix + "normalizer.std"] = ToTensor(network.normalizer_std.data(), {network.normalizer_std.size()});
}

std::string FilterText(const SkillLibrary& library) {
  char text[64];
  std::snprintf(text, sizeof(text), "%g Hz, order %d", library.action_filter_hz(), library.action_filter_order());
  return text;
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
  namespace fs = std::filesystem;
  if (parts.empty()) throw InputError("compose: give at least one library");
  std::vector<SkillLibrary> libraries;
  for (const LibraryPart& part : parts) {
    std::error_code error;
    if (fs::equivalent(part.path, output, error)) {
      throw InputError(output + ": is also an input; write the joined library to another file");
    }
    libraries.push_back(SkillLibrary::Load(part.path));
  }
  const SkillLibrary& first = libraries.front();
  for (size_t i = 1; i < libraries.size(); ++i) {
    if (libraries[i].action_filter_hz() != first.action_filter_hz() ||
        libraries[i].action_filter_order() != first.action_filter_order()) {
      throw InputError(parts[i].path + ": its skills run behind a target filter of " + FilterText(libraries[i]) +
                       ", but " + parts[0].path + "'s behind one of " + FilterText(first) +
                       "; one library runs one filter");
    }
  }

  // New skill ids in the order chosen; new policies in the order first used, one per trained
  // policy however many parts name its file.
  struct Source {
    int part, skill;
  };
  std::vector<Source> sources;
  std::vector<std::map<int, int>> new_id(parts.size());
  std::map<std::pair<std::string, int>, std::string> chosen_in;  // (fingerprint, skill) -> part
  for (size_t i = 0; i < parts.size(); ++i) {
    for (int k : ChosenSkills(parts[i], libraries[i])) {
      const auto [it, fresh] = chosen_in.emplace(std::make_pair(libraries[i].fingerprint(), k), parts[i].path);
      if (!fresh) {
        throw InputError(parts[i].path + ": skill " + std::to_string(k) + " is already chosen from " + it->second +
                         " (the same file)");
      }
      new_id[i][k] = static_cast<int>(sources.size());
      sources.push_back({static_cast<int>(i), k});
    }
  }
  std::map<std::pair<std::string, int>, int> new_policy;  // (fingerprint, policy) -> index
  std::vector<std::pair<int, int>> policy_sources;       // index -> (part, policy)
  auto policy_key = [&](int part, int policy) { return std::make_pair(libraries[part].fingerprint(), policy); };
  for (const Source& s : sources) {
    const int policy = libraries[s.part].skills()[s.skill].policy;
    if (new_policy.emplace(policy_key(s.part, policy), static_cast<int>(policy_sources.size())).second) {
      policy_sources.emplace_back(s.part, policy);
    }
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
  metadata["policies"] = nlohmann::json::array();
  for (size_t p = 0; p < policy_sources.size(); ++p) {
    const auto [part, policy] = policy_sources[p];
    const SkillLibrary& library = libraries[part];
    nlohmann::json stored = PolicyMetadata(library, policy);
    nlohmann::json source = {{"library", parts[part].path}, {"fingerprint", library.fingerprint()}, {"policy", policy}};
    if (stored.contains("source")) source["from"] = stored["source"];  // joined before
    stored["source"] = source;
    metadata["policies"].push_back(stored);
    VisitPolicyFacts(write, static_cast<int>(p), library.policies()[policy].num_skills);
    AddNetwork(file, library.policies()[policy].network, PolicyTensorPrefix(static_cast<int>(p)));
  }

  nlohmann::json skills = nlohmann::json::array();
  nlohmann::json origins = nlohmann::json::array();
  for (size_t id = 0; id < sources.size(); ++id) {
    const Source& s = sources[id];
    SkillDescriptor d = libraries[s.part].skills()[s.skill];
    d.id = static_cast<int>(id);
    d.mirror_skill = new_id[s.part].at(d.mirror_skill);
    d.policy = new_policy.at(policy_key(s.part, d.policy));
    skills.push_back(DescriptorJson(d));
    origins.push_back({{"library", parts[s.part].path}, {"skill", s.skill}});
  }
  metadata["skills"] = skills;
  metadata["composed_from"] = origins;
  file.metadata["flsd"] = metadata.dump();

  WriteCheckedLibrary(output, file);

  nlohmann::json dropped = nlohmann::json::array();
  for (size_t i = 0; i < parts.size(); ++i) {
    if (libraries[i].selector()) dropped.push_back(parts[i].path);
  }
  return {{"library", output},
          {"num_skills", sources.size()},
          {"policies", policy_sources.size()},
          {"skills_from", origins},
          {"selectors_not_carried_over", dropped}};
}

}  // namespace flsd
