// Error types shared by the library and the command-line tool.
//
// InputError:     the user gave bad input (a scenario value, a file, an option). It carries the
//                 option's key (when one is to blame) and the reason as fields; the CLI prints
//                 it on one line and exits with code 2.
// NumericalError: a computation failed (divergence, NaN). The message says where it happened.
// MOREAU_ASSERT:  an always-on internal check; failing it is a bug in moreau, not bad input.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>

namespace moreau {

class InputError : public std::runtime_error {
 public:
  // A reason that names no key (a file, a combination of inputs).
  explicit InputError(const std::string& reason) : std::runtime_error(reason), reason_(reason) {}
  // A value of the option `key` (dotted, relative to the options struct that checked it) is
  // wrong; what() is "KEY: REASON".
  InputError(std::string key, std::string reason)
      : std::runtime_error(key + ": " + reason), key_(std::move(key)), reason_(std::move(reason)) {}

  const std::string& key() const { return key_; }        // "" when the error names no key
  const std::string& reason() const { return reason_; }  // what() without the key

  // The same error with its key under `prefix` ("newton" + "armijo": "newton.armijo"); an error
  // that names no key is returned as it is.
  InputError Under(const std::string& prefix) const {
    return key_.empty() ? *this : InputError(prefix + "." + key_, reason_);
  }

 private:
  std::string key_;
  std::string reason_;
};

class NumericalError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

namespace internal {
[[noreturn]] void AssertionFailed(const char* condition, const char* file, int line);
}  // namespace internal

}  // namespace moreau

#define MOREAU_ASSERT(condition)                                           \
  do {                                                                     \
    if (!(condition)) {                                                    \
      ::moreau::internal::AssertionFailed(#condition, __FILE__, __LINE__); \
    }                                                                      \
  } while (false)
