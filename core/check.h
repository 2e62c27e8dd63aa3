#pragma once
// Two error channels (see STYLE.md, lesson 4):
// - FLSD_DEMAND(cond): a broken internal invariant, i.e. a bug. Aborts with the condition's text.
// - flsd::InputError: bad user input (files, configs, requests). Thrown inside a layer and turned
//   into a message at its edge; the message names what was wrong and what was expected.

#include <stdexcept>
#include <string>

namespace flsd {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

[[noreturn]] void AbortOnBrokenInvariant(const char* condition, const char* file, int line);

}  // namespace flsd

#define FLSD_DEMAND(condition)                                                   \
  do {                                                                           \
    if (!(condition)) ::flsd::AbortOnBrokenInvariant(#condition, __FILE__, __LINE__); \
  } while (false)
