// Switching between every ordered pair of the shipped library's dependable skills: every pair is
// run once, each skill also from a stand, and a started skill moves as its descriptor says. The
// time-sharing selector's cycles played for several periods, and the record of those that fell.

#include "skills/learning/evaluation/transition_eval.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numeric>

#include "core/paths.h"
#include "skills/learning/export/compose_library.h"
#include "tests/common/test_support.h"
#include "skills/learning/evaluation/tracking_eval.h"
#include "skills/runtime/nearest_skill.h"
#include "skills/runtime/safetensors.h"

namespace flsd {
namespace {

TEST(EvaluateTransitions, RunsEveryOrderedPairAndEachSkillFromAStand) {
  const SkillLibrary library = SkillLibrary::Load(ResolveDataPath("models/a1_flsd.safetensors"));
  const TransitionEvaluation e = EvaluateTransitions(library, TrainingEnvOf(library), 0.5, 2.0, 1.0, 1);
  const std::vector<int> skills = NearestSkillSelector(library).candidates();
  const int n = static_cast<int>(skills.size());
  ASSERT_EQ(e.skills, skills);
  EXPECT_EQ(e.pairs, n * (n - 1));
  ASSERT_EQ(e.results.size(), static_cast<size_t>(n * n));  // n - 1 sources and the stand per target
  EXPECT_EQ(std::accumulate(e.falls_into.begin(), e.falls_into.end(), 0), e.falls);
  // The fastest backward skill started from a stand: no fall, and after a second of it within 25 %
  // of the speed its descriptor records.
  const SkillDescriptor* fastest = nullptr;
  for (int id : skills) {
    const SkillDescriptor& d = library.skills()[id];
    if (!fastest || d.mean_linear_velocity.x() < fastest->mean_linear_velocity.x()) fastest = &d;
  }
  for (const TransitionResult& r : e.results) {
    if (r.from != -1 || r.to != fastest->id) continue;
    EXPECT_FALSE(r.fell);
    EXPECT_NEAR(r.achieved[0], fastest->mean_linear_velocity.x(), 0.25 * std::abs(fastest->mean_linear_velocity.x()));
  }
  const nlohmann::json json = TransitionJson(e);
  EXPECT_EQ(json["results"][0]["from"], "stand");
  EXPECT_EQ(json["pairs"], e.pairs);
}

// Switched at more moments of a's stride, a pair falls at least where it fell at the first (which
// is the same rollout); the falls recorded in the library are those of the evaluations, replaced
// by a later record. Three skills of the shipped library: the 0.88 m/s walk and the two turns in
// place, the left one of which the walk falls into.
TEST(EvaluateTransitions, MoreHandoversFindAtLeastTheFallsOfOneAndTheRecordKeepsThem) {
  const std::string path = testutil::UniqueTempPath("transitions.safetensors");
  ComposeLibraries({{ResolveDataPath("models/a1_flsd.safetensors"), {6, 10, 11}}}, path);
  const SkillLibrary library = SkillLibrary::Load(path);
  const TransitionEvaluation one = EvaluateTransitions(library, TrainingEnvOf(library), 2.0, 4.0, 1.0, 1);
  const TransitionEvaluation five = EvaluateTransitions(library, TrainingEnvOf(library), 2.0, 4.0, 1.0, 1, 5);
  EXPECT_EQ(five.handovers, 5);
  ASSERT_EQ(one.results.size(), five.results.size());
  for (size_t i = 0; i < one.results.size(); ++i) {
    EXPECT_EQ(one.results[i].achieved, five.results[i].achieved);  // the first handover's
    if (one.results[i].fell) {
      EXPECT_TRUE(five.results[i].fell);
    }
  }
  EXPECT_GE(five.falls, one.falls);
  EXPECT_GT(five.falls, 0) << "the walk into the left turn fell at the fourth or fifth handover: nothing was recorded";

  RecordTransitions(path, {five});
  const SkillLibrary recorded = SkillLibrary::Load(path);
  int recorded_falls = 0;
  for (const TransitionResult& r : five.results) {
    if (r.from < 0) continue;
    EXPECT_EQ(recorded.SwitchFell(r.from, r.to), r.fell) << r.from << " to " << r.to;
    recorded_falls += recorded.SwitchFell(r.from, r.to);
  }
  EXPECT_EQ(recorded_falls, five.falls);
  EXPECT_EQ(recorded.metadata()["transitions"]["handovers"], 5);
  TransitionEvaluation none = five;
  for (TransitionResult& r : none.results) r.fell = false;
  RecordTransitions(path, {none});
  EXPECT_TRUE(SkillLibrary::Load(path).falling_switches().empty());
  // Two evaluations (a switch after 1 s of a, and after 2 s): a switch that fell in either is kept.
  TransitionEvaluation earlier = none;
  earlier.first_seconds = 1.0;
  earlier.results.back().fell = earlier.results.back().from >= 0;
  RecordTransitions(path, {five, earlier});
  const SkillLibrary both = SkillLibrary::Load(path);
  EXPECT_EQ(static_cast<int>(both.falling_switches().size()), five.falls + !five.results.back().fell);
  EXPECT_EQ(both.metadata()["transitions"]["first_seconds"], nlohmann::json::array({2.0, 1.0}));
  std::remove(path.c_str());
}

// The shipped library without its record of cycles: played for four periods, the cycle of the
// left turn in place, the 0.88 m/s walk and the left arc (10, 6, 3) falls, as it did on two
// commands of the tracking evaluation set, though none of its switches falls from a stand. The
// record keeps exactly the cycles that fell, and measured again over the recorded library (whose
// record it does not trust) the same cycles fall: the record is replaced, not added to.
TEST(EvaluateCycles, FindsACycleThatFallsOnlyAfterPeriodsAndTheRecordKeepsItOut) {
  const std::string path = testutil::UniqueTempPath("cycles.safetensors");
  SafeTensors file = ReadSafeTensors(ResolveDataPath("models/a1_flsd.safetensors"));
  nlohmann::json metadata = nlohmann::json::parse(file.metadata.at("flsd"));
  metadata.erase("cycles");
  file.metadata["flsd"] = metadata.dump();
  WriteSafeTensors(path, file);
  const SkillLibrary library = SkillLibrary::Load(path);
  ASSERT_TRUE(library.falling_cycles().empty());
  const CycleEvaluation e = EvaluateCycles(library, TrainingEnvOf(library), 9, 4, 1);
  EXPECT_EQ(e.hold_seconds, 1.0);
  EXPECT_GE(e.rounds, 2);  // the falls' commands got other cycles, played in the next round
  int falls = 0;
  FallingCycles fell;
  const int turn_walk_arc[3] = {10, 6, 3};
  for (const CycleResult& r : e.results) {
    ASSERT_GE(r.skills.size(), 2u);
    EXPECT_GE(r.commands, 1);
    EXPECT_LT(r.fell_at_step, 4 * 50 * static_cast<int>(r.skills.size()));
    if (r.fell_at_step < 0) continue;
    ++falls;
    FallingCycles one;
    one.Add(r.skills.data(), static_cast<int>(r.skills.size()));
    if (one.Contains(turn_walk_arc, 3)) EXPECT_GT(r.fell_at_step, 2 * 150) << "it held two periods in the tracking evaluation";
    fell.Add(r.skills.data(), static_cast<int>(r.skills.size()));
  }
  EXPECT_EQ(falls, e.falls);
  EXPECT_TRUE(fell.Contains(turn_walk_arc, 3)) << "the evaluation set's falling cycle was not found";

  // A cycle is recorded if it fell from any of its holds (a cycle entered at one hold can stand
  // where the same cycle entered at another falls).
  RecordCycles(path, e);
  const SkillLibrary recorded = SkillLibrary::Load(path);
  EXPECT_EQ(recorded.falling_cycles().cycles(), fell.cycles());
  EXPECT_EQ(recorded.metadata()["cycles"]["periods"], 4);
  const CycleEvaluation again = EvaluateCycles(recorded, TrainingEnvOf(recorded), 9, 4, 1);
  EXPECT_EQ(again.falls, e.falls);
  RecordCycles(path, again);
  EXPECT_EQ(SkillLibrary::Load(path).falling_cycles().cycles(), fell.cycles());
  std::remove(path.c_str());
}

}  // namespace
}  // namespace flsd
