#include "sim/env.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"
#include "robot/observation.h"

namespace flsd {
namespace {

// MuJoCo's contact damping ratio that gives restitution coefficient e for its spring-damper
// contact: e = exp(-zeta pi / sqrt(1 - zeta^2)); e = 0 is critical damping.
double DampingRatioForRestitution(double e) {
  if (e <= 0.0) return 1.0;
  const double log_e = std::log(e);
  return -log_e / std::sqrt(M_PI * M_PI + log_e * log_e);
}

double Draw(Rng& rng, const RandomRange& r, double nominal) {
  return r.enabled ? Uniform(rng, r.range.lo, r.range.hi) : nominal;
}

}  // namespace

const char* ToString(Termination t) {
  switch (t) {
    case Termination::kNone: return "none";
    case Termination::kTimeOut: return "time_out";
    case Termination::kBodyContact: return "body_contact";
    case Termination::kTilt: return "tilt";
    case Termination::kLowBase: return "low_base";
    case Termination::kJointSpeed: return "joint_speed";
    case Termination::kJointRange: return "joint_range";
    case Termination::kInvalidAction: return "invalid_action";
    case Termination::kPhysics: return "physics";
  }
  return "unknown";
}

Env::Env(const mjModel& model, const EnvConfig& config, uint64_t seed)
    : model_(CopyMjModel(model)),
      data_(mj_makeData(model_.get())),
      index_(A1ModelIndex::Find(*model_)),
      config_(config),
      rng_(seed),
      target_filter_(config.action_filter_hz, config.action_filter_order) {
  FLSD_DEMAND(data_ != nullptr);
  if (std::abs(model_->opt.timestep - a1::kPhysicsDt) > 1e-12) {
    throw InputError(config.model + ": option timestep is " + std::to_string(model_->opt.timestep) +
                     " s, but the control convention needs " + std::to_string(a1::kPhysicsDt));
  }
  const Interval delay = config_.randomization.action_delay.range;
  if (delay.lo < 0.0 || delay.hi > RandomizationConfig::kMaxActionDelay) {
    throw InputError("randomization.action_delay.range: expected steps within [0, " +
                     std::to_string(RandomizationConfig::kMaxActionDelay) + "], got [" + std::to_string(delay.lo) +
                     ", " + std::to_string(delay.hi) + "]");
  }
  nominal_body_mass_.assign(model_->body_mass, model_->body_mass + model_->nbody);
  nominal_body_inertia_.assign(model_->body_inertia, model_->body_inertia + 3 * model_->nbody);
  push_interval_steps_ =
      std::max(1, static_cast<int>(std::lround(config_.randomization.push.interval_s / a1::kControlDt)));
  Reset();
}

void Env::Reset() {
  SampleRandomization();
  ApplyRandomization();
  mj_resetData(model_.get(), data_.get());
  PlaceInitialState();
  for (auto& a : action_history_) a.fill(0.0f);
  history_head_ = 0;
  episode_step_ = 0;
  overspeed_.Reset();
  SyncState();
  target_filter_.Reset(state_.joint_position);
}

void Env::SampleRandomization() {
  const RandomizationConfig& c = config_.randomization;
  EnvRandomization& r = randomization_;
  r.friction = Draw(rng_, c.friction, 1.0);
  r.restitution = Draw(rng_, c.restitution, 0.0);
  r.base_mass_offset = Draw(rng_, c.base_mass_offset, 0.0);
  r.link_mass_scale = Draw(rng_, c.link_mass_scale, 1.0);
  r.action_delay = static_cast<int>(std::lround(Draw(rng_, c.action_delay, 0.0)));
  for (double& s : r.motor_strength) s = Draw(rng_, c.motor_strength, 1.0);
}

void Env::ApplyRandomization() {
  mjModel& m = *model_;
  const double damping_ratio = DampingRatioForRestitution(randomization_.restitution);
  for (int g = 0; g < m.ngeom; ++g) {
    m.geom_friction[3 * g] = randomization_.friction;  // contacts take the larger of the two
    m.geom_solref[mjNREF * g + 1] = damping_ratio;     // and mix solref equally
  }
  bool mass_changed = false;
  for (int b = 1; b < m.nbody; ++b) {
    const double nominal = nominal_body_mass_[b];
    const double mass = b == index_.trunk_body ? nominal + randomization_.base_mass_offset
                                               : nominal * randomization_.link_mass_scale;
    const double ratio = nominal > 0.0 ? mass / nominal : 1.0;
    mass_changed |= m.body_mass[b] != mass;
    m.body_mass[b] = mass;
    for (int k = 0; k < 3; ++k) m.body_inertia[3 * b + k] = nominal_body_inertia_[3 * b + k] * ratio;
  }
  // Derived constants (subtree masses, inverse weights) follow the masses.
  if (mass_changed) mj_setConst(model_.get(), data_.get());
}

void Env::PlaceInitialState() {
  mjData& d = *data_;
  const ResetConfig& c = config_.reset;
  // Drawn only when asked for, so that configs without standing starts keep their random streams.
  const bool standing = c.standing_fraction > 0.0 && Uniform(rng_, 0.0, 1.0) < c.standing_fraction;
  for (int j = 0; j < a1::kNumJoints; ++j) {
    const double scale = standing ? 1.0 : Uniform(rng_, c.joint_pos_scale.lo, c.joint_pos_scale.hi);
    const double q = a1::kDefaultJointPos[j] * scale;
    d.qpos[index_.qpos[j]] = std::clamp(q, a1::JointMin(j), a1::JointMax(j));
  }
  mjtNum* root = d.qpos + index_.root_qpos;
  root[0] = root[1] = root[2] = 0.0;
  root[3] = 1.0;
  root[4] = root[5] = root[6] = 0.0;
  // Lower the robot until its lowest foot is foot_clearance above the floor.
  mj_kinematics(model_.get(), data_.get());
  double lowest = INFINITY;
  for (int g : index_.foot_geom) lowest = std::min(lowest, d.geom_xpos[3 * g + 2] - model_->geom_size[3 * g]);
  root[2] = -lowest + c.foot_clearance;
  for (int k = 0; k < 6; ++k) {
    d.qvel[index_.root_qvel + k] = standing ? 0.0 : Uniform(rng_, -c.base_velocity, c.base_velocity);
  }
}

Termination Env::Step(const float* action) {
  for (int j = 0; j < a1::kNumJoints; ++j) {
    if (!std::isfinite(action[j])) return Termination::kInvalidAction;
  }
  history_head_ = (history_head_ + 1) % kHistory;
  std::copy(action, action + a1::kNumJoints, action_history_[history_head_].begin());
  const int delayed = (history_head_ - randomization_.action_delay + kHistory) % kHistory;
  const a1::JointArray<double>& targets = target_filter_.Apply(JointTargetsFromAction(action_history_[delayed].data()));
  return Advance(JointCommand::Track(targets), a1::kDecimation);
}

Termination Env::StepCommand(const JointCommand& command, int substeps) { return Advance(command, substeps); }

Termination Env::Advance(const JointCommand& command, int substeps) {
  mjData& d = *data_;
  for (int substep = 0; substep < substeps; ++substep) {
    for (int j = 0; j < a1::kNumJoints; ++j) {
      d.ctrl[index_.actuator[j]] =
          MotorTorque(command.kp[j], command.kd[j], command.position[j], command.velocity[j],
                      d.qpos[index_.qpos[j]], d.qvel[index_.qvel[j]], command.torque[j],
                      randomization_.motor_strength[j], config_.torque_speed_limit,
                      config_.torque_speed_knee);
    }
    mj_step(model_.get(), data_.get());
    // MuJoCo resets the data itself after a non-finite or huge position, velocity or
    // acceleration; the episode is void.
    if (d.warning[mjWARN_BADQACC].number + d.warning[mjWARN_BADQPOS].number + d.warning[mjWARN_BADQVEL].number > 0) {
      return Termination::kPhysics;
    }
  }
  ++episode_step_;

  const PushConfig& push = config_.randomization.push;
  if (push.enabled && episode_step_ % push_interval_steps_ == 0) {
    d.qvel[index_.root_qvel + 0] = Uniform(rng_, -push.max_velocity, push.max_velocity);
    d.qvel[index_.root_qvel + 1] = Uniform(rng_, -push.max_velocity, push.max_velocity);
  }
  ReadState();
  if (config_.termination.limits.max_joint_speed > 0.0) {
    overspeed_.Update(FasterThan(state_.joint_velocity, config_.termination.limits.max_joint_speed),
                      substeps * model_->opt.timestep);
  }
  return CheckTermination();
}

double Env::StanceFootSpeed() const {
  double sum = 0.0;
  int feet = 0;
  for (int leg = 0; leg < a1::kNumLegs; ++leg) {
    if (!state_.foot_contact[leg]) continue;
    sum += FootSpeed(leg);
    ++feet;
  }
  return feet > 0 ? sum / feet : 0.0;
}

double Env::FastestStanceFoot(double min_force) const {
  double fastest = 0.0;
  for (int leg = 0; leg < a1::kNumLegs; ++leg) {
    if (!state_.foot_contact[leg] || state_.foot_force[leg] <= min_force) continue;
    fastest = std::max(fastest, FootSpeed(leg));
  }
  return fastest;
}

double Env::FootSpeed(int leg) const {
  mjtNum velocity[6];  // angular, then linear, in the world frame
  mj_objectVelocity(model_.get(), data_.get(), mjOBJ_GEOM, index_.foot_geom[leg], velocity, 0);
  return std::hypot(velocity[3], velocity[4]);
}

void Env::SyncState() {
  mj_forward(model_.get(), data_.get());
  ReadState();
}

void Env::ReadState() {
  const mjData& d = *data_;
  const mjtNum* q = d.qpos + index_.root_qpos;
  const mjtNum* v = d.qvel + index_.root_qvel;
  state_.time = d.time;
  state_.base_position = Eigen::Vector3d(q[0], q[1], q[2]);
  state_.base_orientation = Eigen::Quaterniond(q[3], q[4], q[5], q[6]).normalized();
  // The free joint's linear velocity is in the world frame, its angular velocity in the body frame.
  state_.base_linear_velocity = state_.base_orientation.conjugate() * Eigen::Vector3d(v[0], v[1], v[2]);
  state_.base_angular_velocity = Eigen::Vector3d(v[3], v[4], v[5]);
  for (int j = 0; j < a1::kNumJoints; ++j) {
    state_.joint_position[j] = d.qpos[index_.qpos[j]];
    state_.joint_velocity[j] = d.qvel[index_.qvel[j]];
    state_.joint_torque[j] = d.ctrl[index_.actuator[j]];
  }

  // Contacts found at the start of the last physics step.
  state_.foot_contact.fill(false);
  state_.foot_force.fill(0.0);
  body_contact_ = calf_contact_ = false;
  for (int c = 0; c < d.ncon; ++c) {
    const mjContact& contact = d.contact[c];
    const bool first_is_floor = index_.geom_role[contact.geom1] == GeomRole::kFloor;
    const int geom = first_is_floor ? contact.geom2 : contact.geom1;
    switch (index_.geom_role[geom]) {
      case GeomRole::kFoot: {
        const int leg = index_.geom_leg[geom];
        mjtNum force[6];
        mj_contactForce(model_.get(), data_.get(), c, force);
        state_.foot_contact[leg] = true;
        state_.foot_force[leg] += force[0];
        break;
      }
      case GeomRole::kCalf: calf_contact_ = true; break;
      case GeomRole::kTrunk:
      case GeomRole::kHip:
      case GeomRole::kThigh: body_contact_ = true; break;
      default: break;
    }
  }
}

Termination Env::CheckTermination() const {
  const TerminationConfig& c = config_.termination;
  if (body_contact_ || (c.on_calf_contact && calf_contact_)) return Termination::kBodyContact;
  const uint32_t broken = BrokenLimits(state_, c.limits);
  if (broken & kBreaksTilt) return Termination::kTilt;
  if (broken & kBreaksBaseHeight) return Termination::kLowBase;
  const StateLimits& limits = c.limits;
  if (limits.max_joint_speed > 0.0 && Outlasts(overspeed_.Longest(), limits.max_joint_speed_time)) {
    return Termination::kJointSpeed;
  }
  if (broken & kBreaksJointRange) return Termination::kJointRange;
  if (episode_step_ >= config_.episode_steps) return Termination::kTimeOut;
  return Termination::kNone;
}

}  // namespace flsd
