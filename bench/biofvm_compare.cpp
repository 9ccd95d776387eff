// One LOD diffusion–decay step of BioFVM (Ghaffarizadeh, Friedman & Macklin 2016) against one
// FieldSet::Step on the same grid, in turns within one run: 100³ voxels of edge 1, zero-flux
// faces (BioFVM's default without Dirichlet nodes), D = 1, λ = 0.1, Δt = 0.1, `substrates`
// substrates, `threads` OpenMP threads for both. Built and run by bench/biofvm_compare.sh against
// a BioFVM source tree; not part of the CMake build.
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "BioFVM.h"
#include "moreau/fields/field_set.h"

namespace {

double Now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: biofvm_compare THREADS SUBSTRATES ROUNDS\n");
    return 2;
  }
  const int threads = std::atoi(argv[1]);
  const int substrates = std::atoi(argv[2]);
  const int rounds = std::atoi(argv[3]);
  const int side = 100;
  const double dt = 0.1;
  omp_set_num_threads(threads);

  BioFVM::Microenvironment m;
  m.set_density(0, "s0", "1");
  for (int s = 1; s < substrates; ++s) m.add_density("s" + std::to_string(s), "1");
  for (int s = 0; s < substrates; ++s) {
    m.diffusion_coefficients[s] = 1.0;
    m.decay_rates[s] = 0.1;
  }
  m.resize_space_uniform(0.0, side, 0.0, side, 0.0, side, 1.0);
  m.diffusion_decay_solver = BioFVM::diffusion_decay_solver__constant_coefficients_LOD_3D;

  moreau::fields::Grid grid;
  grid.dimension = 3;
  grid.spacing = 1.0;
  grid.upper = {side, side, side};
  std::vector<moreau::fields::Substrate> subs(static_cast<std::size_t>(substrates));
  for (int s = 0; s < substrates; ++s) {
    subs[static_cast<std::size_t>(s)].name = "s" + std::to_string(s);
    subs[static_cast<std::size_t>(s)].diffusion = 1.0;
    subs[static_cast<std::size_t>(s)].decay = 0.1;
  }
  moreau::fields::FieldSet fields(grid, subs, threads);
  const int voxels = side * side * side;
  for (int v = 0; v < voxels; ++v) {
    const double c = 1.0 + (v % 97) / 97.0;
    for (int s = 0; s < substrates; ++s) {
      m.density_vector(v)[static_cast<std::size_t>(s)] = c;
      fields.values(s)[static_cast<std::size_t>(v)] = c;
    }
  }
  m.simulate_diffusion_decay(dt);  // first touch and factorisations outside the timing
  fields.Step(dt);
  std::vector<double> biofvm, moreau_step;
  for (int r = 0; r < rounds; ++r) {
    const double t0 = Now();
    m.simulate_diffusion_decay(dt);
    const double t1 = Now();
    fields.Step(dt);
    const double t2 = Now();
    biofvm.push_back(t1 - t0);
    moreau_step.push_back(t2 - t1);
  }
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  const double per = 1e9 / voxels / substrates;
  const double b = median(biofvm), f = median(moreau_step);
  std::printf(
      "threads,substrates,biofvm_ns_per_voxel_substrate,moreau_ns_per_voxel_substrate,"
      "biofvm_over_moreau\n%d,%d,%.3f,%.3f,%.2f\n",
      threads, substrates, b * per, f * per, b / f);
  // The two solve the same scheme: the fields agree to round-off after the same steps.
  double worst = 0.0;
  for (int v = 0; v < voxels; v += 997) {
    for (int s = 0; s < substrates; ++s) {
      worst = std::max(worst, std::abs(m.density_vector(v)[static_cast<std::size_t>(s)] -
                                       fields.values(s)[static_cast<std::size_t>(v)]));
    }
  }
  std::fprintf(stderr, "largest difference between the two fields: %.3g\n", worst);
  return 0;
}
