#include "core/config.h"

#include <algorithm>
#include <filesystem>

namespace flsd {

ConfigReader::ConfigReader(YAML::Node node, std::string where)
    : node_(std::move(node)), where_(std::move(where)) {
  if (node_.IsDefined() && !node_.IsNull() && !node_.IsMap()) {
    throw InputError(where_ + ": expected a mapping of keys");
  }
}

void ConfigReader::Finish() const {
  if (!node_.IsMap()) return;
  for (const auto& item : node_) {
    const std::string key = item.first.as<std::string>();
    if (claimed_.count(key) == 0) {
      std::string known;
      for (const std::string& k : claimed_) known += (known.empty() ? "" : ", ") + k;
      throw InputError(Where(key.c_str()) + ": unknown key (known keys: " + known + ")");
    }
  }
}

std::string ConfigReader::Where(const char* key) const {
  // "file.yaml:" starts a path; "file.yaml: env" continues one.
  return where_ + (!where_.empty() && where_.back() == ':' ? " " : ".") + key;
}

void ConfigReader::Fail(const char* key, const std::string& expected, const YAML::Node& got) const {
  YAML::Emitter shown;
  shown << YAML::Flow << got;
  throw InputError(Where(key) + ": expected " + expected + ", got '" + shown.c_str() + "'");
}

YAML::Node LoadYamlFile(const std::string& path) {
  try {
    return YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw InputError(path + ": cannot open file");
  } catch (const YAML::ParserException& e) {
    throw InputError(path + ":" + std::to_string(e.mark.line + 1) + ": malformed YAML: " + e.msg);
  }
}

namespace {

// `over`'s keys replace `base`'s; mappings merge key by key. Returns a new tree: yaml-cpp nodes
// alias, and a base file's tree must stay as it was read.
YAML::Node Merged(const YAML::Node& base, const YAML::Node& over) {
  if (!base.IsMap() || !over.IsMap()) return YAML::Clone(over);
  YAML::Node merged = YAML::Clone(base);
  for (const auto& item : over) {
    const std::string key = item.first.as<std::string>();
    merged[key] = Merged(merged[key], item.second);
  }
  return merged;
}

YAML::Node LoadWithBases(const std::string& path, std::vector<std::string>& chain) {
  if (std::find(chain.begin(), chain.end(), path) != chain.end()) {
    std::string cycle;
    for (const std::string& p : chain) cycle += p + " -> ";
    throw InputError(chain.back() + ": base: a cycle of bases: " + cycle + path);
  }
  YAML::Node node = LoadYamlFile(path);
  if (!node.IsMap() || !node["base"]) return node;
  const YAML::Node base_key = node["base"];
  if (!base_key.IsScalar()) throw InputError(path + ": base: expected the path of a YAML file");
  const std::string base_path =
      (std::filesystem::path(path).parent_path() / base_key.as<std::string>()).lexically_normal().string();
  chain.push_back(path);
  YAML::Node base = LoadWithBases(base_path, chain);
  chain.pop_back();
  node.remove("base");
  return Merged(base, node);
}

void ApplyOverride(YAML::Node& root, const std::string& assignment) {
  const size_t equals = assignment.find('=');
  const std::string path = assignment.substr(0, equals);
  if (equals == std::string::npos || path.empty() || path.front() == '.' || path.back() == '.' ||
      path.find("..") != std::string::npos) {
    throw InputError("--set '" + assignment + "': expected key.path=value, e.g. env.num_envs=64");
  }
  YAML::Node value;
  try {
    value = YAML::Load(assignment.substr(equals + 1));
  } catch (const YAML::ParserException& e) {
    throw InputError("--set '" + assignment + "': the value is not YAML: " + e.msg);
  }
  // Descend with a vector of owned nodes: assigning one yaml-cpp node to another rebinds both.
  std::vector<YAML::Node> nodes{root};
  size_t start = 0;
  for (size_t dot; (dot = path.find('.', start)) != std::string::npos; start = dot + 1) {
    const std::string key = path.substr(start, dot - start);
    YAML::Node child = nodes.back()[key];
    if (child.IsDefined() && !child.IsNull() && !child.IsMap()) {
      throw InputError("--set '" + assignment + "': " + path.substr(0, dot) + " is a value, not a section");
    }
    if (!child.IsMap()) nodes.back()[key] = YAML::Node(YAML::NodeType::Map);
    nodes.push_back(nodes.back()[key]);
  }
  nodes.back()[path.substr(start)] = value;
}

}  // namespace

YAML::Node LoadConfigFile(const std::string& path, const std::vector<std::string>& overrides) {
  std::vector<std::string> chain;
  YAML::Node root = LoadWithBases(path, chain);
  if (!overrides.empty() && !root.IsMap()) throw InputError(path + ": expected a mapping of keys");
  for (const std::string& assignment : overrides) ApplyOverride(root, assignment);
  return root;
}

}  // namespace flsd
