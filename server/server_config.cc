#include "server/server_config.h"

#include "comm/security.h"
#include "core/check.h"
#include "skills/runtime/hierarchical_policy.h"

namespace flsd {

namespace {

void CheckSelectorName(const std::string& name, const std::string& where) {
  if (name == "auto") return;
  try {
    ParseSelectorKind(name);
  } catch (const InputError& e) {
    throw InputError(where + ": " + e.what() + " or auto");
  }
}

}  // namespace

ServerConfig LoadServerConfig(const std::string& path) {
  ServerConfig config;
  ReadConfig(LoadConfigFile(path), path + ":", config);
  CheckSelectorName(config.selector, path + ": selector");
  CheckSelectorName(config.navigation.selector, path + ": navigation.selector");
  if (const std::string error = dds::SecurityFilesError(config.security, path + ":"); !error.empty()) {
    throw InputError(error);
  }
  return config;
}

}  // namespace flsd
