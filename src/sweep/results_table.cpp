#include "moreau/sweep/results_table.h"

#include <hdf5.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include <fmt/format.h>

#include "moreau/common/error.h"

namespace moreau::sweep {
namespace {

std::string CsvField(const nlohmann::json& cell) {
  if (cell.is_null()) return "";
  if (!cell.is_string()) return cell.dump();
  const std::string text = cell.get<std::string>();
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string quoted = "\"";
  for (const char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
}

// An HDF5 identifier closed by `close` when it goes out of scope.
class Hid {
 public:
  Hid(hid_t id, herr_t (*close)(hid_t), const std::filesystem::path& path)
      : id_(id), close_(close) {
    if (id < 0) throw InputError(fmt::format("{}: cannot write the HDF5 table", path.string()));
  }
  ~Hid() { close_(id_); }
  Hid(const Hid&) = delete;
  Hid& operator=(const Hid&) = delete;
  hid_t get() const { return id_; }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

// A new type of variable-length UTF-8 strings (negative when HDF5 fails).
hid_t NewUtf8TextType() {
  const hid_t type = H5Tcopy(H5T_C_S1);
  if (type >= 0 && (H5Tset_size(type, H5T_VARIABLE) < 0 || H5Tset_cset(type, H5T_CSET_UTF8) < 0)) {
    H5Tclose(type);
    return -1;
  }
  return type;
}

enum class ColumnType { kInteger, kNumber, kText };

ColumnType TypeOf(const ResultsTable& table, std::size_t c) {
  bool integers = true;
  for (const auto& row : table.rows) {
    const nlohmann::json& cell = row[c];
    if (!cell.is_number() && !cell.is_null()) return ColumnType::kText;
    if (!cell.is_number_integer()) integers = false;
  }
  return integers ? ColumnType::kInteger : ColumnType::kNumber;
}

void WriteColumn(hid_t group, const ResultsTable& table, std::size_t c,
                 const std::filesystem::path& path) {
  const hsize_t n = table.rows.size();
  Hid space(H5Screate_simple(1, &n, nullptr), H5Sclose, path);
  Hid properties(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, path);
  H5Pset_obj_track_times(properties.get(), false);
  const ColumnType type = TypeOf(table, c);
  const Hid text_type(NewUtf8TextType(), H5Tclose, path);
  const hid_t file_type = type == ColumnType::kInteger  ? H5T_STD_I64LE
                          : type == ColumnType::kNumber ? H5T_IEEE_F64LE
                                                        : text_type.get();
  Hid dataset(H5Dcreate2(group, table.columns[c].c_str(), file_type, space.get(), H5P_DEFAULT,
                         properties.get(), H5P_DEFAULT),
              H5Dclose, path);
  herr_t status = 0;
  if (type == ColumnType::kInteger) {
    std::vector<std::int64_t> values;
    for (const auto& row : table.rows) values.push_back(row[c].get<std::int64_t>());
    status =
        H5Dwrite(dataset.get(), H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
  } else if (type == ColumnType::kNumber) {
    std::vector<double> values;
    for (const auto& row : table.rows) {
      values.push_back(row[c].is_null() ? std::numeric_limits<double>::quiet_NaN()
                                        : row[c].get<double>());
    }
    status =
        H5Dwrite(dataset.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
  } else {
    std::vector<std::string> texts;
    for (const auto& row : table.rows) {
      texts.push_back(row[c].is_string() ? row[c].get<std::string>() : CsvField(row[c]));
    }
    std::vector<const char*> pointers;
    for (const std::string& t : texts) pointers.push_back(t.c_str());
    status =
        H5Dwrite(dataset.get(), text_type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, pointers.data());
  }
  if (status < 0) throw InputError(fmt::format("{}: cannot write column {}", path.string(), c));
}

void WriteColumnNames(hid_t group, const ResultsTable& table, const std::filesystem::path& path) {
  const hsize_t n = table.columns.size();
  Hid space(H5Screate_simple(1, &n, nullptr), H5Sclose, path);
  const Hid text_type(NewUtf8TextType(), H5Tclose, path);
  Hid attribute(
      H5Acreate2(group, "columns", text_type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT),
      H5Aclose, path);
  std::vector<const char*> names;
  for (const std::string& name : table.columns) names.push_back(name.c_str());
  if (H5Awrite(attribute.get(), text_type.get(), names.data()) < 0) {
    throw InputError(fmt::format("{}: cannot write the column names", path.string()));
  }
}

}  // namespace

std::string ResultsCsv(const ResultsTable& table) {
  std::string csv;
  const auto append_line = [&csv](const auto& cells, const auto& text_of) {
    for (std::size_t c = 0; c < cells.size(); ++c) {
      if (c > 0) csv += ',';
      csv += CsvField(text_of(cells[c]));
    }
    csv += '\n';
  };
  append_line(table.columns, [](const std::string& name) { return nlohmann::json(name); });
  for (const auto& row : table.rows) {
    append_line(row, [](const nlohmann::json& cell) { return cell; });
  }
  return csv;
}

void WriteResultsHdf5(const std::filesystem::path& path, const ResultsTable& table) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  Hid file(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose, path);
  Hid group_properties(H5Pcreate(H5P_GROUP_CREATE), H5Pclose, path);
  H5Pset_obj_track_times(group_properties.get(), false);
  Hid group(H5Gcreate2(file.get(), "results", H5P_DEFAULT, group_properties.get(), H5P_DEFAULT),
            H5Gclose, path);
  WriteColumnNames(group.get(), table, path);
  for (std::size_t c = 0; c < table.columns.size(); ++c) WriteColumn(group.get(), table, c, path);
}

}  // namespace moreau::sweep
