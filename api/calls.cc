#include "api/calls.h"

#include <iterator>

namespace flsd {

constexpr bool SpecsInEnumOrder() {
  for (std::size_t i = 0; i < std::size(kCallSpecs); ++i) {
    if (static_cast<std::size_t>(kCallSpecs[i].call) != i) return false;
  }
  return std::size(kCallSpecs) == static_cast<std::size_t>(Call::kReset) + 1;
}
static_assert(SpecsInEnumOrder(), "kCallSpecs: one spec per call, in the order of the enum");

std::optional<Call> FindCall(std::string_view name) {
  for (const CallSpec& spec : kCallSpecs) {
    if (name == spec.name) return spec.call;
  }
  return std::nullopt;
}

std::string KnownCalls() {
  std::string text;
  for (const CallSpec& spec : kCallSpecs) text += (text.empty() ? "" : ", ") + std::string(spec.name);
  return text;
}

}  // namespace flsd
