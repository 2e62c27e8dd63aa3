#include "core/check.h"

#include <cstdio>
#include <cstdlib>

namespace flsd {

void AbortOnBrokenInvariant(const char* condition, const char* file, int line) {
  std::fprintf(stderr, "flsd: internal error: %s failed at %s:%d\n", condition, file, line);
  std::abort();
}

}  // namespace flsd
