// Error types shared by the library and the command-line tool.
//
// InputError:     the user gave bad input (a scenario value, a file, an option). The message names
//                 what was wrong; the CLI prints it on one line and exits with code 2.
// NumericalError: a computation failed (divergence, NaN). The message says where it happened.
// MOREAU_ASSERT:  an always-on internal check; failing it is a bug in moreau, not bad input.
#pragma once

#include <stdexcept>
#include <string>

namespace moreau {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class NumericalError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

namespace internal {
[[noreturn]] void AssertionFailed(const char* condition, const char* file, int line);
}  // namespace internal

}  // namespace moreau

#define MOREAU_ASSERT(condition)                                              \
  do {                                                                        \
    if (!(condition)) {                                                       \
      ::moreau::internal::AssertionFailed(#condition, __FILE__, __LINE__);    \
    }                                                                         \
  } while (false)
