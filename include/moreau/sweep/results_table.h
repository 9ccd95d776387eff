// The table of a sweep: one row per run, as CSV text and as an HDF5 file.
//
// Cells are JSON values: numbers, strings, booleans or null (an empty cell). The CSV writes
// numbers in the shortest form that reads back to the same double (integers exactly), strings
// as they are (quoted when they hold a comma, a quote or a line break), null as nothing. The
// HDF5 file holds a group "/results" with one dataset of length rows per column (int64 when
// every cell is an integer, float64 when every cell is a number or null (null: NaN), else
// variable-length UTF-8 strings) and the attribute "columns" listing the column names in order;
// no timestamps, so the same table gives the same bytes.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace moreau::sweep {

struct ResultsTable {
  std::vector<std::string> columns;               // names, in order
  std::vector<std::vector<nlohmann::json>> rows;  // each of columns.size() cells
};

// The CSV text: a header line, then one line per row.
std::string ResultsCsv(const ResultsTable& table);

// Writes PATH (replaced when present). Throws InputError when the file cannot be written.
void WriteResultsHdf5(const std::filesystem::path& path, const ResultsTable& table);

}  // namespace moreau::sweep
