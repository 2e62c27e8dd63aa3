#pragma once
// Random requests, well- and ill-typed, as a careless or hostile client sends them: any call
// name, ids that mostly grow but sometimes repeat, impossible and expired deadlines, NaN and huge
// numbers, broken, explosive and heavy maps.

#include <cstdint>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "fuzz/raw_client.h"

namespace flsd::fuzz {

// A map a request may carry, and what skilld must make of it.
struct MapCase {
  std::string yaml;   // empty: the server's own map
  bool valid = true;  // within docs/serving.md's limits, every value finite and in range
  bool heavy = false; // tens of kilobytes or thousands of aliases to read
};

// Every map RandomRequests sends; without `heavy`, only the light ones.
const std::vector<MapCase>& SampleMaps();

class RandomRequests {
 public:
  // `heavy_maps` false leaves out the maps whose reading costs the server most.
  // Each request comes from one of `clients` (named twice: twice as often).
  RandomRequests(uint64_t seed, std::vector<std::string> clients, bool heavy_maps = true);

  RawRequest Next();
  // `call` from `client_id` with its next id, no deadline and no arguments.
  RawRequest Plain(const std::string& client_id, const std::string& call);

  // The case of a map this generator sent; nullptr for any other text.
  static const MapCase* FindMap(const std::string& yaml);

 private:
  std::mt19937_64 rng_;
  std::vector<std::string> clients_;
  std::vector<const MapCase*> maps_;
  std::map<std::string, uint64_t> last_id_;
};

}  // namespace flsd::fuzz
