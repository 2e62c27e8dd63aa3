// The names of the project's enums: one table each (api/modes.h), in the IDL's order and spelled as
// the IDL's enumerators end, so that the IDL, the server, the clients and the Python module agree.

#include "api/modes.h"

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "core/paths.h"

namespace flsd {
namespace {

// The enumerators of `enum name { ... }` in idl/flsd_msgs.idl, comments left out.
std::vector<std::string> IdlEnumerators(const std::string& name) {
  std::ifstream in(ResolveDataPath("idl/flsd_msgs.idl"));
  std::stringstream text;
  text << in.rdbuf();
  const std::string idl = std::regex_replace(text.str(), std::regex("//[^\n]*"), "");
  std::smatch body;
  EXPECT_TRUE(std::regex_search(idl, body, std::regex("enum " + name + R"(\s*\{([^}]*)\})"))) << name;
  std::vector<std::string> out;
  const std::string list = body[1];
  const std::regex enumerator(R"([A-Z_]+)");
  for (std::sregex_iterator it(list.begin(), list.end(), enumerator), end; it != end; ++it) {
    out.push_back(it->str());
  }
  return out;
}

template <class Enum, std::size_t N>
std::vector<std::string> Prefixed(const EnumName<Enum> (&names)[N], const std::string& prefix, std::size_t count) {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < count; ++i) out.push_back(prefix + names[i].identifier);
  return out;
}

TEST(Names, EveryTableIsTheIdlsEnumInOrder) {
  EXPECT_EQ(IdlEnumerators("Mode"), Prefixed(kModeNames, "MODE_", std::size(kModeNames)));
  EXPECT_EQ(IdlEnumerators("TaskState"), Prefixed(kTaskStateNames, "TASK_", std::size(kTaskStateNames)));
  // kNoReply, the last, is the client's own.
  EXPECT_EQ(IdlEnumerators("ReplyStatus"),
            Prefixed(kReplyStatusNames, "STATUS_", std::size(kReplyStatusNames) - 1));
}

TEST(Names, ValuesAreNamedForPeopleAndAnUnknownValueSaysSo) {
  EXPECT_STREQ(Name(Mode::kNavigate), "navigate");
  EXPECT_STREQ(Name(ReplyStatus::kNotInControl), "not in control");
  EXPECT_STREQ(Name(ReplyStatus::kNoReply), "no reply");
  EXPECT_STREQ(Name(TaskState::kLeaseLost), "lease lost");
  EXPECT_STREQ(Name(static_cast<Mode>(42)), "unknown");
}

}  // namespace
}  // namespace flsd
