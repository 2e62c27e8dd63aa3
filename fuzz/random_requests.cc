#include "fuzz/random_requests.h"

#include <algorithm>
#include <cmath>
#include <iterator>

namespace flsd::fuzz {
namespace {

// One of `options`, at random.
template <class C>
const auto& PickOne(std::mt19937_64& rng, const C& options) {
  return options[rng() % std::size(options)];
}

// 2000 uses of one polygon through a YAML alias: 8000 points from a few bytes.
std::string AliasBomb() {
  std::string yaml = "polygons:\n  - &p [[0, 0], [1, 0], [1, 1], [0, 1]]\n";
  for (int i = 0; i < 2000; ++i) yaml += "  - *p\n";
  return yaml;
}

// A valid map near the limits: `circles` small obstacles on a grid, away from the start.
std::string Forest(int circles) {
  std::string yaml = "bounds: [-30, 30, -30, 30]\ncircles:\n";
  for (int i = 0; i < circles; ++i) {
    yaml += "  - {center: [" + std::to_string(2 + i % 25) + ".5, " + std::to_string(-20 + i / 25) +
            ".25], radius: 0.05}\n";
  }
  return yaml;
}

}  // namespace

const std::vector<MapCase>& SampleMaps() {
  static const std::vector<MapCase> maps = {
      {"", true, false},
      {"bounds: [-5, 5, -5, 5]\n", true, false},
      {"bounds: [-5, 5, -5, 5]\ncircles: [{center: [2, 0], radius: 0.5}]\n", true, false},
      {"bounds: [1]", false, false},
      {"{{{", false, false},
      {std::string(4000, '[') + std::string(4000, ']'), false, true},
      {AliasBomb(), false, true},
      {"bounds: [-.nan, 1, 0, 1]", false, false},
      {"circles: [{center: *x, radius: 1}]", false, false},
      {"robot_radius: 1e400", false, false},
      {Forest(1000), true, true},
      {Forest(2000), false, true},  // over 64 KiB
  };
  return maps;
}

RandomRequests::RandomRequests(uint64_t seed, std::vector<std::string> clients, bool heavy_maps)
    : rng_(seed), clients_(std::move(clients)) {
  for (const MapCase& m : SampleMaps()) {
    if (heavy_maps || !m.heavy) maps_.push_back(&m);
  }
}

const MapCase* RandomRequests::FindMap(const std::string& yaml) {
  const std::vector<MapCase>& maps = SampleMaps();
  const auto it = std::find_if(maps.begin(), maps.end(), [&](const MapCase& m) { return m.yaml == yaml; });
  return it != maps.end() ? &*it : nullptr;
}

RawRequest RandomRequests::Plain(const std::string& client_id, const std::string& call) {
  RawRequest r;
  r.client_id = client_id;
  r.request_id = ++last_id_[client_id];
  r.call = call;
  return r;
}

RawRequest RandomRequests::Next() {
  static const std::string kCalls[] = {"list_skills", "status", "execute_skill", "track_velocity", "navigate",
                                       "stop", "stand", "damp", "clear_stop", "acquire_control", "renew_control",
                                       "release_control", "reset", "", "fly", std::string(300, 'x'), "status\n"};
  static const double kNumbers[] = {0.0, -1.0, 0.3, 1.0, 2.0, 1e9, -1e300, NAN, INFINITY, -INFINITY, 1e-300};
  // 1: a second from now; 2: a second ago (expired).
  static const int64_t kDeadlines[] = {0, 0, 0, INT64_MIN, INT64_MAX, -1, 1, 2};
  RawRequest r;
  r.client_id = PickOne(rng_, clients_);
  // Mostly growing ids, sometimes a repeat or an older one.
  uint64_t& last = last_id_[r.client_id];
  r.request_id = rng_() % 10 == 0 ? last : last + 1 + rng_() % 3;
  last = std::max(last, r.request_id);
  r.deadline_ns = PickOne(rng_, kDeadlines);
  if (r.deadline_ns == 1) r.deadline_ns = dds_time() + 1'000'000'000;
  if (r.deadline_ns == 2) r.deadline_ns = dds_time() - 1'000'000'000;
  r.call = PickOne(rng_, kCalls);
  r.skill = static_cast<int32_t>(rng_() % 40) - 5;
  if (rng_() % 10 == 0) r.skill = rng_() % 2 ? INT32_MIN : INT32_MAX;
  r.duration = rng_() % 3 ? 0.2 + 0.1 * (rng_() % 10) : PickOne(rng_, kNumbers);
  for (double& v : r.velocity) v = PickOne(rng_, kNumbers);
  for (double& g : r.goal) g = rng_() % 2 ? 0.5 : PickOne(rng_, kNumbers);
  r.map_yaml = PickOne(rng_, maps_)->yaml;
  return r;
}

}  // namespace flsd::fuzz
