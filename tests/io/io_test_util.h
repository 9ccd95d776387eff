// Helpers of the io tests (trajectory_test.cpp, grid_writer_test.cpp): temporary directories, the
// text of a file, enough XML to check our own files, base64 and VTK's inline binary arrays, and
// HDF5 read back through the C API.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

// moreau links HDF5 privately, so its include directory does not reach the tests; Debian keeps
// the headers in hdf5/serial/ (their own includes are relative, so this path works).
#if __has_include(<hdf5.h>)
#include <hdf5.h>
#else
#include <hdf5/serial/hdf5.h>
#endif

namespace moreau::io::test_util {

namespace fs = std::filesystem;

// A fresh directory under the system temp directory, removed with everything in it.
class TempDir {
 public:
  TempDir() {
    static std::atomic<int> counter{0};
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() /
            ("moreau_io_" + std::to_string(::getpid()) + "_" + std::to_string(counter++) + "_" +
             (info != nullptr ? std::string(info->name()) : std::string("test")));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::permissions(path_, fs::perms::owner_all, fs::perm_options::add, ec);
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

inline std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline std::size_t CountOccurrences(const std::string& text, const std::string& needle) {
  std::size_t n = 0;
  for (std::size_t p = text.find(needle); p != std::string::npos; p = text.find(needle, p + 1)) ++n;
  return n;
}

// Checks that start and end tags nest properly (enough XML for our own files: no CDATA, no '>'
// inside attribute values). Returns an empty string when they do, else what went wrong.
inline std::string XmlNestingError(const std::string& text) {
  std::vector<std::string> open;
  std::size_t p = 0;
  while ((p = text.find('<', p)) != std::string::npos) {
    const std::size_t end = text.find('>', p);
    if (end == std::string::npos) return "unterminated tag";
    const std::string tag = text.substr(p + 1, end - p - 1);
    p = end + 1;
    if (tag.empty()) return "empty tag";
    if (tag[0] == '?' || tag[0] == '!') continue;
    if (tag[0] == '/') {
      const std::string name = tag.substr(1);
      if (open.empty() || open.back() != name) return "unexpected </" + name + ">";
      open.pop_back();
      continue;
    }
    if (tag.back() == '/') continue;
    open.push_back(tag.substr(0, tag.find_first_of(" \t\n")));
  }
  return open.empty() ? std::string() : "unclosed <" + open.back() + ">";
}

// The value of attribute `name` in the first element at or after `from` that has it.
inline std::string AttributeValue(const std::string& text, const std::string& name,
                                  std::size_t from = 0) {
  const std::string key = " " + name + "=\"";
  const std::size_t p = text.find(key, from);
  if (p == std::string::npos) return {};
  const std::size_t start = p + key.size();
  return text.substr(start, text.find('"', start) - start);
}

inline std::vector<unsigned char> DecodeBase64(const std::string& text) {
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
  };
  std::vector<unsigned char> out;
  unsigned buffer = 0;
  int bits = 0;
  for (const char c : text) {
    const int v = value(c);
    if (v < 0) continue;  // whitespace and '=' padding
    buffer = (buffer << 6) | static_cast<unsigned>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<unsigned char>((buffer >> bits) & 0xFFu));
    }
  }
  return out;
}

// The values of the inline binary DataArray `name` of a VTU file: checks the format and the
// UInt64 byte-count header, returns the payload as T.
template <typename T>
inline std::vector<T> VtuArray(const std::string& vtu, const std::string& name,
                               const std::string& type, int components) {
  const std::size_t p = vtu.find("Name=\"" + name + "\"");
  EXPECT_NE(p, std::string::npos) << name;
  if (p == std::string::npos) return {};
  const std::size_t tag_start = vtu.rfind('<', p);
  EXPECT_EQ(AttributeValue(vtu, "type", tag_start), type) << name;
  EXPECT_EQ(AttributeValue(vtu, "format", tag_start), "binary") << name;
  EXPECT_EQ(AttributeValue(vtu, "NumberOfComponents", tag_start), std::to_string(components));
  const std::size_t body = vtu.find('>', p) + 1;
  const std::vector<unsigned char> raw =
      DecodeBase64(vtu.substr(body, vtu.find("</DataArray>", body) - body));
  std::uint64_t bytes = 0;
  EXPECT_GE(raw.size(), sizeof(bytes));
  if (raw.size() < sizeof(bytes)) return {};
  std::memcpy(&bytes, raw.data(), sizeof(bytes));
  EXPECT_EQ(bytes, raw.size() - sizeof(bytes)) << name;
  EXPECT_EQ(bytes % sizeof(T), 0u) << name;
  std::vector<T> values((raw.size() - sizeof(bytes)) / sizeof(T));
  if (!values.empty())
    std::memcpy(values.data(), raw.data() + sizeof(bytes), values.size() * sizeof(T));
  return values;
}

template <typename T>
inline bool SameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// --- HDF5 reading through the C API -----------------------------------------------------------

class H5 {
 public:
  H5(hid_t id, herr_t (*closer)(hid_t)) : id_(id), closer_(closer) {}
  ~H5() {
    if (id_ >= 0) closer_(id_);
  }
  H5(const H5&) = delete;
  H5& operator=(const H5&) = delete;
  hid_t get() const { return id_; }

 private:
  hid_t id_;
  herr_t (*closer_)(hid_t);
};

struct DatasetInfo {
  std::vector<hsize_t> dims, max_dims, chunk;
  bool chunked = false;
  bool file_type_ok = false;
  std::vector<H5Z_filter_t> filters;  // in pipeline order
  unsigned deflate_level = 0;         // the deflate filter's level, when it is there
  hsize_t storage_bytes = 0;          // bytes allocated in the file
};

// Reads the whole dataset `name` as `memory_type` into `values` and describes it; checks that
// the stored type equals `file_type`.
template <typename T>
inline DatasetInfo ReadDataset(hid_t file, const char* name, hid_t memory_type, hid_t file_type,
                               std::vector<T>& values) {
  DatasetInfo info;
  H5 dataset(H5Dopen2(file, name, H5P_DEFAULT), H5Dclose);
  EXPECT_GE(dataset.get(), 0) << name;
  if (dataset.get() < 0) return info;
  H5 space(H5Dget_space(dataset.get()), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(space.get());
  info.dims.resize(static_cast<std::size_t>(rank));
  info.max_dims.resize(static_cast<std::size_t>(rank));
  H5Sget_simple_extent_dims(space.get(), info.dims.data(), info.max_dims.data());
  H5 type(H5Dget_type(dataset.get()), H5Tclose);
  info.file_type_ok = H5Tequal(type.get(), file_type) > 0;
  H5 properties(H5Dget_create_plist(dataset.get()), H5Pclose);
  info.chunked = H5Pget_layout(properties.get()) == H5D_CHUNKED;
  if (info.chunked) {
    info.chunk.resize(static_cast<std::size_t>(rank));
    H5Pget_chunk(properties.get(), rank, info.chunk.data());
  }
  for (int i = 0; i < H5Pget_nfilters(properties.get()); ++i) {
    unsigned flags = 0, level = 0;
    std::size_t element_count = 1;
    const H5Z_filter_t filter = H5Pget_filter2(properties.get(), static_cast<unsigned>(i), &flags,
                                               &element_count, &level, 0, nullptr, nullptr);
    info.filters.push_back(filter);
    if (filter == H5Z_FILTER_DEFLATE) info.deflate_level = level;
  }
  info.storage_bytes = H5Dget_storage_size(dataset.get());
  hsize_t elements = 1;
  for (const hsize_t d : info.dims) elements *= d;
  values.assign(elements, T{});
  if (elements > 0) {
    EXPECT_GE(H5Dread(dataset.get(), memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), 0);
  }
  return info;
}

template <typename T>
inline T ReadScalarAttribute(hid_t file, const char* name, hid_t memory_type) {
  T value{};
  H5 attribute(H5Aopen(file, name, H5P_DEFAULT), H5Aclose);
  EXPECT_GE(attribute.get(), 0) << name;
  if (attribute.get() >= 0) {
    EXPECT_GE(H5Aread(attribute.get(), memory_type, &value), 0) << name;
  }
  return value;
}

inline std::string ReadStringAttribute(hid_t file, const char* name) {
  H5 attribute(H5Aopen(file, name, H5P_DEFAULT), H5Aclose);
  EXPECT_GE(attribute.get(), 0) << name;
  if (attribute.get() < 0) return {};
  H5 type(H5Aget_type(attribute.get()), H5Tclose);
  std::string value(H5Tget_size(type.get()), '\0');
  EXPECT_GE(H5Aread(attribute.get(), type.get(), value.data()), 0);
  return value.substr(0, value.find('\0'));
}

}  // namespace moreau::io::test_util
