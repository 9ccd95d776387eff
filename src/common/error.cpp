#include "moreau/common/error.h"

#include <cstdio>
#include <cstdlib>

namespace moreau::internal {

void AssertionFailed(const char* condition, const char* file, int line) {
  std::fprintf(stderr, "moreau: internal error (a bug, please report): %s at %s:%d\n", condition,
               file, line);
  std::abort();
}

}  // namespace moreau::internal
