// `flsd bench soak` for two minutes: a real skilld under three clients' random valid and invalid
// calls gives no wrong reply, leaves none unanswered, does not crash, and damps within 50 ms.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <string>

#include "tests/common/process.h"
#include "tests/common/test_support.h"

namespace flsd {
namespace {

// The JSON object a bench printed: from the first line that opens one to the end.
nlohmann::json PrintedJson(const std::string& output) {
  const std::size_t at = output.rfind("\n{\n");
  const std::size_t from = output.rfind("{\n", 0) == 0 ? 0 : at;
  if (from == std::string::npos) return nullptr;
  return nlohmann::json::parse(output.substr(from), nullptr, /*allow_exceptions=*/false);
}

TEST(SoakBenchTest, TwoMinutesOfThreeClientsGiveNoWrongReplyNoDropNoCrashAndQuickDamps) {
  const auto [code, output] = testutil::RunProgram(
      testutil::BinaryPath("flsd"), {"bench", "soak", "--minutes", "2", "--clients", "3", "--domain", "231", "--json"},
      testutil::UniqueTempPath("soak.log"), std::chrono::minutes(5));
  ASSERT_EQ(code, 0) << output;
  const nlohmann::json soak = PrintedJson(output);
  ASSERT_TRUE(soak.is_object()) << output;
  EXPECT_EQ(soak["crashes"], 0) << soak["crash_details"].dump(2);
  EXPECT_EQ(soak["wrong_replies"], 0) << soak["wrong_examples"].dump(2);
  EXPECT_EQ(soak["dropped"], 0) << soak["dropped_examples"].dump(2);
  // 3 clients at 50 requests/s for 120 s, less what waits on the state topic.
  EXPECT_GT(soak["requests"].get<int>(), 10000);
  EXPECT_EQ(soak["answered"], soak["requests"]);
  EXPECT_GT(soak["state_checks"].get<int>(), 100);
  EXPECT_GT(soak["damp_latency_ms"]["count"].get<int>(), 20);
  EXPECT_LT(soak["damp_latency_ms"]["p99"].get<double>(), 50.0);
  EXPECT_GT(soak["skilld"]["rss_mb_end"].get<double>(), 0.0);
  EXPECT_TRUE(soak["tick_lateness_ms"].is_object()) << "skilld's exit line was not found";
}

}  // namespace
}  // namespace flsd
