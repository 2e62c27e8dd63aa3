#pragma once
// skilld's configuration (configs/server.yaml). Read strictly: an unknown key or an out-of-range
// value is an error naming the file and key.

#include <string>

#include "comm/security_config.h"
#include "core/config.h"
#include "hw/hw_config.h"
#include "robot/a1.h"
#include "robot/state_limits.h"
#include "server/navigation/waypoint_follower.h"
#include "sim/sim_backend_config.h"

namespace flsd {

struct SafetyConfig {
  // The state limits training can end episodes by too (robot/state_limits.h). Here: a tilt of 1.0
  // rad (unitree_sdk2's G1 terminations use 1.0); a base height of 0.12 m (0 turns it off: an
  // estimated height may drift); 0.1 rad outside a joint's range; the A1 motor's 21 rad/s, for
  // longer than a foot strike lasts (a joint past it for longer is driven by something else: a
  // fall, a collision, a motor out of control; a time of 0 trips at once).
  StateLimits limits;
  double max_torque_saturation = 0.5;  // s a joint may sit at the torque limit
  double max_power = 1000.0;       // W, sum of |tau qdot| (the SDK's PowerProtect at its level 10)
  double max_power_time = 0.1;     // s above max_power before a trip
  double damping_kd = 1.0;             // N m s / rad of the damped (safe) command
  // s after which any client may clear an emergency stop; before, only the client that pressed it.
  double stop_hold_time = 10.0;
  // Skills that fell sooner than this in the library's own evaluation, or in its randomised one
  // (steps of 20 ms), are refused: an unsupervised skill can be one that throws the robot down.
  // 1000, an evaluation's whole 20 s, refuses any that fell; 0 allows all. (The shipped library's
  // skill 2 fell after 772 randomised steps, and tips past the tilt limit from skilld's stand in
  // about 2 runs of 5.)
  int min_skill_survival = 1000;
  template <class V>
  void Visit(V& v) {
    v("max_tilt", limits.max_tilt, Bounds<double>{0.1, 3.2});
    v("min_base_height", limits.min_base_height, Bounds<double>{0.0, 0.5});
    v("joint_range_margin", limits.joint_range_margin, Bounds<double>{0.0, 1.0});
    v("max_joint_velocity", limits.max_joint_speed, Bounds<double>{1.0, 100.0});
    v("max_joint_velocity_time", limits.max_joint_speed_time, Bounds<double>{0.0, 1.0});
    v("max_torque_saturation", max_torque_saturation, Bounds<double>{0.02, 10.0});
    v("max_power", max_power, Bounds<double>{10.0, 10000.0});
    v("max_power_time", max_power_time, Bounds<double>{0.0, 10.0});
    v("damping_kd", damping_kd, Bounds<double>{0.0, 10.0});
    v("stop_hold_time", stop_hold_time, Bounds<double>{0.0, 86400.0});
    v("min_skill_survival", min_skill_survival, Bounds<int>{0, 1000000});
  }
};

// What counts as standing: a skill, a velocity task or a navigation starts only from a stand
// that meets all of these (the state its policy was trained from), never from a stand that merely
// ran for its time. A robot that does not get there lies down and stands up again; one that still
// does not after max_recoveries has its task ended with the reason.
struct StandCheckConfig {
  double max_tilt = 0.2;             // rad from upright (0.01-0.03 when standing on flat ground)
  double min_base_height = 0.2;      // m (0.27 at the stand's gains, 0.24-0.25 at training's); 0 turns it off
  double max_joint_error = 0.35;     // rad from the default pose (the stand sags 0.12, Kp 20 0.24-0.28)
  double max_joint_speed = 1.0;      // rad/s, every joint
  // rad/s of the base, as the IMU measures it (the base's linear velocity is only estimated on the
  // real robot, and drifts by tenths of a m/s while it stands)
  double max_turn_rate = 0.5;
  double timeout = 1.5;              // s after the stand settled without meeting them: recover
  int max_recoveries = 2;            // lie-down and stand-up sequences per request
  template <class V>
  void Visit(V& v) {
    v("max_tilt", max_tilt, Bounds<double>{0.01, 1.0});
    v("min_base_height", min_base_height, Bounds<double>{0.0, 0.5});
    v("max_joint_error", max_joint_error, Bounds<double>{0.01, 3.0});
    v("max_joint_speed", max_joint_speed, Bounds<double>{0.01, 30.0});
    v("max_turn_rate", max_turn_rate, Bounds<double>{0.01, 10.0});
    v("timeout", timeout, Bounds<double>{0.02, 60.0});
    v("max_recoveries", max_recoveries, Bounds<int>{0, 10});
  }
};

// navigate: the map used when a request brings none, how long to plan, how to follow.
struct NavigationConfig {
  std::string map;                 // YAML map file (navigation_map/map2d.h); empty: requests must send one
  double planning_time = 0.5;      // s of OMPL planning per (re)plan
  double waypoint_spacing = 0.5;   // m between waypoints at most
  double clearance_margin = 0.15;  // m the path keeps beyond the robot's radius where it can
  double replan_inside = 0.1;      // m into the robot's radius of an obstacle: plan again
  double timeout = 120.0;          // s a navigation may take, standing up included
  double rate_hz = 20.0;           // how often the follower steers
  // Paths turn no tighter than this times the library's tightest turn both ways (0: straight
  // segments, for a robot that turns in place); above 1, room for the follower's lag.
  double turn_radius_scale = 1.2;
  FollowerConfig follower;
  // What chooses the skill for navigate, as the top-level selector; "auto" is learned if the
  // library has a selector and nearest_skill if not: the follower's command changes every tick,
  // and time-sharing's 1 s holds lag its steering (docs/serving.md).
  std::string selector = "auto";
  template <class V>
  void Visit(V& v) {
    v("map", map);
    v("planning_time", planning_time, Bounds<double>{0.01, 30.0});
    v("waypoint_spacing", waypoint_spacing, Bounds<double>{0.05, 10.0});
    v("clearance_margin", clearance_margin, Bounds<double>{0.0, 10.0});
    v("replan_inside", replan_inside, Bounds<double>{0.0, 10.0});
    v("timeout", timeout, Bounds<double>{1.0, 86400.0});
    v("rate_hz", rate_hz, Bounds<double>{1.0, 50.0});
    v("turn_radius_scale", turn_radius_scale, Bounds<double>{0.0, 10.0});
    v("follower", follower);
    v("selector", selector);
  }
};

struct ServerConfig {
  int domain_id = 0;
  std::string partition = "flsd";  // several robots share a domain by partition
  double lease_timeout = 1.0;      // s without a request from the controlling client
  double max_duration = 600.0;     // s, the longest skill or velocity command accepted
  double stand_joint_speed = 1.5;  // rad/s at which stand moves joint targets to the default pose
  // PD gains while standing: twice the training stiffness. At the training gains the stand cannot
  // pull the feet a crouched or sitting skill leaves splayed back under the hips, so the stand
  // check failed after 6 of 19 skills of a library and a lie-down recovery followed.
  double stand_kp = 2.0 * a1::kKp;
  double stand_kd = 2.0 * a1::kKd;
  // s that the library's stillest skill runs after a skill, velocity or navigation task, before
  // the stand's targets hold the legs: caught mid-stride in a fast turn, the legs tip the robot
  // (0: stand at once)
  double stand_brake_time = 0.4;
  double requests_per_second = 1000.0;  // per client; beyond it requests are dropped and counted
  int request_burst = 100;
  int control_priority = 80;  // SCHED_FIFO priority of the control loop; 0: the normal scheduler
  int cpu_latency_us = 0;     // /dev/cpu_dma_latency while serving (0: idle CPUs poll); -1: untouched
  // What chooses the skill for track_velocity: "learned" (the library's selector; the call is
  // unavailable without one), "nearest_skill" (the skill whose measured velocity is nearest the
  // command, skills/runtime/nearest_skill.h), "time_sharing" (skills alternated so that their
  // velocities average the command, same file), or "auto": learned if the library has a selector,
  // time_sharing if not. navigation.selector chooses for navigate.
  std::string selector = "auto";
  StandCheckConfig stand_check;
  SafetyConfig safety;
  NavigationConfig navigation;
  SimBackendConfig sim;
  hw::HwConfig hw;
  // DDS Security (comm/security.h, docs/security.md): off by default; when on, a request is
  // executed only under its writer's authenticated identity.
  dds::SecurityConfig security;
  // Motion calls, accepted and refused, with who sent them, are logged; with a path, also
  // appended to this file (created with mode 0600).
  std::string audit_log;
  // A folder whose cert.pem files (at any depth: a make_pki.sh folder) give the audit log the
  // subject names of DDS Security identities; empty: identities only.
  std::string audit_certificates;
  template <class V>
  void Visit(V& v) {
    v("domain_id", domain_id, Bounds<int>{0, 232});
    v("partition", partition);
    v("lease_timeout", lease_timeout, Bounds<double>{0.1, 60.0});
    v("max_duration", max_duration, Bounds<double>{0.1, 86400.0});
    v("stand_joint_speed", stand_joint_speed, Bounds<double>{0.1, 10.0});
    v("stand_kp", stand_kp, Bounds<double>{0.0, 200.0});
    v("stand_kd", stand_kd, Bounds<double>{0.0, 10.0});
    v("stand_brake_time", stand_brake_time, Bounds<double>{0.0, 10.0});
    v("requests_per_second", requests_per_second, Bounds<double>{1.0, 100000.0});
    v("request_burst", request_burst, Bounds<int>{1, 100000});
    v("control_priority", control_priority, Bounds<int>{0, 99});
    v("cpu_latency_us", cpu_latency_us, Bounds<int>{-1, 1000000});
    v("selector", selector);
    v("stand_check", stand_check);
    v("safety", safety);
    v("navigation", navigation);
    v("sim", sim);
    v("hw", hw);
    v("security", security);
    v("audit_log", audit_log);
    v("audit_certificates", audit_certificates);
  }
};

// Reads `path` (resolved with ResolveDataPath); every key is optional.
ServerConfig LoadServerConfig(const std::string& path);

}  // namespace flsd
