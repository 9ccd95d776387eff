#include "io/io_util.h"

#include <fmt/format.h>

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "moreau/common/error.h"

namespace moreau::io::internal {

void ValidateFrame(const ParticleFrame& frame, const std::filesystem::path& file) {
  const std::string where = fmt::format("{}: frame at step {}", file.string(), frame.step);
  if (frame.dimension != 2 && frame.dimension != 3) {
    throw InputError(fmt::format("{} has dimension {} (expected 2 or 3)", where, frame.dimension));
  }
  if (frame.count < 0) {
    throw InputError(fmt::format("{} has a negative particle count {}", where, frame.count));
  }
  if (frame.count > 0 &&
      (frame.positions == nullptr || frame.ids == nullptr || frame.radii == nullptr)) {
    throw InputError(fmt::format("{} has {} particles but a null positions, ids or radii array",
                                 where, frame.count));
  }
  if (!std::isfinite(frame.time)) {
    throw InputError(fmt::format("{} has a non-finite time {}", where, frame.time));
  }
  for (std::size_t a = 0; a < frame.arrays.size(); ++a) {
    const PointArray& array = frame.arrays[a];
    if (array.name.empty() || array.name.find('/') != std::string_view::npos ||
        array.name == "radius" || array.name == "id") {
      throw InputError(
          fmt::format("{}: array name '{}' must be non-empty, without '/', and not "
                      "radius or id",
                      where, array.name));
    }
    if (array.components != 1 && array.components != 3) {
      throw InputError(fmt::format("{}: array {} has {} components (expected 1 or 3)", where,
                                   array.name, array.components));
    }
    if (frame.count > 0 && array.data == nullptr) {
      throw InputError(fmt::format("{}: array {} is null", where, array.name));
    }
    for (std::size_t b = 0; b < a; ++b) {
      if (frame.arrays[b].name == array.name) {
        throw InputError(fmt::format("{}: array name {} is used twice", where, array.name));
      }
    }
  }
}

std::vector<ArraySpec> SpecsOf(std::span<const PointArray> arrays) {
  std::vector<ArraySpec> specs;
  for (const PointArray& a : arrays) specs.push_back({std::string(a.name), a.type, a.components});
  return specs;
}

void CheckSameArrays(const std::vector<ArraySpec>& first, const ParticleFrame& frame,
                     const std::filesystem::path& file) {
  bool same = first.size() == frame.arrays.size();
  for (std::size_t a = 0; same && a < first.size(); ++a) {
    same = first[a].name == frame.arrays[a].name && first[a].type == frame.arrays[a].type &&
           first[a].components == frame.arrays[a].components;
  }
  if (!same) {
    throw InputError(fmt::format("{}: frame at step {} has other point arrays than the first frame",
                                 file.string(), frame.step));
  }
}

void ValidateLists(const std::vector<StringList>& lists, std::span<const std::string_view> taken,
                   const std::filesystem::path& file) {
  for (std::size_t a = 0; a < lists.size(); ++a) {
    const std::string& name = lists[a].name;
    bool bad = name.empty() || name.find('/') != std::string::npos;
    for (const std::string_view t : taken) bad = bad || name == t;
    for (std::size_t b = 0; b < a; ++b) bad = bad || lists[b].name == name;
    if (bad) {
      throw InputError(
          fmt::format("{}: string list name '{}' is empty, has a '/', is used twice "
                      "or is taken",
                      file.string(), name));
    }
  }
}

void CheckParentDirectory(const std::filesystem::path& file) {
  std::filesystem::path parent = file.parent_path();
  if (parent.empty()) parent = ".";
  std::error_code ec;
  if (!std::filesystem::is_directory(parent, ec)) {
    throw InputError(fmt::format("cannot create {}: directory {} does not exist", file.string(),
                                 parent.string()));
  }
}

std::string XmlEscape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string FormatDouble(double value) { return fmt::format("{}", value); }

void AppendBase64(const void* data, std::size_t size, std::string& out) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* bytes = static_cast<const unsigned char*>(data);
  const std::size_t start = out.size();
  out.resize(start + 4 * ((size + 2) / 3));
  char* o = out.data() + start;
  std::size_t i = 0;
  for (; i + 3 <= size; i += 3) {
    const unsigned v = (unsigned{bytes[i]} << 16) | (unsigned{bytes[i + 1]} << 8) | bytes[i + 2];
    *o++ = kAlphabet[(v >> 18) & 63u];
    *o++ = kAlphabet[(v >> 12) & 63u];
    *o++ = kAlphabet[(v >> 6) & 63u];
    *o++ = kAlphabet[v & 63u];
  }
  if (i < size) {
    const bool two = i + 1 < size;
    const unsigned v = (unsigned{bytes[i]} << 16) | (two ? unsigned{bytes[i + 1]} << 8 : 0u);
    *o++ = kAlphabet[(v >> 18) & 63u];
    *o++ = kAlphabet[(v >> 12) & 63u];
    *o++ = two ? kAlphabet[(v >> 6) & 63u] : '=';
    *o++ = '=';
  }
}

void WriteWholeFile(const std::filesystem::path& file, std::string_view content) {
  std::FILE* f = std::fopen(file.c_str(), "wb");
  if (f == nullptr) {
    throw std::runtime_error(
        fmt::format("cannot write {}: {}", file.string(), std::strerror(errno)));
  }
  const std::size_t written = std::fwrite(content.data(), 1, content.size(), f);
  const int write_errno = errno;
  const bool write_ok = written == content.size();
  const bool close_ok = std::fclose(f) == 0;
  if (!write_ok || !close_ok) {
    throw std::runtime_error(fmt::format("cannot write {}: {}", file.string(),
                                         std::strerror(write_ok ? errno : write_errno)));
  }
}

void AppendStringArray(const StringList& list, std::string& out) {
  out += fmt::format(
      "      <Array type=\"String\" Name=\"{}\" NumberOfTuples=\"{}\" format=\"ascii\">\n"
      "       ",
      XmlEscape(list.name), list.values.size());
  for (const std::string& value : list.values) {
    for (const char c : value) out += fmt::format(" {}", static_cast<unsigned char>(c));
    out += " 0";
  }
  out += "\n      </Array>\n";
}

void AppendBinaryDataArray(const char* type, std::string_view name, int components,
                           const void* values, std::size_t bytes, std::string& out) {
  out += fmt::format(
      "        <DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" "
      "format=\"binary\">\n          ",
      type, name, components);
  const std::uint64_t header = bytes;
  // Header and data form one base64 stream, as VTK's own writer encodes them.
  std::vector<unsigned char> raw(sizeof(header) + bytes);
  std::memcpy(raw.data(), &header, sizeof(header));
  if (bytes > 0) std::memcpy(raw.data() + sizeof(header), values, bytes);
  AppendBase64(raw.data(), raw.size(), out);
  out += "\n        </DataArray>\n";
}

void AppendTimeAndStep(double time, std::int64_t step, std::string& out) {
  out += fmt::format(
      "      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" "
      "format=\"ascii\">{}</DataArray>\n",
      FormatDouble(time));
  out += fmt::format(
      "      <DataArray type=\"Int64\" Name=\"step\" NumberOfTuples=\"1\" "
      "format=\"ascii\">{}</DataArray>\n",
      step);
}

std::string PvdText(const std::vector<std::pair<double, std::string>>& files) {
  std::string out;
  out += "<?xml version=\"1.0\"?>\n";
  out +=
      fmt::format("<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"{}\">\n", kByteOrder);
  out += "  <Collection>\n";
  for (const auto& [time, name] : files) {
    out += fmt::format("    <DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"{}\"/>\n",
                       FormatDouble(time), XmlEscape(name));
  }
  out += "  </Collection>\n";
  out += "</VTKFile>\n";
  return out;
}

std::filesystem::path StartSeriesIndex(const std::filesystem::path& dir, const std::string& prefix,
                                       std::string_view kind) {
  const std::filesystem::path pvd = dir / (prefix + ".pvd");
  if (prefix.empty() || prefix.find('/') != std::string::npos) {
    throw InputError(fmt::format("{} series prefix '{}' must be a non-empty file name without '/'",
                                 kind, prefix));
  }
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) {
    throw InputError(fmt::format("cannot write the {} series {}: directory {} does not exist", kind,
                                 pvd.string(), dir.string()));
  }
  try {
    WriteWholeFile(pvd, PvdText({}));
  } catch (const std::runtime_error& e) {
    throw InputError(e.what());
  }
  return pvd;
}

}  // namespace moreau::io::internal
