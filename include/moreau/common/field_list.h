// One list of the fields of an options struct: key, member, default, range or choices, unit and
// a one-line help. Everything that names an option is made from it, so each rule is written once:
//
//   list.Validate(options)      every field's range, then the cross-field checks; throws
//                               InputError(key, reason) for the first value out of range;
//   list.ToJson(options)        the settings echo ({"newton": {"armijo": …}, …});
//   list.Set(options, key, v)   sets one field from a JSON value (the CLI's --set and scenario
//                               tables, Python's keyword arguments), checking type and range;
//   list.fields()               key, type, range, unit, help and default of every field (the
//                               `moreau keys` reference, Python's docstrings).
//
// An options type exposes its list as `static const FieldList<T>& Fields();` beside the struct.
// A field's member is reached through an accessor: a pointer to member (&Options::h) or a lambda
// `[](auto& s) -> auto& { return s.newton.armijo; }` (called with S& and const S&). Mount() reuses
// the list of a member struct under a prefix ("newton.armijo").
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "moreau/common/error.h"

namespace moreau {

// The allowed values of a numeric field.
struct Range {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_open = false;
  bool max_open = false;
  std::string why;  // added to the reason ("so that the time step T/N is positive")

  static Range Any() { return {}; }
  static Range Positive() { return {0.0, Range{}.max, true, false, ""}; }      // > 0
  static Range NonNegative() { return {0.0, Range{}.max, false, false, ""}; }  // ≥ 0
  static Range AtLeast(double a) { return {a, Range{}.max, false, false, ""}; }
  static Range Closed(double a, double b) { return {a, b, false, false, ""}; }   // [a, b]
  static Range Open(double a, double b) { return {a, b, true, true, ""}; }       // (a, b)
  static Range LeftOpen(double a, double b) { return {a, b, true, false, ""}; }  // (a, b]
  Range Because(std::string reason) const;

  bool Contains(double v) const;  // false for NaN
  std::string Describe() const;   // "> 0", "≥ 1", "in [3, 1000]", "" for Any()
  // "" when v is inside, else "must be > 0 (got -1)" (+ why); `got` is v as the user wrote it.
  std::string Violation(double v, std::string_view got) const;
};

// Sets j[a][b]… = value for the dotted key "a.b…".
void SetDotted(nlohmann::json& j, std::string_view key, nlohmann::json value);

// "" for a finite v inside `range`, else the reason ("must be a finite number", "must be > 0
// (got -1)").
std::string NumberViolation(const Range& range, double v);

// The one wording of a value of the wrong JSON type: "expected a number, got a string".
std::string ExpectedType(std::string_view what, const nlohmann::json& got);

template <class S>
class FieldList {
 public:
  struct Field {
    std::string key;
    std::string type;   // "number", "integer", "boolean", "string", "one of a, b", "numbers", …
    std::string range;  // Range::Describe(), or "" when any value of the type is allowed
    std::string unit;   // "s", "m", "frames", … or ""
    std::string help;
    // The member as JSON.
    std::function<nlohmann::json(const S&)> get;
    // Sets the member from JSON; the reason when the type or the value is wrong, else "".
    std::function<std::string(S&, const nlohmann::json&)> set;
    // The reason the member's current value is out of range, else "".
    std::function<std::string(const S&)> check;
  };
  struct Check {
    std::string key;                              // the key the reason is reported under
    std::function<std::string(const S&)> reason;  // "" when the settings are consistent
  };

  template <class A>
  FieldList& Number(std::string key, A ref, Range range, std::string unit, std::string help) {
    auto check = [ref, range](const S& s) { return NumberViolation(range, std::invoke(ref, s)); };
    return Add({std::move(key), "number", range.Describe(), std::move(unit), std::move(help),
                Getter(ref),
                [ref, range](S& s, const nlohmann::json& j) -> std::string {
                  if (!j.is_number()) return ExpectedType("a number", j);
                  const double v = j.get<double>();
                  std::string why = NumberViolation(range, v);
                  if (why.empty()) std::invoke(ref, s) = v;
                  return why;
                },
                check});
  }

  // Any integer type; the range is checked before the value is narrowed to the member's type.
  template <class A>
  FieldList& Integer(std::string key, A ref, Range range, std::string unit, std::string help) {
    using T = std::remove_cvref_t<std::invoke_result_t<A, S&>>;
    static_assert(std::is_integral_v<T>);
    const Range type_range = Range::Closed(static_cast<double>(std::numeric_limits<T>::min()),
                                           static_cast<double>(std::numeric_limits<T>::max()));
    return Add(
        {std::move(key), "integer", range.Describe(), std::move(unit), std::move(help), Getter(ref),
         [ref, range, type_range](S& s, const nlohmann::json& j) -> std::string {
           if (!j.is_number_integer()) return ExpectedType("an integer", j);
           const double v = j.is_number_unsigned() ? static_cast<double>(j.get<std::uint64_t>())
                                                   : static_cast<double>(j.get<std::int64_t>());
           std::string why = range.Violation(v, j.dump());
           if (why.empty()) why = type_range.Violation(v, j.dump());
           if (why.empty()) std::invoke(ref, s) = j.get<T>();
           return why;
         },
         [ref, range](const S& s) {
           const T v = std::invoke(ref, s);
           return range.Violation(static_cast<double>(v), fmt::format("{}", v));
         }});
  }

  template <class A>
  FieldList& Flag(std::string key, A ref, std::string help) {
    return Add({std::move(key), "boolean", "", "", std::move(help), Getter(ref),
                [ref](S& s, const nlohmann::json& j) -> std::string {
                  if (!j.is_boolean()) return ExpectedType("true or false", j);
                  std::invoke(ref, s) = j.get<bool>();
                  return "";
                },
                nullptr});
  }

  // A string; `allowed` non-empty: one of those.
  template <class A>
  FieldList& Text(std::string key, A ref, std::string help, std::vector<std::string> allowed = {}) {
    auto violation = [allowed](const std::string& v) {
      return allowed.empty() ? std::string() : OneOf(allowed, v);
    };
    return Add({std::move(key), allowed.empty() ? "string" : "one of " + Joined(allowed), "", "",
                std::move(help), Getter(ref),
                [ref, violation](S& s, const nlohmann::json& j) -> std::string {
                  if (!j.is_string()) return ExpectedType("a string", j);
                  std::string why = violation(j.get<std::string>());
                  if (why.empty()) std::invoke(ref, s) = j.get<std::string>();
                  return why;
                },
                [ref, violation](const S& s) { return violation(std::invoke(ref, s)); }});
  }

  // An enum written by name: `names` is the enum's name table (pairs of value and name).
  template <class A, class Names>
  FieldList& Choice(std::string key, A ref, const Names& names, std::string help) {
    const std::vector<std::string> allowed = NamesOf(names);
    return Add({std::move(key), "one of " + Joined(allowed), "", "", std::move(help),
                [ref, names](const S& s) { return NameOf(names, std::invoke(ref, s)); },
                [ref, names, allowed](S& s, const nlohmann::json& j) -> std::string {
                  if (!j.is_string()) return ExpectedType("a string", j);
                  if (!ValueOf(names, j.get<std::string>(), &std::invoke(ref, s))) {
                    return OneOf(allowed, j.get<std::string>());
                  }
                  return "";
                },
                nullptr});
  }

  // A list of numbers (TOML [0.1, 0.5]), each finite and inside `range`, at least `min_size`.
  template <class A>
  FieldList& Numbers(std::string key, A ref, Range range, std::size_t min_size, std::string unit,
                     std::string help) {
    auto violation = [range, min_size](const std::vector<double>& v) -> std::string {
      if (v.size() < min_size) return fmt::format("needs at least {} entries", min_size);
      for (double x : v) {
        std::string why = NumberViolation(range, x);
        if (!why.empty()) return why;
      }
      return "";
    };
    return Add({std::move(key), "numbers", range.Describe(), std::move(unit), std::move(help),
                Getter(ref),
                [ref, violation](S& s, const nlohmann::json& j) -> std::string {
                  if (!j.is_array()) return ExpectedType("an array of numbers", j);
                  std::vector<double> v;
                  for (const nlohmann::json& item : j) {
                    if (!item.is_number()) return ExpectedType("an array of numbers", j);
                    v.push_back(item.get<double>());
                  }
                  std::string why = violation(v);
                  if (why.empty()) std::invoke(ref, s) = std::move(v);
                  return why;
                },
                [ref, violation](const S& s) { return violation(std::invoke(ref, s)); }});
  }

  // A list of enum values written by name (TOML ["rigid", "pca"]), at least `min_size` of them.
  template <class A, class Names>
  FieldList& Choices(std::string key, A ref, const Names& names, std::size_t min_size,
                     std::string help) {
    using Enum = typename std::remove_cvref_t<std::invoke_result_t<A, S&>>::value_type;
    const std::vector<std::string> allowed = NamesOf(names);
    auto too_few = [min_size](std::size_t size) {
      return size < min_size ? fmt::format("needs at least {} entries", min_size) : std::string();
    };
    return Add({std::move(key), "names, each one of " + Joined(allowed), "", "", std::move(help),
                [ref, names](const S& s) {
                  nlohmann::json j = nlohmann::json::array();
                  for (Enum v : std::invoke(ref, s)) j.push_back(NameOf(names, v));
                  return j;
                },
                [ref, names, allowed, too_few](S& s, const nlohmann::json& j) -> std::string {
                  if (!j.is_array()) return ExpectedType("an array of names", j);
                  std::vector<Enum> v;
                  for (const nlohmann::json& item : j) {
                    if (!item.is_string()) return ExpectedType("an array of names", j);
                    if (!ValueOf(names, item.get<std::string>(), &v.emplace_back())) {
                      return OneOf(allowed, item.get<std::string>());
                    }
                  }
                  std::string why = too_few(v.size());
                  if (why.empty()) std::invoke(ref, s) = std::move(v);
                  return why;
                },
                [ref, too_few](const S& s) { return too_few(std::invoke(ref, s).size()); }});
  }

  // A field with its get, set and check written out (one key over several members, a fixed number
  // of numbers); `check` may be empty.
  FieldList& Custom(Field field) { return Add(std::move(field)); }

  // A rule over several fields, run by Validate() after the fields' own ranges.
  FieldList& Rule(std::string key, std::function<std::string(const S&)> reason) {
    checks_.push_back({std::move(key), std::move(reason)});
    return *this;
  }

  // Every field and rule of `sub` (the list of the member struct ref(s)) under "prefix." (an
  // empty prefix keeps sub's keys).
  template <class T, class A>
  FieldList& Mount(const std::string& prefix, A ref, const FieldList<T>& sub) {
    const auto under = [&prefix](const std::string& key) {
      return prefix.empty() ? key : prefix + "." + key;
    };
    for (const typename FieldList<T>::Field& f : sub.fields()) {
      Field g{
          under(f.key),
          f.type,
          f.range,
          f.unit,
          f.help,
          [ref, get = f.get](const S& s) { return get(std::invoke(ref, s)); },
          [ref, set = f.set](S& s, const nlohmann::json& j) { return set(std::invoke(ref, s), j); },
          nullptr};
      if (f.check) {
        g.check = [ref, check = f.check](const S& s) { return check(std::invoke(ref, s)); };
      }
      Add(std::move(g));
    }
    for (const typename FieldList<T>::Check& c : sub.checks()) {
      Rule(under(c.key),
           [ref, reason = c.reason](const S& s) { return reason(std::invoke(ref, s)); });
    }
    return *this;
  }

  // Throws InputError(key, reason) for the first field out of range, then the first rule broken.
  void Validate(const S& s) const {
    for (const Field& f : fields_) {
      if (!f.check) continue;
      std::string why = f.check(s);
      if (!why.empty()) throw InputError(f.key, std::move(why));
    }
    for (const Check& c : checks_) {
      std::string why = c.reason(s);
      if (!why.empty()) throw InputError(c.key, std::move(why));
    }
  }

  nlohmann::json ToJson(const S& s) const {
    nlohmann::json j = nlohmann::json::object();
    for (const Field& f : fields_) SetDotted(j, f.key, f.get(s));
    return j;
  }

  // The field named `key`, or nullptr.
  const Field* Find(std::string_view key) const {
    for (const Field& f : fields_) {
      if (f.key == key) return &f;
    }
    return nullptr;
  }

  // Sets the field `key` from `value`; InputError(key, reason) for an unknown key, a wrong type
  // or a value out of range (the member is left unchanged then).
  void Set(S& s, std::string_view key, const nlohmann::json& value) const {
    const Field* f = Find(key);
    if (f == nullptr) throw InputError(std::string(key), "unknown key");
    std::string why = f->set(s, value);
    if (!why.empty()) throw InputError(std::string(key), std::move(why));
  }

  const std::vector<Field>& fields() const { return fields_; }
  const std::vector<Check>& checks() const { return checks_; }

 private:
  FieldList& Add(Field field) {
    fields_.push_back(std::move(field));
    return *this;
  }

  template <class A>
  static std::function<nlohmann::json(const S&)> Getter(A ref) {
    return [ref](const S& s) { return nlohmann::json(std::invoke(ref, s)); };
  }

  // The names of a name table, in its order.
  template <class Names>
  static std::vector<std::string> NamesOf(const Names& names) {
    std::vector<std::string> out;
    for (const auto& entry : names) out.emplace_back(entry.second);
    return out;
  }

  // The name of `value` in the table (null JSON when it has none).
  template <class Names, class Enum>
  static nlohmann::json NameOf(const Names& names, Enum value) {
    for (const auto& entry : names) {
      if (entry.first == value) return nlohmann::json(entry.second);
    }
    return nlohmann::json();
  }

  // Sets *value to the table's value named `name`; false when no entry has that name.
  template <class Names, class Enum>
  static bool ValueOf(const Names& names, const std::string& name, Enum* value) {
    for (const auto& entry : names) {
      if (entry.second == name) {
        *value = entry.first;
        return true;
      }
    }
    return false;
  }

  static std::string Joined(const std::vector<std::string>& items) {
    std::string out;
    for (const std::string& item : items) {
      out += (out.empty() ? "" : ", ") + (item.empty() ? std::string("\"\"") : item);
    }
    return out;
  }

  static std::string OneOf(const std::vector<std::string>& allowed, const std::string& v) {
    for (const std::string& a : allowed) {
      if (a == v) return "";
    }
    return fmt::format("must be one of {} (got \"{}\")", Joined(allowed), v);
  }

  std::vector<Field> fields_;
  std::vector<Check> checks_;
};

}  // namespace moreau
