// Reading and writing motion-capture recordings: C3D (all three processor formats, integer and
// float storage), TRC (OpenSim's tab-separated marker format) and CSV (one row per frame and
// marker). docs/mocap.md describes the formats and the C3D quirks handled.
//
// Missing samples. A C3D point is missing when its residual word is negative, when its three
// coordinates are exactly zero (ReadOptions::zero_is_missing) or when a coordinate is not finite.
// TRC and CSV samples are missing when their x, y, z fields are empty (or "NaN"), or exactly zero
// with zero_is_missing. Missing samples are never turned into positions; writers write them as
// residual −1 (C3D) or empty fields (TRC, CSV).
//
// Errors. Every problem with a file is a moreau::InputError with a one-line message
// "FILE: FIELD: reason". Problems a reader can work around (duplicate labels, a corrupt tail of
// the C3D parameter section, a missing POINT:SCALE, …) are returned as warnings, each one line
// naming the file; the library never prints.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "moreau/common/field_list.h"
#include "moreau/mocap/recording.h"

namespace moreau::mocap {

struct ReadOptions {
  // A sample whose three coordinates are exactly 0 is missing (some C3D writers mark gaps so).
  bool zero_is_missing = true;
  // A file holding fewer frames than it declares: false → InputError; true → read the frames
  // present, with a warning.
  bool allow_truncated = false;
  // Convert positions to these units after reading: "mm", "cm" or "m"; empty keeps the file's.
  std::string units;
  // Units of files that do not state them (CSV): "mm", "cm" or "m".
  std::string units_if_unstated = "mm";
  // Frames per second of a CSV file with a single frame (its time column cannot give the rate).
  double rate_if_unstated = 0.0;

  static const FieldList<ReadOptions>& Fields();  // key, range, unit, help of every field
  // Throws InputError(key, reason).
  void Validate() const;
};

// Reads a recording, choosing the format by extension (.c3d, .trc, .csv; any case). Appends
// one line per work-around to `warnings` when given. Throws InputError (naming the file) for a
// missing or unreadable file, an unknown extension or a malformed file.
Recording ReadRecording(const std::filesystem::path& path, const ReadOptions& options = {},
                        std::vector<std::string>* warnings = nullptr);

// The same for one format, whatever the extension. A C3D file that declares no parameters (its
// parameter section ends at once, as PhaseSpace writes it) is read from its header alone: point
// count, frame range, scale, rate and data start; the markers are labelled "M1", "M2", … (as an
// empty label is anywhere else) and the units are mm, with one warning saying so.
Recording ReadC3d(const std::filesystem::path& path, const ReadOptions& options = {},
                  std::vector<std::string>* warnings = nullptr);
Recording ReadTrc(const std::filesystem::path& path, const ReadOptions& options = {},
                  std::vector<std::string>* warnings = nullptr);
Recording ReadCsv(const std::filesystem::path& path, const ReadOptions& options = {},
                  std::vector<std::string>* warnings = nullptr);

// Writes a recording, choosing the format by extension (.c3d, .trc, .csv). The file appears
// complete or not at all: it is written under a temporary name in the same directory and renamed.
// Throws InputError naming the file (unknown extension, missing directory, a label that the
// format cannot hold, a write failure).
void WriteRecording(const Recording& recording, const std::filesystem::path& path);

// C3D, Intel processor, float storage, no analog data: POINT:USED/SCALE(−1)/RATE/UNITS/FRAMES/
// DATA_START, LABELS (LABELS2, LABELS3, … beyond 255 markers) and DESCRIPTIONS likewise, and
// TRIAL:ACTUAL_START_FIELD/ACTUAL_END_FIELD; for model outputs (recording.h) POINT:ANGLES,
// FORCES, MOMENTS, POWERS, SCALARS, REACTIONS (the labels of each type present) and ANGLE_UNITS, …
// (each type's units the recording states). More than 65535 frames: the header's last frame
// and POINT:FRAMES (a 16-bit integer) saturate at 65535 and the TRIAL fields hold the true
// range. Missing samples have residual −1 and coordinates 0; every other sample residual 0 (a
// recording keeps no residuals).
void WriteC3d(const Recording& recording, const std::filesystem::path& path);
// TRC (PathFileType 4): rate, units, C3D frame numbers, time f / rate, blank fields where missing.
void WriteTrc(const Recording& recording, const std::filesystem::path& path);
// CSV with header `frame,time,marker,x,y,z`: one row per frame and marker, frame = C3D frame
// number, time = f / rate in seconds, empty x,y,z where missing. CSV holds no units: a reader
// takes ReadOptions::units_if_unstated.
void WriteCsv(const Recording& recording, const std::filesystem::path& path);

}  // namespace moreau::mocap
