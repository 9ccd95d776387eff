// Segments (2D) binned on a grid of square cells: each cell lists, in index order, every segment
// whose bounding box widened by a cut-off (and one cell more) meets the cell, so every segment
// closer than the cut-off to a point of the cell is listed. A point outside the grid is farther
// than the cut-off from every segment. Used to visit only the segments near a person (the
// collision-free walls' repulsion, the projection onto segment obstacles) in the same order as
// a loop over all of them.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "moreau/particles/model.h"

namespace moreau::particles::internal {

class SegmentGrid {
 public:
  SegmentGrid() = default;
  // a, b: 2 per segment; about `side` cells along the longer axis of the segments' reach.
  SegmentGrid(const std::vector<double>& a, const std::vector<double>& b, double cut, int side) {
    const std::size_t count = a.size() / 2;
    if (count == 0 || !(cut >= 0.0) || !std::isfinite(cut)) return;
    double lo[2] = {kInf, kInf}, hi[2] = {-kInf, -kInf};
    for (std::size_t s = 0; s < count; ++s) {
      for (int q = 0; q < 2; ++q) {
        lo[q] = std::min({lo[q], a[2 * s + q] - cut, b[2 * s + q] - cut});
        hi[q] = std::max({hi[q], a[2 * s + q] + cut, b[2 * s + q] + cut});
      }
    }
    cell_ = std::max(hi[0] - lo[0], hi[1] - lo[1]) / side;
    if (!(cell_ > 0.0) || !std::isfinite(cell_)) return;
    for (int q = 0; q < 2; ++q) {
      origin_[q] = lo[q];
      cells_[q] = std::min(4 * side, static_cast<int>(std::ceil((hi[q] - lo[q]) / cell_)) + 1);
    }
    Bin(a, b, cut, count);
  }

  // The grid of a model's segments (2D), or an inactive one for four segments or fewer, where a
  // loop over all of them is as fast.
  static SegmentGrid Of(const std::vector<SegmentObstacle>& segments, double cut, int side) {
    if (segments.size() <= 4) return {};
    std::vector<double> a, b;
    for (const SegmentObstacle& g : segments) {
      a.insert(a.end(), {g.a[0], g.a[1]});
      b.insert(b.end(), {g.b[0], g.b[1]});
    }
    return SegmentGrid(a, b, cut, side);
  }

  // Whether the grid is in use (else visit every segment).
  bool active() const { return !start_.empty(); }

  // f(s) for the segments that can be near x, in index order, until f returns true: the cell's
  // list, or every one of the `count` segments when the grid is not in use or x is not finite.
  template <class F>
  void ForEachNear(const double* x, std::size_t count, F&& f) const {
    if (!active() || !std::isfinite(x[0]) || !std::isfinite(x[1])) {
      for (std::size_t s = 0; s < count; ++s) {
        if (f(s)) return;
      }
      return;
    }
    const int* first = nullptr;
    const int* last = nullptr;
    Near(x, &first, &last);
    for (; first != last; ++first) {
      if (f(static_cast<std::size_t>(*first))) return;
    }
  }

  // The listed segments of the cell of x into [*first, *last) (empty outside the grid).
  void Near(const double* x, const int** first, const int** last) const {
    const double f0 = (x[0] - origin_[0]) / cell_, f1 = (x[1] - origin_[1]) / cell_;
    if (!(f0 >= 0.0 && f0 < cells_[0] && f1 >= 0.0 && f1 < cells_[1])) {
      *first = *last = index_.data();
      return;
    }
    const std::size_t c = static_cast<std::size_t>(f1) * static_cast<std::size_t>(cells_[0]) +
                          static_cast<std::size_t>(f0);
    *first = index_.data() + start_[c];
    *last = index_.data() + start_[c + 1];
  }

 private:
  static constexpr double kInf = std::numeric_limits<double>::infinity();

  void Bin(const std::vector<double>& a, const std::vector<double>& b, double cut,
           std::size_t count) {
    const int nx = cells_[0];
    start_.assign(static_cast<std::size_t>(nx) * static_cast<std::size_t>(cells_[1]) + 1, 0);
    std::vector<int> fill;
    for (int pass = 0; pass < 2; ++pass) {
      for (std::size_t s = 0; s < count; ++s) {
        int i[2][2];
        for (int q = 0; q < 2; ++q) {
          const double l = std::min(a[2 * s + q], b[2 * s + q]) - cut;
          const double h = std::max(a[2 * s + q], b[2 * s + q]) + cut;
          i[q][0] = std::clamp(static_cast<int>(std::floor((l - origin_[q]) / cell_)) - 1, 0,
                               cells_[q] - 1);
          i[q][1] = std::clamp(static_cast<int>(std::floor((h - origin_[q]) / cell_)) + 1, 0,
                               cells_[q] - 1);
        }
        for (int cy = i[1][0]; cy <= i[1][1]; ++cy) {
          for (int cx = i[0][0]; cx <= i[0][1]; ++cx) {
            const std::size_t c = static_cast<std::size_t>(cy) * static_cast<std::size_t>(nx) +
                                  static_cast<std::size_t>(cx);
            if (pass == 0) {
              ++start_[c + 1];
            } else {
              index_[static_cast<std::size_t>(fill[c]++)] = static_cast<int>(s);
            }
          }
        }
      }
      if (pass == 0) {
        for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
        index_.assign(static_cast<std::size_t>(start_.back()), 0);
        fill.assign(start_.begin(), start_.end() - 1);
      }
    }
  }

  double origin_[2] = {0.0, 0.0};
  double cell_ = 0.0;
  int cells_[2] = {0, 0};
  std::vector<int> start_;  // per cell + 1; empty: no grid
  std::vector<int> index_;
};

}  // namespace moreau::particles::internal
