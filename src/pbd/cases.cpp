#include "moreau/pbd/cases.h"

#include <cmath>
#include <fmt/format.h>
#include <numbers>

#include "moreau/common/error.h"
#include "moreau/common/random.h"

namespace moreau::pbd {

void SlidingCase::Validate() const {
  if (dimension < 3) throw InputError(fmt::format("dimension must be ≥ 3 (got {})", dimension));
  if (!(C > 0.0) || !std::isfinite(C)) throw InputError(fmt::format("C must be > 0 (got {})", C));
  if (!(alpha > 0.0 && alpha < std::numbers::pi)) {
    throw InputError(fmt::format("alpha must be in (0, π) (got {})", alpha));
  }
  if (!(T > 0.0) || !std::isfinite(T)) throw InputError(fmt::format("T must be > 0 (got {})", T));
}

double SlidingCase::radius() const { return std::sqrt(1.0 + C * C); }

double SlidingCase::c1() const {
  return 0.5 * std::log((1.0 - std::cos(alpha)) / (1.0 + std::cos(alpha)));
}

double SlidingCase::sliding_end_time() const { return std::max(0.0, -c1()); }

std::unique_ptr<ConstraintSetList> SlidingCase::MakeConstraints() const {
  Validate();
  const int d = dimension;
  auto list = std::make_unique<ConstraintSetList>(d);
  for (int j = 1; j <= d - 2; ++j) {
    Vector c = Vector::Zero(d);
    c[j + 1] = C;  // C e_{j+2} in 1-based numbering
    list->Add(std::make_unique<BallExterior>(c, radius()));
  }
  Vector last = Vector::Zero(d);
  last.tail(d - 2).setConstant(-C / std::sqrt(static_cast<double>(d - 2)));
  list->Add(std::make_unique<BallExterior>(last, radius()));
  return list;
}

std::unique_ptr<Drift> SlidingCase::MakeDrift() const {
  Vector f = Vector::Zero(dimension);
  f[1] = -1.0;
  return std::make_unique<ConstantDrift>(f);
}

Vector SlidingCase::InitialState() const {
  Vector x = Vector::Zero(dimension);
  x[0] = std::sin(alpha);
  x[1] = std::cos(alpha);
  return x;
}

Vector SlidingCase::ExactSolution(double t) const {
  Vector x = Vector::Zero(dimension);
  if (alpha >= 0.5 * std::numbers::pi) {
    // Starts below the equator: no contact, free motion straight down.
    x[0] = std::sin(alpha);
    x[1] = std::cos(alpha) - t;
    return x;
  }
  const double ts = sliding_end_time();
  if (t <= ts) {
    // tan(θ/2) = e^{c_1 + t}, θ the angle from e_2: x_1 = sin θ, x_2 = cos θ.
    const double e = std::exp(2.0 * (c1() + t));
    x[0] = 2.0 * std::exp(c1() + t) / (1.0 + e);
    x[1] = (1.0 - e) / (1.0 + e);
  } else {
    x[0] = 1.0;
    x[1] = -(t - ts);
  }
  return x;
}

Vector SlidingCase::ExactVelocity(double t) const {
  Vector v = Vector::Zero(dimension);
  if (alpha >= 0.5 * std::numbers::pi || t > sliding_end_time()) {
    v[1] = -1.0;
    return v;
  }
  // θ' = sin θ on the circle x = (sin θ, cos θ): v = sin θ (cos θ, −sin θ).
  const Vector x = ExactSolution(t);
  v[0] = x[0] * x[1];
  v[1] = -x[0] * x[0];
  return v;
}

void DisksCase::Validate() const {
  if (count < 1 || count > kMaxCount) {
    throw InputError(fmt::format("count must be between 1 and {} (the start tests all N²/2 "
                                 "pairs; got {})",
                                 kMaxCount, count));
  }
  if (!(radius > 0.0) || !std::isfinite(radius)) {
    throw InputError(fmt::format("radius must be > 0 (got {})", radius));
  }
  if (!std::isfinite(gamma)) throw InputError("gamma must be finite");
  if (!(T > 0.0) || !std::isfinite(T)) throw InputError(fmt::format("T must be > 0 (got {})", T));
  if (!(box >= 0.0)) throw InputError(fmt::format("box must be ≥ 0 (got {})", box));
  if (box > 0.0 && box < radius) {
    throw InputError(fmt::format("box half-width {} is smaller than the radius {}", box, radius));
  }
}

double DisksCase::box_half_width() const {
  return box > 0.0 ? box : radius * std::sqrt(std::numbers::pi * count);
}

particles::ParticleModel DisksCase::MakeModel() const {
  Validate();
  particles::ParticleModel model;
  model.dimension = 2;
  model.radius.assign(static_cast<std::size_t>(count), radius);
  if (wall) model.walls.push_back(particles::Wall{{0.0, 1.0, 0.0}, *wall});
  return model;
}

std::unique_ptr<Drift> DisksCase::MakeDrift() const {
  return std::make_unique<HarmonicDrift>(gamma);
}

Vector DisksCase::InitialState() const {
  Validate();
  const double L = box_half_width();
  const double xlo = -L + radius;
  const double xhi = L - radius;
  const double ylo = wall ? std::max(xlo, *wall + radius) : xlo;
  if (xhi < xlo || xhi < ylo) {
    throw InputError(fmt::format("disks of radius {} do not fit in the box [-{}, {}]² above the wall",
                                 radius, L, L));
  }
  SplitMix64 rng(seed);
  Vector x(2 * count);
  const double min_d2 = 4.0 * radius * radius;
  constexpr int kMaxAttempts = 100000;
  for (int i = 0; i < count; ++i) {
    bool placed = false;
    for (int attempt = 0; attempt < kMaxAttempts && !placed; ++attempt) {
      const double px = xlo + (xhi - xlo) * rng.Uniform01();
      const double py = ylo + (xhi - ylo) * rng.Uniform01();
      placed = true;
      for (int j = 0; j < i && placed; ++j) {
        const double dx = px - x[2 * j];
        const double dy = py - x[2 * j + 1];
        placed = dx * dx + dy * dy >= min_d2;
      }
      if (placed) {
        x[2 * i] = px;
        x[2 * i + 1] = py;
      }
    }
    if (!placed) {
      throw InputError(fmt::format(
          "could not place {} disks of radius {} without overlap in [-{}, {}]² (placed {})", count,
          radius, L, L, i));
    }
  }
  return x;
}

}  // namespace moreau::pbd
