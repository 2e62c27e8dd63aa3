#pragma once
// `flsd eval-library`: every skill of a library file rolled out once from the same start, by
// skilld's own policy code (PolicyRunner, Eigen) behind the library's target filter, and the
// paper's metrics and the library bar computed over the trajectories. A library joined from
// several runs (compose-library) has no run to evaluate: this is where its pooled metrics come
// from. Plain C++.

#include "skills/learning/evaluation/skill_rollouts.h"
#include "skills/runtime/skill_library.h"

namespace flsd {

Evaluation EvaluateLibrary(const SkillLibrary& library, const EvaluationOptions& options);

}  // namespace flsd
