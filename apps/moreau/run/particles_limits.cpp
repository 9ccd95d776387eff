// Size and geometry checks of a particle scenario, run after every field is read.
#include <algorithm>
#include <cstdint>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/common/memory.h"
#include "moreau/common/steps.h"
#include "run/particles_scenario.h"

namespace moreau::cli {
namespace {

using PS = ParticleScenario;

void CheckOutputSize(const PS& s) {
  const std::int64_t steps = StepCount(s.T, s.solver.h);
  (void)CheckFrameCount(
      steps, s.output.stride > 0 ? s.output.stride : std::max<std::int64_t>(1, steps / 100));
  // The evacuation series is kept in memory, one line of about 24 bytes a step.
  if (s.room || s.geometry) {
    CheckMemory(fmt::format("{} steps of the evacuation series", steps),
                24.0 * static_cast<double>(steps));
  }
}

[[noreturn]] void FailOutside(const particles::Room& room, const std::string& what) {
  throw InputError(
      fmt::format("{} is outside the room [0, {}] × [0, {}]", what, room.width, room.height));
}

bool InsideTheRoom(const particles::Room& room, double x, double y) {
  return x >= 0.0 && x <= room.width && y >= 0.0 && y <= room.height;
}

// Everybody starts inside the room: every given position ...
void CheckPositionsInTheRoom(const PS& s) {
  if (!s.room || !s.positions || s.dimension != 2) return;
  const std::vector<double>& x = *s.positions;
  for (std::size_t i = 0; 2 * i + 1 < x.size(); ++i) {
    if (!InsideTheRoom(*s.room, x[2 * i], x[2 * i + 1])) {
      FailOutside(*s.room, fmt::format("position {} ({}, {})", i, x[2 * i], x[2 * i + 1]));
    }
  }
}

// ... or the random start's box (initial.lo/hi, else the domain).
void CheckStartBoxInTheRoom(const PS& s) {
  if (!s.room || s.positions || s.dimension != 2) return;
  const particles::Vec3 lo = s.initial_lo.value_or(s.domain_lo);
  const particles::Vec3 hi = s.initial_hi.value_or(s.domain_hi);
  if (!InsideTheRoom(*s.room, lo[0], lo[1]) || !InsideTheRoom(*s.room, hi[0], hi[1])) {
    FailOutside(*s.room,
                fmt::format("the start box [{}, {}] × [{}, {}]", lo[0], hi[0], lo[1], hi[1]));
  }
}

}  // namespace

void AddParticleLimitChecks(FieldTable<ParticleScenario>& table) {
  table.Check("output.stride", CheckOutputSize)
      .Check("initial.positions", CheckPositionsInTheRoom)
      .Check("domain.lo",
             [](const PS& s) {
               if (!s.initial_lo && !s.initial_hi) CheckStartBoxInTheRoom(s);
             })
      .Check("initial.lo", [](const PS& s) {
        if (s.initial_lo || s.initial_hi) CheckStartBoxInTheRoom(s);
      });
}

}  // namespace moreau::cli
