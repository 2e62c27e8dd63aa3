#pragma once
// A controller over the real MuJoCo A1 and the shipped skill library, ticked by the test
// (lockstep): no threads, no clock, no DDS.

#include <gtest/gtest.h>

#include <memory>

#include "core/paths.h"
#include "server/controller.h"
#include "sim/sim_backend.h"

namespace flsd::testutil {

inline const SkillLibrary& ShippedLibrary() {
  static const SkillLibrary library = SkillLibrary::Load(ResolveDataPath("models/a1_flsd.safetensors"));
  return library;
}

class ControllerFixture : public ::testing::Test {
 protected:
  ControllerFixture() : backend_(SimBackendConfig{}), controller_(backend_, ShippedLibrary(), config_) {}

  // Ticks for `seconds` of control time; returns how many ticks were in `mode`.
  int RunFor(double seconds, Mode mode = Mode::kIdle) {
    int in_mode = 0;
    const int ticks = static_cast<int>(std::lround(seconds / a1::kControlDt));
    for (int i = 0; i < ticks; ++i) {
      controller_.Tick();
      in_mode += controller_.status().mode == mode;
    }
    return in_mode;
  }

  static ControlRequest Request(ControlRequest::Kind kind, int skill = 0, double duration = 0.0) {
    ControlRequest r;
    r.kind = kind;
    r.skill = skill;
    r.duration = duration;
    SetText(r.client_id, "test-client");
    r.request_id = 42;
    return r;
  }

  void StandUp() {
    ASSERT_TRUE(controller_.Submit(Request(ControlRequest::Kind::kStand)));
    RunFor(3.0);
    ASSERT_EQ(controller_.status().mode, Mode::kStand);
  }

  ServerConfig config_;
  SimBackend backend_;
  Controller controller_;
};

}  // namespace flsd::testutil
