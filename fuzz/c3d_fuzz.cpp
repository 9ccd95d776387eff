// libFuzzer target: bytes → the C3D reader (and its ReadOptions defaults). Bad input must end in
// moreau::InputError; any other exception, a crash or a sanitizer report is a finding.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fuzz_input_file.h"
#include "moreau/common/error.h"
#include "moreau/mocap/recording_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = moreau::fuzz::WriteInputFile(data, size, ".c3d");
  try {
    std::vector<std::string> warnings;
    [[maybe_unused]] const moreau::mocap::Recording recording =
        moreau::mocap::ReadC3d(path, {}, &warnings);
  } catch (const moreau::InputError&) {
    // expected for bad input
  }
  return 0;
}
