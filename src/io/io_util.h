// Helpers shared by the trajectory writers (internal).
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "moreau/io/trajectory.h"

namespace moreau::io::internal {

// Throws InputError (message starting with `file`) unless the frame has dimension 2 or 3,
// count ≥ 0, non-null arrays when count > 0, and a finite time; and unless its extra arrays have
// good names (not empty, no '/', not radius or id, each once) and 1 or 3 components.
void ValidateFrame(const ParticleFrame& frame, const std::filesystem::path& file);

// What a writer keeps of an extra array of the first frame.
struct ArraySpec {
  std::string name;
  PointArray::Type type = PointArray::Type::kFloat64;
  int components = 1;
};
std::vector<ArraySpec> SpecsOf(std::span<const PointArray> arrays);

// Throws InputError naming `file` unless `frame` has the extra arrays `first` has: the same
// names, types and components in the same order.
void CheckSameArrays(const std::vector<ArraySpec>& first, const ParticleFrame& frame,
                     const std::filesystem::path& file);

// Throws InputError naming `file` unless every list name is non-empty, without '/', used once and
// none of `taken`.
void ValidateLists(const std::vector<StringList>& lists, std::span<const std::string_view> taken,
                   const std::filesystem::path& file);

// Throws InputError naming `file` unless the directory that will hold it exists.
void CheckParentDirectory(const std::filesystem::path& file);

// `text` with &, <, >, " and ' replaced by XML entities.
std::string XmlEscape(std::string_view text);

// Shortest decimal text that reads back to the same double (fmt "{}").
std::string FormatDouble(double value);

// Appends the standard base64 (RFC 4648, with '=' padding) of `size` bytes at `data` to `out`.
void AppendBase64(const void* data, std::size_t size, std::string& out);

// Writes `content` to `file` (created or truncated). Throws std::runtime_error
// "cannot write FILE: reason" on any failure, including at close.
void WriteWholeFile(const std::filesystem::path& file, std::string_view content);

// Appends `list` as one FieldData string array, as VTK's XML writer stores a vtkStringArray in
// ASCII: each string's bytes as numbers, each string ended by 0.
void AppendStringArray(const StringList& list, std::string& out);

// The byte order VTK's XML files declare: the machine's own (the arrays are written raw).
inline constexpr const char* kByteOrder =
    std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian";

// Appends one inline binary DataArray of a VTK XML file: base64 of (UInt64 byte count, the
// `bytes` raw bytes at `values`), as VTK's own writer encodes it with header_type="UInt64".
void AppendBinaryDataArray(const char* type, std::string_view name, int components,
                           const void* values, std::size_t bytes, std::string& out);
template <typename T>
void AppendDataArray(const char* type, std::string_view name, int components, const T* values,
                     std::size_t value_count, std::string& out) {
  AppendBinaryDataArray(type, name, components, values, value_count * sizeof(T), out);
}

// Appends a frame's FieldData arrays TimeValue (its time, Float64) and step (Int64), ASCII.
void AppendTimeAndStep(double time, std::int64_t step, std::string& out);

// The PVD index of a series: one DataSet per (time, file name relative to the index).
std::string PvdText(const std::vector<std::pair<double, std::string>>& files);

// Starts the series DIR/PREFIX_iiiiii.* of `kind` (VTU, VTI): writes the empty index DIR/PREFIX.pvd
// and returns its path. Throws InputError if `prefix` is empty or has a '/', if `dir` is not an
// existing directory, or if the index cannot be written.
std::filesystem::path StartSeriesIndex(const std::filesystem::path& dir, const std::string& prefix,
                                       std::string_view kind);

}  // namespace moreau::io::internal
