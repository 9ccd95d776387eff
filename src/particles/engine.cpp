#include "moreau/particles/engine.h"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/common/steps.h"
#include "moreau/common/summary_json.h"
#include "particles/kernels.h"

namespace moreau::particles {

std::string_view SweepOrderName(SweepOrder order) {
  return order == SweepOrder::kColoured ? "coloured" : "lexicographic";
}

SweepOrder ParseSweepOrder(std::string_view name) {
  if (name == "coloured" || name == "colored") return SweepOrder::kColoured;
  if (name == "lexicographic") return SweepOrder::kLexicographic;
  throw InputError(
      fmt::format("unknown sweep order '{}' (expected coloured or lexicographic)", name));
}

void EngineOptions::Validate() const {
  if (!(h > 0.0) || !std::isfinite(h)) throw InputError(fmt::format("h must be > 0 (got {})", h));
  if (!(skin_factor > 0.0) || !std::isfinite(skin_factor)) {
    throw InputError(fmt::format("skin_factor must be > 0 (got {})", skin_factor));
  }
  if (threads < 0) throw InputError(fmt::format("threads must be ≥ 0 (got {})", threads));
  if (sweeps < 1) throw InputError(fmt::format("sweeps must be ≥ 1 (got {})", sweeps));
  if (block_cells < 0) {
    throw InputError(fmt::format("block_cells must be ≥ 0 (got {})", block_cells));
  }
  if (!(initial_tolerance >= 0.0)) {
    throw InputError(fmt::format("initial_tolerance must be ≥ 0 (got {})", initial_tolerance));
  }
  if (memory_limit_bytes < 0) {
    throw InputError(fmt::format("memory_limit_bytes must be ≥ 0 (got {})", memory_limit_bytes));
  }
}

nlohmann::json EngineOptions::ToJson() const {
  return {{"h", h},
          {"seed", seed},
          {"order", SweepOrderName(order)},
          {"search", search == NeighbourSearch::kCellGrid ? "cell_grid" : "brute_force"},
          {"skin_factor", skin_factor},
          {"threads", threads},
          {"block_cells", block_cells},
          {"sweeps", sweeps},
          {"monitor_overlap", monitor_overlap},
          {"check_initial_state", check_initial_state},
          {"initial_tolerance", initial_tolerance},
          {"memory_limit_bytes", memory_limit_bytes}};
}

nlohmann::json EngineSummary::ToJson() const {
  nlohmann::json j = SummaryJson(termination, message, stats.total_seconds);
  j["steps"] = stats.steps;
  j["final_time"] = stats.time;
  j["neighbour_list_builds"] = stats.neighbour_list_builds;
  j["verlet_retries"] = stats.verlet_retries;
  j["candidate_pairs"] = stats.candidate_pairs;
  j["constraint_evaluations"] = stats.constraint_evaluations;
  j["constraint_sets_paper_count"] = stats.constraint_sets;
  j["projections"] = stats.projections;
  j["max_overlap"] = stats.max_overlap;
  j["last_overlap"] = stats.last_overlap;
  j["setup_seconds"] = stats.setup_seconds;
  j["force_seconds"] = stats.force_seconds;
  j["neighbour_seconds"] = stats.neighbour_seconds;
  j["sweep_seconds"] = stats.sweep_seconds;
  j["monitor_seconds"] = stats.monitor_seconds;
  if (!ok()) {
    j["failed_step"] = failed_step;
    if (failed_particle >= 0) j["failed_particle"] = failed_particle;
  }
  j["settings"] = settings.ToJson();
  return j;
}

std::string EngineSummary::BriefReport() const {
  std::string s = fmt::format(
      "steps {} t {:.6g} builds {} retries {} pairs {} max overlap {:.3g} wall {:.3f} s",
      stats.steps, stats.time, stats.neighbour_list_builds, stats.verlet_retries, stats.candidate_pairs,
      stats.max_overlap, stats.total_seconds);
  if (!ok()) s += " — " + message;
  return s;
}

namespace {

using Clock = std::chrono::steady_clock;
double Seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

std::uint64_t Morton(const int* c, int k) {
  std::uint64_t code = 0;
  for (int bit = 0; bit < 21; ++bit) {
    for (int a = 0; a < k; ++a) {
      code |= ((static_cast<std::uint64_t>(c[a]) >> bit) & 1u) << (k * bit + a);
    }
  }
  return code;
}

}  // namespace

struct Engine::Impl {
  ParticleModel model;
  Forces forces;
  EngineOptions options;
  int k = 2;
  int n = 0;
  int threads = 1;

  // Fixed sets, normalised: walls n (k per wall) and b = offset (radius added per particle).
  std::vector<double> wall_n, wall_b, sphere_c, sphere_r, seg_a, seg_b;
  int fixed_sets = 0;

  // Per storage slot.
  std::vector<double> cur, nxt, ref, radius, mobility, force, path;
  std::vector<std::uint32_t> stamp;
  std::vector<int> id, slot_of, key;
  std::vector<int> perm;
  std::vector<double> scratch1, scratch_k;

  // Periodic axes.
  bool any_periodic = false;
  bool periodic[3] = {false, false, false};
  double dlo[3] = {0, 0, 0};
  double len[3] = {0, 0, 0};
  double shift[27][3] = {};

  // Grid and blocks.
  bool have_geometry = false;
  double reach = 0.0;  // cell edge lower bound used for the current geometry
  int nc[3] = {1, 1, 1};
  double glo[3] = {0, 0, 0};
  double gedge[3] = {1, 1, 1};
  double ginv[3] = {1, 1, 1};
  int nb[3] = {1, 1, 1};
  int block_edge = 8;
  std::vector<std::int64_t> cell_rank;   // row-major cell → rank (blocks in Morton order)
  std::vector<std::int64_t> cell_start;  // rank → first position in cell_members; size cells+1
  std::vector<int> cell_members;         // slots sorted by cell rank (identity when coloured)
  std::vector<std::int64_t> block_cell_begin;  // block rank → first cell rank; size blocks+1
  std::vector<int> colour_begin;               // colour → first entry of colour_blocks
  std::vector<int> colour_blocks;              // block ranks by colour, in rank order
  std::vector<std::int64_t> count_scratch;

  // Verlet half-lists: pairs (s, nbr[p]) for p in [row_start[s], row_start[s+1]), nbr > s.
  std::vector<int> row_start;  // int: the list is capped at INT_MAX pairs
  std::vector<int> nbr;
  std::vector<std::uint8_t> image;          // per pair, periodic only: Σ (code_a + 1) 3^a
  std::vector<std::vector<int>> chunk_nbr;  // build buffers, reused
  std::vector<std::vector<std::uint8_t>> chunk_image;
  double skin = 0.0;
  double nominal_skin = 0.0;
  double skin_limit = std::numeric_limits<double>::infinity();
  double attraction_range = 0.0;
  double rmax = 0.0;
  bool uniform_radius = false;    // all r_i equal: the sweep skips the radius loads
  bool uniform_mobility = false;  // all μ_i = 1: the prediction skips the mobility loads
  bool built_here = false;        // list built at the current predicted positions
  double drift_bound = 0.0;       // ≥ max_i ‖X_i − X_i^build‖ at the current positions
  std::uint32_t sweep_id = 0;

  std::int64_t step = 0;
  EngineStats stats;
  Termination termination = Termination::kCompleted;
  std::string message;
  std::int64_t failed_step = -1;
  std::int64_t failed_particle = -1;

  void Setup(std::span<const double> positions);
  void Wrap(double* x) const;
  void Rebuild(std::vector<double>* at);
  void MakeGeometry(const double* x);
  template <int K, bool P>
  void BuildRows(const double* x);
  bool Step();
  void Predict(double* max_move, std::int64_t* bad_id);
  template <int K, bool P>
  void PredictImpl(double* max_move, std::int64_t* bad_id);
  template <int K, bool P>
  void Attraction();
  double Sweep(std::int64_t* projections);
  template <int K, bool P>
  double SweepImpl(std::int64_t* projections);
  template <int K, bool P, bool U>
  void SweepRows(int begin, int end, double* x, double* max_path, std::int64_t* proj);
  template <int K, bool P>
  void SweepRowsAny(int begin, int end, double* x, double* max_path, std::int64_t* proj) {
    if (uniform_radius) {
      SweepRows<K, P, true>(begin, end, x, max_path, proj);
    } else {
      SweepRows<K, P, false>(begin, end, x, max_path, proj);
    }
  }
  template <int K>
  void SweepFixed(int begin, int end, double* x, double* max_path, std::int64_t* proj);
  double MaxOverlap(const double* x) const;
  template <int K, bool P>
  double MaxOverlapImpl(const double* x) const;
  double MaxFixedViolation(const double* x) const;
  double ExactMove() const;  // max_i ‖Y_i − X_i^build‖ (predicted positions)

  template <int K, bool P>
  inline void PairDisplacement(const double* x, int s, int t, std::int64_t p, double* u) const {
    for (int a = 0; a < K; ++a) u[a] = x[K * s + a] - x[K * t + a];
    if constexpr (P) {
      const int code = image[static_cast<std::size_t>(p)];
      if (code != 13) {
        for (int a = 0; a < K; ++a) u[a] -= shift[code][a];
      }
    }
  }

  double PathOf(int s) const {
    return stamp[static_cast<std::size_t>(s)] == sweep_id ? path[static_cast<std::size_t>(s)] : 0.0;
  }
  double AddPath(int s, double d) {
    const auto us = static_cast<std::size_t>(s);
    if (stamp[us] != sweep_id) {
      stamp[us] = sweep_id;
      path[us] = 0.0;
    }
    path[us] += d;
    return path[us];
  }
};

void Engine::Impl::Wrap(double* x) const {
  if (!any_periodic) return;
  for (int a = 0; a < k; ++a) {
    if (!periodic[a]) continue;
    for (int s = 0; s < n; ++s) {
      double& v = x[static_cast<std::size_t>(k * s + a)];
      v = internal::Wrap(v, dlo[a], len[a]);
    }
  }
}

void Engine::Impl::Setup(std::span<const double> positions) {
  options.Validate();
  if (model.dimension != 2 && model.dimension != 3) {
    throw InputError(
        fmt::format("dimension must be 2 or 3 for the particle engine (got {})", model.dimension));
  }
  CheckParticleMemory(model.dimension, model.count(), options.memory_limit_bytes);
  model.Validate();
  forces.Validate();
  k = model.dimension;
  n = model.count();
  if (positions.size() != static_cast<std::size_t>(k) * static_cast<std::size_t>(n)) {
    throw InputError(fmt::format("initial state: positions have {} entries for {} particles in {}D",
                                 positions.size(), n, k));
  }
  if (options.check_initial_state) {
    CheckInitialState(model, positions, options.initial_tolerance);
  } else {
    for (double v : positions) {
      if (!std::isfinite(v)) throw InputError("initial state: positions must be finite");
    }
  }
  // Automatic: one thread per ~20000 particles (barriers dominate below), at most the OpenMP
  // default. The results do not depend on it.
  threads = options.threads > 0 ? options.threads
                                : std::clamp(n / 20000, 1, std::max(1, omp_get_max_threads()));
  if (options.order == SweepOrder::kLexicographic) threads = 1;

  for (const internal::UnitWall& w : internal::UnitWalls(model)) {
    for (int a = 0; a < k; ++a) wall_n.push_back(w.n[a]);
    wall_b.push_back(w.b);
  }
  for (const SphereObstacle& o : model.spheres) {
    for (int a = 0; a < k; ++a) sphere_c.push_back(o.center[static_cast<std::size_t>(a)]);
    sphere_r.push_back(o.radius);
  }
  for (const SegmentObstacle& g : model.segments) {
    seg_a.push_back(g.a[0]);
    seg_a.push_back(g.a[1]);
    seg_b.push_back(g.b[0]);
    seg_b.push_back(g.b[1]);
  }
  fixed_sets = static_cast<int>(model.walls.size() + model.spheres.size() + model.segments.size());

  rmax = model.max_radius();
  uniform_radius = std::all_of(model.radius.begin(), model.radius.end(),
                               [&](double r) { return r == model.radius.front(); });
  uniform_mobility =
      model.mobility.empty() ||
      std::all_of(model.mobility.begin(), model.mobility.end(), [](double m) { return m == 1.0; });
  attraction_range =
      forces.attraction && forces.attraction->stiffness > 0.0 ? forces.attraction->range : 0.0;
  skin = options.skin_factor * rmax;
  for (int a = 0; a < k; ++a) {
    const auto ua = static_cast<std::size_t>(a);
    periodic[a] = model.periodic[ua];
    if (!periodic[a]) continue;
    any_periodic = true;
    dlo[a] = model.domain_lo[ua];
    len[a] = model.domain_hi[ua] - model.domain_lo[ua];
    // Minimum images must be unique within the list reach: 2 r_max + ℓ + skin < L/2.
    const double room = 0.5 * len[a] - 2.0 * rmax - attraction_range;
    if (!(room > 0.0)) {
      throw InputError(
          fmt::format("forces.attraction.range {} is too large for periodic axis {} of length {}",
                      attraction_range, a, len[a]));
    }
    skin_limit = std::min(skin_limit, 0.99 * room);
  }
  nominal_skin = skin;
  skin = std::min(skin, skin_limit);
  for (int code = 0; code < 27; ++code) {
    int c = code;
    for (int a = 0; a < 3; ++a) {
      const int o = c % 3 - 1;
      c /= 3;
      shift[code][a] = a < k ? o * len[a] : 0.0;
    }
  }

  const auto nk = static_cast<std::size_t>(k) * static_cast<std::size_t>(n);
  const auto un = static_cast<std::size_t>(n);
  cur.assign(positions.begin(), positions.end());
  nxt.assign(nk, 0.0);
  ref.assign(nk, 0.0);
  force.assign(attraction_range > 0.0 ? nk : 0, 0.0);
  radius = model.radius;
  mobility.resize(un);
  for (int i = 0; i < n; ++i) mobility[static_cast<std::size_t>(i)] = model.mobility_of(i);
  path.assign(un, 0.0);
  stamp.assign(un, 0);
  id.resize(un);
  std::iota(id.begin(), id.end(), 0);
  slot_of = id;
  key.resize(un);
  perm.resize(un);
  row_start.assign(un + 1, 0);
  Rebuild(&cur);
}

// ---------------------------------------------------------------------------------------------
// Neighbour lists.

void Engine::Impl::MakeGeometry(const double* x) {
  const double need = 2.0 * rmax + attraction_range + skin;
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  for (int a = 0; a < k; ++a) {
    if (periodic[a]) {
      lo[a] = dlo[a];
      hi[a] = dlo[a] + len[a];
      continue;
    }
    double mn = std::numeric_limits<double>::infinity();
    double mx = -mn;
#pragma omp parallel for num_threads(threads) reduction(min                 \
                                                        : mn) reduction(max \
                                                                        : mx) schedule(static)
    for (int s = 0; s < n; ++s) {
      const double v = x[k * s + a];
      mn = std::min(mn, v);
      mx = std::max(mx, v);
    }
    lo[a] = mn;
    hi[a] = mx;
  }
  if (have_geometry && reach == need) {
    bool fits = true;
    for (int a = 0; a < k && fits; ++a) {
      if (periodic[a]) continue;
      const double ghi = glo[a] + nc[a] * gedge[a];
      const double span = hi[a] - lo[a];
      fits = lo[a] >= glo[a] && hi[a] <= ghi && (ghi - glo[a]) <= 1.5 * span + 8.0 * need;
    }
    if (fits) return;
  }
  have_geometry = true;
  reach = need;
  std::int64_t total = 1;
  for (int a = 0; a < k; ++a) {
    if (!periodic[a]) {
      lo[a] -= 2.0 * need;
      hi[a] += 2.0 * need;
    }
    const double span = hi[a] - lo[a];
    int cells = static_cast<int>(std::clamp(std::floor(span / need), 1.0, 1.0e6));
    while (cells > 1 && span / cells < need) --cells;
    nc[a] = cells;
    glo[a] = lo[a];
    total *= cells;
  }
  const std::int64_t max_cells = std::max<std::int64_t>(64, 4 * static_cast<std::int64_t>(n));
  while (total > max_cells) {
    total = 1;
    for (int a = 0; a < k; ++a) {
      nc[a] = std::max(1, nc[a] / 2);
      total *= nc[a];
    }
  }
  for (int a = 0; a < k; ++a) {
    const double span = periodic[a] ? len[a] : hi[a] - lo[a];
    gedge[a] = span / nc[a];
    ginv[a] = nc[a] / span;
  }
  for (int a = k; a < 3; ++a) {
    nc[a] = 1;
    glo[a] = 0.0;
    gedge[a] = 1.0;
    ginv[a] = 0.0;
  }
  // Block edge: as given, or automatic from the cell count alone (never from the thread count):
  // as large as possible (long runs of consecutive memory per block; up to 64 cells in 2D, 16 in
  // 3D) while keeping ≥ 8 blocks per colour for load balance.
  if (options.block_cells > 0) {
    block_edge = options.block_cells;
  } else if (k == 2) {
    block_edge = static_cast<int>(
        std::clamp(std::floor(std::sqrt(static_cast<double>(total) / 72.0)), 2.0, 64.0));
  } else {
    block_edge = static_cast<int>(
        std::clamp(std::floor(std::cbrt(static_cast<double>(total) / 216.0)), 2.0, 16.0));
  }
  // Blocks of block_edge cells per axis; on a periodic axis 1, 2 or a multiple of 3 of them so
  // that the colouring b mod 3 separates same-colour blocks across the boundary too.
  std::int64_t blocks = 1;
  for (int a = 0; a < 3; ++a) {
    int b = (nc[a] + block_edge - 1) / block_edge;
    if (a < k && periodic[a] && b >= 3) b = 3 * (b / 3);
    nb[a] = std::max(1, b);
    blocks *= nb[a];
  }
  // Blocks in Morton order, cells row-major within a block.
  std::vector<std::pair<std::uint64_t, std::int64_t>> order(static_cast<std::size_t>(blocks));
  for (std::int64_t b = 0; b < blocks; ++b) {
    const int c[3] = {static_cast<int>(b % nb[0]), static_cast<int>((b / nb[0]) % nb[1]),
                      static_cast<int>(b / (static_cast<std::int64_t>(nb[0]) * nb[1]))};
    order[static_cast<std::size_t>(b)] = {Morton(c, k), b};
  }
  std::sort(order.begin(), order.end());
  // Block b covers cells [block_lo(b), block_lo(b + 1)) of an axis; cell c lies in block
  // ((c + 1) nb − 1) / nc, the largest b with block_lo(b) ≤ c.
  auto block_lo = [&](int a, int b) {
    return static_cast<int>(static_cast<std::int64_t>(b) * nc[a] / nb[a]);
  };
  std::vector<std::int64_t> rank_of_block(static_cast<std::size_t>(blocks));
  block_cell_begin.assign(static_cast<std::size_t>(blocks) + 1, 0);
  std::vector<int> colour_count(27, 0);
  std::vector<int> block_colour(static_cast<std::size_t>(blocks));
  for (std::int64_t r = 0; r < blocks; ++r) {
    const std::int64_t b = order[static_cast<std::size_t>(r)].second;
    rank_of_block[static_cast<std::size_t>(b)] = r;
    const int c[3] = {static_cast<int>(b % nb[0]), static_cast<int>((b / nb[0]) % nb[1]),
                      static_cast<int>(b / (static_cast<std::int64_t>(nb[0]) * nb[1]))};
    std::int64_t cells = 1;
    int colour = 0;
    int weight = 1;
    for (int a = 0; a < 3; ++a) {
      cells *= block_lo(a, c[a] + 1) - block_lo(a, c[a]);
      colour += (c[a] % 3) * weight;
      weight *= 3;
    }
    block_cell_begin[static_cast<std::size_t>(r) + 1] =
        block_cell_begin[static_cast<std::size_t>(r)] + cells;
    block_colour[static_cast<std::size_t>(r)] = colour;
    ++colour_count[static_cast<std::size_t>(colour)];
  }
  colour_begin.assign(28, 0);
  for (int c = 0; c < 27; ++c)
    colour_begin[static_cast<std::size_t>(c) + 1] =
        colour_begin[static_cast<std::size_t>(c)] + colour_count[static_cast<std::size_t>(c)];
  colour_blocks.assign(static_cast<std::size_t>(blocks), 0);
  {
    std::vector<int> fill(colour_begin.begin(), colour_begin.end() - 1);
    for (std::int64_t r = 0; r < blocks; ++r) {
      const int c = block_colour[static_cast<std::size_t>(r)];
      colour_blocks[static_cast<std::size_t>(fill[static_cast<std::size_t>(c)]++)] =
          static_cast<int>(r);
    }
  }
  cell_rank.assign(static_cast<std::size_t>(total), 0);
  for (int z = 0; z < nc[2]; ++z) {
    const int bz = static_cast<int>(((static_cast<std::int64_t>(z) + 1) * nb[2] - 1) / nc[2]);
    for (int y = 0; y < nc[1]; ++y) {
      const int by = static_cast<int>(((static_cast<std::int64_t>(y) + 1) * nb[1] - 1) / nc[1]);
      for (int xx = 0; xx < nc[0]; ++xx) {
        const int bx = static_cast<int>(((static_cast<std::int64_t>(xx) + 1) * nb[0] - 1) / nc[0]);
        // Row-major position inside the block.
        const int lx = xx - block_lo(0, bx), ly = y - block_lo(1, by), lz = z - block_lo(2, bz);
        const int wx = block_lo(0, bx + 1) - block_lo(0, bx);
        const int wy = block_lo(1, by + 1) - block_lo(1, by);
        const std::int64_t b = (static_cast<std::int64_t>(bz) * nb[1] + by) * nb[0] + bx;
        const std::int64_t r = rank_of_block[static_cast<std::size_t>(b)];
        cell_rank[static_cast<std::size_t>((static_cast<std::int64_t>(z) * nc[1] + y) * nc[0] +
                                           xx)] = block_cell_begin[static_cast<std::size_t>(r)] +
                                                  (static_cast<std::int64_t>(lz) * wy + ly) * wx +
                                                  lx;
      }
    }
  }
  // The ranks are a permutation of the cells (an internal invariant the colouring relies on).
  {
    std::vector<char> seen(static_cast<std::size_t>(total), 0);
    for (const std::int64_t r : cell_rank) {
      MOREAU_ASSERT(r >= 0 && r < total && !seen[static_cast<std::size_t>(r)]);
      seen[static_cast<std::size_t>(r)] = 1;
    }
  }
  cell_start.assign(static_cast<std::size_t>(total) + 1, 0);
}

void Engine::Impl::Rebuild(std::vector<double>* at) {
  const auto t0 = Clock::now();
  double* x = at->data();
  Wrap(x);
  MakeGeometry(x);
  const std::int64_t cells = static_cast<std::int64_t>(cell_rank.size());
  // Cell key of every slot.
#pragma omp parallel for num_threads(threads) schedule(static)
  for (int s = 0; s < n; ++s) {
    int c[3] = {0, 0, 0};
    for (int a = 0; a < k; ++a) {
      const double t = (x[k * s + a] - glo[a]) * ginv[a];
      c[a] = !(t >= 0.0) ? 0 : (t >= nc[a] ? nc[a] - 1 : static_cast<int>(t));
    }
    key[static_cast<std::size_t>(s)] = static_cast<int>(cell_rank[static_cast<std::size_t>(
        (static_cast<std::int64_t>(c[2]) * nc[1] + c[1]) * nc[0] + c[0])]);
  }
  // Counting sort by key (stable), then by id within each cell.
  // Parallel and stable: thread t counts its contiguous chunk of slots, the offsets of (cell, t)
  // follow cells then threads, and each thread scatters its chunk in order. A stable sort has
  // one result, so the permutation does not depend on the thread count.
  {
    const int T = threads;
    const auto ucells = static_cast<std::size_t>(cells);
    count_scratch.resize(static_cast<std::size_t>(T) * ucells);
    std::vector<std::int64_t> partial(static_cast<std::size_t>(T) + 1, 0);
#pragma omp parallel num_threads(T)
    {
      const int t = omp_get_thread_num();
      std::int64_t* cnt = count_scratch.data() + static_cast<std::size_t>(t) * ucells;
      std::fill(cnt, cnt + cells, 0);
      const int sb = static_cast<int>(static_cast<std::int64_t>(t) * n / T);
      const int se = static_cast<int>(static_cast<std::int64_t>(t + 1) * n / T);
      for (int s = sb; s < se; ++s) ++cnt[key[static_cast<std::size_t>(s)]];
#pragma omp barrier
      // Cells [cb, ce) are this thread's for the scan.
      const std::int64_t cb = static_cast<std::int64_t>(t) * cells / T;
      const std::int64_t ce = static_cast<std::int64_t>(t + 1) * cells / T;
      std::int64_t local = 0;
      for (std::int64_t c = cb; c < ce; ++c) {
        for (int u = 0; u < T; ++u)
          local +=
              count_scratch[static_cast<std::size_t>(u) * ucells + static_cast<std::size_t>(c)];
      }
      partial[static_cast<std::size_t>(t) + 1] = local;
#pragma omp barrier
#pragma omp single
      for (int u = 0; u < T; ++u)
        partial[static_cast<std::size_t>(u) + 1] += partial[static_cast<std::size_t>(u)];
      // (implicit barrier after single)
      std::int64_t run = partial[static_cast<std::size_t>(t)];
      for (std::int64_t c = cb; c < ce; ++c) {
        cell_start[static_cast<std::size_t>(c)] = run;
        for (int u = 0; u < T; ++u) {
          std::int64_t& v =
              count_scratch[static_cast<std::size_t>(u) * ucells + static_cast<std::size_t>(c)];
          const std::int64_t count = v;
          v = run;
          run += count;
        }
      }
#pragma omp barrier
      for (int s = sb; s < se; ++s)
        perm[static_cast<std::size_t>(cnt[key[static_cast<std::size_t>(s)]]++)] = s;
    }
    cell_start[ucells] = n;
  }
#pragma omp parallel for num_threads(threads) schedule(static)
  for (std::int64_t c = 0; c < cells; ++c) {
    const std::int64_t b = cell_start[static_cast<std::size_t>(c)];
    const std::int64_t e = cell_start[static_cast<std::size_t>(c) + 1];
    for (std::int64_t i = b + 1; i < e; ++i) {  // insertion sort by id (cells hold few slots)
      const int v = perm[static_cast<std::size_t>(i)];
      std::int64_t j = i;
      while (j > b && id[static_cast<std::size_t>(perm[static_cast<std::size_t>(j - 1)])] >
                          id[static_cast<std::size_t>(v)]) {
        perm[static_cast<std::size_t>(j)] = perm[static_cast<std::size_t>(j - 1)];
        --j;
      }
      perm[static_cast<std::size_t>(j)] = v;
    }
  }
  if (options.order == SweepOrder::kColoured) {
    // Reorder storage along the blocks' Morton curve: new slot s holds old slot perm[s].
    auto gather = [&](std::vector<double>& v, int width) {
      if (v.empty()) return;
      // One scratch buffer per width, so that swapping keeps every capacity (no reallocation,
      // no fresh pages at later builds).
      std::vector<double>& scratch = width == 1 ? scratch1 : scratch_k;
      scratch.resize(v.size());
#pragma omp parallel for num_threads(threads) schedule(static)
      for (int s = 0; s < n; ++s) {
        const int o = perm[static_cast<std::size_t>(s)];
        for (int a = 0; a < width; ++a)
          scratch[static_cast<std::size_t>(width * s + a)] =
              v[static_cast<std::size_t>(width * o + a)];
      }
      v.swap(scratch);
    };
    gather(cur, k);
    gather(nxt, k);
    gather(force, k);
    gather(radius, 1);
    gather(mobility, 1);
    // key is free now: it takes the new ids.
    int* new_id = key.data();
#pragma omp parallel for num_threads(threads) schedule(static)
    for (int s = 0; s < n; ++s) {
      new_id[s] = id[static_cast<std::size_t>(perm[static_cast<std::size_t>(s)])];
      stamp[static_cast<std::size_t>(s)] = 0;
    }
    id.swap(key);
#pragma omp parallel for num_threads(threads) schedule(static)
    for (int s = 0; s < n; ++s)
      slot_of[static_cast<std::size_t>(id[static_cast<std::size_t>(s)])] = s;
    x = at->data();
  } else {
    cell_members = perm;
  }
  {
    const double* src = at->data();
    double* dst = ref.data();
    const std::int64_t total = static_cast<std::int64_t>(ref.size());
#pragma omp parallel for num_threads(threads) schedule(static)
    for (std::int64_t i = 0; i < total; ++i) dst[i] = src[i];
  }
  internal::DispatchDimensionPeriodic(
      k, any_periodic, [&](auto kk, auto p) { BuildRows<kk, p>(x); });
  ++stats.neighbour_list_builds;
  stats.candidate_pairs = static_cast<std::int64_t>(nbr.size());
  built_here = true;
  drift_bound = 0.0;
  stats.neighbour_seconds += Seconds(t0, Clock::now());
}

template <int K, bool P>
void Engine::Impl::BuildRows(const double* x) {
  const double extra = attraction_range + skin;
  const bool brute = options.search == NeighbourSearch::kBruteForce;
  const bool identity_members = options.order == SweepOrder::kColoured;
  // Visits the partners t > s of slot s within reach, in a fixed order; f(t, image code).
  auto visit = [&](int s, auto&& f) {
    const double* xs = x + K * s;
    const double rs = radius[static_cast<std::size_t>(s)];
    auto consider = [&](int t) {
      if (t <= s) return;
      double u[K];
      int code = 13;
      int weight = 1;
      for (int a = 0; a < K; ++a) {
        u[a] = xs[a] - x[K * t + a];
        if constexpr (P) {
          if (periodic[a]) {
            if (u[a] > 0.5 * len[a]) {
              u[a] -= len[a];
              code += weight;
            } else if (u[a] < -0.5 * len[a]) {
              u[a] += len[a];
              code -= weight;
            }
          }
        }
        weight *= 3;
      }
      const double r2 = internal::SquaredNorm<K>(u);
      const double c = rs + radius[static_cast<std::size_t>(t)] + extra;
      if (r2 < c * c) f(t, code);
    };
    if (brute) {
      for (int t = s + 1; t < n; ++t) consider(t);
      return;
    }
    int c[3] = {0, 0, 0};
    for (int a = 0; a < K; ++a) {
      const double tt = (xs[a] - glo[a]) * ginv[a];
      c[a] = !(tt >= 0.0) ? 0 : (tt >= nc[a] ? nc[a] - 1 : static_cast<int>(tt));
    }
    int lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    for (int a = 0; a < K; ++a) {
      if (periodic[a] && nc[a] >= 3) {
        lo[a] = c[a] - 1;
        hi[a] = c[a] + 1;
      } else if (periodic[a]) {
        lo[a] = 0;
        hi[a] = nc[a] - 1;
      } else {
        lo[a] = std::max(0, c[a] - 1);
        hi[a] = std::min(nc[a] - 1, c[a] + 1);
      }
    }
    for (int z = lo[2]; z <= hi[2]; ++z) {
      const int zz = z < 0 ? z + nc[2] : (z >= nc[2] ? z - nc[2] : z);
      for (int y = lo[1]; y <= hi[1]; ++y) {
        const int yy = y < 0 ? y + nc[1] : (y >= nc[1] ? y - nc[1] : y);
        const std::int64_t row = (static_cast<std::int64_t>(zz) * nc[1] + yy) * nc[0];
        if (identity_members) {
          // Storage is sorted by cell rank: visit slot ranges, merging cells of consecutive rank
          // (neighbours along x inside a block), and skip slots ≤ s (the half list).
          std::int64_t run_b = -1, run_e = -1;
          for (int xx = lo[0]; xx <= hi[0]; ++xx) {
            const int x0 = xx < 0 ? xx + nc[0] : (xx >= nc[0] ? xx - nc[0] : xx);
            const std::int64_t cell = cell_rank[static_cast<std::size_t>(row + x0)];
            if (cell == run_e) {
              run_e = cell + 1;
              continue;
            }
            if (run_b >= 0) {
              const std::int64_t e = cell_start[static_cast<std::size_t>(run_e)];
              for (std::int64_t q =
                       std::max<std::int64_t>(cell_start[static_cast<std::size_t>(run_b)], s + 1);
                   q < e; ++q) {
                consider(static_cast<int>(q));
              }
            }
            run_b = cell;
            run_e = cell + 1;
          }
          const std::int64_t e = cell_start[static_cast<std::size_t>(run_e)];
          for (std::int64_t q =
                   std::max<std::int64_t>(cell_start[static_cast<std::size_t>(run_b)], s + 1);
               q < e; ++q) {
            consider(static_cast<int>(q));
          }
          continue;
        }
        for (int xx = lo[0]; xx <= hi[0]; ++xx) {
          const int x0 = xx < 0 ? xx + nc[0] : (xx >= nc[0] ? xx - nc[0] : xx);
          const std::int64_t cell = cell_rank[static_cast<std::size_t>(row + x0)];
          const std::int64_t e = cell_start[static_cast<std::size_t>(cell) + 1];
          for (std::int64_t q = cell_start[static_cast<std::size_t>(cell)]; q < e; ++q) {
            consider(cell_members[static_cast<std::size_t>(q)]);
          }
        }
      }
    }
  };
  const bool sort_rows = options.order == SweepOrder::kLexicographic || brute;
  // One pass: contiguous chunks of slots append their rows to reusable chunk buffers, then the
  // buffers are concatenated in chunk order (the same list for any thread count).
  const int chunks = std::max(1, std::min(n, 16 * threads));
  if (static_cast<int>(chunk_nbr.size()) < chunks) {
    chunk_nbr.resize(static_cast<std::size_t>(chunks));
    chunk_image.resize(static_cast<std::size_t>(chunks));
  }
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1)
  for (int q = 0; q < chunks; ++q) {
    const int begin = static_cast<int>(static_cast<std::int64_t>(q) * n / chunks);
    const int end = static_cast<int>(static_cast<std::int64_t>(q + 1) * n / chunks);
    std::vector<int>& buf = chunk_nbr[static_cast<std::size_t>(q)];
    std::vector<std::uint8_t>& img = chunk_image[static_cast<std::size_t>(q)];
    buf.clear();
    img.clear();
    for (int s = begin; s < end; ++s) {
      const std::size_t first = buf.size();
      visit(s, [&](int t, int code) {
        buf.push_back(t);
        if constexpr (P) img.push_back(static_cast<std::uint8_t>(code));
      });
      row_start[static_cast<std::size_t>(s) + 1] = static_cast<int>(buf.size() - first);
      if (sort_rows) {
        // Insertion sort of the row by t, images along (t is unique in a row: images are unique
        // within reach).
        for (std::size_t i = first + 1; i < buf.size(); ++i) {
          const int t = buf[i];
          const std::uint8_t c = P ? img[i] : 0;
          std::size_t j = i;
          while (j > first && buf[j - 1] > t) {
            buf[j] = buf[j - 1];
            if constexpr (P) img[j] = img[j - 1];
            --j;
          }
          buf[j] = t;
          if constexpr (P) img[j] = c;
        }
      }
    }
  }
  row_start[0] = 0;
  std::int64_t total = 0;
  for (int s = 0; s < n; ++s) {
    total += row_start[static_cast<std::size_t>(s) + 1];
    if (total > std::numeric_limits<int>::max()) {
      throw NumericalError(fmt::format("neighbour list with more than {} pairs is too large",
                                       std::numeric_limits<int>::max()));
    }
    row_start[static_cast<std::size_t>(s) + 1] = static_cast<int>(total);
  }
  nbr.resize(static_cast<std::size_t>(total));
  if constexpr (P) image.resize(static_cast<std::size_t>(total));
#pragma omp parallel for num_threads(threads) schedule(static)
  for (int q = 0; q < chunks; ++q) {
    const int begin = static_cast<int>(static_cast<std::int64_t>(q) * n / chunks);
    const auto at = static_cast<std::size_t>(row_start[static_cast<std::size_t>(begin)]);
    const std::vector<int>& buf = chunk_nbr[static_cast<std::size_t>(q)];
    std::copy(buf.begin(), buf.end(), nbr.begin() + static_cast<std::ptrdiff_t>(at));
    if constexpr (P) {
      const std::vector<std::uint8_t>& img = chunk_image[static_cast<std::size_t>(q)];
      std::copy(img.begin(), img.end(), image.begin() + static_cast<std::ptrdiff_t>(at));
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Drift and prediction.

template <int K, bool P>
void Engine::Impl::Attraction() {
  const double stiffness = forces.attraction->stiffness;
  const double range = attraction_range;
  double* f = force.data();
  const double* x = cur.data();
  std::fill(force.begin(), force.end(), 0.0);
  auto rows = [&](int begin, int end) {
    for (int s = begin; s < end; ++s) {
      const double rs = radius[static_cast<std::size_t>(s)];
      for (std::int64_t p = row_start[static_cast<std::size_t>(s)];
           p < row_start[static_cast<std::size_t>(s) + 1]; ++p) {
        const int t = nbr[static_cast<std::size_t>(p)];
        double u[K];
        PairDisplacement<K, P>(x, s, t, p, u);
        const double r = std::sqrt(internal::SquaredNorm<K>(u));
        const double g = r - (rs + radius[static_cast<std::size_t>(t)]);
        if (!(g > 0.0 && g < range)) continue;
        const double scale = stiffness * g * (1.0 - g / range) / r;
        for (int a = 0; a < K; ++a) {
          f[K * s + a] -= scale * u[a];
          f[K * t + a] += scale * u[a];
        }
      }
    }
  };
  if (options.order == SweepOrder::kLexicographic) {
    rows(0, n);
    return;
  }
#pragma omp parallel num_threads(threads)
  for (int colour = 0; colour < 27; ++colour) {
#pragma omp for schedule(static)
    for (int q = colour_begin[static_cast<std::size_t>(colour)];
         q < colour_begin[static_cast<std::size_t>(colour) + 1]; ++q) {
      const int b = colour_blocks[static_cast<std::size_t>(q)];
      rows(static_cast<int>(
               cell_start[static_cast<std::size_t>(block_cell_begin[static_cast<std::size_t>(b)])]),
           static_cast<int>(cell_start[static_cast<std::size_t>(
               block_cell_begin[static_cast<std::size_t>(b) + 1])]));
    }
  }
}

template <int K, bool P>
void Engine::Impl::PredictImpl(double* max_move, std::int64_t* bad_id) {
  const double h = options.h;
  const bool trap = forces.trap.has_value();
  const double gamma = trap ? forces.trap->gamma : 0.0;
  double center[3] = {0, 0, 0}, f0[3] = {0, 0, 0};
  bool any_const = false;
  for (int a = 0; a < K; ++a) {
    if (trap) center[a] = forces.trap->center[static_cast<std::size_t>(a)];
    f0[a] = forces.constant_force[static_cast<std::size_t>(a)];
    any_const = any_const || f0[a] != 0.0;
  }
  const bool prop = forces.propulsion.has_value() && forces.propulsion->speed > 0.0;
  const double v0 = prop ? forces.propulsion->speed : 0.0;
  double ta[3] = {0, 0, 0}, tb[3] = {0, 0, 0};
  const bool seg = prop && forces.propulsion->target_end.has_value();
  for (int a = 0; a < K; ++a) {
    if (prop) ta[a] = forces.propulsion->target[static_cast<std::size_t>(a)];
    if (seg) tb[a] = (*forces.propulsion->target_end)[static_cast<std::size_t>(a)];
  }
  // Past the target (⟨X − target, e⟩ > 0) the desired direction is the exit direction e.
  const bool exit_dir = prop && forces.propulsion->exit_direction.has_value();
  double ed[3] = {0, 0, 0};
  if (exit_dir) {
    double n2 = 0.0;
    for (int a = 0; a < K; ++a) {
      ed[a] = (*forces.propulsion->exit_direction)[static_cast<std::size_t>(a)];
      n2 += ed[a] * ed[a];
    }
    for (int a = 0; a < K; ++a) ed[a] /= std::sqrt(n2);
  }
  const bool attract = !force.empty();
  const bool noise = forces.diffusion > 0.0;
  const double sigma = noise ? std::sqrt(2.0 * forces.diffusion * h) : 0.0;
  const std::uint64_t seed = options.seed;
  const std::int64_t stepno = step;
  const double* x = cur.data();
  double* y = nxt.data();
  const double* fa = force.data();
  double worst = 0.0;
  std::int64_t bad = std::numeric_limits<std::int64_t>::max();
#pragma omp parallel for num_threads(threads) schedule(static) reduction(max                    \
                                                                         : worst) reduction(min \
                                                                                            : bad)
  for (int s = 0; s < n; ++s) {
    double xw[K];
    for (int a = 0; a < K; ++a) {
      xw[a] = x[K * s + a];
      if constexpr (P) {
        if (periodic[a] && (trap || prop)) xw[a] = internal::Wrap(xw[a], dlo[a], len[a]);
      }
    }
    double F[K];
    for (int a = 0; a < K; ++a) F[a] = trap ? -gamma * (xw[a] - center[a]) : 0.0;
    if (any_const) {
      for (int a = 0; a < K; ++a) F[a] += f0[a];
    }
    if (attract) {
      for (int a = 0; a < K; ++a) F[a] += fa[K * s + a];
    }
    const double mu = uniform_mobility ? 1.0 : mobility[static_cast<std::size_t>(s)];
    double v[K];
    for (int a = 0; a < K; ++a) v[a] = mu * F[a];
    double beyond = 0.0;
    if (exit_dir) {
      for (int a = 0; a < K; ++a) beyond += (xw[a] - ta[a]) * ed[a];
    }
    if (prop && beyond > 0.0) {
      for (int a = 0; a < K; ++a) v[a] += v0 * ed[a];
    } else if (prop) {
      double target[K];
      if (seg) {
        double e2 = 0.0, dot = 0.0;
        for (int a = 0; a < K; ++a) {
          e2 += (tb[a] - ta[a]) * (tb[a] - ta[a]);
          dot += (xw[a] - ta[a]) * (tb[a] - ta[a]);
        }
        const double t = e2 > 0.0 ? std::clamp(dot / e2, 0.0, 1.0) : 0.0;
        for (int a = 0; a < K; ++a) target[a] = ta[a] + t * (tb[a] - ta[a]);
      } else {
        for (int a = 0; a < K; ++a) target[a] = ta[a];
      }
      double d[K];
      for (int a = 0; a < K; ++a) d[a] = target[a] - xw[a];
      const double dist = std::sqrt(internal::SquaredNorm<K>(d));
      if (dist > 1e-12) {
        for (int a = 0; a < K; ++a) v[a] += v0 * (d[a] / dist);
      }
    }
    double yy[K];
    for (int a = 0; a < K; ++a) yy[a] = x[K * s + a] + h * v[a];
    if (noise) {
      double xi[3];
      GaussianNoise(seed, id[static_cast<std::size_t>(s)], stepno, K, xi);
      for (int a = 0; a < K; ++a) yy[a] += sigma * xi[a];
    }
    double d2 = 0.0;
    bool finite = true;
    for (int a = 0; a < K; ++a) {
      y[K * s + a] = yy[a];
      finite = finite && std::isfinite(yy[a]);
      const double d = yy[a] - x[K * s + a];
      d2 += d * d;
    }
    if (!finite) {
      bad = std::min<std::int64_t>(bad, id[static_cast<std::size_t>(s)]);
    } else {
      worst = std::max(worst, d2);
    }
  }
  *max_move = std::sqrt(worst);
  *bad_id = bad == std::numeric_limits<std::int64_t>::max() ? -1 : bad;
}

void Engine::Impl::Predict(double* max_move, std::int64_t* bad_id) {
  internal::DispatchDimensionPeriodic(
      k, any_periodic, [&](auto kk, auto p) { PredictImpl<kk, p>(max_move, bad_id); });
}

// ---------------------------------------------------------------------------------------------
// The sweep.

template <int K, bool P, bool U>
void Engine::Impl::SweepRows(int begin, int end, double* x, double* max_path, std::int64_t* proj) {
  const int* rs = row_start.data();
  const int* nb_ = nbr.data();
  const double* rad = radius.data();
  const double uniform_c = 2.0 * radius[0];  // r_i + r_j when all radii are equal (exact)
  const double uniform_c2 = uniform_c * uniform_c;
  double local_max = *max_path;
  std::int64_t moved = 0;
  for (int s = begin; s < end; ++s) {
    std::int64_t p = rs[s];
    const std::int64_t e = rs[s + 1];
    if (p == e) continue;
    double* xs_mem = x + K * s;
    double xs[K];
    for (int a = 0; a < K; ++a) xs[a] = xs_mem[a];
    const double ri = U ? 0.0 : rad[s];
    double add = 0.0;
    for (; p < e; ++p) {
      const int t = nb_[p];
      double* xt = x + K * t;
      double u[K];
      for (int a = 0; a < K; ++a) u[a] = xs[a] - xt[a];
      if constexpr (P) {
        const int code = image[static_cast<std::size_t>(p)];
        if (code != 13) {
          for (int a = 0; a < K; ++a) u[a] -= shift[code][a];
        }
      }
      const double c = U ? uniform_c : ri + rad[t];
      const double r2 = internal::SquaredNorm<K>(u);
      if (r2 >= (U ? uniform_c2 : c * c)) continue;
      const double d = internal::ProjectOverlappingPair<K>(xs, xt, u, r2, c);
      add += d;
      local_max = std::max(local_max, AddPath(t, d));
      ++moved;
    }
    if (add > 0.0) {  // write back only a moved particle (no dirty cache lines otherwise)
      for (int a = 0; a < K; ++a) xs_mem[a] = xs[a];
      local_max = std::max(local_max, AddPath(s, add));
    }
  }
  *max_path = local_max;
  *proj += moved;
}

template <int K>
void Engine::Impl::SweepFixed(int begin, int end, double* x, double* max_path, std::int64_t* proj) {
  const int walls = static_cast<int>(wall_b.size());
  const int spheres = static_cast<int>(sphere_r.size());
  const int segments = static_cast<int>(seg_a.size() / 2);
  double local_max = *max_path;
  std::int64_t moved = 0;
  for (int s = begin; s < end; ++s) {
    double* xs = x + K * s;
    const double r = radius[static_cast<std::size_t>(s)];
    double add = 0.0;
    for (int w = 0; w < walls; ++w) {
      const double d = internal::ProjectWall<K>(xs, &wall_n[static_cast<std::size_t>(K * w)],
                                                wall_b[static_cast<std::size_t>(w)] + r);
      if (d > 0.0) {
        add += d;
        ++moved;
      }
    }
    for (int o = 0; o < spheres; ++o) {
      const double d =
          internal::ProjectSphereExterior<K>(xs, &sphere_c[static_cast<std::size_t>(K * o)],
                                             sphere_r[static_cast<std::size_t>(o)] + r);
      if (d > 0.0) {
        add += d;
        ++moved;
      }
    }
    if constexpr (K == 2) {
      for (int g = 0; g < segments; ++g) {
        const double d =
            internal::ProjectSegmentExterior(xs, &seg_a[static_cast<std::size_t>(2 * g)],
                                             &seg_b[static_cast<std::size_t>(2 * g)], r);
        if (d > 0.0) {
          add += d;
          ++moved;
        }
      }
    }
    if (add > 0.0) local_max = std::max(local_max, AddPath(s, add));
  }
  *max_path = local_max;
  *proj += moved;
}

template <int K, bool P>
double Engine::Impl::SweepImpl(std::int64_t* projections) {
  double* x = nxt.data();
  double max_path = 0.0;
  std::int64_t proj = 0;
  if (options.order == SweepOrder::kLexicographic) {
    SweepRowsAny<K, P>(0, n, x, &max_path, &proj);
    if (fixed_sets > 0) SweepFixed<K>(0, n, x, &max_path, &proj);
    *projections += proj;
    return max_path;
  }
#pragma omp parallel num_threads(threads) reduction(max : max_path) reduction(+ : proj)
  {
    for (int colour = 0; colour < 27; ++colour) {
      const int qb = colour_begin[static_cast<std::size_t>(colour)];
      const int qe = colour_begin[static_cast<std::size_t>(colour) + 1];
      if (qb == qe) continue;
#pragma omp for schedule(static)
      for (int q = qb; q < qe; ++q) {
        const auto b = static_cast<std::size_t>(colour_blocks[static_cast<std::size_t>(q)]);
        SweepRowsAny<K, P>(
            static_cast<int>(cell_start[static_cast<std::size_t>(block_cell_begin[b])]),
            static_cast<int>(cell_start[static_cast<std::size_t>(block_cell_begin[b + 1])]), x,
            &max_path, &proj);
      }
    }
    if (fixed_sets > 0) {
#pragma omp for schedule(static)
      for (int chunk = 0; chunk < (n + 1023) / 1024; ++chunk) {
        SweepFixed<K>(chunk * 1024, std::min(n, chunk * 1024 + 1024), x, &max_path, &proj);
      }
    }
  }
  *projections += proj;
  return max_path;
}

double Engine::Impl::Sweep(std::int64_t* projections) {
  ++sweep_id;
  if (sweep_id == 0) {  // wrapped around: clear the stamps
    std::fill(stamp.begin(), stamp.end(), 0);
    sweep_id = 1;
  }
  return internal::DispatchDimensionPeriodic(
      k, any_periodic, [&](auto kk, auto p) { return SweepImpl<kk, p>(projections); });
}

template <int K, bool P>
double Engine::Impl::MaxOverlapImpl(const double* x) const {
  double worst = 0.0;
#pragma omp parallel for num_threads(threads) schedule(static) reduction(max : worst)
  for (int s = 0; s < n; ++s) {
    const double ri = radius[static_cast<std::size_t>(s)];
    for (std::int64_t p = row_start[static_cast<std::size_t>(s)];
         p < row_start[static_cast<std::size_t>(s) + 1]; ++p) {
      const int t = nbr[static_cast<std::size_t>(p)];
      double u[K];
      PairDisplacement<K, P>(x, s, t, p, u);
      const double c = ri + radius[static_cast<std::size_t>(t)];
      const double r2 = internal::SquaredNorm<K>(u);
      if (r2 >= c * c) continue;
      worst = std::max(worst, c - std::sqrt(r2));
    }
  }
  return worst;
}

double Engine::Impl::MaxOverlap(const double* x) const {
  return internal::DispatchDimensionPeriodic(
      k, any_periodic, [&](auto kk, auto p) { return MaxOverlapImpl<kk, p>(x); });
}

double Engine::Impl::ExactMove() const {
  const double* y = nxt.data();
  const double* r0 = ref.data();
  const std::int64_t total = static_cast<std::int64_t>(nxt.size());
  double worst = 0.0;
  const int kk = k;
#pragma omp parallel for num_threads(threads) schedule(static) reduction(max : worst)
  for (std::int64_t s = 0; s < total / kk; ++s) {
    double d2 = 0.0;
    for (int a = 0; a < kk; ++a) {
      const double d = y[kk * s + a] - r0[kk * s + a];
      d2 += d * d;
    }
    worst = std::max(worst, d2);
  }
  return std::sqrt(worst);
}

double Engine::Impl::MaxFixedViolation(const double* x) const {
  double worst = 0.0;
  for (int s = 0; s < n; ++s) {
    const double* xs = x + k * s;
    const double r = radius[static_cast<std::size_t>(s)];
    for (std::size_t w = 0; w < wall_b.size(); ++w) {
      double g = -(wall_b[w] + r);
      for (int a = 0; a < k; ++a)
        g += wall_n[static_cast<std::size_t>(k) * w + static_cast<std::size_t>(a)] * xs[a];
      worst = std::max(worst, -g);
    }
    for (std::size_t o = 0; o < sphere_r.size(); ++o) {
      double r2 = 0.0;
      for (int a = 0; a < k; ++a) {
        const double d =
            xs[a] - sphere_c[static_cast<std::size_t>(k) * o + static_cast<std::size_t>(a)];
        r2 += d * d;
      }
      worst = std::max(worst, sphere_r[o] + r - std::sqrt(r2));
    }
    for (std::size_t g = 0; g < seg_a.size() / 2; ++g) {
      worst = std::max(worst, -internal::SegmentGap(xs, &seg_a[2 * g], &seg_b[2 * g], r));
    }
  }
  return worst;
}

// ---------------------------------------------------------------------------------------------
// One step.

bool Engine::Impl::Step() {
  if (termination != Termination::kCompleted) return false;
  const auto t0 = Clock::now();
  if (!force.empty()) {
    internal::DispatchDimensionPeriodic(k, any_periodic,
                                        [&](auto kk, auto p) { Attraction<kk, p>(); });
  }
  double step_move = 0.0;
  std::int64_t bad = -1;
  Predict(&step_move, &bad);
  stats.force_seconds += Seconds(t0, Clock::now());
  if (bad >= 0) {
    termination = Termination::kNonFinite;
    failed_step = step + 1;
    failed_particle = bad;
    message = fmt::format(
        "step {} (t = {:.6g}): the drift or noise gave a non-finite position for particle {}; "
        "the state of step {} is kept",
        step + 1, static_cast<double>(step + 1) * options.h, bad, step);
    return false;
  }
  built_here = false;
  // max_i ‖Y_i − X_i^build‖ ≤ (bound on ‖X_i − X_i^build‖) + max_i ‖Y_i − X_i‖: a bound without
  // reading the build positions; only when it reaches skin/4 is the exact maximum computed.
  double moved = drift_bound + step_move;
  if (moved > 0.25 * skin) moved = ExactMove();
  if (moved > 0.25 * skin) {
    // A skin widened by earlier redos relaxes back toward the nominal one at regular builds.
    skin = std::max(std::min(nominal_skin, skin_limit), 0.5 * skin);
    Rebuild(&nxt);
    moved = 0.0;
  }
  for (int attempt = 0;; ++attempt) {
    const double accept = 0.5 * skin * (1.0 - 1e-9);
    const auto ts = Clock::now();
    std::int64_t proj = 0;
    // The sum over sweeps of the longest path bounds every particle's path in this step.
    double max_path = 0.0;
    for (int sweep = 0; sweep < options.sweeps; ++sweep) max_path += Sweep(&proj);
    stats.sweep_seconds += Seconds(ts, Clock::now());
    stats.constraint_evaluations +=
        options.sweeps *
        (static_cast<std::int64_t>(nbr.size()) + static_cast<std::int64_t>(n) * fixed_sets);
    stats.constraint_sets +=
        options.sweeps * (static_cast<std::int64_t>(n) * (n - 1) / 2 +
                          static_cast<std::int64_t>(n) * fixed_sets);
    stats.projections += proj;
    if ((moved + max_path) * (1.0 + 1e-12) < accept) {
      drift_bound = (moved + max_path) * (1.0 + 1e-12);  // bounds ‖X_i − X_i^build‖ after the step
      break;
    }
    // A particle may have come within reach of a pair left out of the list: redo the step from
    // its start with a list built at the predicted positions (and a wider skin if that was so).
    ++stats.verlet_retries;
    if (attempt >= 20) {
      throw NumericalError(fmt::format(
          "step {}: a particle moves more than the Verlet skin allows in one sweep", step + 1));
    }
    if (built_here) {
      if (skin >= skin_limit) {
        throw NumericalError(fmt::format(
            "step {}: projections move particles farther than the periodic domain allows the "
            "neighbour lists to reach",
            step + 1));
      }
      skin = std::min(2.0 * skin, skin_limit);
    }
    const auto tp = Clock::now();
    double unused = 0.0;
    Predict(&unused, &bad);
    stats.force_seconds += Seconds(tp, Clock::now());
    Rebuild(&nxt);
    moved = 0.0;
  }
  cur.swap(nxt);
  ++step;
  stats.steps = step;
  stats.time = static_cast<double>(step) * options.h;
  if (options.monitor_overlap) {
    const auto tm = Clock::now();
    stats.last_overlap = MaxOverlap(cur.data());
    stats.max_overlap = std::max(stats.max_overlap, stats.last_overlap);
    stats.monitor_seconds += Seconds(tm, Clock::now());
  }
  stats.total_seconds += Seconds(t0, Clock::now());
  return true;
}

// ---------------------------------------------------------------------------------------------
// Engine.

Engine::Engine(ParticleModel model, Forces forces, EngineOptions options,
               std::span<const double> positions)
    : impl_(std::make_unique<Impl>()) {
  const auto t0 = Clock::now();
  impl_->model = std::move(model);
  impl_->forces = std::move(forces);
  impl_->options = options;
  impl_->Setup(positions);
  impl_->stats.setup_seconds = Seconds(t0, Clock::now());
  impl_->stats.neighbour_seconds = 0.0;
}

Engine::~Engine() = default;
Engine::Engine(Engine&&) noexcept = default;
Engine& Engine::operator=(Engine&&) noexcept = default;

bool Engine::Step() { return impl_->Step(); }

EngineSummary Engine::Run(double T, const EngineObserver& observer) {
  const std::int64_t steps = StepCount(T, impl_->options.h);
  std::vector<double> x(observer ? impl_->cur.size() : 0);
  if (observer) {
    CopyPositions(x);
    observer(step(), time(), x);
  }
  for (std::int64_t i = 0; i < steps; ++i) {
    try {
      if (!Step()) break;
    } catch (const NumericalError& e) {  // the state is the last good one
      Impl& m = *impl_;
      m.termination = Termination::kNonFinite;
      m.failed_step = m.step + 1;
      m.message = fmt::format("{}; the state of step {} is kept", e.what(), m.step);
      break;
    }
    if (observer) {
      CopyPositions(x);
      observer(step(), time(), x);
    }
  }
  return summary();
}

void Engine::CopyPositions(std::span<double> out) const {
  const Impl& m = *impl_;
  MOREAU_ASSERT(out.size() == m.cur.size());
#pragma omp parallel for num_threads(m.threads) schedule(static)
  for (int s = 0; s < m.n; ++s) {
    const int i = m.id[static_cast<std::size_t>(s)];
    for (int a = 0; a < m.k; ++a) {
      double v = m.cur[static_cast<std::size_t>(m.k * s + a)];
      if (m.periodic[a]) v = internal::Wrap(v, m.dlo[a], m.len[a]);
      out[static_cast<std::size_t>(m.k * i + a)] = v;
    }
  }
}

std::vector<double> Engine::Positions() const {
  std::vector<double> x(impl_->cur.size());
  CopyPositions(x);
  return x;
}

int Engine::dimension() const { return impl_->k; }
int Engine::count() const { return impl_->n; }
std::int64_t Engine::step() const { return impl_->step; }
double Engine::time() const { return static_cast<double>(impl_->step) * impl_->options.h; }
int Engine::threads() const { return impl_->threads; }
const ParticleModel& Engine::model() const { return impl_->model; }
const Forces& Engine::forces() const { return impl_->forces; }
const EngineOptions& Engine::options() const { return impl_->options; }

EngineSummary Engine::summary() const {
  EngineSummary s;
  s.stats = impl_->stats;
  s.settings = impl_->options;
  s.termination = impl_->termination;
  s.message = impl_->message;
  s.failed_step = impl_->failed_step;
  s.failed_particle = impl_->failed_particle;
  return s;
}

double Engine::MaxPairOverlap() const { return impl_->MaxOverlap(impl_->cur.data()); }

double Engine::MaxViolation() const {
  return std::max(impl_->MaxOverlap(impl_->cur.data()),
                  impl_->MaxFixedViolation(impl_->cur.data()));
}

std::vector<std::pair<int, int>> Engine::CandidatePairs() const {
  const Impl& m = *impl_;
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(m.nbr.size());
  for (int s = 0; s < m.n; ++s) {
    for (std::int64_t p = m.row_start[static_cast<std::size_t>(s)];
         p < m.row_start[static_cast<std::size_t>(s) + 1]; ++p) {
      int a = m.id[static_cast<std::size_t>(s)];
      int b = m.id[static_cast<std::size_t>(m.nbr[static_cast<std::size_t>(p)])];
      if (a > b) std::swap(a, b);
      pairs.emplace_back(a, b);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

int FixOverlaps(const ParticleModel& model, std::span<double> positions,
                const FixOverlapsOptions& options) {
  if (!(options.tolerance >= 0.0)) {
    throw InputError(fmt::format("tolerance must be ≥ 0 (got {})", options.tolerance));
  }
  if (options.max_sweeps < 1) {
    throw InputError(fmt::format("max_sweeps must be ≥ 1 (got {})", options.max_sweeps));
  }
  EngineOptions eo;
  eo.h = 1.0;
  eo.order = options.order;
  eo.threads = options.threads;
  eo.check_initial_state = false;
  eo.monitor_overlap = false;
  eo.skin_factor = 1.0;
  Engine engine(model, Forces{}, eo, positions);
  const double rmin = *std::min_element(model.radius.begin(), model.radius.end());
  const double tol = options.tolerance * rmin;
  int sweeps = 0;
  while (engine.MaxViolation() > tol) {
    if (sweeps >= options.max_sweeps) {
      throw NumericalError(fmt::format("FixOverlaps: still a violation of {} after {} sweeps",
                                       engine.MaxViolation(), sweeps));
    }
    engine.Step();
    ++sweeps;
  }
  engine.CopyPositions(positions);
  return sweeps;
}

}  // namespace moreau::particles
