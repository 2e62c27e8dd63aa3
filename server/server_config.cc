#include "server/server_config.h"

namespace flsd {

ServerConfig LoadServerConfig(const std::string& path) {
  ServerConfig config;
  ReadConfig(LoadYamlFile(path), path + ":", config);
  return config;
}

}  // namespace flsd
