// libFuzzer target: bytes → the gap list of `fill-gaps --gaps` (ReadGapList: the CSV rows
// marker,first_frame,last_frame checked against a recording), then what fill-gaps does with the
// rows: the samples deleted and every gap filled (linear and pca). Bad input must end in
// moreau::InputError (the CLI's exit 2); any other exception, a crash or a sanitizer report is
// a finding.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fill_gaps/fill_gaps_scenario.h"
#include "fuzz_input_file.h"
#include "moreau/common/error.h"
#include "moreau/mocap/gap_fill.h"
#include "moreau/mocap/recording.h"

namespace {

// Five markers named as in a lab (labels may be given instead of indices) on 120 frames at
// 100 Hz, moving smoothly and observed everywhere.
const moreau::mocap::Recording& Subject() {
  static const moreau::mocap::Recording recording = [] {
    moreau::mocap::Recording r({"LASI", "RASI", "LKNE", "RKNE", "C7"}, 120, 100.0, "mm");
    for (std::int64_t f = 0; f < r.frames(); ++f) {
      for (int m = 0; m < r.markers(); ++m) {
        const double t = 0.01 * static_cast<double>(f);
        r.SetPoint(f, m, {100.0 * m + 10.0 * std::sin(t + m), 50.0 * std::cos(t), 900.0 - 100.0 * m});
      }
    }
    return r;
  }();
  return recording;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace moreau;
  const std::string path = fuzz::WriteInputFile(data, size, ".csv");
  const mocap::Recording& truth = Subject();
  try {
    const std::vector<mocap::Gap> deletions = cli::ReadGapList(path, truth);
    mocap::Recording gapped = truth;
    for (const mocap::Gap& d : deletions) {
      for (std::int64_t f = d.first; f <= d.last; ++f) gapped.ClearPoint(f, d.marker);
    }
    for (const mocap::GapFillMethod method :
         {mocap::GapFillMethod::kLinear, mocap::GapFillMethod::kPca}) {
      mocap::GapFillOptions options;
      options.method = method;
      mocap::Recording filled;
      (void)mocap::FillGaps(gapped, mocap::FindGaps(gapped), options, &filled);
    }
  } catch (const InputError&) {
    // expected for bad input
  }
  return 0;
}
