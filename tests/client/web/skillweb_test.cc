// skillweb end to end: a real skilld on loopback, skillweb in front of it over HTTPS with logins,
// and its page in headless Chromium driven by drive_page.cjs like users on phones: an operator, a
// second operator and an observer. The test records the state topic with a client of its own and
// checks what the pages showed and did against it.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <thread>

#include <nlohmann/json.hpp>

#include "tests/client/web/skillweb_process.h"
#include "tests/common/client_skilld_fixture.h"

namespace flsd {
namespace {

using testutil::RunProgram;
using testutil::UniqueTempPath;

// Every state sample the test's own client sees, by tick.
class StateRecorder {
 public:
  explicit StateRecorder(const Client& client)
      : thread_([this, &client] {
          uint64_t tick = 0;
          while (running_) {
            if (const auto s = client.NextState(tick, std::chrono::milliseconds(100))) {
              tick = s->tick;
              std::lock_guard<std::mutex> lock(mutex_);
              samples_[tick] = *s;
            }
          }
        }) {}
  ~StateRecorder() {
    running_ = false;
    thread_.join();
  }

  // The sample of `tick` itself, if recorded.
  std::optional<StateReport> At(uint64_t tick) const {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = samples_.find(tick);
    if (it == samples_.end()) return std::nullopt;
    return it->second;
  }
  // The newest sample at or before `tick` (the topic may drop one).
  std::optional<StateReport> AtOrBefore(uint64_t tick) const {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = samples_.upper_bound(tick);
    if (it == samples_.begin()) return std::nullopt;
    return (--it)->second;
  }

 private:
  mutable std::mutex mutex_;
  std::map<uint64_t, StateReport> samples_;
  std::atomic<bool> running_{true};
  std::thread thread_;
};

class SkillwebTest : public testutil::ClientSkilldFixture {};

TEST_F(SkillwebTest, PageFollowsTheStateTopicRunsASkillAndDamps) {
  StartServer();
  const auto client = Connect();
  StateRecorder recorder(*client);
  const std::string dir = UniqueTempPath("logins");
  std::filesystem::create_directories(dir);
  testutil::MakeHttpsLogins(dir, {{"alice", "operator"}, {"bob", "operator"}, {"carol", "observer"}});
  std::vector<std::string> web_args = {"--domain", std::to_string(domain_), "--partition", partition_};
  for (const std::string& a : testutil::HttpsLoginArgs(dir)) web_args.push_back(a);
  const testutil::Skillweb web = testutil::StartSkillweb(web_args, UniqueTempPath("skillweb.log"));
  const std::string& url = web.url;
  ASSERT_EQ(url.rfind("https://", 0), 0u) << url;
  const auto login = [](const std::string& name) { return nlohmann::json{name, testutil::TestPassword(name)}; };
  std::ofstream(dir + "/users.json") << nlohmann::json{{"operator", login("alice")},
                                                       {"second_operator", login("bob")},
                                                       {"observer", login("carol")}};

  // SKILLWEB_SCREENSHOT=path: the page while the skill runs, as docs/skillweb.png was taken.
  std::vector<std::string> args = {FLSD_SOURCE_DIR "/tests/client/web/drive_page.cjs", url, FLSD_CHROMIUM,
                                   dir + "/users.json"};
  if (const char* shot = std::getenv("SKILLWEB_SCREENSHOT")) args.push_back(shot);
  setenv("NODE_PATH", FLSD_NODE_MODULES, 1);
  const auto [code, output] = RunProgram(FLSD_NODE, args, UniqueTempPath("drive_page.log"), std::chrono::seconds(120));
  ASSERT_EQ(code, 0) << output << "\nskillweb: " << web.process->Log() << "\nskilld: " << server_->Log();
  const nlohmann::json seen = nlohmann::json::parse(output.substr(output.rfind("\n{") + 1));

  std::filesystem::remove_all(dir);
  EXPECT_TRUE(seen["console_errors"].empty()) << seen["console_errors"].dump(1);
  EXPECT_EQ(seen["wrong_login"]["reply"], "wrong user name or password");
  EXPECT_EQ(seen["wrong_login"]["main_hidden"], true);
  EXPECT_EQ(seen["operator"]["who"], "alice · operator");
  EXPECT_EQ(seen["operator"]["stand_disabled"], false);

  // Two pages, two clients, two leases: the second operator's stand is refused while the first
  // page holds control, and the state topic names the first page's client as the holder.
  const std::string first_id = seen["operator"]["client_id"], second_id = seen["second_operator"]["client_id"];
  EXPECT_NE(first_id, second_id);
  EXPECT_EQ(seen["second_operator"]["controller"], first_id);
  EXPECT_EQ(seen["second_operator"]["reply"].get<std::string>().rfind("stand: not in control", 0), 0u)
      << seen["second_operator"]["reply"];
  EXPECT_NE(seen["second_operator"]["reply"].get<std::string>().find(first_id), std::string::npos);
  EXPECT_EQ(seen["second_operator"]["logged_out"], true);
  EXPECT_EQ(seen["reopened"]["login_hidden"], true);  // the session outlives its page
  EXPECT_EQ(seen["reopened"]["client_id"], first_id);

  // The observer's page follows the robot, and every control is disabled, saying why.
  EXPECT_GT(seen["observer"]["tick"].get<uint64_t>(), 0u);
  EXPECT_EQ(seen["observer"]["who"], "carol · observer");
  const std::string why = "observer: may watch, not command (log in as an operator to command)";
  EXPECT_EQ(seen["observer"]["note"], why);
  for (const auto& control : seen["observer"]["controls"]) {
    EXPECT_EQ(control["disabled"], true) << control["id"];
    EXPECT_EQ(control["title"], why) << control["id"];
  }
  EXPECT_TRUE(seen["observer"]["posts"].empty()) << seen["observer"]["posts"].dump();
  const std::string log = web.process->Log();
  EXPECT_NE(log.find("alice (operator, client " + first_id + "): stand {} -> ok: "), std::string::npos) << log;
  EXPECT_NE(log.find("bob (operator, client " + second_id + "): stand {} -> not in control: "), std::string::npos) << log;
  EXPECT_FALSE(seen["phone"]["overflow"].get<bool>()) << "the page is wider than a phone's screen";
  EXPECT_TRUE(seen["phone"]["estop_visible"].get<bool>());

  // The scene's joints are the state topic's angles of the tick it says it shows, and they moved
  // while the robot stood up.
  int matched = 0;
  double moved = 0.0;
  const auto& samples = seen["samples"];
  for (const auto& sample : samples) {
    const std::optional<StateReport> state = recorder.At(sample["tick"].get<uint64_t>());
    if (!state) continue;  // a sample this test's reader did not get
    ++matched;
    for (int j = 0; j < 12; ++j) {
      EXPECT_NEAR(sample["joints"][j].get<double>(), state->joint_position[j], 1e-9) << "tick " << sample["tick"];
    }
  }
  for (int j = 0; j < 12; ++j) {
    moved = std::max(moved, std::abs(samples.back()["joints"][j].get<double>() - samples.front()["joints"][j].get<double>()));
  }
  EXPECT_GE(matched, 3) << "the test's own reader missed the scene's ticks";  // both may drop samples under load
  EXPECT_GT(moved, 0.05) << "the scene's joints did not follow the robot standing up";

  // The skill started from the page walked the simulated robot.
  const auto from = recorder.AtOrBefore(seen["skill"]["from_tick"].get<uint64_t>());
  const auto to = recorder.AtOrBefore(seen["skill"]["to_tick"].get<uint64_t>());
  ASSERT_TRUE(from && to);
  EXPECT_EQ(to->mode, Mode::kSkill);
  EXPECT_EQ(to->skill, seen["skill"]["id"].get<int>());
  EXPECT_GT(std::hypot(to->position[0] - from->position[0], to->position[1] - from->position[1]), 0.1)
      << "from (" << from->position[0] << ", " << from->position[1] << ") at tick " << from->tick;

  // The page's emergency stop damps the robot, and it stays damped.
  const std::optional<StateReport> now = client->NextState(seen["damp"]["tick"].get<uint64_t>(), std::chrono::seconds(2));
  ASSERT_TRUE(now);
  EXPECT_EQ(now->mode, Mode::kDamp) << seen["damp"]["reply"];
}

}  // namespace
}  // namespace flsd
