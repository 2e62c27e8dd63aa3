#pragma once
// A training run held in memory, without a run folder: a task and the on-policy runner that trains
// it, built the way the training commands build them.

#include "skills/learning/runners/on_policy_runner.h"
#include "skills/learning/tasks/skill_discovery_task.h"
#include "skills/learning/tasks/velocity_tracking_task.h"

namespace flsd::testutil {

template <class Task, class Config>
struct InMemoryRun {
  explicit InMemoryRun(const Config& config, const Communicator& comm = Communicator::Self())
      : task(config, comm), runner(task, config.ppo, config.seed, comm) {}
  Task task;
  OnPolicyRunner runner;
};

using SkillRun = InMemoryRun<SkillDiscoveryTask, TrainConfig>;
using VelocityRun = InMemoryRun<VelocityTrackingTask, VelocityTrainConfig>;

}  // namespace flsd::testutil
