#include "io/hdf5_file.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "moreau/common/error.h"

namespace moreau::io::internal {

namespace {
// No clean-up of HDF5 at exit. A file whose close failed (a full disk: closing flushes, and the
// flush fails again) stays half-closed inside HDF5, and the library's exit handler that closes it
// once more dereferences freed state and crashes the process after its error was reported. Every
// writer closes its file itself, so the exit handler has nothing left to do; H5dont_atexit must
// come before HDF5's first call, hence a static initialiser.
[[maybe_unused]] const bool kNoHdf5ExitHandler = H5dont_atexit() >= 0;
}  // namespace

Hdf5File::Hdf5File(std::filesystem::path path, int compression)
    : path_(std::move(path)), compression_(compression) {
  // The library never prints: errors are turned into exceptions below.
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  // Each frame adds a group of virtual datasets that is written once and closed: evicting the
  // metadata of closed objects keeps the writer's memory flat over a long run (the soak test).
  Handle access(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
  if (access.get() < 0 || H5Pset_evict_on_close(access.get(), true) < 0) {
    throw InputError(fmt::format("cannot create {}: {}", path_.string(), Hdf5ErrorText()));
  }
  const hid_t file = H5Fcreate(path_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access.get());
  if (file < 0) {
    throw InputError(fmt::format("cannot create {}: {}", path_.string(), Hdf5ErrorText()));
  }
  file_ = Handle(file, H5Fclose);
}

void Hdf5File::Check(std::int64_t status, const std::string& what) const {
  if (status < 0) {
    throw std::runtime_error(
        fmt::format("HDF5 error writing {} ({}): {}", path_.string(), what, Hdf5ErrorText()));
  }
}

Handle Hdf5File::CreateExtensible(hid_t location, const char* name, hid_t file_type,
                                  const std::vector<hsize_t>& chunk, std::size_t fixed_tail,
                                  hid_t memory_type, const void* fill,
                                  const std::vector<hsize_t>& fixed) {
  const std::size_t rank = chunk.size();
  std::vector<hsize_t> dims(rank, 0), max_dims(rank, H5S_UNLIMITED);
  for (std::size_t a = rank - fixed_tail; a < rank; ++a) {
    dims[a] = max_dims[a] = fixed.empty() ? chunk[a] : fixed[a - (rank - fixed_tail)];
  }
  const std::string what = fmt::format("creating /{}", name);
  Handle space(H5Screate_simple(static_cast<int>(rank), dims.data(), max_dims.data()), H5Sclose);
  Check(space.get(), what);
  Handle properties(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  Check(properties.get(), what);
  Check(H5Pset_chunk(properties.get(), static_cast<int>(rank), chunk.data()), what);
  Check(H5Pset_fill_value(properties.get(), memory_type, fill), what);
  if (compression_ > 0) {
    // Shuffling groups the bytes of equal significance, which deflate then compresses far better.
    Check(H5Pset_shuffle(properties.get()), what);
    Check(H5Pset_deflate(properties.get(), static_cast<unsigned>(compression_)), what);
  }
  // No modification times in the file: the same run gives the same bytes.
  Check(H5Pset_obj_track_times(properties.get(), false), what);
  Handle dataset(H5Dcreate2(location, name, file_type, space.get(), H5P_DEFAULT, properties.get(),
                            H5P_DEFAULT),
                 H5Dclose);
  Check(dataset.get(), what);
  return dataset;
}

void Hdf5File::WriteBlock(const Handle& dataset, const char* name, hid_t memory_type,
                          const std::vector<hsize_t>& dims, const std::vector<hsize_t>& start,
                          const std::vector<hsize_t>& count, const void* data) {
  const std::string what = fmt::format("writing /{}", name);
  Check(H5Dset_extent(dataset.get(), dims.data()), what);
  hsize_t elements = 1;
  for (const hsize_t extent : count) elements *= extent;
  if (elements == 0) return;
  Handle file_space(H5Dget_space(dataset.get()), H5Sclose);
  Check(file_space.get(), what);
  Check(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start.data(), nullptr, count.data(),
                            nullptr),
        what);
  Handle memory_space(H5Screate_simple(static_cast<int>(count.size()), count.data(), nullptr),
                      H5Sclose);
  Check(memory_space.get(), what);
  Check(
      H5Dwrite(dataset.get(), memory_type, memory_space.get(), file_space.get(), H5P_DEFAULT, data),
      what);
}

void Hdf5File::CreateView(hid_t group, const char* name, hid_t file_type, const char* source,
                          const std::vector<hsize_t>& source_dims,
                          const std::vector<hsize_t>& start, const std::vector<hsize_t>& count,
                          const std::vector<hsize_t>& shape) {
  const std::string what = fmt::format("view of /{}", source);
  Handle source_space(
      H5Screate_simple(static_cast<int>(source_dims.size()), source_dims.data(), nullptr),
      H5Sclose);
  Check(source_space.get(), what);
  Check(H5Sselect_hyperslab(source_space.get(), H5S_SELECT_SET, start.data(), nullptr, count.data(),
                            nullptr),
        what);
  // By default the view drops the axis of extent 1 at the front of the block (the frame axis).
  const std::vector<hsize_t> view_shape =
      !shape.empty()
          ? shape
          : std::vector<hsize_t>(count.size() > 1 ? count.begin() + 1 : count.begin(), count.end());
  Handle view_space(
      H5Screate_simple(static_cast<int>(view_shape.size()), view_shape.data(), nullptr), H5Sclose);
  Check(view_space.get(), what);
  Handle properties(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  Check(properties.get(), what);
  Check(H5Pset_obj_track_times(properties.get(), false), what);
  // "." is this file, so the views move with it.
  Check(H5Pset_virtual(properties.get(), view_space.get(), ".", source, source_space.get()), what);
  Handle view(H5Dcreate2(group, name, file_type, view_space.get(), H5P_DEFAULT, properties.get(),
                         H5P_DEFAULT),
              H5Dclose);
  Check(view.get(), what);
}

Handle Hdf5File::CreateGroup(const std::string& name) {
  const std::string what = "creating " + name;
  Handle properties(H5Pcreate(H5P_GROUP_CREATE), H5Pclose);
  Check(properties.get(), what);
  Check(H5Pset_obj_track_times(properties.get(), false), what);  // same run, same bytes
  Handle group(H5Gcreate2(file_.get(), name.c_str(), H5P_DEFAULT, properties.get(), H5P_DEFAULT),
               H5Gclose);
  Check(group.get(), what);
  return group;
}

void Hdf5File::WriteAttribute(const char* name, hid_t file_type, hid_t memory_type,
                              const void* value, hsize_t count) {
  const std::string what = fmt::format("attribute {}", name);
  const htri_t exists = H5Aexists(file_.get(), name);
  Check(exists, what);
  Handle attribute;
  if (exists > 0) {
    attribute = Handle(H5Aopen(file_.get(), name, H5P_DEFAULT), H5Aclose);
  } else {
    Handle space(count > 0 ? H5Screate_simple(1, &count, nullptr) : H5Screate(H5S_SCALAR),
                 H5Sclose);
    Check(space.get(), what);
    attribute = Handle(
        H5Acreate2(file_.get(), name, file_type, space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  }
  Check(attribute.get(), what);
  Check(H5Awrite(attribute.get(), memory_type, value), what);
}

void Hdf5File::WriteStringAttribute(const char* name, const std::string& value) {
  const std::string what = fmt::format("attribute {}", name);
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  Check(type.get(), what);
  Check(H5Tset_size(type.get(), value.size() + 1), what);
  Check(H5Tset_strpad(type.get(), H5T_STR_NULLTERM), what);
  WriteAttribute(name, type.get(), type.get(), value.c_str());
}

void Hdf5File::WriteStringList(const StringList& list) {
  const std::string what = fmt::format("attribute {}", list.name);
  std::size_t width = 1;
  for (const std::string& v : list.values) width = std::max(width, v.size() + 1);
  std::vector<char> text(width * list.values.size(), '\0');
  for (std::size_t i = 0; i < list.values.size(); ++i) {
    std::copy(list.values[i].begin(), list.values[i].end(), text.begin() + i * width);
  }
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  Check(type.get(), what);
  Check(H5Tset_size(type.get(), width), what);
  Check(H5Tset_strpad(type.get(), H5T_STR_NULLTERM), what);
  const hsize_t n = list.values.size();
  Handle space(H5Screate_simple(1, &n, nullptr), H5Sclose);
  Check(space.get(), what);
  Handle attribute(
      H5Acreate2(file_.get(), list.name.c_str(), type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT),
      H5Aclose);
  Check(attribute.get(), what);
  Check(H5Awrite(attribute.get(), type.get(), text.data()), what);
}

void Hdf5File::Flush() { Check(H5Fflush(file_.get(), H5F_SCOPE_LOCAL), "flush"); }

}  // namespace moreau::io::internal
