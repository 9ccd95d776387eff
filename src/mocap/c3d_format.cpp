#include "mocap/c3d_format.h"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <limits>

#include "moreau/common/error.h"

namespace moreau::mocap::c3d {

std::string_view ProcessorName(Processor processor) {
  switch (processor) {
    case Processor::kIntel:
      return "intel";
    case Processor::kDec:
      return "dec";
    case Processor::kMips:
      return "mips";
  }
  return "unknown";
}

std::int16_t NumberDecoder::Int16(const std::uint8_t* bytes) const {
  const unsigned lo = processor == Processor::kMips ? bytes[1] : bytes[0];
  const unsigned hi = processor == Processor::kMips ? bytes[0] : bytes[1];
  return static_cast<std::int16_t>(static_cast<std::uint16_t>(lo | (hi << 8)));
}

float DecodeVaxFloat(const std::uint8_t* bytes) {
  const std::uint32_t high = bytes[0] | (std::uint32_t{bytes[1]} << 8);
  const std::uint32_t low = bytes[2] | (std::uint32_t{bytes[3]} << 8);
  const std::uint32_t word = (high << 16) | low;
  const int exponent = static_cast<int>((word >> 23) & 0xffu);
  const bool negative = (word >> 31) != 0;
  if (exponent == 0) return negative ? std::numeric_limits<float>::quiet_NaN() : 0.0f;
  const double mantissa = 1.0 + static_cast<double>(word & 0x7fffffu) / 8388608.0;  // 2^23
  const double value = std::ldexp(mantissa, exponent - 129);
  return static_cast<float>(negative ? -value : value);
}

float NumberDecoder::Float(const std::uint8_t* bytes) const {
  if (processor == Processor::kDec) return DecodeVaxFloat(bytes);
  std::uint32_t word = 0;
  for (int i = 0; i < 4; ++i) {
    const int shift = processor == Processor::kMips ? 8 * (3 - i) : 8 * i;
    word |= std::uint32_t{bytes[i]} << shift;
  }
  return std::bit_cast<float>(word);
}

std::size_t Parameter::Count() const {
  std::size_t n = 1;
  for (int d : dimensions) n *= static_cast<std::size_t>(d);
  return n;
}

namespace {

std::string Key(std::string_view group, std::string_view name) {
  std::string key = fmt::format("{}:{}", group, name);
  for (char& c : key) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return key;
}

std::string Trim(std::string_view text) {
  const auto blank = [](char c) { return c == ' ' || c == '\0' || c == '\t'; };
  std::size_t b = 0, e = text.size();
  while (b < e && blank(text[b])) ++b;
  while (e > b && blank(text[e - 1])) --e;
  return std::string(text.substr(b, e - b));
}

// One item of the section: a group (id < 0) or a parameter (id > 0).
struct Item {
  int id = 0;
  std::string name;
  Parameter parameter;
  std::size_t next = 0;  // byte of the next item; 0: this was the last
};

// Reads the item at `pos`; nullopt (with the reason) when it does not fit in `section`.
std::optional<Item> ReadItem(std::span<const std::uint8_t> section, std::size_t pos,
                             const NumberDecoder& decode, std::string& reason) {
  const auto fits = [&](std::size_t end) { return end <= section.size(); };
  if (!fits(pos + 2)) return reason = "item header beyond the file", std::nullopt;
  const int name_length = std::abs(static_cast<int>(static_cast<std::int8_t>(section[pos])));
  Item item;
  item.id = static_cast<std::int8_t>(section[pos + 1]);
  std::size_t p = pos + 2;
  if (!fits(p + static_cast<std::size_t>(name_length) + 2)) {
    return reason = "name beyond the file", std::nullopt;
  }
  item.name.assign(reinterpret_cast<const char*>(&section[p]),
                   static_cast<std::size_t>(name_length));
  p += static_cast<std::size_t>(name_length);
  const int offset = decode.Int16(&section[p]);
  if (offset < 0 || (offset > 0 && offset < 2)) {
    return reason = fmt::format("offset {} to the next item", offset), std::nullopt;
  }
  item.next = offset == 0 ? 0 : p + static_cast<std::size_t>(offset);
  p += 2;
  if (item.id > 0) {
    if (!fits(p + 2)) return reason = "parameter type beyond the file", std::nullopt;
    Parameter& par = item.parameter;
    par.type = static_cast<std::int8_t>(section[p]);
    if (par.type != -1 && par.type != 1 && par.type != 2 && par.type != 4) {
      return reason = fmt::format("data type {}", par.type), std::nullopt;
    }
    const int rank = section[p + 1];
    p += 2;
    if (!fits(p + static_cast<std::size_t>(rank)))
      return reason = "dimensions beyond the file", std::nullopt;
    for (int d = 0; d < rank; ++d) par.dimensions.push_back(section[p++]);
    const std::size_t bytes = static_cast<std::size_t>(std::abs(par.type)) * par.Count();
    if (!fits(p + bytes)) return reason = "data beyond the file", std::nullopt;
    par.data.assign(section.begin() + static_cast<std::ptrdiff_t>(p),
                    section.begin() + static_cast<std::ptrdiff_t>(p + bytes));
  }
  return item;
}

// The byte where the chain of items ends (exclusive): the end of the parameter blocks that the
// section's third byte declares, or the header's first data block (word 9) when that comes later;
// the whole file when neither is usable. Real writers leave a last item whose link points past
// the section, into the data: the chain stops there, as BTK stops it.
std::size_t ChainEnd(std::span<const std::uint8_t> file, std::size_t start,
                     const NumberDecoder& decode) {
  const std::size_t declared = start + std::size_t{file[start + 2]} * kBlockBytes;
  const std::size_t data_block = file.size() >= 18 ? decode.UInt16(&file[16]) : 0;
  const std::size_t data = data_block >= 2 ? (data_block - 1) * kBlockBytes : 0;
  const std::size_t end = std::max(declared, data);
  return end > start + 4 ? std::min(end, file.size()) : file.size();
}

}  // namespace

ParameterSection ParseParameterSection(std::span<const std::uint8_t> file, std::size_t start,
                                       const std::filesystem::path& path,
                                       std::vector<std::string>& warnings) {
  if (start + 4 > file.size()) {
    throw InputError(
        fmt::format("{}: parameter section: starts at byte {}, beyond the file's {} bytes",
                    path.string(), start, file.size()));
  }
  const int processor_byte = file[start + 3];
  if (processor_byte < 84 || processor_byte > 86) {
    throw InputError(fmt::format(
        "{}: parameter section: processor type {} is not 84 (Intel), 85 (DEC) or 86 (MIPS)",
        path.string(), processor_byte));
  }
  ParameterSection section;
  section.processor = static_cast<Processor>(processor_byte);
  const NumberDecoder decode{section.processor};
  std::map<int, std::string> groups;
  std::vector<std::pair<int, Item>> items;
  std::size_t pos = start + 4;
  if (pos < file.size() && file[pos] == 0) return section;  // no parameters declared
  const std::size_t end = ChainEnd(file, start, decode);
  while (pos != 0 && pos < end) {
    if (file[pos] == 0) break;  // name length 0 ends the section
    std::string reason;
    std::optional<Item> item = ReadItem(file, pos, decode, reason);
    if (item && item->next != 0 && item->next <= pos) reason = "next item points backwards";
    if (!item || !reason.empty()) {
      warnings.push_back(
          fmt::format("{}: parameter section: the item at byte {} is corrupt ({}); the section is "
                      "read up to it",
                      path.string(), pos, reason));
      break;
    }
    if (item->id < 0) groups[-item->id] = item->name;
    if (item->id == 0) break;
    pos = item->next;
    if (item->id > 0) items.emplace_back(item->id, std::move(*item));
  }
  for (auto& [group_id, item] : items) {
    const auto group = groups.find(group_id);
    if (group == groups.end()) continue;  // a parameter of an undeclared group is unreachable
    section.parameters[Key(group->second, item.name)] = std::move(item.parameter);
  }
  if (section.parameters.empty()) {
    throw InputError(
        fmt::format("{}: parameter section: no parameter could be read", path.string()));
  }
  return section;
}

const Parameter* ParameterSection::Find(std::string_view group, std::string_view name) const {
  const auto it = parameters.find(Key(group, name));
  return it == parameters.end() ? nullptr : &it->second;
}

std::optional<double> ParameterSection::Number(std::string_view group, std::string_view name,
                                               std::size_t index) const {
  const Parameter* p = Find(group, name);
  if (p == nullptr || p->type == -1 || index >= p->Count()) return std::nullopt;
  const NumberDecoder decode{processor};
  const std::uint8_t* at = p->data.data() + index * static_cast<std::size_t>(p->type);
  if (p->type == 1) return at[0];
  if (p->type == 2) return decode.Int16(at);
  return decode.Float(at);
}

std::optional<std::int64_t> ParameterSection::Count(std::string_view group, std::string_view name,
                                                    std::size_t index) const {
  const Parameter* p = Find(group, name);
  std::optional<double> value = Number(group, name, index);
  if (!value) return std::nullopt;
  if (p->type == 2) return static_cast<std::int64_t>(*value < 0.0 ? *value + 65536.0 : *value);
  if (!std::isfinite(*value) || *value < 0.0 || *value > 9e15) return std::nullopt;
  return static_cast<std::int64_t>(std::llround(*value));
}

std::vector<std::string> ParameterSection::Strings(std::string_view group,
                                                   std::string_view name) const {
  const Parameter* p = Find(group, name);
  std::vector<std::string> out;
  if (p == nullptr || p->type != -1) return out;
  const std::size_t length = p->dimensions.empty() ? 1 : static_cast<std::size_t>(p->dimensions[0]);
  if (length == 0) return out;
  const std::size_t count = p->Count() / length;
  for (std::size_t i = 0; i < count; ++i) {
    out.push_back(
        Trim(std::string_view(reinterpret_cast<const char*>(p->data.data()) + i * length, length)));
  }
  return out;
}

}  // namespace moreau::mocap::c3d
