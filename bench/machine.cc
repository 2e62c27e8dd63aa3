#include "bench/machine.h"

#include <sys/utsname.h>

#include <fstream>
#include <string>
#include <thread>

namespace flsd {

nlohmann::json MachineDescription() {
  std::string cpu = "unknown";
  std::ifstream cpuinfo("/proc/cpuinfo");
  for (std::string line; std::getline(cpuinfo, line);) {
    if (line.rfind("model name", 0) == 0) {
      cpu = line.substr(line.find(':') + 2);
      break;
    }
  }
  utsname os{};
  uname(&os);
  return {{"cpu", cpu},
          {"cores", std::thread::hardware_concurrency()},
          {"os", std::string(os.sysname) + " " + os.release}};
}

}  // namespace flsd
