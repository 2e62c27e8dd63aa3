#include "server/server_config.h"

#include "core/check.h"
#include "skills/runtime/hierarchical_policy.h"

namespace flsd {

ServerConfig LoadServerConfig(const std::string& path) {
  ServerConfig config;
  ReadConfig(LoadConfigFile(path), path + ":", config);
  if (config.selector != "auto") {
    try {
      ParseSelectorKind(config.selector);
    } catch (const InputError& e) {
      throw InputError(path + ": selector: " + e.what() + " or auto");
    }
  }
  if (const std::string error = dds::SecurityFilesError(config.security, path + ":"); !error.empty()) {
    throw InputError(error);
  }
  return config;
}

}  // namespace flsd
