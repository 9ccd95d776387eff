#include "scenario.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <new>
#include <system_error>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/common/input_file.h"
#include "moreau/common/memory.h"

namespace moreau::cli {
namespace {

std::vector<std::string> SplitKey(std::string_view key) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = key.find('.', start);
    parts.emplace_back(key.substr(start, dot == std::string_view::npos ? dot : dot - start));
    if (dot == std::string_view::npos) break;
    start = dot + 1;
  }
  return parts;
}

// Parses the right-hand side of "key=value" as a TOML value, or keeps it as a string.
toml::table ParseOverrideValue(const std::string& value) {
  try {
    return toml::parse("v = " + value);
  } catch (const toml::parse_error&) {
    toml::table t;
    t.insert("v", value);
    return t;
  }
}

// The table of `entries` whose key "name" is `name`, or nullptr.
toml::node* NamedEntry(toml::array& entries, std::string_view name) {
  for (toml::node& entry : entries) {
    const toml::table* t = entry.as_table();
    if (t != nullptr && t->get("name") != nullptr && t->get("name")->value<std::string>() == name) {
      return &entry;
    }
  }
  return nullptr;
}

const char* TypeName(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a number";
    case toml::node_type::boolean:
      return "a boolean";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::table:
      return "a table";
    default:
      return "a date or time";
  }
}

// The keys of values, and of empty tables with a "." appended ("bogus." for `[bogus]`).
void CollectLeafKeys(const toml::table& table, const std::string& prefix,
                     std::vector<std::string>* keys) {
  for (const auto& [k, node] : table) {
    const std::string full =
        prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
    if (const toml::table* sub = node.as_table(); sub != nullptr && !sub->empty()) {
      CollectLeafKeys(*sub, full, keys);
    } else if (node.is_table()) {
      keys->push_back(full + ".");
    } else {
      keys->push_back(full);
    }
  }
}

// The number of single-character edits (insert, delete, replace) that turn a into b.
std::size_t EditDistance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// " (did you mean X?)" for the closest candidate within two edits, else "".
template <class Range>
std::string Suggestion(std::string_view key, const Range& candidates) {
  std::string best;
  std::size_t best_distance = 3;
  for (const auto& candidate : candidates) {
    const std::size_t d = EditDistance(key, candidate);
    if (d < best_distance) {
      best_distance = d;
      best = std::string(candidate);
    }
  }
  return best.empty() ? "" : fmt::format(" (did you mean {}?)", best);
}


// The deepest key path of a TOML text: the parts of a table header or of a dotted key (dots
// outside quotes), under the last header, plus the inline tables and arrays around the key.
// It counts only what can nest and parses no value, so it never underestimates. toml++ builds
// and frees such a path by recursion, so a path thousands of parts deep would overflow the stack;
// nested inline values are bounded by toml++ itself (TOML_MAX_NESTED_VALUES).
std::size_t KeyDepth(std::string_view text) {
  std::size_t deepest = 0;
  std::size_t header = 0;      // parts of the last table header
  std::size_t line_key = 0;    // parts of the key of this line's key = value
  std::size_t parts = 1;       // parts of the key being read
  bool key = true;             // reading a key (else a value or a header)
  bool in_header = false;
  bool line_start = true;
  std::vector<char> open;      // the inline tables and arrays around the position
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') {
      line_start = open.empty();
      if (line_start) key = true, parts = 1, line_key = 0, in_header = false;
      continue;
    }
    if (c == ' ' || c == '\t' || c == '\r') continue;
    if (c == '#') {
      while (i + 1 < text.size() && text[i + 1] != '\n') ++i;
      continue;
    }
    if (c == '"' || c == '\'') {  // a string or quoted key: skipped to its end
      const bool triple = text.substr(i, 3) == std::string(3, c);
      const std::string_view close = triple ? text.substr(i, 3) : text.substr(i, 1);
      std::size_t j = i + close.size();
      while (j < text.size() && text.substr(j, close.size()) != close) j += (c == '"' && text[j] == '\\') ? 2 : 1;
      i = std::min(text.size(), j + close.size()) - 1;
      line_start = false;
      continue;
    }
    if (line_start && c == '[') {
      in_header = true, key = false, header = 1;
    } else if (in_header) {
      if (c == '.') deepest = std::max(deepest, ++header);
      if (c == ']') in_header = false;
    } else if (key && c == '.') {
      deepest = std::max(deepest, header + line_key + open.size() + ++parts);
    } else if (key && c == '=') {
      key = false;
      if (open.empty()) line_key = parts;
    } else if (!key && (c == '{' || c == '[')) {
      open.push_back(c);
      if (c == '{') key = true, parts = 1;
    } else if (!key && (c == '}' || c == ']') && !open.empty()) {
      open.pop_back();
    } else if (!key && c == ',' && !open.empty() && open.back() == '{') {
      key = true, parts = 1;
    }
    line_start = false;
  }
  return deepest;
}

}  // namespace

Scenario Scenario::Load(const std::string& path, const std::vector<std::string>& overrides) {
  Scenario s;
  s.path_ = path;
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw InputError(fmt::format("{}: is a directory, not a scenario file", path));
  }
  const std::string text = ReadInputFile(path);  // a regular file only: not a FIFO, not /dev/zero
  // toml++ can end the process when an allocation fails inside it (a bad_alloc through a noexcept
  // function), so a file whose parsed tree clearly cannot fit is refused before parsing.
  constexpr double kParsedBytesPerFileByte = 32.0;  // measured: ≈ 30 for arrays of positions
  const MemoryLimit limit = AvailableMemory();
  const double need = kParsedBytesPerFileByte * static_cast<double>(text.size());
  if (limit.bytes > 0 && need > static_cast<double>(limit.bytes)) {
    throw OutOfMemoryError(fmt::format(
        "{}: out of memory while reading the file (about {} as parsed TOML, {} available: {})",
        path, FormatBytes(need), FormatBytes(static_cast<double>(limit.bytes)), limit.source));
  }
  if (const std::size_t depth = KeyDepth(text); depth > kMaxKeyDepth) {
    throw InputError(fmt::format("{}: tables nest {} levels deep, more than the {} accepted", path,
                                 depth, kMaxKeyDepth));
  }
  try {
    s.table_ = toml::parse(text, path);
  } catch (const std::bad_alloc&) {
    throw OutOfMemoryError(fmt::format("{}: out of memory while reading the file", path));
  } catch (const toml::parse_error& e) {
    const auto& where = e.source().begin;
    if (where.line == 0) {
      throw InputError(fmt::format("{}: cannot read the file ({})", path, e.description()));
    }
    throw InputError(
        fmt::format("{}: line {}, column {}: {}", path, where.line, where.column, e.description()));
  }
  s.ApplyOverrides(overrides);
  return s;
}

Scenario Scenario::FromCommandLine(const std::vector<std::string>& overrides) {
  Scenario s;
  s.path_ = "command line";
  s.ApplyOverrides(overrides);
  return s;
}

void Scenario::ApplyOverrides(const std::vector<std::string>& overrides) {
  for (const std::string& item : overrides) {
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos || eq == 0) {
      throw InputError(fmt::format("--set {}: expected key=value", item));
    }
    const std::string key = item.substr(0, eq);
    const std::vector<std::string> parts = SplitKey(key);
    toml::table* table = &table_;
    for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
      toml::node* child = table->get(parts[i]);
      if (child == nullptr) {
        table->insert(parts[i], toml::table{});
        child = table->get(parts[i]);
      }
      if (toml::array* entries = child->as_array(); entries != nullptr && i + 2 < parts.size()) {
        // An array of tables named by their `name` key ([[types]]): types.cell.radius.
        child = NamedEntry(*entries, parts[i + 1]);
        if (child == nullptr) {
          throw InputError(fmt::format("--set {}: no [[{}]] entry has name = \"{}\"", item,
                                       parts[i], parts[i + 1]));
        }
        ++i;
      }
      table = child->as_table();
      if (table == nullptr) {
        throw InputError(fmt::format("--set {}: {} is not a table", item, parts[i]));
      }
    }
    toml::table parsed = ParseOverrideValue(item.substr(eq + 1));
    table->insert_or_assign(parts.back(), std::move(*parsed.get("v")));
  }
}

const toml::node* Scenario::Find(std::string_view key) const {
  const toml::node* node = &table_;
  for (const std::string& part : SplitKey(key)) {
    const toml::table* t = node->as_table();
    if (t == nullptr) return nullptr;
    node = t->get(part);
    if (node == nullptr) return nullptr;
  }
  return node;
}

void Scenario::MarkUsed(std::string_view key) { used_.emplace(key); }

bool Scenario::Has(std::string_view key) const { return Find(key) != nullptr; }

void Scenario::Fail(std::string_view key, std::string_view reason) const {
  throw ScenarioError(fmt::format("{}: {}: {}", path_, key, reason));
}

void Scenario::Warn(std::string_view key, std::string_view text) const {
  std::fprintf(stderr, "moreau: warning: %s: %.*s: %.*s\n", path_.c_str(),
               static_cast<int>(key.size()), key.data(), static_cast<int>(text.size()),
               text.data());
}

void Scenario::CheckTableKeys(std::string_view at, const toml::table& table,
                              std::initializer_list<std::string_view> known) const {
  for (const auto& [k, node] : table) {
    (void)node;
    if (std::find(known.begin(), known.end(), k.str()) != known.end()) continue;
    Fail(fmt::format("{}.{}", at, k.str()), "unknown key" + Suggestion(k.str(), known));
  }
}

double Scenario::GetDouble(std::string_view key, double fallback) {
  MarkUsed(key);
  const toml::node* node = Find(key);
  if (node == nullptr) return fallback;
  if (auto v = node->value_exact<double>()) {
    if (!std::isfinite(*v)) Fail(key, "must be a finite number");
    return *v;
  }
  if (auto v = node->value_exact<std::int64_t>()) return static_cast<double>(*v);
  Fail(key, fmt::format("expected a number, got {}", TypeName(*node)));
}

double Scenario::RequireDouble(std::string_view key) {
  if (!Has(key)) Fail(key, "required key is missing");
  return GetDouble(key, 0.0);
}

std::optional<double> Scenario::GetOptionalDouble(std::string_view key) {
  if (!Has(key)) {
    MarkUsed(key);
    return std::nullopt;
  }
  return GetDouble(key, 0.0);
}

std::int64_t Scenario::GetInt(std::string_view key, std::int64_t fallback) {
  MarkUsed(key);
  const toml::node* node = Find(key);
  if (node == nullptr) return fallback;
  if (auto v = node->value_exact<std::int64_t>()) return *v;
  Fail(key, fmt::format("expected an integer, got {}", TypeName(*node)));
}

std::int64_t Scenario::RequireInt(std::string_view key) {
  if (!Has(key)) Fail(key, "required key is missing");
  return GetInt(key, 0);
}

bool Scenario::GetBool(std::string_view key, bool fallback) {
  MarkUsed(key);
  const toml::node* node = Find(key);
  if (node == nullptr) return fallback;
  if (auto v = node->value_exact<bool>()) return *v;
  Fail(key, fmt::format("expected true or false, got {}", TypeName(*node)));
}

std::string Scenario::GetString(std::string_view key, const std::string& fallback) {
  MarkUsed(key);
  const toml::node* node = Find(key);
  if (node == nullptr) return fallback;
  if (auto v = node->value_exact<std::string>()) return *v;
  Fail(key, fmt::format("expected a string, got {}", TypeName(*node)));
}

std::string Scenario::RequireString(std::string_view key) {
  if (!Has(key)) Fail(key, "required key is missing");
  return GetString(key, "");
}

std::vector<double> Scenario::GetDoubleArray(std::string_view key,
                                             const std::vector<double>& fallback) {
  MarkUsed(key);
  const toml::node* node = Find(key);
  if (node == nullptr) return fallback;
  const toml::array* arr = node->as_array();
  if (arr == nullptr)
    Fail(key, fmt::format("expected an array of numbers, got {}", TypeName(*node)));
  std::vector<double> out;
  for (const toml::node& item : *arr) {
    if (auto v = item.value<double>()) {
      if (!std::isfinite(*v)) Fail(key, "entries must be finite numbers");
      out.push_back(*v);
    } else {
      Fail(key, fmt::format("expected an array of numbers, found {}", TypeName(item)));
    }
  }
  return out;
}

const toml::node* Scenario::GetNode(std::string_view key) {
  MarkUsed(key);
  return Find(key);
}

double Scenario::RequirePositive(std::string_view key, double value) const {
  if (!(value > 0.0)) Fail(key, fmt::format("must be > 0 (got {})", value));
  return value;
}

std::int64_t Scenario::RequirePositive(std::string_view key, std::int64_t value) const {
  if (value <= 0) Fail(key, fmt::format("must be > 0 (got {})", value));
  return value;
}

void Scenario::CheckAllKeysUsed() const {
  std::vector<std::string> keys;
  CollectLeafKeys(table_, "", &keys);
  for (std::string key : keys) {
    // A key is used when it, or a table above it, was asked for; an empty table when a key in
    // it was (a table the command knows, written without keys).
    const bool table = !key.empty() && key.back() == '.';
    if (table) {
      key.pop_back();
      const auto below = used_.lower_bound(key + ".");
      if (below != used_.end() && below->rfind(key + ".", 0) == 0) continue;
    }
    bool used = false;
    std::string prefix = key;
    while (true) {
      if (used_.count(prefix) != 0) {
        used = true;
        break;
      }
      const std::size_t dot = prefix.rfind('.');
      if (dot == std::string::npos) break;
      prefix.resize(dot);
    }
    if (!used) Fail(key, (table ? "unknown table" : "unknown key") + Suggestion(key, used_));
  }
}

}  // namespace moreau::cli
