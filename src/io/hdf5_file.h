// An HDF5 file that a writer creates and fills (internal): every call checked, every failure a
// std::runtime_error whose one line names the file, no modification times (the same input gives
// the same bytes). The trajectory writer and the grid writer share it.
#pragma once

#include <hdf5.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "io/hdf5_handle.h"
#include "moreau/io/trajectory.h"

namespace moreau::io::internal {

class Hdf5File {
 public:
  // Creates (truncates) `path`; throws InputError "cannot create PATH: reason". Datasets made by
  // CreateExtensible are shuffled and deflated at `compression` when it is > 0 (0 … 9, checked by
  // the caller). HDF5's own error printing is switched off.
  Hdf5File(std::filesystem::path path, int compression);

  const std::filesystem::path& path() const { return path_; }
  hid_t get() const { return file_.get(); }

  // Throws std::runtime_error naming the file and `what` when `status` < 0.
  void Check(std::int64_t status, const std::string& what) const;
  // A chunked dataset of extent 0 along every axis but the last `fixed_tail` ones, which have the
  // extents `fixed` (default: the chunk's); every other axis is unlimited. `fill` (of
  // `memory_type`) is what unwritten elements read as.
  Handle CreateExtensible(hid_t location, const char* name, hid_t file_type,
                          const std::vector<hsize_t>& chunk, std::size_t fixed_tail,
                          hid_t memory_type, const void* fill,
                          const std::vector<hsize_t>& fixed = {});
  // Sets the extent of `dataset` to `dims` and writes `data` (shape `count`) at `start`.
  void WriteBlock(const Handle& dataset, const char* name, hid_t memory_type,
                  const std::vector<hsize_t>& dims, const std::vector<hsize_t>& start,
                  const std::vector<hsize_t>& count, const void* data);
  // A virtual dataset `name` in `group` that shows the block of `source` (extent `source_dims`)
  // of shape `count` at `start`; its shape is `shape` (as many elements), by default `count`
  // without its first axis (the frame axis, of extent 1).
  void CreateView(hid_t group, const char* name, hid_t file_type, const char* source,
                  const std::vector<hsize_t>& source_dims, const std::vector<hsize_t>& start,
                  const std::vector<hsize_t>& count, const std::vector<hsize_t>& shape = {});
  // The group `name` (absolute path), without modification times.
  Handle CreateGroup(const std::string& name);
  // The root attribute `name`: a scalar, or when `count` > 0 an array of `count` values.
  void WriteAttribute(const char* name, hid_t file_type, hid_t memory_type, const void* value,
                      hsize_t count = 0);
  void WriteStringAttribute(const char* name, const std::string& value);
  // The root attribute list.name: an array of fixed-length strings.
  void WriteStringList(const StringList& list);
  // Writes what HDF5 holds in memory to the file (checked: a full disk throws).
  void Flush();
  // Closes the file; false if HDF5 reported an error (close the datasets first).
  bool Close() { return file_.Reset(); }

 private:
  std::filesystem::path path_;
  int compression_ = 0;
  Handle file_;
};

}  // namespace moreau::io::internal
