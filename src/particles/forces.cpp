#include "moreau/particles/forces.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "moreau/common/error.h"

namespace moreau::particles {

namespace {

// Separates the desired-speed stream from the Brownian noise of the same seed.
constexpr std::uint64_t kDesiredSpeedStream = 0x510e527fade682d1ULL;

void ValidateWalkingSpeeds(const WalkingSpeeds& w, const std::optional<SelfPropulsion>& p) {
  if (w.speed_sd == 0.0 && !w.density && !w.collision_free) return;
  if (!p) throw InputError("forces.walking needs forces.propulsion");
  if (!(w.speed_sd >= 0.0) || !(3.0 * w.speed_sd <= p->speed)) {
    throw InputError(fmt::format(
        "forces.walking.speed_sd must be in [0, speed/3] = [0, {}] (got {}): the truncated "
        "normal must give no negative speed",
        p->speed / 3.0, w.speed_sd));
  }
  if (w.collision_free) {
    if (w.density) {
      throw InputError("forces.walking.collision_free does not go with forces.walking.density");
    }
    try {
      w.collision_free->Validate();
    } catch (const InputError& e) {
      throw e.Under("forces.walking.collision_free");
    }
  }
  if (!w.density) return;
  const DensitySpeed& d = *w.density;
  const auto check = [](double v, const char* field) {
    if (!(v > 0.0) || !std::isfinite(v)) {
      throw InputError(fmt::format("forces.walking.density.{} must be > 0 (got {})", field, v));
    }
  };
  check(d.gamma, "gamma");
  check(d.max_density, "max_density");
  check(d.radius, "radius");
}

void ValidateClassStiffness(const std::vector<double>& K) {
  const int c = static_cast<int>(std::lround(std::sqrt(static_cast<double>(K.size()))));
  if (static_cast<std::size_t>(c) * static_cast<std::size_t>(c) != K.size()) {
    throw InputError(fmt::format(
        "forces.attraction.class_stiffness has {} entries: it must be C × C (a square)", K.size()));
  }
  const auto at = [&](int a, int b) { return K[static_cast<std::size_t>(a * c + b)]; };
  for (int a = 0; a < c; ++a) {
    for (int b = 0; b < c; ++b) {
      if (!(at(a, b) >= 0.0) || !std::isfinite(at(a, b))) {
        throw InputError(
            fmt::format("forces.attraction.class_stiffness[{}][{}] must be ≥ 0 and finite (got {})",
                        a, b, at(a, b)));
      }
      if (at(a, b) != at(b, a)) {
        throw InputError(
            fmt::format("forces.attraction.class_stiffness[{}][{}] ({}) must equal [{}][{}] ({}): "
                        "the matrix must be symmetric",
                        a, b, at(a, b), b, a, at(b, a)));
      }
    }
  }
}

void ValidateAttraction(const PairAttraction& attraction) {
  if (!(attraction.stiffness >= 0.0) || !std::isfinite(attraction.stiffness)) {
    throw InputError(
        fmt::format("forces.attraction.stiffness must be ≥ 0 (got {})", attraction.stiffness));
  }
  ValidateClassStiffness(attraction.class_stiffness);
  if (!(attraction.range >= 0.0) || !std::isfinite(attraction.range) ||
      (attraction.attracts() && !(attraction.range > 0.0))) {
    throw InputError(fmt::format("forces.attraction.range must be > 0 (got {})", attraction.range));
  }
}

}  // namespace

const FieldList<CollisionFreeSpeed>& CollisionFreeSpeed::Fields() {
  static const FieldList<CollisionFreeSpeed> list = [] {
    using C = CollisionFreeSpeed;
    FieldList<C> t;
    t.Number("time_gap", &C::time_gap, Range::Positive(), "time", "T of V(s) = (s − ℓ)/T")
        .Number("length", &C::length, Range::Positive(), "length", "ℓ, the body diameter")
        .Number("repulsion", &C::repulsion, Range::NonNegative(), "1", "a, neighbours' repulsion")
        .Number("repulsion_range", &C::repulsion_range, Range::Positive(), "length",
                "D, its range")
        .Number("wall_repulsion", &C::wall_repulsion, Range::NonNegative(), "1",
                "a_w, walls' repulsion")
        .Number("wall_repulsion_range", &C::wall_repulsion_range, Range::Positive(), "length",
                "D_w, its range");
    return t;
  }();
  return list;
}

void CollisionFreeSpeed::Validate() const { Fields().Validate(*this); }

double CollisionFreeSpeedAt(const CollisionFreeSpeed& model, double v0, double headway) {
  return std::min(v0, std::max(0.0, (headway - model.length) / model.time_gap));
}

double CollisionFreeRange(const CollisionFreeSpeed& model, double max_speed) {
  return model.length +
         std::max(model.time_gap * max_speed, 10.0 * model.repulsion_range);
}

int PairAttraction::classes() const {
  return static_cast<int>(std::lround(std::sqrt(static_cast<double>(class_stiffness.size()))));
}

bool PairAttraction::attracts() const {
  if (class_stiffness.empty()) return stiffness > 0.0;
  return std::any_of(class_stiffness.begin(), class_stiffness.end(),
                     [](double k) { return k > 0.0; });
}

void CheckAdhesionClasses(const ParticleModel& model, const Forces& forces) {
  if (!forces.attraction || forces.attraction->class_stiffness.empty()) return;
  const int c = forces.attraction->classes();
  for (std::size_t i = 0; i < model.adhesion_class.size(); ++i) {
    if (model.adhesion_class[i] >= c) {
      throw InputError(
          fmt::format("adhesion class of particle {} is {}, but "
                      "forces.attraction.class_stiffness has {} classes",
                      i, model.adhesion_class[i], c));
    }
  }
}

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
    if (propulsion->direction) {
      const Vec3& e = *propulsion->direction;
      if (!finite3(e) || e[0] * e[0] + e[1] * e[1] + e[2] * e[2] == 0.0) {
        throw InputError("forces.propulsion.direction must be finite and non-zero");
      }
    }
    if (propulsion->target_end && !finite3(*propulsion->target_end)) {
      throw InputError("forces.propulsion.target_end must be finite");
    }
  }
  ValidateWalkingSpeeds(walking, propulsion);
  if (attraction) ValidateAttraction(*attraction);
  if (!(diffusion >= 0.0) || !std::isfinite(diffusion)) {
    throw InputError(fmt::format("forces.diffusion must be ≥ 0 (got {})", diffusion));
  }
}

double DesiredSpeed(std::uint64_t seed, std::int64_t id, double mean, double sd) {
  if (sd == 0.0) return mean;
  for (std::int64_t m = 0;; ++m) {
    double z[2];
    GaussianNoise(seed ^ kDesiredSpeedStream, id, m, 2, z);
    for (double zi : z) {
      if (std::abs(zi) <= 3.0) return mean + sd * zi;
    }
  }
}

double WeidmannSpeedFactor(const DensitySpeed& law, double density) {
  if (!(density > 0.0)) return 1.0;
  if (density >= law.max_density) return 0.0;
  return -std::expm1(-law.gamma * (1.0 / density - 1.0 / law.max_density));
}

double PairListWidening(const Forces& forces, double min_radius) {
  double widening = 0.0;
  if (forces.attraction && forces.attraction->attracts()) widening = forces.attraction->range;
  if (forces.propulsion && forces.walking.density) {
    widening = std::max(widening, forces.walking.density->radius - 2.0 * min_radius);
  }
  if (forces.propulsion && forces.walking.collision_free) {
    const double v_max = forces.propulsion->speed + 3.0 * forces.walking.speed_sd;
    widening = std::max(
        widening, CollisionFreeRange(*forces.walking.collision_free, v_max) - 2.0 * min_radius);
  }
  return widening;
}

}  // namespace moreau::particles
