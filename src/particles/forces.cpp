#include "moreau/particles/forces.h"

#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/common/random.h"

namespace moreau::particles {

void Forces::Validate() const {
  auto finite3 = [](const Vec3& v) {
    return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
  };
  if (trap) {
    if (!(trap->gamma >= 0.0) || !std::isfinite(trap->gamma)) {
      throw InputError(fmt::format("forces.trap.gamma must be ≥ 0 (got {})", trap->gamma));
    }
    if (!finite3(trap->center)) throw InputError("forces.trap.center must be finite");
  }
  if (!finite3(constant_force)) throw InputError("forces.constant_force must be finite");
  if (propulsion) {
    if (!(propulsion->speed >= 0.0) || !std::isfinite(propulsion->speed)) {
      throw InputError(
          fmt::format("forces.propulsion.speed must be ≥ 0 (got {})", propulsion->speed));
    }
    if (!finite3(propulsion->target)) throw InputError("forces.propulsion.target must be finite");
    if (propulsion->exit_direction) {
      const Vec3& e = *propulsion->exit_direction;
      if (!finite3(e) || e[0] * e[0] + e[1] * e[1] + e[2] * e[2] == 0.0) {
        throw InputError("forces.propulsion.exit_direction must be finite and non-zero");
      }
    }
    if (propulsion->target_end && !finite3(*propulsion->target_end)) {
      throw InputError("forces.propulsion.target_end must be finite");
    }
  }
  if (attraction) {
    if (!(attraction->stiffness >= 0.0) || !std::isfinite(attraction->stiffness)) {
      throw InputError(
          fmt::format("forces.attraction.stiffness must be ≥ 0 (got {})", attraction->stiffness));
    }
    if (!(attraction->range >= 0.0) || !std::isfinite(attraction->range) ||
        (attraction->stiffness > 0.0 && !(attraction->range > 0.0))) {
      throw InputError(
          fmt::format("forces.attraction.range must be > 0 (got {})", attraction->range));
    }
  }
  if (!(diffusion >= 0.0) || !std::isfinite(diffusion)) {
    throw InputError(fmt::format("forces.diffusion must be ≥ 0 (got {})", diffusion));
  }
}

void GaussianNoise(std::uint64_t seed, std::int64_t id, std::int64_t step, int k, double* out) {
  const std::array<std::uint32_t, 2> key{static_cast<std::uint32_t>(seed),
                                         static_cast<std::uint32_t>(seed >> 32)};
  const auto ustep = static_cast<std::uint64_t>(step);
  for (int block = 0; 2 * block < k; ++block) {
    const auto w =
        Philox4x32({static_cast<std::uint32_t>(id),
                    static_cast<std::uint32_t>(block) |
                        static_cast<std::uint32_t>(static_cast<std::uint64_t>(id) >> 32 << 2),
                    static_cast<std::uint32_t>(ustep), static_cast<std::uint32_t>(ustep >> 32)},
                   key);
    // Two uniforms in (0, 1) from 53 bits each (the +0.5 keeps them off 0 and 1).
    const std::uint64_t a = (static_cast<std::uint64_t>(w[0]) << 32 | w[1]) >> 11;
    const std::uint64_t b = (static_cast<std::uint64_t>(w[2]) << 32 | w[3]) >> 11;
    const double u1 = (static_cast<double>(a) + 0.5) * 0x1.0p-53;
    const double u2 = (static_cast<double>(b) + 0.5) * 0x1.0p-53;
    const double radius = std::sqrt(-2.0 * std::log(u1));
    const double angle = 2.0 * std::numbers::pi * u2;
    out[2 * block] = radius * std::cos(angle);
    if (2 * block + 1 < k) out[2 * block + 1] = radius * std::sin(angle);
  }
}

}  // namespace moreau::particles
