#pragma once
// The mechanics of bringing the robot to its stand: the brake (the library's stillest skill runs on
// for stand_brake_time after a policy, as holding the legs where a fast skill left them tips the
// robot), joint targets that move to a pose at stand_joint_speed and then hold while the robot
// settles, the check that it stands as it should (stand_check), and the count of lie-down and
// stand-up recoveries. The controller decides which of these runs (its states, controller.h).

#include <cstddef>

#include "robot/robot_state.h"
#include "server/server_config.h"

namespace flsd {

class StandSequence {
 public:
  // Legs folded and spread, as the A1 lies after its motors go slack: a recovery lies down in this
  // pose, so that the robot rests on its belly with its feet wide, then stands up from it. (From
  // legs folded under the body, the rising robot pins its feet too close and stands pitched.)
  static constexpr a1::JointArray<double> kLyingPose = {-0.45, 1.1,  -2.6, 0.45, 1.1,  -2.6,
                                                        -0.45, 1.45, -2.6, 0.45, 1.45, -2.6};
  static constexpr double kSettle = 0.5;  // s the targets hold before the stand counts as settled

  explicit StandSequence(const ServerConfig& config) : config_(config) {}

  // The brake's ticks: stand_brake_time. TakeBrakeTick counts one down; false once none is left.
  void StartBrake();
  bool TakeBrakeTick();
  int brake_ticks_left() const { return brake_ticks_left_; }

  // Targets from where the joints of `robot` are to `to`.
  void MoveTo(const RobotState& robot, const a1::JointArray<double>& to);
  // This tick's targets, at the stand's gains; moves them on by one tick.
  JointCommand Command();
  // The targets reached `to` and held for kSettle.
  bool settled() const { return ticks_ >= total_ticks_; }
  int ticks_left() const { return total_ticks_ > ticks_ ? total_ticks_ - ticks_ : 0; }
  // The ticks a move from `from` to `to` and its hold take.
  int Ticks(const a1::JointArray<double>& from, const a1::JointArray<double>& to) const;

  // Once settled, per tick: whether the robot stands within stand_check, has not yet for less than
  // stand_check.timeout, should lie down and stand up again (a recovery, counted), or has run out of
  // recoveries (then the count of unverified ticks starts over).
  enum class Verdict { kStanding, kSettling, kRecover, kFailed };
  Verdict Verify(const RobotState& robot);
  // Whether `robot` stands within stand_check; if not and `why` is given, says how not.
  bool Standing(const RobotState& robot, char* why = nullptr, std::size_t size = 0) const;
  int recoveries() const { return recoveries_; }
  void ResetRecoveries() { recoveries_ = 0; }

 private:
  const ServerConfig& config_;
  a1::JointArray<double> from_{}, to_{};
  int ticks_ = 0;
  int move_ticks_ = 1;   // moving the targets
  int total_ticks_ = 1;  // then holding them while the robot settles
  int brake_ticks_left_ = 0;
  int unverified_ticks_ = 0;  // settled, but not standing as it should
  int recoveries_ = 0;        // since the last request
};

}  // namespace flsd
