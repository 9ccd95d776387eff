// libFuzzer target: TOML text → every command's scenario reader (run: particles and the paper's
// steppers, control, sweep). Bad input must end in moreau::InputError (the CLI's exit 2); any
// other exception, a crash or a sanitizer report is a finding.
#include <cstddef>
#include <cstdint>

#include "control/control_scenario.h"
#include "fuzz_input_file.h"
#include "moreau/common/error.h"
#include "run/particles_scenario.h"
#include "run/pbd_scenario.h"
#include "scenario.h"
#include "sweep/sweep_scenario.h"

namespace {

template <typename Reader>
void Read(const std::string& path, Reader&& read) {
  try {
    moreau::cli::Scenario scenario = moreau::cli::Scenario::Load(path, {});
    read(scenario);
    scenario.CheckAllKeysUsed();
  } catch (const moreau::InputError&) {
    // expected for bad input
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace moreau::cli;
  const std::string path = moreau::fuzz::WriteInputFile(data, size, ".toml");
  Read(path, [](Scenario& s) { ReadParticleScenario(s, false); });
  Read(path, [](Scenario& s) { ReadPbdScenario(s); });
  Read(path, [](Scenario& s) { ReadControlScenario(s); });
  Read(path, [](Scenario& s) { ReadSweepScenario(s); });
  return 0;
}
