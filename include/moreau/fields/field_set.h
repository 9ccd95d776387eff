// Diffusing fields: substrates (oxygen, a nutrient, a signal) on a regular grid over the
// simulation box, that agents secrete, take up and sense (docs/fields.md).
//
// Each substrate c (amount per volume) obeys, on the box Ω ⊂ R^k (k = 2 or 3),
//
//   ∂c/∂t = D ∇²c − λ c + S (c* − c) − U c + R,
//
// D the diffusion coefficient, λ the decay rate, and per voxel the secretion rate S (1/time)
// toward the saturation value c*, the uptake rate U (1/time) and a free source R (amount per
// volume and time): the form of BioFVM (Ghaffarizadeh et al. 2016, Bioinformatics 32(8)). The
// agents' terms reach the voxels through Deposit (the sources are per-voxel arrays a caller fills
// and clears). One Step(Δt):
//   1. the sources, per voxel, implicitly: c ← (c + Δt (S c* + R)) / (1 + Δt (S + U));
//   2. diffusion and decay, locally one-dimensional (LOD): for each axis in turn, the backward
//      Euler step of ∂c/∂t = D ∂²c/∂x_a² − (λ/k) c, second-order central differences in space,
//      one tridiagonal solve (Thomas) per grid line.
// Unconditionally stable and positivity-preserving; first order in Δt (the splitting), second
// order in the voxel size h. The same bits for any thread count: every line is solved alone.
//
// Voxels are cell-centred: voxel (i, j, l) covers [lower + h (i, j, l), lower + h (i + 1, …)),
// index i + n_x (j + n_y l), x fastest. Boundary conditions per face: zero flux (the ghost value
// mirrors the voxel), fixed value c_b on the face (the ghost value 2 c_b − c), or periodic (both
// faces of the axis periodic).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "moreau/common/enum_names.h"
#include "moreau/common/field_list.h"
#include "moreau/common/random.h"
#include "moreau/common/termination.h"

namespace moreau::fields {

enum class BoundaryKind { kZeroFlux, kFixed, kPeriodic };
inline constexpr EnumNames<BoundaryKind, 3> kBoundaryKindNames{
    {{BoundaryKind::kZeroFlux, "zero_flux"},
     {BoundaryKind::kFixed, "fixed"},
     {BoundaryKind::kPeriodic, "periodic"}}};

// The six faces, in this order: x_min, x_max, y_min, y_max, z_min, z_max (face 2a + side).
inline constexpr int kFaces = 6;

struct FaceBoundary {
  BoundaryKind kind = BoundaryKind::kZeroFlux;
  double value = 0.0;  // c_b for kFixed (finite)
};

// The grid: the box [lower, upper] of the simulation cut into cubic voxels of edge h. The number
// of voxels per axis is n_a = round((upper_a − lower_a) / h) ≥ 1, and the extent must be n_a h
// within 10⁻⁹ relative (else InputError naming the axis). In 2D the z entries are ignored (n_z = 1,
// the voxel "volume" is the area h²).
struct Grid {
  int dimension = 2;  // k ∈ {2, 3}
  std::array<double, 3> lower{0.0, 0.0, 0.0};
  std::array<double, 3> upper{1.0, 1.0, 1.0};
  double spacing = 0.1;  // h > 0

  static const FieldList<Grid>& Fields();
  void Validate() const;             // InputError(key, reason)
  std::array<int, 3> cells() const;  // (n_x, n_y, n_z); n_z = 1 in 2D
  std::int64_t voxel_count() const;  // n_x n_y n_z
  double voxel_volume() const;       // h^k
  // The voxel that holds point x (k coordinates), each index clamped into [0, n_a − 1].
  std::int64_t VoxelOf(const double* x) const;
  // The centre of voxel `index` (k coordinates written to `centre`).
  void Centre(std::int64_t index, double* centre) const;
};

// One substrate: its name, coefficients, initial value and boundary conditions.
struct Substrate {
  std::string name = "oxygen";                  // unique among the substrates, not empty
  double diffusion = 1.0;                       // D > 0 (length²/time)
  double decay = 0.0;                           // λ ≥ 0 (1/time)
  double initial = 0.0;                         // c(x, 0), finite
  std::array<FaceBoundary, kFaces> boundary{};  // per face; periodic on both faces of an axis

  // Keys: name, diffusion, decay, initial, boundary (every face's kind at once), boundary_value
  // (every face's value), and per face x_min, x_min_value, …, z_max_value; the rule that a
  // periodic face has a periodic opposite face.
  static const FieldList<Substrate>& Fields();
};

// How the agents' terms reach the voxels, and the fields reach the agents.
//   kVoxel   the voxel that holds the agent (BioFVM's choice): deposits and samples the one voxel;
//   kLinear  cloud-in-cell: the 2^k voxels around the agent with (bi/tri)linear weights, the same
//            weights for sampling (the transpose), so a deposit and a sample are adjoint.
// Both conserve what is deposited exactly (the weights of an agent sum to 1; at a face the weight
// that would fall outside goes to the face's voxel, or wraps on a periodic axis).
enum class Interpolation { kVoxel, kLinear };
inline constexpr EnumNames<Interpolation, 2> kInterpolationNames{
    {{Interpolation::kVoxel, "voxel"}, {Interpolation::kLinear, "linear"}}};

struct SteadyStateOptions {
  double tolerance = 1e-10;  // stop when ‖D∇²c − λc + …‖_∞ ≤ tolerance · (the residual at c = 0)
  int max_iterations = 10000;
  static const FieldList<SteadyStateOptions>& Fields();
};

struct SteadyStateSummary {
  Termination termination = Termination::kConverged;
  std::string message;
  int iterations = 0;
  double residual = 0.0;  // final relative residual
  double seconds = 0.0;
  bool ok() const { return IsSuccess(termination); }
  nlohmann::json ToJson() const;
};

namespace internal {

// The tridiagonal factorisation of one axis of one substrate for a time step, kept by FieldSet
// while Δt is unchanged (src/fields/lod_diffusion.cpp): every grid line of the axis has the same
// matrix, (1 + Δt λ/k + 2r) on the diagonal, −r off it, r = D Δt / h², changed on the face rows
// by the faces' conditions (off is 2r on a periodic axis of two voxels).
struct LineSolve {
  std::vector<double> inverse_pivot;  // Thomas: 1 / (b_i + r c'_{i−1})
  std::vector<double> upper;          // c'_i = −r / (b_i + r c'_{i−1})
  double off = 0.0;                   // r: minus the off-diagonal entries
  double lower_face = 0.0;            // 2 r c_b added to the first row (a fixed face), else 0
  double upper_face = 0.0;            // the same for the last row
  // A periodic axis (Sherman–Morrison on the cyclic matrix): the solution of the modified
  // matrix for the corner vector, and x = y − z (y_0 + corner y_{n−1}) · periodic_scale.
  std::vector<double> periodic_z;
  double periodic_corner = 0.0;
  double periodic_scale = 0.0;
};

// Solves `count` contiguous x lines of n values from c in place (src/fields/line_solves.cpp) with
// the copy of the loops for `set` (tests compare the copies, which give the same bits); kAvx2 and
// kAvx512 run the AVX2 copy where the processor has it, which solves groups of sixteen lines of
// at least four values and leaves other groups to the portable one.
void SolveXLinesOn(random_internal::InstructionSet set, const LineSolve& f, double* c,
                   std::int64_t n, int count);

// The line solve of an axis of n voxels (src/fields/line_solves.cpp): r = D Δt / h², decay_part
// = Δt λ / k on a k-dimensional grid, the faces' conditions at either end.
LineSolve MakeLineSolve(int n, double r, double decay_part, const FaceBoundary& lower,
                        const FaceBoundary& upper);

}  // namespace internal

class FieldSet {
 public:
  // Throws InputError: the grid's or a substrate's key ("substrates.oxygen.diffusion", …), a name
  // used twice, a periodic face whose opposite is not periodic, or more voxels than the memory
  // holds ("grid.spacing", before anything is allocated). Values start at `initial`.
  FieldSet(Grid grid, std::vector<Substrate> substrates, int threads = 1);

  const Grid& grid() const { return grid_; }
  const std::vector<Substrate>& substrates() const { return substrates_; }
  int substrate_count() const { return static_cast<int>(substrates_.size()); }
  // The index of the substrate called `name`; InputError "unknown substrate 'x' (substrates: …)".
  int SubstrateIndex(std::string_view name) const;

  // The concentrations of substrate s, voxel_count values (index order above), read and write.
  std::span<double> values(int s) { return values_.at(s); }
  std::span<const double> values(int s) const { return values_.at(s); }

  // The per-voxel source terms of substrate s for the next steps (S, S c*, U, R; voxel_count each),
  // read and write; ClearSources zeroes all four for every substrate. Deposit adds to them.
  std::span<double> secretion(int s);         // S (1/time)
  std::span<double> secretion_target(int s);  // S c* (amount/(volume·time))
  std::span<double> uptake(int s);            // U (1/time)
  std::span<double> source(int s);            // R (amount/(volume·time))
  void ClearSources();

  // Adds the agents' terms to substrate s's sources: agent i at x_i (k·N positions) with volume
  // V_i contributes per voxel v its weight w_iv times V_i / V_voxel times its rates: S += s_i …,
  // S c* += s_i c*_i …, U += u_i …, and R += r_i w_iv / V_voxel for an amount rate r_i
  // (amount/time). Any span may be empty (that term is not added). Summed in agent order: the
  // same bits for any thread count.
  void Deposit(int s, std::span<const double> positions, std::span<const double> volumes,
               std::span<const double> secretion, std::span<const double> saturation,
               std::span<const double> uptake, std::span<const double> amount_rate,
               Interpolation interpolation);
  // The value at each agent (N) and, when `gradient` is not empty, ∇c (k·N: central differences
  // at the voxel centres, one-sided at a zero-flux or fixed face, interpolated as the value).
  void Sample(int s, std::span<const double> positions, Interpolation interpolation,
              std::span<double> value, std::span<double> gradient = {}) const;

  // One step of length dt > 0 (see the top of this file) for every substrate.
  void Step(double dt);
  // Solves 0 = D ∇²c − λ c + S (c* − c) − U c + R (the same discrete operator as Step, the
  // sources as they are now) for every substrate by conjugate gradients from the current values.
  // Ends kConverged, or kMaxIterations. A substrate without decay, uptake, secretion or a fixed
  // face has no unique steady state: InputError naming it, before any work.
  SteadyStateSummary SolveSteadyState(const SteadyStateOptions& options = {});

  // ∫ c dV over the box: V_voxel Σ_v c_v, summed in index order.
  double Total(int s) const;
  double time() const { return time_; }
  std::int64_t steps() const { return steps_; }
  // Restores values and time (checkpoints): sizes must match (InputError otherwise).
  void Restore(std::vector<std::vector<double>> values, double time, std::int64_t steps);

 private:
  void FactorLines(double dt);
  // `lines` x lines from `first_line` (counted x fastest); the y lines of plane z, of its block
  // of columns `block` or of all (−1); the x and y sweeps; the z sweep (lod_diffusion.cpp).
  void SolveXLinesOf(int s, std::int64_t first_line, std::int64_t lines);
  void SolveYLinesOf(int s, std::int64_t z, std::int64_t block);
  void SolvePlanes(int s);
  void SolveZLines(int s);
  std::span<double> SourcesFor(std::vector<std::vector<double>>& term, int s);

  Grid grid_;
  std::vector<Substrate> substrates_;
  int threads_ = 1;
  std::vector<std::vector<double>> values_;
  std::vector<std::vector<double>> secretion_, secretion_target_, uptake_, source_;
  double time_ = 0.0;
  std::int64_t steps_ = 0;
  std::vector<internal::LineSolve> line_solves_;  // substrate-major, then axis; for line_solves_dt_
  double line_solves_dt_ = 0.0;                   // 0: none yet
  // Per substrate: whether its sources were ever handed out for writing (a span or Deposit); Step
  // reads no source array of a substrate whose sources were not.
  std::vector<char> sources_written_;
  // Deposit's stencils, kept between calls: each agent's voxels and weights ÷ voxel volume.
  std::vector<std::int64_t> deposit_voxel_;
  std::vector<double> deposit_share_;
};

}  // namespace moreau::fields
