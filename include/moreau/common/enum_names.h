// Enums to and from the names files, flags and summary.json use, from one table per enum:
// std::array<std::pair<Enum, std::string_view>, N>.
#pragma once

#include <array>
#include <cstddef>
#include <string_view>
#include <utility>

#include <fmt/format.h>

#include "moreau/common/error.h"

namespace moreau {

template <typename Enum, std::size_t N>
using EnumNames = std::array<std::pair<Enum, std::string_view>, N>;

// The name of `value` (every value must be in the table: a missing one is a bug).
template <typename Enum, std::size_t N>
std::string_view EnumName(const EnumNames<Enum, N>& names, Enum value) {
  for (const auto& [v, name] : names) {
    if (v == value) return name;
  }
  MOREAU_ASSERT(false);
}

// The value named `name`; InputError "unknown WHAT 'NAME'" otherwise.
template <typename Enum, std::size_t N>
Enum ParseEnumName(const EnumNames<Enum, N>& names, std::string_view name, std::string_view what) {
  for (const auto& [value, name_of] : names) {
    if (name_of == name) return value;
  }
  throw InputError(fmt::format("unknown {} '{}'", what, name));
}

}  // namespace moreau
