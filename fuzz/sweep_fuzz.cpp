// libFuzzer target: TOML text → the sweep file (ReadSweepScenario: the keys, axes, seeds, zipped
// or crossed grid), then what `moreau sweep` does with it before any run: the settings echoed as
// JSON, and for the first runs their overrides, their hash and the overrides applied to a
// scenario (as each run's scenario gets them). Bad input must end in moreau::InputError (the
// CLI's exit 2); any other exception, a crash or a sanitizer report is a finding.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_input_file.h"
#include "moreau/common/error.h"
#include "moreau/common/summary_json.h"
#include "moreau/sweep/grid.h"
#include "scenario.h"
#include "sweep/sweep_scenario.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace moreau;
  const std::string path = fuzz::WriteInputFile(data, size, ".toml");
  try {
    cli::Scenario file = cli::Scenario::Load(path, {});
    const cli::SweepScenario sweep = cli::ReadSweepScenario(file);
    file.CheckAllKeysUsed();
    (void)JsonText(cli::EchoSweepScenario(sweep));
    const std::int64_t runs = std::min<std::int64_t>(sweep.grid.RunCount(), 64);
    for (std::int64_t i = 0; i < runs; ++i) {
      (void)sweep::RunHash(sweep.context, sweep.grid.Run(i));
      const cli::Scenario run = cli::Scenario::FromCommandLine(sweep.Overrides(i));
      (void)run.Has("problem.seed");
    }
  } catch (const InputError&) {
    // expected for bad input
  }
  return 0;
}
