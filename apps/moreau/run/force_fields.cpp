#include "run/force_fields.h"

#include <algorithm>
#include <vector>

#include <fmt/format.h>

#include "moreau/common/error.h"

namespace moreau::cli {

using particles::Vec3;

std::optional<Vec3> ReadVec(Scenario& sc, const std::string& key, int k) {
  if (!sc.Has(key)) {
    (void)sc.GetNode(key);
    return std::nullopt;
  }
  const std::vector<double> v = sc.GetDoubleArray(key, {});
  if (static_cast<int>(v.size()) != k) {
    sc.Fail(key, fmt::format("expected {} numbers (the dimension), got {}", k, v.size()));
  }
  Vec3 out{0.0, 0.0, 0.0};
  std::copy(v.begin(), v.end(), out.begin());
  return out;
}

nlohmann::json EchoVec(const Vec3& v, int k) {
  return std::vector<double>(v.begin(), v.begin() + k);
}

nlohmann::json EchoVec(const std::optional<Vec3>& v, int k) {
  return v ? EchoVec(*v, k) : nlohmann::json();
}

void AddForceFields(FieldTable<ParticleScenario>& t) {
  const auto f = [](auto& s) -> auto& { return s.forces; };
  FieldTable<ParticleForceSettings> sub;
  using F = ParticleForceSettings;
  sub.OptionalNumber("trap_gamma", &F::trap_gamma, Range::NonNegative(), "harmonic trap γ")
      .OptionalNumber("propulsion_speed", &F::propulsion_speed, Range::NonNegative(),
                      "walking speed v0")
      .Number("propulsion_speed_sd", &F::propulsion_speed_sd, Range::NonNegative(), "σ_v of v0,i")
      .OptionalNumber("density_radius", &F::density_radius, Range::Positive(),
                      "R of ρ_i (Weidmann)")
      .OptionalNumber("density_gamma", &F::density_gamma, Range::Positive(), "Weidmann γ (1.913)")
      .OptionalNumber("density_max", &F::density_max, Range::Positive(), "Weidmann ρ_max (5.4)")
      .OptionalNumber("attraction_stiffness", &F::attraction_stiffness, Range::NonNegative(),
                      "pair attraction k")
      .OptionalNumber("attraction_range", &F::attraction_range, Range::Positive(), "its range ℓ")
      .Number("diffusion", &F::diffusion, Range::NonNegative(), "diffusion D (noise)")
      .Choice(
          "pedestrian_model", &F::pedestrian_model,
          [](const std::string& name) {
            if (name != "propulsion" && name != "collision_free") {
              throw InputError(fmt::format(
                  "unknown pedestrian model '{}' (propulsion, collision_free)", name));
            }
            return name;
          },
          [](const std::string& name) { return name; }, "propulsion, collision_free",
          "walking speed and direction: v0,i toward the target, or the collision-free speed "
          "model (forces.collision_free.*)")
      .Mount("collision_free", &F::collision_free, particles::CollisionFreeSpeed::Fields())
      .Check("propulsion_speed_sd", [](const F& s) {
        if (s.propulsion_speed && 3.0 * s.propulsion_speed_sd > *s.propulsion_speed) {
          throw InputError(
              fmt::format("must be at most propulsion_speed / 3 = {} (got {}): the "
                          "truncated normal must give no negative speed",
                          *s.propulsion_speed / 3.0, s.propulsion_speed_sd));
        }
      });
  t.Mount("forces", f, sub);
  AddVec(
      t, "forces.trap_center", [](auto& s) -> auto& { return s.forces.trap_center; },
      "trap centre");
  AddVec(
      t, "forces.constant", [](auto& s) -> auto& { return s.forces.constant; }, "force f");
  AddVec(
      t, "forces.target", [](auto& s) -> auto& { return s.forces.target; }, "walking target");
  AddVec(
      t, "forces.target_end", [](auto& s) -> auto& { return s.forces.target_end; },
      "the target is the segment [target, target_end]");
  AddVec(
      t, "forces.direction", [](auto& s) -> auto& { return s.forces.direction; },
      "one desired walking direction everywhere (a corridor, a ring)");
}

particles::Forces ParticleScenario::MakeForces() const {
  particles::Forces f;
  const ParticleForceSettings& in = forces;
  if (in.trap_gamma) f.trap = particles::HarmonicTrap{*in.trap_gamma, in.trap_center};
  f.constant_force = in.constant;
  if (in.propulsion_speed || room || route) {
    const double speed = in.propulsion_speed.value_or(1.0);
    if (room) {
      // The collision-free model steers at the door shrunk by its body radius ℓ/2 (room.h).
      const bool walk = in.pedestrian_model == "collision_free";
      f.propulsion = room->WalkToTheDoor(speed, walk ? 0.5 * in.collision_free.length : 0.0);
    } else if (route) {
      particles::SelfPropulsion p;
      p.speed = speed;
      p.route = route;
      f.propulsion = p;
    } else {
      particles::SelfPropulsion p;
      p.speed = speed;
      p.target = in.target.value_or(Vec3{0.0, 0.0, 0.0});
      p.target_end = in.target_end;
      p.direction = in.direction;
      f.propulsion = p;
    }
  }
  f.walking.speed_sd = in.propulsion_speed_sd;
  if (in.density_radius) {
    particles::DensitySpeed& law = f.walking.density.emplace();
    law.radius = *in.density_radius;
    law.gamma = in.density_gamma.value_or(law.gamma);
    law.max_density = in.density_max.value_or(law.max_density);
  }
  if (in.pedestrian_model == "collision_free") f.walking.collision_free = in.collision_free;
  // population.adhesion alone: the pairs it does not name do not attract.
  if (in.attraction_stiffness || (in.attraction_range && !population.rules.adhesion.empty())) {
    f.attraction = particles::PairAttraction{
        in.attraction_stiffness.value_or(0.0), in.attraction_range.value_or(0.0), {}};
  }
  f.diffusion = in.diffusion;
  f.Validate();
  return f;
}

}  // namespace moreau::cli
