#include "moreau/particles/model.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "moreau/common/error.h"

namespace moreau::particles {

double ParticleModel::max_radius() const {
  return radius.empty() ? 0.0 : *std::max_element(radius.begin(), radius.end());
}

void ParticleModel::AddBoxWalls(const Vec3& lo, const Vec3& hi) {
  for (int a = 0; a < dimension; ++a) {
    const auto ua = static_cast<std::size_t>(a);
    if (periodic[ua]) continue;
    Wall low;
    low.normal = {0.0, 0.0, 0.0};
    low.normal[ua] = 1.0;
    low.offset = lo[ua];
    walls.push_back(low);
    Wall high;
    high.normal = {0.0, 0.0, 0.0};
    high.normal[ua] = -1.0;
    high.offset = -hi[ua];
    walls.push_back(high);
  }
}

namespace {

// The walls, sphere obstacles and segment obstacles of ParticleModel::Validate.
void ValidateFixedSets(const ParticleModel& model) {
  const auto k = static_cast<std::size_t>(model.dimension);
  for (std::size_t w = 0; w < model.walls.size(); ++w) {
    double n2 = 0.0;
    bool finite = std::isfinite(model.walls[w].offset);
    for (std::size_t a = 0; a < k; ++a) {
      n2 += model.walls[w].normal[a] * model.walls[w].normal[a];
      finite = finite && std::isfinite(model.walls[w].normal[a]);
    }
    if (!finite) throw InputError(fmt::format("walls[{}] must be finite", w));
    if (!(n2 > 0.0)) throw InputError(fmt::format("walls[{}].normal must be non-zero", w));
  }
  for (std::size_t s = 0; s < model.spheres.size(); ++s) {
    if (!(model.spheres[s].radius > 0.0) || !std::isfinite(model.spheres[s].radius)) {
      throw InputError(
          fmt::format("spheres[{}].radius must be > 0 (got {})", s, model.spheres[s].radius));
    }
    for (std::size_t a = 0; a < k; ++a) {
      if (!std::isfinite(model.spheres[s].center[a])) {
        throw InputError(fmt::format("spheres[{}].center must be finite", s));
      }
    }
  }
  for (std::size_t s = 0; s < model.segments.size(); ++s) {
    if (model.dimension != 2) {
      throw InputError(
          fmt::format("segments need dimension 2 (segments[{}] given in {}D)", s, model.dimension));
    }
    const auto& g = model.segments[s];
    if (!std::isfinite(g.a[0]) || !std::isfinite(g.a[1]) || !std::isfinite(g.b[0]) ||
        !std::isfinite(g.b[1])) {
      throw InputError(fmt::format("segments[{}] must be finite", s));
    }
    if (g.a[0] == g.b[0] && g.a[1] == g.b[1]) {
      throw InputError(fmt::format("segments[{}] needs a ≠ b", s));
    }
  }
}

}  // namespace

void ParticleModel::Validate() const {
  if (dimension < 1 || dimension > 3) {
    throw InputError(fmt::format("dimension must be 1, 2 or 3 (got {})", dimension));
  }
  if (radius.empty()) throw InputError("a particle model needs at least one particle");
  for (std::size_t i = 0; i < radius.size(); ++i) {
    if (!(radius[i] > 0.0) || !std::isfinite(radius[i])) {
      throw InputError(fmt::format("radius of particle {} must be > 0 (got {})", i, radius[i]));
    }
  }
  if (!mobility.empty() && mobility.size() != radius.size()) {
    throw InputError(
        fmt::format("mobility has {} entries for {} particles", mobility.size(), radius.size()));
  }
  if (!stable_ids.empty() && stable_ids.size() != radius.size()) {
    throw InputError(fmt::format("stable_ids has {} entries for {} particles", stable_ids.size(),
                                 radius.size()));
  }
  for (std::size_t i = 0; i < stable_ids.size(); ++i) {
    if (stable_ids[i] < 0 || stable_ids[i] >= (std::int64_t{1} << 62)) {
      throw InputError(
          fmt::format("stable id of particle {} must be in [0, 2^62) (got {})", i, stable_ids[i]));
    }
  }
  if (!adhesion_class.empty() && adhesion_class.size() != radius.size()) {
    throw InputError(fmt::format("adhesion_class has {} entries for {} particles",
                                 adhesion_class.size(), radius.size()));
  }
  for (std::size_t i = 0; i < adhesion_class.size(); ++i) {
    if (adhesion_class[i] < 0) {
      throw InputError(
          fmt::format("adhesion class of particle {} must be ≥ 0 (got {})", i, adhesion_class[i]));
    }
  }
  for (std::size_t i = 0; i < mobility.size(); ++i) {
    if (!(mobility[i] > 0.0) || !std::isfinite(mobility[i])) {
      throw InputError(fmt::format("mobility of particle {} must be > 0 (got {})", i, mobility[i]));
    }
  }
  ValidateFixedSets(*this);
  const auto k = static_cast<std::size_t>(dimension);
  const double rmax = max_radius();
  for (std::size_t a = 0; a < k; ++a) {
    if (!periodic[a]) continue;
    const double lo = domain_lo[a];
    const double hi = domain_hi[a];
    if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo < hi)) {
      throw InputError(
          fmt::format("domain of periodic axis {} needs lo < hi (got [{}, {}))", a, lo, hi));
    }
    if (!(4.0 * rmax < hi - lo)) {
      const auto it = std::max_element(radius.begin(), radius.end());
      throw InputError(fmt::format(
          "radius of particle {} ({}) is too large for periodic axis {} of length {}: need 4 r < L",
          it - radius.begin(), rmax, a, hi - lo));
    }
  }
}

}  // namespace moreau::particles
