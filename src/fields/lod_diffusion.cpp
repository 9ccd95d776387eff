// One Step: the sources per voxel, then diffusion and decay axis by axis (LOD), one tridiagonal
// solve per grid line with a factorisation shared by every line of the axis.
//
// Every line is solved by the same operations in the same order whatever its neighbours and the
// thread that runs it, so the bits do not depend on the thread count (the solves themselves are in
// line_solves.cpp). The x lines are contiguous and solved kLinesTogether at a time; the lines of y
// and z a row of contiguous values at a time, in blocks small enough to stay in cache between the
// elimination and the back substitution. In 3D a z plane that fits in a core's cache is swept
// along x and then along y before the next plane, so x and y cost one pass over memory together;
// z is a second pass. The sources are applied to a group of x lines just before its solve; a
// substrate whose sources were never handed out for writing skips them.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include <fmt/format.h>

#include "fields/line_solves.h"
#include "fields/team.h"
#include "moreau/common/error.h"
#include "moreau/common/random.h"
#include "moreau/fields/field_set.h"

namespace moreau::fields {
namespace {

// x lines solved in one group (line_solves.h).
constexpr int kLinesTogether = internal::kXLinesTogether;
// Doubles in one block of columns of a y or z sweep (256 KiB).
constexpr std::int64_t kBlockDoubles = 32768;
// A z plane up to this size is swept along x and then y while it stays in a core's cache.
constexpr std::int64_t kPlaneBytes = std::int64_t{1} << 20;

// The sources of one voxel: c ← (c + Δt (S c* + R)) / (1 + Δt (S + U)), over n voxels.
void ApplySources(double dt, std::int64_t n, double* c, const double* secretion,
                  const double* target, const double* uptake, const double* source) {
  for (std::int64_t i = 0; i < n; ++i) {
    c[i] = (c[i] + dt * (target[i] + source[i])) / (1.0 + dt * (secretion[i] + uptake[i]));
  }
}

// `count` ≤ kLinesTogether contiguous x lines of n values from c, the sources applied first when
// `sources` is not null, with the widest copy this processor runs.
void SolveXLines(const internal::LineSolve& f, double* c, std::int64_t n, int count,
                 const double* const* sources, double dt) {
  if (sources != nullptr) {
    ApplySources(dt, count * n, c, sources[0], sources[1], sources[2], sources[3]);
  }
  internal::SolveXLinesOn(random_internal::BestInstructionSet(), f, c, n, count);
}

// Columns of x solved side by side in a y sweep: a block of ny rows within kBlockDoubles.
std::int64_t YBlockWidth(std::int64_t nx, std::int64_t ny) {
  return std::min(nx, std::max<std::int64_t>(kBlockDoubles / ny / 8 * 8, 8));
}

}  // namespace

void FieldSet::FactorLines(double dt) {
  const std::array<int, 3> n = grid_.cells();
  const int k = grid_.dimension;
  const double h2 = grid_.spacing * grid_.spacing;
  line_solves_.clear();
  for (const Substrate& sub : substrates_) {
    for (int a = 0; a < 3; ++a) {
      if (a >= k) {
        line_solves_.emplace_back();
        continue;
      }
      line_solves_.push_back(internal::MakeLineSolve(n[a], sub.diffusion * dt / h2,
                                                     dt * sub.decay / k, sub.boundary[2 * a],
                                                     sub.boundary[2 * a + 1]));
    }
  }
  line_solves_dt_ = dt;
}

void FieldSet::SolveXLinesOf(int s, std::int64_t first_line, std::int64_t lines) {
  const std::int64_t nx = grid_.cells()[0];
  const auto u = static_cast<std::size_t>(s);
  const internal::LineSolve& f = line_solves_[3 * u];
  double* c = values_[u].data();
  const bool with_sources = sources_written_[u] != 0;
  for (std::int64_t l = first_line; l < first_line + lines; l += kLinesTogether) {
    const std::int64_t begin = l * nx;
    const double* sources[4] = {secretion_[u].data() + begin, secretion_target_[u].data() + begin,
                                uptake_[u].data() + begin, source_[u].data() + begin};
    SolveXLines(f, c + begin, nx,
                static_cast<int>(std::min<std::int64_t>(kLinesTogether, first_line + lines - l)),
                with_sources ? sources : nullptr, line_solves_dt_);
  }
}

void FieldSet::SolveYLinesOf(int s, std::int64_t z, std::int64_t block) {
  const std::array<int, 3> n = grid_.cells();
  const std::int64_t nx = n[0];
  const std::int64_t ny = n[1];
  const internal::LineSolve& f = line_solves_[static_cast<std::size_t>(3 * s + 1)];
  double* c = values_[static_cast<std::size_t>(s)].data() + z * nx * ny;
  const std::int64_t width = YBlockWidth(nx, ny);
  const std::int64_t first = block < 0 ? 0 : block;
  const std::int64_t last = block < 0 ? (nx + width - 1) / width : block + 1;
  for (std::int64_t b = first; b < last; ++b) {
    internal::SolveStridedLines(f, c + b * width, ny, nx, std::min(width, nx - b * width));
  }
}

void FieldSet::SolvePlanes(int s) {
  const std::array<int, 3> n = grid_.cells();
  const std::int64_t plane = std::int64_t{n[0]} * n[1];
  const int threads = internal::TeamSize(threads_, plane * n[2]);
  if (grid_.dimension == 3 && plane * static_cast<std::int64_t>(sizeof(double)) <= kPlaneBytes) {
    // One z plane at a time: its x lines, then its y lines while the plane is in cache.
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1)
    for (std::int64_t z = 0; z < n[2]; ++z) {
      SolveXLinesOf(s, z * n[1], n[1]);
      SolveYLinesOf(s, z, -1);
    }
    return;
  }
  // The x lines of the whole grid, then the y lines in blocks of columns.
  const std::int64_t lines = plane / n[0] * n[2];
  const std::int64_t groups = (lines + kLinesTogether - 1) / kLinesTogether;
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1)
  for (std::int64_t g = 0; g < groups; ++g) {
    SolveXLinesOf(s, g * kLinesTogether,
                  std::min<std::int64_t>(kLinesTogether, lines - g * kLinesTogether));
  }
  if (grid_.dimension < 2) return;
  const std::int64_t blocks = (n[0] + YBlockWidth(n[0], n[1]) - 1) / YBlockWidth(n[0], n[1]);
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1)
  for (std::int64_t item = 0; item < n[2] * blocks; ++item) {
    SolveYLinesOf(s, item / blocks, item % blocks);
  }
}

void FieldSet::SolveZLines(int s) {
  const std::array<int, 3> n = grid_.cells();
  const internal::LineSolve& f = line_solves_[static_cast<std::size_t>(3 * s + 2)];
  double* c = values_[static_cast<std::size_t>(s)].data();
  const std::int64_t plane = std::int64_t{n[0]} * n[1];
  const std::int64_t nz = n[2];
  const int threads = internal::TeamSize(threads_, plane * nz);
  // The z lines of a block of consecutive (x, y) columns side by side: `width` contiguous values
  // of each plane.
  const std::int64_t width = std::min(plane, std::max<std::int64_t>(kBlockDoubles / nz / 8 * 8, 8));
  const std::int64_t blocks = (plane + width - 1) / width;
#pragma omp parallel for num_threads(threads) schedule(static) if (threads > 1)
  for (std::int64_t b = 0; b < blocks; ++b) {
    const std::int64_t begin = b * width;
    internal::SolveStridedLines(f, c + begin, nz, plane, std::min(width, plane - begin));
  }
}

void FieldSet::Step(double dt) {
  if (!(dt > 0.0) || !std::isfinite(dt)) {
    throw InputError("dt", fmt::format("must be > 0 and finite (got {})", dt));
  }
  if (dt != line_solves_dt_) FactorLines(dt);
  for (int s = 0; s < substrate_count(); ++s) {
    SolvePlanes(s);
    if (grid_.dimension == 3) SolveZLines(s);
  }
  time_ += dt;
  ++steps_;
}

}  // namespace moreau::fields
