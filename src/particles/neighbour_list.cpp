#include "particles/neighbour_list.h"

#include <cmath>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "particles/parallel.h"

namespace moreau::particles::internal {

void NeighbourList::Configure(const PeriodicBox& box, int n, double skin, double skin_limit,
                              double attraction_range) {
  box_ = box;
  n_ = n;
  nominal_skin_ = skin;
  skin_limit_ = skin_limit;
  skin_ = std::min(skin, skin_limit);
  attraction_range_ = attraction_range;
  row_start_.assign(static_cast<std::size_t>(n) + 1, 0);
  reference_.assign(static_cast<std::size_t>(box.k) * static_cast<std::size_t>(n), 0.0);
}

namespace {

// u = xs − xt, the minimum image on periodic axes (P); returns the image code (13: none).
template <int K, bool P>
inline int MinimumImage(const double* xs, const double* xt, const PeriodicBox& box, double* u) {
  int code = 13;
  int weight = 1;
  for (int a = 0; a < K; ++a) {
    u[a] = xs[a] - xt[a];
    if constexpr (P) {
      if (box.periodic[a]) {
        if (u[a] > 0.5 * box.len[a]) {
          u[a] -= box.len[a];
          code += weight;
        } else if (u[a] < -0.5 * box.len[a]) {
          u[a] += box.len[a];
          code -= weight;
        }
      }
    }
    weight *= 3;
  }
  return code;
}

// Calls f(t, image code) for the slots t > s within reach of slot s, in the list's order: the
// slots of the adjacent cells through `members`, or all slots (brute_force).
template <int K, bool P, typename F>
void VisitPartners(int s, const double* x, const double* radius, double extra,
                   const PeriodicBox& box, const CellList& cells, const int* members, int n,
                   bool brute_force, F&& f) {
  const double* xs = x + K * s;
  const double rs = radius[s];
  auto consider = [&](int t) {
    if (t <= s) return;
    double u[K];
    const int code = MinimumImage<K, P>(xs, x + K * t, box, u);
    const double r2 = SquaredNorm<K>(u);
    const double c = rs + radius[t] + extra;
    if (r2 < c * c) f(t, code);
  };
  if (brute_force) {
    for (int t = s + 1; t < n; ++t) consider(t);
    return;
  }
  cells.grid().ForEachAdjacentCell<K>(xs, [&](std::int64_t cell) {
    const std::int64_t rank = cells.rank(cell);
    const std::int64_t e = cells.cell_start(rank + 1);
    for (std::int64_t q = cells.cell_start(rank); q < e; ++q) consider(members[q]);
  });
}

// Insertion sort of buf[first …] by t, the image codes along (t is unique in a row).
template <bool P>
void SortRow(std::vector<int>& buf, std::vector<std::uint8_t>& img, std::size_t first) {
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

}  // namespace

// One pass: contiguous chunks of slots append their rows to reusable chunk buffers, then the
// buffers are concatenated in chunk order (the same list for any thread count).
template <int K, bool P>
void NeighbourList::BuildRows(const double* x, const double* radius, const CellList& cells,
                              const int* members, bool sort_rows, bool brute_force, int threads) {
  const int n = n_;
  const double extra = this->extra();
  const int chunks = std::max(1, std::min(n, 16 * threads));
  if (static_cast<int>(chunk_nbr_.size()) < chunks) {
    chunk_nbr_.resize(static_cast<std::size_t>(chunks));
    chunk_image_.resize(static_cast<std::size_t>(chunks));
  }
  if (members == nullptr && !brute_force) {
    MOREAU_ASSERT(!sort_rows);
    BuildCellRows<K, P>(x, radius, cells, threads);
    return;
  }
  chunk_slot_.resize(static_cast<std::size_t>(chunks) + 1);
  for (int q = 0; q <= chunks; ++q) {
    chunk_slot_[static_cast<std::size_t>(q)] =
        static_cast<int>(static_cast<std::int64_t>(q) * n / chunks);
  }
  ParallelFor<true>(threads, 0, chunks, [&](std::int64_t q) {
    const int begin = chunk_slot_[static_cast<std::size_t>(q)];
    const int end = chunk_slot_[static_cast<std::size_t>(q) + 1];
    std::vector<int>& buf = chunk_nbr_[static_cast<std::size_t>(q)];
    std::vector<std::uint8_t>& img = chunk_image_[static_cast<std::size_t>(q)];
    buf.clear();
    img.clear();
    for (int s = begin; s < end; ++s) {
      const std::size_t first = buf.size();
      VisitPartners<K, P>(s, x, radius, extra, box_, cells, members, n, brute_force,
                          [&](int t, int code) {
                            buf.push_back(t);
                            if constexpr (P) img.push_back(static_cast<std::uint8_t>(code));
                          });
      row_start_[static_cast<std::size_t>(s) + 1] = static_cast<int>(buf.size() - first);
      if (sort_rows) SortRow<P>(buf, img, first);
    }
  });
  Concatenate(P, chunks, threads);
}

// Storage in cell order. Every slot of a cell has the same candidates, the slot ranges of its
// adjacent cells in VisitPartners' order, and only slots after its own count. Inside a block
// (cells row-major) a cell whose neighbours all lie in the block has them at fixed rank offsets:
// the cells before it in that order hold slots before its own, so its candidates are the rest of
// its own cell and the next cell, then the three-cell rows above (2D: one row; 3D: one in its
// plane, three in the next), each a contiguous slot range. Other cells look their neighbours up
// and gather them once per cell. Chunks are runs of whole blocks of about n/chunks slots. The rows
// are VisitPartners' (with members = identity), entry by entry.
template <int K, bool P>
void NeighbourList::BuildCellRows(const double* x, const double* radius, const CellList& cells,
                                  int threads) {
  const int n = n_;
  const double extra = this->extra();
  const int chunks = std::max(1, std::min(n, 16 * threads));
  const std::int32_t* start = cells.cell_starts();
  const std::int64_t blocks = cells.blocks();
  std::vector<std::int64_t> chunk_block(static_cast<std::size_t>(chunks) + 1, blocks);
  for (int q = 0; q < chunks; ++q) {
    const std::int64_t slot = static_cast<std::int64_t>(q) * n / chunks;
    std::int64_t lo = 0, hi = blocks;  // the first block starting at or after slot
    while (lo < hi) {
      const std::int64_t mid = (lo + hi) / 2;
      if (cells.BlockSlotBegin(mid) < slot)
        lo = mid + 1;
      else
        hi = mid;
    }
    chunk_block[static_cast<std::size_t>(q)] = lo;
  }
  chunk_slot_.resize(static_cast<std::size_t>(chunks) + 1);
  for (int q = 0; q <= chunks; ++q) {
    chunk_slot_[static_cast<std::size_t>(q)] =
        cells.BlockSlotBegin(chunk_block[static_cast<std::size_t>(q)]);
  }
  const PeriodicBox& box = box_;
  ParallelFor<true>(threads, 0, chunks, [&](std::int64_t q) {
    std::vector<int>& buf = chunk_nbr_[static_cast<std::size_t>(q)];
    std::vector<std::uint8_t>& img = chunk_image_[static_cast<std::size_t>(q)];
    std::size_t used = 0;
    std::vector<int> run;  // candidate slot ranges of a cell: [run[2i], run[2i + 1])
    // Rows of slots [b, e): candidates from the ranges in `run` (the first from s + 1 when
    // own_first), tested without branches.
    auto rows = [&](int b, int e, bool own_first) {
      std::size_t most = 0;
      for (std::size_t i = 0; i < run.size(); i += 2)
        most += static_cast<std::size_t>(run[i + 1] - run[i]);
      if (buf.size() < used + most * static_cast<std::size_t>(e - b)) {
        buf.resize(2 * (used + most * static_cast<std::size_t>(e - b)));
        if constexpr (P) img.resize(buf.size());
      }
      for (int s = b; s < e; ++s) {
        int* out = buf.data() + used;
        std::uint8_t* out_img = P ? img.data() + used : nullptr;
        const double* xs = x + static_cast<std::ptrdiff_t>(K) * s;
        const double rs = radius[s];
        std::size_t found = 0;
        for (std::size_t i = 0; i < run.size(); i += 2) {
          const int from = i == 0 && own_first ? s + 1 : std::max(run[i], s + 1);
          for (int t = from; t < run[i + 1]; ++t) {
            double u[K];
            const int code = MinimumImage<K, P>(xs, x + static_cast<std::ptrdiff_t>(K) * t, box, u);
            const double c = rs + radius[t] + extra;
            out[found] = t;
            if constexpr (P) out_img[found] = static_cast<std::uint8_t>(code);
            found += static_cast<std::size_t>(SquaredNorm<K>(u) < c * c);
          }
        }
        used += found;
        row_start_[static_cast<std::size_t>(s) + 1] = static_cast<int>(found);
      }
    };
    for (std::int64_t blk = chunk_block[static_cast<std::size_t>(q)];
         blk < chunk_block[static_cast<std::size_t>(q) + 1]; ++blk) {
      int origin[3], w[3];
      cells.BlockShape(blk, origin, w);
      const std::int64_t wx = w[0], plane = static_cast<std::int64_t>(w[0]) * w[1];
      std::int64_t r = cells.block_cell_begin(blk);
      for (int lz = 0; lz < w[2]; ++lz) {
        for (int ly = 0; ly < w[1]; ++ly) {
          for (int lx = 0; lx < w[0]; ++lx, ++r) {
            const int b = start[r], e = start[r + 1];
            if (b == e) continue;
            run.clear();
            const bool inside = lx >= 1 && lx + 2 <= w[0] &&
                                (K < 2 || (ly >= 1 && ly + 2 <= w[1])) &&
                                (K < 3 || (lz >= 1 && lz + 2 <= w[2]));
            if (inside) {
              run.insert(run.end(), {b, start[r + 2]});
              auto row = [&](std::int64_t o) {
                run.insert(run.end(), {start[r + o - 1], start[r + o + 2]});
              };
              if constexpr (K >= 2) row(wx);
              if constexpr (K == 3) {
                row(plane - wx);
                row(plane);
                row(plane + wx);
              }
              rows(b, e, true);
              continue;
            }
            std::int64_t run_b = -1, run_e = -1;
            auto flush = [&] {
              const int from = std::max(start[run_b], b + 1);
              if (from < start[run_e]) run.insert(run.end(), {from, start[run_e]});
            };
            cells.grid().ForEachAdjacentCell<K>(x + static_cast<std::ptrdiff_t>(K) * b,
                                                [&](std::int64_t cell) {
                                                  const std::int64_t rank = cells.rank(cell);
                                                  if (rank == run_e) {
                                                    run_e = rank + 1;
                                                    return;
                                                  }
                                                  if (run_b >= 0) flush();
                                                  run_b = rank;
                                                  run_e = rank + 1;
                                                });
            flush();
            rows(b, e, false);
          }
        }
      }
    }
    buf.resize(used);
    if constexpr (P) img.resize(used);
  });
  Concatenate(P, chunks, threads);
}

// Row offsets: the chunks' totals are summed in chunk order, then every chunk turns its row
// counts into offsets from its first row on, in parallel; then the rows are copied.
void NeighbourList::Concatenate(bool periodic, int chunks, int threads) {
  std::vector<std::int64_t> chunk_first(static_cast<std::size_t>(chunks) + 1, 0);
  for (int q = 0; q < chunks; ++q) {
    chunk_first[static_cast<std::size_t>(q) + 1] =
        chunk_first[static_cast<std::size_t>(q)] +
        static_cast<std::int64_t>(chunk_nbr_[static_cast<std::size_t>(q)].size());
  }
  const std::int64_t total = chunk_first[static_cast<std::size_t>(chunks)];
  if (total > std::numeric_limits<int>::max()) {
    throw NumericalError(fmt::format("neighbour list with more than {} pairs is too large",
                                     std::numeric_limits<int>::max()));
  }
  nbr_.resize(static_cast<std::size_t>(total));
  if (periodic) image_.resize(static_cast<std::size_t>(total));
  row_start_[0] = 0;
  ParallelFor(threads, 0, chunks, [&](std::int64_t q) {
    const int begin = chunk_slot_[static_cast<std::size_t>(q)];
    const int end = chunk_slot_[static_cast<std::size_t>(q) + 1];
    auto run = static_cast<int>(chunk_first[static_cast<std::size_t>(q)]);
    for (int s = begin; s < end; ++s) {
      run += row_start_[static_cast<std::size_t>(s) + 1];
      row_start_[static_cast<std::size_t>(s) + 1] = run;
    }
    const auto at = static_cast<std::size_t>(chunk_first[static_cast<std::size_t>(q)]);
    const std::vector<int>& buf = chunk_nbr_[static_cast<std::size_t>(q)];
    std::copy(buf.begin(), buf.end(), nbr_.begin() + static_cast<std::ptrdiff_t>(at));
    if (periodic) {
      const std::vector<std::uint8_t>& img = chunk_image_[static_cast<std::size_t>(q)];
      std::copy(img.begin(), img.end(), image_.begin() + static_cast<std::ptrdiff_t>(at));
    }
  });
}

void NeighbourList::Build(const double* x, const double* radius, const CellList& cells,
                          const int* members, bool sort_rows, bool brute_force, std::int64_t step,
                          int threads) {
  double* ref = reference_.data();
  const auto total = static_cast<std::int64_t>(reference_.size());
  ParallelFor(threads, 0, total, [&](std::int64_t i) { ref[i] = x[i]; });
  if (box_.k == 1 && box_.any) {
    BuildRows<1, true>(x, radius, cells, members, sort_rows, brute_force, threads);
  } else if (box_.k == 1) {
    BuildRows<1, false>(x, radius, cells, members, sort_rows, brute_force, threads);
  } else {
    DispatchDimensionPeriodic(box_.k, box_.any, [&](auto k, auto p) {
      BuildRows<k, p>(x, radius, cells, members, sort_rows, brute_force, threads);
    });
  }
  ++stats_.builds;
  stats_.candidate_pairs = pairs();
  if (last_build_step_ >= 0) {
    const std::int64_t interval = step - last_build_step_;
    if (stats_.shortest_rebuild_interval < 0 || interval < stats_.shortest_rebuild_interval) {
      stats_.shortest_rebuild_interval = interval;
    }
  }
  last_build_step_ = step;
  built_here_ = true;
  drift_bound_ = 0.0;
}

double NeighbourList::BoundAfterPrediction(double step_move, const double* y, int threads) {
  // max_i ‖Y_i − X_i^build‖ ≤ (bound on ‖X_i − X_i^build‖) + max_i ‖Y_i − X_i‖: a bound without
  // reading the build positions; only when it reaches skin/4 is the exact maximum computed.
  const double moved = drift_bound_ + step_move;
  far_slots_ = std::numeric_limits<std::int64_t>::max();
  if (!(moved > 0.25 * skin_)) return moved;
  const double* r0 = reference_.data();
  const int k = box_.k;
  const std::int64_t n = n_;
  const double quarter2 = 0.0625 * skin_ * skin_;
  double worst = 0.0;
  std::int64_t far = 0;
#pragma omp parallel for num_threads(threads) schedule(static) reduction(max : worst) \
    reduction(+ : far)
  for (std::int64_t s = 0; s < n; ++s) {
    double d2 = 0.0;
    for (int a = 0; a < k; ++a) {
      const double d = y[k * s + a] - r0[k * s + a];
      d2 += d * d;
    }
    worst = std::max(worst, d2);
    if (d2 > quarter2) ++far;
  }
  far_slots_ = far;
  return std::sqrt(worst);
}

bool NeighbourList::Accept(double moved) {
  const double accept = 0.5 * skin_ * (1.0 - 1e-9);
  if (!(moved * (1.0 + 1e-12) < accept)) return false;
  drift_bound_ = moved * (1.0 + 1e-12);  // bounds ‖X_i − X_i^build‖ after the step
  return true;
}

bool NeighbourList::Listed(int s, int t) const {
  const int a = std::min(s, t), b = std::max(s, t);
  const int* row = nbr_.data();
  for (int p = row_start_[static_cast<std::size_t>(a)];
       p < row_start_[static_cast<std::size_t>(a) + 1]; ++p) {
    if (row[p] == b) return true;
  }
  return false;
}

// Slot f (fast) and every slot t with a build position within 2 cells of f's are a pair of the
// list or were apart at the build by more than their contact distance plus both bounds (the
// minimum image on periodic axes). Slots farther away are ≥ 2 min edge apart (AcceptEach).
template <int K>
bool NeighbourList::LocalPairsApart(int f, const CellList& cells, const int* members,
                                    const double* radius) const {
  const double* rf = reference_.data() + static_cast<std::ptrdiff_t>(K) * f;
  const double bf = bound_[static_cast<std::size_t>(f)];
  bool apart = true;
  auto check = [&](int t) {
    if (t == f || !apart) return;
    double d2 = 0.0;
    for (int a = 0; a < K; ++a) {
      double u = rf[a] - reference_[static_cast<std::size_t>(K * t + a)];
      if (box_.periodic[a]) u -= box_.len[a] * std::nearbyint(u / box_.len[a]);
      d2 += u * u;
    }
    const double contact =
        radius[f] + radius[t] + attraction_range_ + bf + bound_[static_cast<std::size_t>(t)];
    if (!(std::sqrt(d2) * (1.0 - 1e-12) > contact) && !Listed(f, t)) apart = false;
  };
  cells.grid().ForEachCellWithin<K>(rf, 2, [&](std::int64_t cell) {
    const std::int64_t rank = cells.rank(cell);
    for (std::int64_t q = cells.cell_start(rank); q < cells.cell_start(rank + 1); ++q) {
      check(members != nullptr ? members[q] : static_cast<int>(q));
    }
  });
  return apart;
}

bool NeighbourList::AcceptEach(const double* start, const double* x, const double* radius,
                               const std::vector<double>& path, const CellList& cells,
                               const int* members, int threads) {
  const int k = box_.k;
  const std::int64_t n = n_;
  const double half = 0.5 * skin_;
  bound_.resize(static_cast<std::size_t>(n));
  double* b = bound_.data();
  const double* r0 = reference_.data();
  double largest = 0.0;  // the largest bound
  double end = 0.0;      // max_s ‖x_s − X_s^build‖
  double rmax = 0.0;
  std::int64_t fast_count = 0;
#pragma omp parallel for num_threads(threads) schedule(static) \
    reduction(max : largest, end, rmax) reduction(+ : fast_count)
  for (std::int64_t s = 0; s < n; ++s) {
    double e2 = 0.0, f2 = 0.0;
    for (int a = 0; a < k; ++a) {
      const double d = start[k * s + a] - r0[k * s + a];
      const double f = x[k * s + a] - r0[k * s + a];
      e2 += d * d;
      f2 += f * f;
    }
    const double to_end = std::sqrt(f2);
    end = std::max(end, to_end);
    rmax = std::max(rmax, radius[s]);
    // A point P on a path of length L from A to B has |P − A| + |P − B| ≤ L, so
    // |P − X^build| ≤ (|A − X^build| + |B − X^build| + L) / 2.
    b[s] = 0.5 * (std::sqrt(e2) + to_end + path[static_cast<std::size_t>(s)]) * (1.0 + 1e-12);
    largest = std::max(largest, b[s]);
    if (b[s] >= half) ++fast_count;
  }
  // Two slots left out of the list stay apart when b_s + b_t < skin: every pair of slow slots;
  // pairs more than 2 cells apart are ≥ 2 min edge apart at the build.
  double edge = std::numeric_limits<double>::infinity();
  for (int a = 0; a < k; ++a) edge = std::min(edge, cells.grid().edge[a]);
  const double room = skin_ * (1.0 - 1e-9);
  if (fast_count > std::max<std::int64_t>(kMaxFastSlots, n / 16) || !(largest < room) ||
      !(2.0 * largest < (2.0 * edge - 2.0 * rmax - attraction_range_) * (1.0 - 1e-9))) {
    return false;
  }
  for (int f = 0; f < n_; ++f) {
    if (bound_[static_cast<std::size_t>(f)] < half) continue;
    const bool apart = k == 2 ? LocalPairsApart<2>(f, cells, members, radius)
                              : (k == 3 ? LocalPairsApart<3>(f, cells, members, radius)
                                        : LocalPairsApart<1>(f, cells, members, radius));
    if (!apart) return false;
  }
  drift_bound_ = end * (1.0 + 1e-12);  // bounds ‖X_i − X_i^build‖ after the step
  return true;
}

bool NeighbourList::PrepareRedo() {
  if (!built_here_) return true;
  if (skin_ >= skin_limit_) return false;
  skin_ = std::min(2.0 * skin_, skin_limit_);
  return true;
}

LexicographicPairList::LexicographicPairList(const PeriodicBox& box, int n, double max_radius,
                                             double skin)
    : box_(box), reach_(2.0 * max_radius + skin), id_(static_cast<std::size_t>(n)) {
  list_.Configure(box, n, skin, std::numeric_limits<double>::infinity(), 0.0);
  for (int i = 0; i < n; ++i) id_[static_cast<std::size_t>(i)] = i;
}

void LexicographicPairList::Build(const double* x, const double* radius) {
  const int n = static_cast<int>(id_.size());
  cells_.Fit(x, n, box_, reach_, 0, 1);
  cells_.Sort(x, id_.data(), n, 1);
  list_.Build(x, radius, cells_, cells_.permutation().data(), true, false, 0, 1);
}

namespace {

template <int K, bool P>
double MaxPairOverlapImpl(const NeighbourList& list, const double* x, const double* radius, int n,
                          int threads) {
  double worst = 0.0;
#pragma omp parallel for num_threads(threads) schedule(static) reduction(max : worst)
  for (int s = 0; s < n; ++s) worst = std::max(worst, list.RowOverlap<K, P>(x, radius, s));
  return worst;
}

}  // namespace

double MaxPairOverlap(const NeighbourList& list, const double* x, const double* radius, int n,
                      int threads) {
  return DispatchDimensionPeriodic(list.box().k, list.box().any, [&](auto kk, auto p) {
    return MaxPairOverlapImpl<kk, p>(list, x, radius, n, threads);
  });
}

}  // namespace moreau::particles::internal
