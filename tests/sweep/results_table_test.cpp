// The sweep's table: CSV text (known answer) and the HDF5 file read back.
#include "moreau/sweep/results_table.h"

#include <hdf5.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

namespace moreau::sweep {
namespace {

namespace fs = std::filesystem;

ResultsTable SmallTable() {
  ResultsTable table;
  table.columns = {"run", "door width", "status", "time", "message"};
  table.rows.push_back({0, 0.8, "completed", 12.5, ""});
  table.rows.push_back({1, 1.2, "input_error", nullptr, "f.toml: a, b: \"bad\""});
  return table;
}

std::string Bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(SweepResultsTable, CsvQuotesWhatNeedsItAndLeavesNullEmpty) {
  EXPECT_EQ(ResultsCsv(SmallTable()),
            "run,door width,status,time,message\n"
            "0,0.8,completed,12.5,\n"
            "1,1.2,input_error,,\"f.toml: a, b: \"\"bad\"\"\"\n");
}

TEST(SweepResultsTable, Hdf5HoldsTypedColumnsInOrderAndTheSameTableGivesTheSameBytes) {
  const fs::path a = fs::temp_directory_path() / "moreau_results_table_a.h5";
  const fs::path b = fs::temp_directory_path() / "moreau_results_table_b.h5";
  WriteResultsHdf5(a, SmallTable());
  WriteResultsHdf5(b, SmallTable());
  EXPECT_EQ(Bytes(a), Bytes(b));

  const hid_t file = H5Fopen(a.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  std::int64_t run[2] = {-1, -1};
  const hid_t run_set = H5Dopen2(file, "/results/run", H5P_DEFAULT);
  const hid_t run_type = H5Dget_type(run_set);
  EXPECT_EQ(H5Tget_class(run_type), H5T_INTEGER);
  H5Tclose(run_type);
  H5Dread(run_set, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, run);
  EXPECT_EQ(run[0], 0);
  EXPECT_EQ(run[1], 1);
  double time[2] = {0.0, 0.0};
  const hid_t time_set = H5Dopen2(file, "/results/time", H5P_DEFAULT);
  H5Dread(time_set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, time);
  EXPECT_EQ(time[0], 12.5);
  EXPECT_TRUE(std::isnan(time[1]));
  const hid_t text = H5Tcopy(H5T_C_S1);
  H5Tset_size(text, H5T_VARIABLE);
  H5Tset_cset(text, H5T_CSET_UTF8);
  char* status[2] = {nullptr, nullptr};
  const hid_t status_set = H5Dopen2(file, "/results/status", H5P_DEFAULT);
  H5Dread(status_set, text, H5S_ALL, H5S_ALL, H5P_DEFAULT, status);
  EXPECT_STREQ(status[0], "completed");
  EXPECT_STREQ(status[1], "input_error");
  char* columns[5] = {};
  const hid_t group = H5Gopen2(file, "/results", H5P_DEFAULT);
  const hid_t attribute = H5Aopen(group, "columns", H5P_DEFAULT);
  H5Aread(attribute, text, columns);
  EXPECT_STREQ(columns[0], "run");
  EXPECT_STREQ(columns[1], "door width");
  EXPECT_STREQ(columns[4], "message");
  H5free_memory(status[0]);
  H5free_memory(status[1]);
  for (char* c : columns) H5free_memory(c);
  H5Aclose(attribute);
  H5Gclose(group);
  H5Dclose(status_set);
  H5Dclose(time_set);
  H5Dclose(run_set);
  H5Tclose(text);
  H5Fclose(file);
  fs::remove(a);
  fs::remove(b);
}

}  // namespace
}  // namespace moreau::sweep
