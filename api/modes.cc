#include "api/modes.h"

#include <iterator>

namespace flsd {
namespace {

template <class Enum, std::size_t N>
constexpr bool InEnumOrder(const EnumName<Enum> (&names)[N]) {
  for (std::size_t i = 0; i < N; ++i) {
    if (static_cast<std::size_t>(names[i].value) != i) return false;
  }
  return true;
}
static_assert(InEnumOrder(kModeNames) && std::size(kModeNames) == static_cast<std::size_t>(Mode::kDamp) + 1);
static_assert(InEnumOrder(kTaskStateNames) &&
              std::size(kTaskStateNames) == static_cast<std::size_t>(TaskState::kTimeout) + 1);
static_assert(InEnumOrder(kReplyStatusNames) &&
              std::size(kReplyStatusNames) == static_cast<std::size_t>(ReplyStatus::kNoReply) + 1);

template <class Enum, std::size_t N>
const char* NameIn(const EnumName<Enum> (&names)[N], Enum value) {
  const auto i = static_cast<std::size_t>(value);
  return i < N ? names[i].name : "unknown";
}

}  // namespace

const char* Name(Mode mode) { return NameIn(kModeNames, mode); }
const char* Name(TaskState state) { return NameIn(kTaskStateNames, state); }
const char* Name(ReplyStatus status) { return NameIn(kReplyStatusNames, status); }

}  // namespace flsd
