#pragma once
// The simulated A1 backend's settings (configs/server.yaml's `sim:` section), apart from the
// backend, so that the server's config can name them without including MuJoCo.

#include <string>

#include "core/config.h"

namespace flsd {

struct SimBackendConfig {
  std::string model = "robot/a1/scene.xml";
  // The training randomisation (friction, masses, delay, motor strength, pushes) for testing a
  // library's robustness in the server; off by default: the nominal robot on the nominal floor.
  bool randomize = false;
  int seed = 1;
  template <class V>
  void Visit(V& v) {
    v("model", model);
    v("randomize", randomize);
    v("seed", seed, Bounds<int>{0, 2147483647});
  }
};

}  // namespace flsd
