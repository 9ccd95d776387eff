// Shared helpers for the population tests: a small growing colony and a bitwise comparison.
#pragma once

#include <cstring>
#include <vector>

#include "moreau/particles/population.h"

namespace moreau::particles::testing {

// A 2D colony: cells of radius 0.5 that grow and divide at 0.7, die at a small rate, with noise.
struct Colony {
  ParticleModel geometry;
  Forces forces;
  EngineOptions options;
  PopulationRules rules;
  std::vector<int> types;
  std::vector<double> x0;
};

inline Colony GrowingColony() {
  Colony c;
  c.geometry.dimension = 2;
  c.forces.diffusion = 1e-3;
  c.options.h = 0.01;
  c.options.seed = 11;
  AgentType cell;
  cell.radius = 0.5;
  cell.growth_rate = 0.05;
  cell.division_radius = 0.7;
  cell.death_rate = 0.02;
  cell.speed = 0.1;
  cell.persistence_time = 2.0;
  AgentType tumour = cell;
  tumour.name = "tumour";
  tumour.growth_rate = 0.1;
  tumour.alignment = 0.5;
  c.rules.types = {cell, tumour};
  c.rules.interval = 5;
  c.rules.seed = 5;
  c.types = {0, 1, 0, 1};
  c.x0 = {0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 1.0};
  return c;
}

inline Population Make(const Colony& c) {
  return Population(c.geometry, c.forces, c.options, c.rules, c.types, c.x0);
}

inline bool SameBits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

}  // namespace moreau::particles::testing
