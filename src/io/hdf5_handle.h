// RAII handles of HDF5 identifiers and the text of HDF5's last error (internal).
#pragma once

#include <hdf5.h>

#include <string>
#include <utility>

namespace moreau::io::internal {

class Handle {
 public:
  using Closer = herr_t (*)(hid_t);
  Handle() = default;
  Handle(hid_t id, Closer closer) : id_(id), closer_(closer) {}
  Handle(Handle&& other) noexcept
      : id_(std::exchange(other.id_, H5I_INVALID_HID)), closer_(other.closer_) {}
  Handle& operator=(Handle&& other) noexcept {
    if (this != &other) {
      Reset();
      id_ = std::exchange(other.id_, H5I_INVALID_HID);
      closer_ = other.closer_;
    }
    return *this;
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() { Reset(); }

  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }
  // Closes the identifier; returns false if HDF5 reported an error.
  bool Reset() {
    if (id_ < 0) return true;
    const herr_t status = closer_(id_);
    id_ = H5I_INVALID_HID;
    return status >= 0;
  }

 private:
  hid_t id_ = H5I_INVALID_HID;
  Closer closer_ = nullptr;
};

inline herr_t KeepInnermostError(unsigned /*n*/, const H5E_error2_t* error, void* client_data) {
  auto* text = static_cast<std::string*>(client_data);
  if (text->empty() && error != nullptr && error->desc != nullptr) *text = error->desc;
  return 0;
}

// The description of the innermost error on HDF5's current error stack (which it clears), on one
// line. A failed system call's description spans lines (time, file, descriptor, errno, the system's
// message, buffer, sizes): it is cut to its first words and the system's message, "file write
// failed: File too large".
inline std::string Hdf5ErrorText() {
  std::string text;
  const hid_t stack = H5Eget_current_stack();
  if (stack >= 0) {
    H5Ewalk2(stack, H5E_WALK_UPWARD, KeepInnermostError, &text);
    H5Eclose_stack(stack);
  }
  if (text.empty()) return "unknown HDF5 error";
  const std::string::size_type message = text.find("error message = '");
  const std::string::size_type colon = text.find(':');
  if (message != std::string::npos && colon < message) {
    const std::string::size_type start = message + 17;
    return text.substr(0, colon) + ": " + text.substr(start, text.find('\'', start) - start);
  }
  for (char& c : text) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  return text;
}

}  // namespace moreau::io::internal
