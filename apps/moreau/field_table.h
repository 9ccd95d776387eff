// A command's scenario fields in one list: key, type, range, help and the member each fills.
//
// The table drives everything a scenario file needs, so each field is named once:
//   Read(scenario, settings)  reads every field present into its member (absent fields keep the
//                             member's value: the default of the settings struct), checks the
//                             type and the range, then runs the cross-field checks; errors are
//                             InputError "FILE: KEY: REASON";
//   Echo(settings)            the JSON of the settings used ({"solver": {"h": …}, …});
//   Rows(settings)            one row per field: key, type, default, range, unit, help.
// A field's member is reached through an accessor: a pointer to member (&Options::h) or a generic
// lambda `[](auto& s) -> auto& { return s.newton.armijo; }` (called with S& to read, const S& to
// echo). Mount() takes a library options struct's field list (field_list.h) under a prefix, so
// its ranges, help and checks are the library's, or reuses another table of the command's.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "moreau/common/error.h"
#include "moreau/common/field_list.h"
#include "moreau/common/memory.h"
#include "scenario.h"

namespace moreau::cli {

using moreau::Range;

// Throws through scenario.Fail ("must be > 0 (got -1)" + why) when v is outside `range`.
void CheckRange(const Scenario& scenario, std::string_view key, const Range& range, double v,
                std::string_view got);

// A scenario value as JSON (number, integer, boolean, string, array); marks the key used.
nlohmann::json NodeToJson(const toml::node& node);

// The most trajectory frames one run may write (docs/reliability.md, "Limits and validation").
inline constexpr std::int64_t kMaxFrames = 1'000'000;

// The frames of a run of `steps` steps that writes one every `stride` steps (and the last one).
// Throws InputError "N frames (STEPS steps, one every STRIDE) is more than the 1000000 allowed"
// above kMaxFrames.
std::int64_t CheckFrameCount(std::int64_t steps, std::int64_t stride);

// Runs `work`; a std::bad_alloc it throws is re-thrown as OutOfMemoryError "FILE: KEY: out of
// memory while reading this key".
void NamingAllocations(const Scenario& scenario, std::string_view key,
                       const std::function<void()>& work);
// Runs `check`; an InputError it throws is re-thrown as "FILE: KEY: REASON", KEY being `key`
// followed by the error's own key when it names one ("solver" + "h": "solver.h").
void WithKey(const Scenario& scenario, std::string_view key, const std::function<void()>& check);

// A key of a command's reference (`moreau keys`).
struct KeyRow {
  std::string key, type, default_value, range, unit, help;
};

// The rows of a library list under "prefix." (defaults of a default-constructed T).
template <class T>
std::vector<KeyRow> ListRows(const moreau::FieldList<T>& list, const std::string& prefix) {
  std::vector<KeyRow> rows;
  const T defaults{};
  for (const auto& f : list.fields()) {
    rows.push_back({prefix + "." + f.key, f.type, f.get(defaults).dump(), f.range, f.unit, f.help});
  }
  return rows;
}

template <class S>
class FieldTable {
 public:
  struct Field {
    std::string key;
    std::string type;  // "number", "integer", "boolean", "string", "one of …", …
    std::string range;
    std::string help;
    bool required = false;
    std::function<void(Scenario&, S&, const std::string& key)> read;
    std::function<nlohmann::json(const S&)> echo;  // null json: not echoed
    // Fields mounted from a library list: sets the member from JSON ("" or the reason).
    std::function<std::string(S&, const nlohmann::json&)> set = nullptr;
    std::string unit = "";
  };

  // Where a library list's key lands in the scenario: under `prefix`, except a key that one of
  // `moved`'s entries names, or that lies below it, which goes to the scenario key it maps to
  // (the control command's [newton] and [fixed_point] tables hold ContinuationOptions' newton.*
  // and fixed_point.*); mapped to "", the key is not mounted (the command sets that member from
  // another key, e.g. the engine's seed from problem.seed).
  using Moved = std::vector<std::pair<std::string, std::string>>;
  static std::string Rekey(const std::string& prefix, const Moved& moved, const std::string& key) {
    for (const auto& [from, to] : moved) {
      if (key == from) return to;
      if (key.starts_with(from + ".") && !to.empty()) return to + key.substr(from.size());
    }
    return Prefixed(prefix, key);
  }

  template <class A>
  FieldTable& Number(std::string key, A ref, Range range, std::string help) {
    return Add({std::move(key), "number", range.Describe(), std::move(help), false,
                [ref, range](Scenario& sc, S& s, const std::string& k) {
                  double& v = std::invoke(ref, s);
                  v = sc.GetDouble(k, v);
                  CheckRange(sc, k, range, v, fmt::format("{}", v));
                },
                Echoer(ref)});
  }

  // An optional number: absent leaves the member empty (and unechoed).
  template <class A>
  FieldTable& OptionalNumber(std::string key, A ref, Range range, std::string help) {
    return Add({std::move(key), "number (optional)", range.Describe(), std::move(help), false,
                [ref, range](Scenario& sc, S& s, const std::string& k) {
                  std::optional<double>& v = std::invoke(ref, s);
                  if (sc.Has(k)) {
                    v = sc.GetDouble(k, 0.0);
                    CheckRange(sc, k, range, *v, fmt::format("{}", *v));
                  } else {
                    (void)sc.GetNode(k);  // known key, absent
                  }
                },
                [ref](const S& s) {
                  const std::optional<double>& v = std::invoke(ref, s);
                  return v ? nlohmann::json(*v) : nlohmann::json();
                }});
  }

  // Any integer type; the range is checked before the value is narrowed to T.
  template <class A>
  FieldTable& Integer(std::string key, A ref, Range range, std::string help) {
    using T = std::remove_reference_t<std::invoke_result_t<A, S&>>;
    static_assert(std::is_integral_v<T>);
    const Range type_range = Range::Closed(static_cast<double>(std::numeric_limits<T>::min()),
                                           static_cast<double>(std::numeric_limits<T>::max()));
    return Add({std::move(key), "integer", range.Describe(), std::move(help), false,
                [ref, range, type_range](Scenario& sc, S& s, const std::string& k) {
                  T& v = std::invoke(ref, s);
                  const std::int64_t read = sc.GetInt(k, static_cast<std::int64_t>(v));
                  const std::string got = fmt::format("{}", read);
                  CheckRange(sc, k, range, static_cast<double>(read), got);
                  CheckRange(sc, k, type_range, static_cast<double>(read), got);
                  v = static_cast<T>(read);
                },
                Echoer(ref)});
  }

  template <class A>
  FieldTable& Flag(std::string key, A ref, std::string help) {
    return Add({std::move(key), "boolean", "", std::move(help), false,
                [ref](Scenario& sc, S& s, const std::string& k) {
                  bool& v = std::invoke(ref, s);
                  v = sc.GetBool(k, v);
                },
                Echoer(ref)});
  }

  template <class A>
  FieldTable& Text(std::string key, A ref, std::string help) {
    return Add({std::move(key), "string", "", std::move(help), false,
                [ref](Scenario& sc, S& s, const std::string& k) {
                  std::string& v = std::invoke(ref, s);
                  v = sc.GetString(k, v);
                },
                Echoer(ref)});
  }

  // An enum written by name: parse(name) throws InputError for an unknown name.
  template <class A, class Parse, class Name>
  FieldTable& Choice(std::string key, A ref, Parse parse, Name name, std::string choices,
                     std::string help) {
    return Add({std::move(key), "one of " + choices, "", std::move(help), false,
                [ref, parse, name](Scenario& sc, S& s, const std::string& k) {
                  auto& v = std::invoke(ref, s);
                  const std::string text = sc.GetString(k, std::string(name(v)));
                  WithKey(sc, k, [&] { v = parse(text); });
                },
                [ref, name](const S& s) {
                  return nlohmann::json(std::string(name(std::invoke(ref, s))));
                }});
  }

  // A fixed number of numbers (std::array<double, N>).
  template <class A>
  FieldTable& Numbers(std::string key, A ref, std::string help) {
    constexpr std::size_t N = std::tuple_size_v<std::remove_cvref_t<std::invoke_result_t<A, S&>>>;
    return Add({std::move(key), fmt::format("{} numbers", N), "", std::move(help), false,
                [ref](Scenario& sc, S& s, const std::string& k) {
                  auto& v = std::invoke(ref, s);
                  const std::vector<double> read = sc.GetDoubleArray(k, {v.begin(), v.end()});
                  if (read.size() != v.size()) {
                    sc.Fail(k, fmt::format("expected {} numbers", v.size()));
                  }
                  std::copy(read.begin(), read.end(), v.begin());
                },
                Echoer(ref)});
  }

  // A structured value read by hand (arrays of tables, matrices); `echo` may be empty or return
  // null (not echoed).
  FieldTable& Custom(std::string key, std::string type,
                     std::function<void(Scenario&, S&, const std::string& key)> read,
                     std::function<nlohmann::json(const S&)> echo, std::string help) {
    return Add({std::move(key), std::move(type), "", std::move(help), false, std::move(read),
                std::move(echo)});
  }

  // Marks the field added last as required: absent, Read fails "required key is missing".
  FieldTable& Required() {
    fields_.back().required = true;
    return *this;
  }

  // A check over several fields, run after every field is read; its InputError names `key`.
  FieldTable& Check(std::string key, std::function<void(const S&)> check) {
    checks_.emplace_back(std::move(key), std::move(check));
    return *this;
  }

  // Every field and check of `sub` (a table of the struct ref(s)) under "prefix." (an empty
  // prefix keeps the sub-table's keys).
  template <class T, class A>
  FieldTable& Mount(const std::string& prefix, A ref, const FieldTable<T>& sub) {
    for (const typename FieldTable<T>::Field& f : sub.fields()) {
      Add({Prefixed(prefix, f.key), f.type, f.range, f.help, f.required,
           [ref, read = f.read](Scenario& sc, S& s, const std::string& k) {
             read(sc, std::invoke(ref, s), k);
           },
           f.echo ? std::function<nlohmann::json(const S&)>(
                        [ref, echo = f.echo](const S& s) { return echo(std::invoke(ref, s)); })
                  : nullptr,
           f.set ? std::function<std::string(S&, const nlohmann::json&)>(
                       [ref, set = f.set](S& s, const nlohmann::json& j) {
                         return set(std::invoke(ref, s), j);
                       })
                 : nullptr,
           f.unit});
    }
    for (const auto& item : sub.checks()) {  // no structured binding: clang 14 cannot capture one
      checks_.emplace_back(Prefixed(prefix, item.first),
                           [ref, check = item.second](const S& s) { check(std::invoke(ref, s)); });
    }
    return *this;
  }

  // Every field of the library's list of the options struct ref(s) under "prefix." (an empty
  // prefix keeps the list's keys): read from the scenario, checked and echoed by the list, so the
  // CLI states no rule of its own; then the list's Validate() as this table's check.
  template <class T, class A>
  FieldTable& Mount(const std::string& prefix, A ref, const moreau::FieldList<T>& list,
                    Moved moved = {}) {
    for (const typename moreau::FieldList<T>::Field& f : list.fields()) {
      auto set = [ref, set = f.set](S& s, const nlohmann::json& j) {
        return set(std::invoke(ref, s), j);
      };
      const std::string key = Rekey(prefix, moved, f.key);
      if (key.empty()) continue;
      Add({key, f.type, f.range, f.help, false,
           [set](Scenario& sc, S& s, const std::string& k) {
             const toml::node* node = sc.GetNode(k);
             if (node == nullptr) return;
             const std::string why = set(s, NodeToJson(*node));
             if (!why.empty()) sc.Fail(k, why);
           },
           [ref, get = f.get](const S& s) { return get(std::invoke(ref, s)); }, set, f.unit});
    }
    // The list's Validate() names its own key; report it under the scenario's key.
    checks_.emplace_back("", [ref, &list, prefix, moved](const S& s) {
      try {
        list.Validate(std::invoke(ref, s));
      } catch (const InputError& e) {
        throw InputError(Rekey(prefix, moved, e.key()), e.reason());
      }
    });
    return *this;
  }

  // Marks the field `key` as required: absent, Read fails "required key is missing".
  FieldTable& Require(const std::string& key) {
    for (Field& f : fields_) {
      if (f.key == key) f.required = true;
    }
    return *this;
  }

  // The mounted thread count `key` (≥ 0, 0: automatic) is capped to the machine's hardware
  // threads, with a warning line on stderr (oversubscribed threads only wait for each other).
  FieldTable& CapThreads(const std::string& key) {
    for (Field& f : fields_) {
      if (f.key != key) continue;
      MOREAU_ASSERT(f.set != nullptr);
      f.read = [read = f.read, echo = f.echo, set = f.set](Scenario& sc, S& s,
                                                           const std::string& k) {
        read(sc, s, k);
        const auto hardware = static_cast<std::int64_t>(std::thread::hardware_concurrency());
        const auto v = echo(s).template get<std::int64_t>();
        if (hardware > 0 && v > hardware) {
          sc.Warn(k, fmt::format("{} threads is more than the {} hardware threads; using {}", v,
                                 hardware, hardware));
          (void)set(s, hardware);
        }
      };
      return *this;
    }
    MOREAU_ASSERT(false);  // no such key
  }

  // A std::bad_alloc while reading or checking a key becomes OutOfMemoryError naming the key.
  void Read(Scenario& scenario, S& settings) const {
    for (const Field& f : fields_) {
      if (f.required && !scenario.Has(f.key)) scenario.Fail(f.key, "required key is missing");
      NamingAllocations(scenario, f.key, [&] { f.read(scenario, settings, f.key); });
    }
    for (const auto& entry : checks_) {  // no structured binding: clang 14 cannot capture one
      const std::string& key = entry.first;
      NamingAllocations(scenario, key,
                        [&] { WithKey(scenario, key, [&] { entry.second(settings); }); });
    }
  }

  nlohmann::json Echo(const S& settings) const {
    nlohmann::json j = nlohmann::json::object();
    for (const Field& f : fields_) {
      if (!f.echo) continue;
      nlohmann::json value = f.echo(settings);
      if (!value.is_null()) SetDotted(j, f.key, std::move(value));
    }
    return j;
  }

  // One row per field (the defaults are those of `defaults`): the key reference.
  std::vector<KeyRow> Rows(const S& defaults) const {
    std::vector<KeyRow> rows;
    for (const Field& f : fields_) {
      const nlohmann::json value = f.echo ? f.echo(defaults) : nlohmann::json();
      rows.push_back({f.key, f.type,
                      f.required        ? "(required)"
                      : value.is_null() ? "-"
                                        : value.dump(),
                      f.range, f.unit, f.help});
    }
    return rows;
  }

  const std::vector<Field>& fields() const { return fields_; }
  const std::vector<std::pair<std::string, std::function<void(const S&)>>>& checks() const {
    return checks_;
  }

 private:
  static std::string Prefixed(const std::string& prefix, const std::string& key) {
    return prefix.empty() ? key : prefix + "." + key;
  }

  FieldTable& Add(Field field) {
    fields_.push_back(std::move(field));
    return *this;
  }

  template <class A>
  static std::function<nlohmann::json(const S&)> Echoer(A ref) {
    return [ref](const S& s) { return nlohmann::json(std::invoke(ref, s)); };
  }

  std::vector<Field> fields_;
  std::vector<std::pair<std::string, std::function<void(const S&)>>> checks_;
};

}  // namespace moreau::cli
