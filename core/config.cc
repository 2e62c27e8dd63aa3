#include "core/config.h"

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

}  // namespace flsd
