// SkillLibrary: a library written by the learning side loads, matches libtorch's policy to float
// precision, runs without heap allocation, and every field that differs from this robot is
// rejected with a message naming it.

#include "skills/runtime/skill_library.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <fstream>

#include "core/paths.h"
#include "robot/observation.h"
#include "skills/learning/export/export.h"
#include "skills/runtime/safetensors.h"
#include "tests/common/test_support.h"
#include "tests/skills/runtime/test_libraries.h"

#include "tests/common/malloc_counter.h"

namespace flsd {
namespace {

using ::testing::HasSubstr;
using testutil::InputErrorMessage;
using testutil::UniqueTempPath;

using testutil::RandomPolicy;
using testutil::WriteTestLibrary;

constexpr int kSkills = 5;  // pairs (0, 2) and (1, 3); skill 4 its own mirror image

class SkillLibraryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = UniqueTempPath("lib.safetensors");
    WriteTestLibrary(path_, config_, policy_);
  }
  void TearDown() override { std::remove(path_.c_str()); }

  // Rewrites the library with one metadata edit and returns Load's error message.
  std::string LoadWithEdit(const std::function<void(nlohmann::json&)>& edit) {
    SafeTensors file = ReadSafeTensors(path_);
    nlohmann::json meta = nlohmann::json::parse(file.metadata["flsd"]);
    edit(meta);
    file.metadata["flsd"] = meta.dump();
    const std::string edited = UniqueTempPath("edited.safetensors");
    WriteSafeTensors(edited, file);
    const std::string message = InputErrorMessage([&] { SkillLibrary::Load(edited); });
    std::remove(edited.c_str());
    return message;
  }

  TrainConfig config_ = testutil::SmallLibraryConfig(kSkills);
  TrainedPolicy policy_ = RandomPolicy(config_);
  std::string path_;
};

TEST_F(SkillLibraryTest, LoadsShapesAndDescriptors) {
  const SkillLibrary lib = SkillLibrary::Load(path_);
  EXPECT_EQ(lib.num_skills(), kSkills);
  ASSERT_EQ(lib.policies().size(), 1u);
  const SkillPolicy& policy = lib.policies()[0];
  EXPECT_EQ(policy.num_skills, kSkills);
  ASSERT_EQ(policy.network.layers.size(), 3u);
  EXPECT_EQ(policy.network.layers[0].weight.rows(), 32);
  EXPECT_EQ(policy.network.layers[0].weight.cols(), 33 + 12 + kSkills);
  EXPECT_EQ(policy.network.layers[2].weight.rows(), 12);
  EXPECT_EQ(policy.training["iteration"], 7);
  EXPECT_EQ(lib.skills()[3].policy, 0);
  EXPECT_EQ(lib.skills()[3].policy_skill, 3);
  ASSERT_EQ(lib.skills().size(), static_cast<size_t>(kSkills));
  EXPECT_EQ(lib.skills()[3].survival_steps, 997);
  EXPECT_DOUBLE_EQ(lib.skills()[3].mean_linear_velocity.x(), 0.3 * 1.0);
  // What a user reads of a skill beyond its velocities: its mirror image, slip, randomised life.
  EXPECT_EQ(lib.skills()[0].mirror_skill, 2);
  EXPECT_EQ(lib.skills()[3].mirror_skill, 1);
  EXPECT_EQ(lib.skills()[4].mirror_skill, 4);
  EXPECT_DOUBLE_EQ(lib.skills()[3].mean_stance_foot_speed.value(), 0.03);
  EXPECT_EQ(lib.skills()[3].randomized_survival_steps.value(), 397);
  EXPECT_DOUBLE_EQ(lib.skills()[3].randomized_stance_foot_speed.value(), 0.06);
  EXPECT_FALSE(lib.skills()[3].randomized_fell);
  EXPECT_TRUE(lib.skills()[4].randomized_fell);
  EXPECT_EQ(lib.metadata()["policies"][0]["randomized_evaluation"]["randomized"], true);
}

TEST_F(SkillLibraryTest, MirrorImagesMustPairBothWaysAndOlderLibrariesHaveNone) {
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["skills"][0]["mirror_skill"] = 3; }),
              HasSubstr("/skills/0/mirror_skill is 3, but skill 3's is not 0"));
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["skills"][1]["mirror_skill"] = 9; }),
              HasSubstr("/skills/1/mirror_skill"));
  SafeTensors file = ReadSafeTensors(path_);
  nlohmann::json meta = nlohmann::json::parse(file.metadata["flsd"]);
  for (nlohmann::json& skill : meta["skills"]) {
    for (const char* key : {"mirror_skill", "mean_stance_foot_speed", "randomized_survival_steps", "randomized_fell",
                            "randomized_stance_foot_speed"}) {
      skill.erase(key);
    }
  }
  file.metadata["flsd"] = meta.dump();
  const std::string old = UniqueTempPath("old.safetensors");
  WriteSafeTensors(old, file);
  const SkillLibrary lib = SkillLibrary::Load(old);
  EXPECT_EQ(lib.skills()[3].mirror_skill, 3);
  EXPECT_FALSE(lib.skills()[3].mean_stance_foot_speed.has_value());
  EXPECT_FALSE(lib.skills()[3].randomized_survival_steps.has_value());
  EXPECT_FALSE(lib.skills()[3].randomized_stance_foot_speed.has_value());
  std::remove(old.c_str());
}

// The descriptor's one field list writes every field and reads it back; a required one that is
// missing is named, with the skill.
TEST_F(SkillLibraryTest, DescriptorsRoundTripThroughTheirFieldList) {
  const SkillLibrary lib = SkillLibrary::Load(path_);
  const SkillDescriptor& d = lib.skills()[3];
  const nlohmann::json written = DescriptorJson(d);
  EXPECT_EQ(written, lib.metadata()["skills"][3]);  // export wrote exactly this
  EXPECT_EQ(written.size(), 14u);
  EXPECT_EQ(written["mean_linear_velocity"], nlohmann::json({0.1 * 3, -0.2, 0.0}));  // FakeEvaluation's
  SkillDescriptor without_optionals = d;
  without_optionals.mean_stance_foot_speed.reset();
  without_optionals.randomized_survival_steps.reset();
  without_optionals.randomized_stance_foot_speed.reset();
  EXPECT_EQ(DescriptorJson(without_optionals).size(), 11u);
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["skills"][2].erase("gait_frequency_hz"); }),
              HasSubstr("/skills/2/gait_frequency_hz is missing"));
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["skills"][1]["mean_angular_velocity"] = {0.0, 1.0}; }),
              HasSubstr("/skills/1/mean_angular_velocity must have 3 entries"));
}

// The Eigen runner and libtorch agree on the same weights and inputs, for every skill.
TEST_F(SkillLibraryTest, EigenPolicyMatchesLibtorch) {
  const SkillLibrary lib = SkillLibrary::Load(path_);
  PolicyRunner runner(lib);
  torch::NoGradGuard no_grad;
  const torch::Tensor motion = torch::randn({20, kMotionObsSize}) * 2.0;
  const torch::Tensor previous = torch::randn({20, kActionSize});
  torch::Tensor obs = torch::zeros({20, PolicyObservationSize(kSkills)});
  for (int i = 0; i < 20; ++i) {
    BuildPolicyObservation(motion[i].data_ptr<float>(), previous[i].data_ptr<float>(), i % kSkills, kSkills,
                           obs[i].data_ptr<float>());
  }
  const torch::Tensor expected = policy_.policy->ActionMean(NormalizeLeadingColumns(policy_.normalizer, obs));
  for (int i = 0; i < 20; ++i) {
    float action[kActionSize];
    runner.Act(motion[i].data_ptr<float>(), previous[i].data_ptr<float>(), i % kSkills, action);
    for (int j = 0; j < kActionSize; ++j) EXPECT_NEAR(action[j], expected[i][j].item<float>(), 2e-5) << i << "," << j;
  }
  float action[kActionSize];
  EXPECT_THAT(InputErrorMessage([&] { runner.Act(motion[0].data_ptr<float>(), previous[0].data_ptr<float>(), kSkills, action); }),
              HasSubstr("skill 5 is not in"));
}

TEST_F(SkillLibraryTest, ActAllocatesNothing) {
  const SkillLibrary lib = SkillLibrary::Load(path_);
  PolicyRunner runner(lib);
  std::vector<float> motion(kMotionObsSize, 0.5f), previous(kActionSize, 0.1f);
  float action[kActionSize];
  runner.Act(motion.data(), previous.data(), 2, action);
  EXPECT_EQ(testutil::CountMallocs([&] {
              for (int i = 0; i < 100; ++i) runner.Act(motion.data(), previous.data(), i % kSkills, action);
            }),
            0);
}

// A version 1 library as the project shipped it loads and acts.
TEST(SkillLibraryVersion1, TheShippedDiaynLibraryLoadsAndActs) {
  const SkillLibrary lib = SkillLibrary::Load(ResolveDataPath("models/a1_diayn.safetensors"));
  ASSERT_EQ(lib.metadata()["format_version"], 1);
  ASSERT_EQ(lib.policies().size(), 1u);
  EXPECT_EQ(lib.policies()[0].num_skills, lib.num_skills());
  EXPECT_EQ(lib.policies()[0].training["method"], "diayn");
  PolicyRunner runner(lib);
  std::vector<float> motion(kMotionObsSize, 0.1f), previous(kActionSize, 0.0f), action(kActionSize);
  runner.Act(motion.data(), previous.data(), lib.num_skills() - 1, action.data());
  for (float a : action) EXPECT_TRUE(std::isfinite(a));
  EXPECT_NE(action, std::vector<float>(kActionSize, 0.0f));
}

// A library written by format version 1 (one policy, no policy per skill) runs as it did.
TEST_F(SkillLibraryTest, ReadsVersion1Libraries) {
  const std::string v1 = UniqueTempPath("v1.safetensors");
  testutil::WriteAsVersion1(path_, v1);
  const SkillLibrary old = SkillLibrary::Load(v1), now = SkillLibrary::Load(path_);
  ASSERT_EQ(old.policies().size(), 1u);
  EXPECT_EQ(old.policies()[0].num_skills, kSkills);
  EXPECT_EQ(old.policies()[0].training["iteration"], 7);
  EXPECT_EQ(old.skills()[3].policy_skill, 3);
  PolicyRunner old_runner(old), runner(now);
  std::vector<float> motion(kMotionObsSize, 0.3f), previous(kActionSize, -0.2f);
  float a[kActionSize], b[kActionSize];
  old_runner.Act(motion.data(), previous.data(), 3, a);
  runner.Act(motion.data(), previous.data(), 3, b);
  for (int j = 0; j < kActionSize; ++j) EXPECT_EQ(a[j], b[j]);
  std::remove(v1.c_str());
}

TEST_F(SkillLibraryTest, EachSkillNamesAPolicyAndOneOfItsSkills) {
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["skills"][1]["policy"] = 1; }),
              HasSubstr("/skills/1/policy must be a policy index, 0 to 0"));
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["skills"][1]["policy_skill"] = kSkills; }),
              HasSubstr("/skills/1/policy_skill must be 0 to 4 (policy 0's skills)"));
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["skills"][2]["policy_skill"] = 0; }),
              HasSubstr("/skills/2/policy_skill is skill 0's too"));
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["policies"] = nlohmann::json::array(); }),
              HasSubstr("/policies must list at least one policy"));
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["skills"][1]["policy"] = 0.5; }),
              HasSubstr("/skills/1/policy must be an integer (it is 0.5)"));
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["skills"][1]["policy_skill"] = true; }),
              HasSubstr("/skills/1/policy_skill must be an integer"));
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["skills"][1].erase("policy"); }),
              HasSubstr("/skills/1/policy is missing"));
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["policies"][0].erase("training"); }),
              HasSubstr("/policies/0/training/config is missing"));
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["policies"][0]["num_skills"] = 2000000; }),
              HasSubstr("/policies/0/num_skills must be within [1, 1000000]"));
}

// The switches that fell in `flsd transitions --record` (/transitions/falls), checked as every
// other field is: a pair of distinct skill ids.
TEST_F(SkillLibraryTest, RecordsTheSwitchesThatFell) {
  EXPECT_TRUE(SkillLibrary::Load(path_).falling_switches().empty());
  SafeTensors file = ReadSafeTensors(path_);
  nlohmann::json meta = nlohmann::json::parse(file.metadata["flsd"]);
  meta["transitions"]["falls"] = {{0, 3}, {4, 1}};
  file.metadata["flsd"] = meta.dump();
  WriteSafeTensors(path_, file);
  const SkillLibrary lib = SkillLibrary::Load(path_);
  EXPECT_TRUE(lib.SwitchFell(0, 3));
  EXPECT_TRUE(lib.SwitchFell(4, 1));
  EXPECT_FALSE(lib.SwitchFell(3, 0));  // a switch has a direction
  EXPECT_FALSE(lib.SwitchFell(-1, 3));
  EXPECT_EQ(lib.falling_switches().size(), 2u);

  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["transitions"]["falls"] = {{0, kSkills}}; }),
              HasSubstr("/transitions/falls/0 names skill 5; expected 0 to 4"));
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["transitions"]["falls"] = {{1, 3}, {2, 2}}; }),
              HasSubstr("/transitions/falls/1 switches skill 2 to itself"));
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["transitions"]["falls"] = {{1, 3, 4}}; }),
              HasSubstr("/transitions/falls/0 must be a [from, to] pair of skill ids"));
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["transitions"]["falls"] = {{1, 0.5}}; }),
              HasSubstr("/transitions/falls/0/1 must be an integer (it is 0.5)"));
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["transitions"]["falls"] = "0 to 3"; }),
              HasSubstr("/transitions/falls must be a list of [from, to] skill id pairs"));
}

// The cycles that fell in `flsd cycles --record` (/cycles/falls): 2 or 3 skill ids that switch.
TEST_F(SkillLibraryTest, RecordsTheCyclesThatFell) {
  EXPECT_TRUE(SkillLibrary::Load(path_).falling_cycles().empty());
  SafeTensors file = ReadSafeTensors(path_);
  nlohmann::json meta = nlohmann::json::parse(file.metadata["flsd"]);
  meta["cycles"]["falls"] = {{4, 0, 2}, {1, 3}};
  file.metadata["flsd"] = meta.dump();
  WriteSafeTensors(path_, file);
  const SkillLibrary lib = SkillLibrary::Load(path_);
  const FallingCycles& cycles = lib.falling_cycles();
  const int entered_at_two[3] = {2, 4, 0}, two[2] = {3, 1};
  EXPECT_TRUE(cycles.Contains(entered_at_two, 3));
  EXPECT_TRUE(cycles.Contains(two, 2));
  EXPECT_EQ(cycles.cycles().size(), 2u);

  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["cycles"]["falls"] = {{0, kSkills}}; }),
              HasSubstr("/cycles/falls/0 names skill 5; expected 0 to 4"));
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["cycles"]["falls"] = {{1, 3}, {2, 2, 2}}; }),
              HasSubstr("/cycles/falls/1 holds skill 2 throughout: a cycle switches"));
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["cycles"]["falls"] = {{1, 3, 4, 0}}; }),
              HasSubstr("/cycles/falls/0 must be a cycle of 2 to 3 skill ids"));
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["cycles"]["falls"] = {{1, 0.5}}; }),
              HasSubstr("/cycles/falls/0/1 must be an integer (it is 0.5)"));
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["cycles"]["falls"] = "1 then 3"; }),
              HasSubstr("/cycles/falls must be a list of cycles, each 2 to 3 skill ids"));
}

TEST_F(SkillLibraryTest, RejectsEachMismatchNamingTheField) {
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { std::swap(m["joint_names"][0], m["joint_names"][1]); }),
              HasSubstr("/joint_names/0 is 'FR_thigh_joint' but this build expects 'FR_hip_joint'"));
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["control"]["kp"] = 25.0; }),
              HasSubstr("/control/kp is 25 but this robot uses 20"));
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["observation"]["motion"][1]["scale"] = 1.0; }),
              HasSubstr("/observation/motion/1/scale is 1 but this robot uses 0.25"));
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["action"]["default_joint_positions"][4] = 0.9; }),
              HasSubstr("/action/default_joint_positions/4 is 0.9 but this robot uses 0.8"));
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["control"]["control_dt"] = 0.01; }),
              HasSubstr("/control/control_dt"));
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["format_version"] = 3; }),
              HasSubstr("/format_version is 3 but this build reads versions 1 to 2"));
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m.erase("limits"); }), HasSubstr("/limits/torque is missing"));
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["limits"]["joint_max"][2] = -0.5; }),
              HasSubstr("/limits/joint_max/2 is -0.5 but this robot uses -0.916298"));
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["robot"] = "go1"; }), HasSubstr("/robot is 'go1'"));
  // A policy that claims more skills than its first layer takes; a library that lists fewer.
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["policies"][0]["num_skills"] = kSkills + 1; }),
              HasSubstr("/policies/0/observation_size is 50 but this robot uses 51"));
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["num_skills"] = kSkills + 1; }),
              HasSubstr("/skills must describe each of the 6 skills"));
}

TEST_F(SkillLibraryTest, CarriesTheTargetFilterOfTraining) {
  EXPECT_EQ(SkillLibrary::Load(path_).action_filter_hz(), 0.0);
  TrainConfig filtered = config_;
  filtered.env.action_filter_hz = 4.0;
  const std::string path = UniqueTempPath("filtered.safetensors");
  WriteTestLibrary(path, filtered, policy_);
  EXPECT_EQ(SkillLibrary::Load(path).action_filter_hz(), 4.0);
  EXPECT_EQ(SkillLibrary::Load(path).action_filter_order(), 1);
  filtered.env.action_filter_hz = 10.0;
  filtered.env.action_filter_order = 2;
  WriteTestLibrary(path, filtered, policy_);
  EXPECT_EQ(SkillLibrary::Load(path).action_filter_order(), 2);
  std::remove(path.c_str());
  // Libraries from before the filter have no entry, and ran without one; a bad one is named.
  SafeTensors file = ReadSafeTensors(path_);
  nlohmann::json meta = nlohmann::json::parse(file.metadata["flsd"]);
  meta["action"].erase("filter_hz");
  file.metadata["flsd"] = meta.dump();
  const std::string old = UniqueTempPath("old.safetensors");
  WriteSafeTensors(old, file);
  EXPECT_EQ(SkillLibrary::Load(old).action_filter_hz(), 0.0);
  std::remove(old.c_str());
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["action"]["filter_hz"] = 40.0; }),
              HasSubstr("/action/filter_hz must be within [0, 25"));
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["action"]["filter_order"] = 3; }),
              HasSubstr("/action/filter_order must be within [1, 2]"));
  EXPECT_THAT(LoadWithEdit([](nlohmann::json& m) { m["num_skills"] = 0; }), HasSubstr("/num_skills must be within [1, "));
}

TEST_F(SkillLibraryTest, RejectsBadTensors) {
  SafeTensors file = ReadSafeTensors(path_);
  SafeTensors missing = file;
  missing.tensors.erase("policies.0.layer1.bias");
  const std::string edited = UniqueTempPath("tensors.safetensors");
  WriteSafeTensors(edited, missing);
  EXPECT_THAT(InputErrorMessage([&] { SkillLibrary::Load(edited); }), HasSubstr("no tensor 'policies.0.layer1.bias'"));
  SafeTensors poisoned = file;
  poisoned.tensors["policies.0.layer0.weight"].values[5] = NAN;
  WriteSafeTensors(edited, poisoned);
  EXPECT_THAT(InputErrorMessage([&] { SkillLibrary::Load(edited); }), HasSubstr("NaN"));
  SafeTensors foreign;
  foreign.tensors["x"] = FloatTensor{{1}, {1.0f}};
  WriteSafeTensors(edited, foreign);
  EXPECT_THAT(InputErrorMessage([&] { SkillLibrary::Load(edited); }), HasSubstr("not an FLSD skill library"));
  std::remove(edited.c_str());
}

TEST_F(SkillLibraryTest, TruncatedFileIsAnErrorNotACrash) {
  std::ifstream in(path_, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string cut = UniqueTempPath("cut.safetensors");
  for (size_t keep : {size_t{0}, size_t{7}, size_t{100}, bytes.size() / 2, bytes.size() - 1}) {
    std::ofstream(cut, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(keep));
    EXPECT_THAT(InputErrorMessage([&] { SkillLibrary::Load(cut); }), HasSubstr(cut)) << keep;
  }
  std::remove(cut.c_str());
}

}  // namespace
}  // namespace flsd
