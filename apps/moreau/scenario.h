// A scenario file (TOML) with command-line overrides, read with typed getters.
//
// Every getter names the key in dotted form ("problem.radius"). Booleans must be true or false
// (an integer is not taken as a boolean). A missing required key, a value of
// the wrong type or a value out of range throws moreau::InputError with the message
// "FILE: KEY: REASON". After reading, CheckAllKeysUsed() rejects keys nobody asked for, so a typo
// in a scenario is an error rather than a silently ignored setting.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

#include "moreau/common/error.h"

namespace moreau::cli {

// An InputError that names its file and key already ("FILE: KEY: REASON").
class ScenarioError : public InputError {
 public:
  using InputError::InputError;
};

class Scenario {
 public:
  // The deepest table or key path a scenario file may hold (`[a.b.c]`, `a.b.c = 1`, inline
  // tables included); the scenarios of moreau nest 4 levels at most.
  static constexpr std::size_t kMaxKeyDepth = 64;

  // Reads PATH and applies OVERRIDES ("key=value", the value parsed as a TOML value, or taken as
  // a string when it is not one). Throws InputError when the file cannot be read (not a regular
  // file: a FIFO, a device), nests deeper than kMaxKeyDepth or cannot be parsed.
  static Scenario Load(const std::string& path, const std::vector<std::string>& overrides);
  // The overrides alone, for commands whose scenario file is optional; messages name
  // "command line" where they would name the file.
  static Scenario FromCommandLine(const std::vector<std::string>& overrides);

  const std::string& path() const { return path_; }
  bool Has(std::string_view key) const;

  double GetDouble(std::string_view key, double fallback);
  double RequireDouble(std::string_view key);
  std::int64_t GetInt(std::string_view key, std::int64_t fallback);
  std::int64_t RequireInt(std::string_view key);
  bool GetBool(std::string_view key, bool fallback);
  std::string GetString(std::string_view key, const std::string& fallback);
  std::string RequireString(std::string_view key);
  std::vector<double> GetDoubleArray(std::string_view key, const std::vector<double>& fallback);
  std::optional<double> GetOptionalDouble(std::string_view key);

  // The raw node (for structured values such as arrays of tables); marks KEY and everything
  // below it as used. Returns nullptr when absent.
  const toml::node* GetNode(std::string_view key);

  // Throws InputError "FILE: KEY: REASON".
  [[noreturn]] void Fail(std::string_view key, std::string_view reason) const;
  // Prints "moreau: warning: FILE: KEY: TEXT" on stderr (the run goes on).
  void Warn(std::string_view key, std::string_view text) const;

  // Fails "FILE: AT.NAME: unknown key (did you mean …?)" for the first key of TABLE (one entry of
  // an array of tables such as [[walls]], named AT = "walls[0]") that is not in KNOWN.
  void CheckTableKeys(std::string_view at, const toml::table& table,
                      std::initializer_list<std::string_view> known) const;

  // Range checks that throw through Fail().
  double RequirePositive(std::string_view key, double value) const;
  std::int64_t RequirePositive(std::string_view key, std::int64_t value) const;

  // Throws InputError for the first key present in the file (or set by an override) that no
  // getter asked for.
  void CheckAllKeysUsed() const;

 private:
  const toml::node* Find(std::string_view key) const;
  void MarkUsed(std::string_view key);
  void ApplyOverrides(const std::vector<std::string>& overrides);

  std::string path_;
  toml::table table_;
  std::set<std::string, std::less<>> used_;
};

}  // namespace moreau::cli
