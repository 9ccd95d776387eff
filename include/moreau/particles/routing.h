// Routing a crowd to its exits: the walking distance d(x) from x to the nearest exit of a
// CrowdGeometry (geometry.h) on a grid, and the desired direction e0 = −∇d / ‖∇d‖ it gives.
//
// The grid has nodes (x0 + i h, y0 + j h) over the walkable polygon's bounding box, h the
// spacing. A node is free when it lies in the walkable area (inside the walkable polygon, outside
// every obstacle) and at least `clearance` from every wall (walls.h: the polygon's edges without
// the exits, and the obstacles' edges): the walls are inflated by the clearance so that routes
// keep off corners. d is the exact Euclidean distance to the exit segment at the free nodes
// within 1.5 h of an exit, and elsewhere the first-order fast marching solution (Sethian 1996) of
// the eikonal equation ‖∇d‖ = 1 over the free nodes (4 neighbours, a binary heap; ties by node
// index, so the field is a pure function of the geometry and options). Its error is O(h) (a
// rectangle with a door: docs/crowds.md has the measured errors). Nodes that are not free or
// not reached keep d = +∞.
//
// The direction at a node is −∇d normalised, ∇d by central differences (one-sided next to a
// node without d); nodes without d take the mean direction of their neighbours that have one,
// layer by layer outward, so every node has a direction. Direction(x) interpolates the nodes'
// directions bilinearly and normalises. A point outside the walkable polygon (through an exit)
// gets the outward normal of its nearest exit: a person past an exit keeps walking out.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include "moreau/common/field_list.h"
#include "moreau/particles/geometry.h"

namespace moreau::particles {

struct RoutingOptions {
  double spacing = 0.1;    // h > 0, the grid spacing (length)
  double clearance = 0.2;  // ≥ 0, how far the free nodes keep from the walls (length)

  static const FieldList<RoutingOptions>& Fields();  // spacing, clearance
  // Throws InputError(key, reason): ("spacing", "must be > 0 (got 0)").
  void Validate() const;
};

class DistanceField {
 public:
  // Validates both; throws InputError("spacing", "the grid would have N nodes (more than
  // 1e7)") for a grid too fine, and InputError("clearance", "no free grid node within the
  // spacing of exit K …") when an exit cannot be reached.
  DistanceField(const CrowdGeometry& geometry, const RoutingOptions& options);

  // d at (x, y): the bilinear interpolant of the nodes of its cell that have d (weights
  // renormalised over them); +∞ when none has.
  double Distance(double x, double y) const;
  // e0 at x = (x, y) into e (2 values, a unit vector, or zero where the interpolated directions
  // cancel).
  void Direction(const double* x, double* e) const;
  // Where the node directions that Direction(x) reads start (for a prefetch a few people ahead;
  // no effect on any result): 4 values from there and 4 from there + DirectionRowStride(). NaN
  // coordinates count as 0. (A function that prefetches itself is pure to GCC 12, which then
  // drops its calls.)
  const double* DirectionNodes(const double* x) const {
    const double fx = (x[0] - x0_) / h_, fy = (x[1] - y0_) / h_;
    const int i = static_cast<int>(std::min(std::max(0.0, fx), nx_ - 2.0));
    const int j = static_cast<int>(std::min(std::max(0.0, fy), ny_ - 2.0));
    return dir_.data() + 2 * Index(i, j);
  }
  std::ptrdiff_t DirectionRowStride() const { return 2 * static_cast<std::ptrdiff_t>(nx_); }

  const CrowdGeometry& geometry() const { return geometry_; }
  int nx() const { return nx_; }
  int ny() const { return ny_; }
  double spacing() const { return h_; }
  // d at node (i, j) (+∞ when not free or not reached).
  double NodeDistance(int i, int j) const { return d_[Index(i, j)]; }

 private:
  std::size_t Index(int i, int j) const {
    return static_cast<std::size_t>(j) * static_cast<std::size_t>(nx_) +
           static_cast<std::size_t>(i);
  }
  // Per node, 1 when free (the walkable area, `clearance` off the walls).
  std::vector<char> FreeNodes(double clearance) const;
  void March(const std::vector<char>& free);
  void NodeDirections();

  CrowdGeometry geometry_;
  PolygonStrips walkable_;  // geometry_.walkable's inside test
  std::vector<Point2> exit_normal_;
  double x0_ = 0.0, y0_ = 0.0, h_ = 0.1;
  int nx_ = 0, ny_ = 0;
  std::vector<double> d_;    // per node
  std::vector<double> dir_;  // 2 per node
};

}  // namespace moreau::particles
