// C3D building blocks shared by the reader and the writer (internal): the three processor
// formats' numbers and the parameter section.
//
// A C3D file is a sequence of 512-byte blocks: the header (block 1), the parameter section (from
// the block named by the header's first byte) and the 3D/analog data (from POINT:DATA_START).
// Integers and floats are written in the byte order and float format of the processor named by
// the parameter section's fourth byte (83 + 1 Intel, 83 + 2 DEC/VAX, 83 + 3 SGI/MIPS).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "moreau/mocap/recording.h"

namespace moreau::mocap::c3d {

inline constexpr std::size_t kBlockBytes = 512;

enum class Processor { kIntel = 84, kDec = 85, kMips = 86 };

// "intel", "dec" or "mips".
std::string_view ProcessorName(Processor processor);

// Reads numbers stored by one processor type (any host byte order).
struct NumberDecoder {
  Processor processor = Processor::kIntel;

  std::int16_t Int16(const std::uint8_t* bytes) const;
  std::uint16_t UInt16(const std::uint8_t* bytes) const {
    return static_cast<std::uint16_t>(Int16(bytes));
  }
  // IEEE single (Intel little-endian, MIPS big-endian) or VAX F-float (DEC), as a float.
  float Float(const std::uint8_t* bytes) const;
};

// VAX F-float: two little-endian 16-bit words, the first holding the sign, the 8-bit exponent
// (bias 128) and the high mantissa bits, with the hidden bit after the binary point; the value is
// a quarter of the IEEE single read from the words swapped. Exponent 0 is zero (or, with the sign
// set, a reserved operand: NaN).
float DecodeVaxFloat(const std::uint8_t* bytes);

// One parameter: its type (-1 char, 1 byte, 2 16-bit integer, 4 float), dimensions and raw data.
struct Parameter {
  int type = 0;
  std::vector<int> dimensions;
  std::vector<std::uint8_t> data;  // |type| · product(dimensions) bytes

  std::size_t Count() const;
};

// The parsed parameter section, looked up by "GROUP:NAME" (upper case).
class ParameterSection {
 public:
  Processor processor = Processor::kIntel;
  std::map<std::string, Parameter, std::less<>> parameters;

  const Parameter* Find(std::string_view group, std::string_view name) const;
  // Element `index` as a number (16-bit integers signed, bytes unsigned); nullopt when the
  // parameter is absent, not numeric or too short.
  std::optional<double> Number(std::string_view group, std::string_view name,
                               std::size_t index = 0) const;
  // A count: 16-bit integers read unsigned (0 … 65535), floats rounded; nullopt when absent or
  // not a finite non-negative number.
  std::optional<std::int64_t> Count(std::string_view group, std::string_view name,
                                    std::size_t index = 0) const;
  // The strings of a character parameter (dimensions [length, n…]), trimmed of surrounding
  // spaces and NULs; empty when absent or not characters.
  std::vector<std::string> Strings(std::string_view group, std::string_view name) const;
};

// The POINT parameters that name the points of one model-output type and state its units.
struct PointTypeParameters {
  PointType type;
  std::string_view labels;  // POINT:ANGLES, …
  std::string_view units;   // POINT:ANGLE_UNITS, …
};
inline constexpr std::array<PointTypeParameters, 6> kPointTypeParameters = {{
    {PointType::kAngle, "ANGLES", "ANGLE_UNITS"},
    {PointType::kForce, "FORCES", "FORCE_UNITS"},
    {PointType::kMoment, "MOMENTS", "MOMENT_UNITS"},
    {PointType::kPower, "POWERS", "POWER_UNITS"},
    {PointType::kScalar, "SCALARS", "SCALAR_UNITS"},
    {PointType::kReaction, "REACTIONS", "REACTION_UNITS"},
}};

// Parses the parameter section starting at byte `start` of `file`. The chain of items ends at a
// name length 0, a link 0, or a link past the parameter blocks that the section declares (its
// third byte; the header's first data block when later): a link into the data ends the section
// without a warning, as BTK reads it. An item that runs outside the file or points backwards
// ends the section with a warning (real writers leave such bytes).
// A section that ends at once (its first item's name length is 0: the file declares no
// parameters, as PhaseSpace writes) is returned without parameters, for the caller to read the
// header alone; any other section without a single parameter is an InputError naming `path`.
ParameterSection ParseParameterSection(std::span<const std::uint8_t> file, std::size_t start,
                                       const std::filesystem::path& path,
                                       std::vector<std::string>& warnings);

}  // namespace moreau::mocap::c3d
