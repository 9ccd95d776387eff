// The measurements crowd research makes on trajectories (docs/crowds.md "Measurements"), in the
// plane, lengths in metres and times in seconds:
//
//   - classic density in a measurement area A: ρ = N_A / |A|, N_A the people whose position lies
//     in A;
//   - Voronoi density and speed in A (Steffen & Seyfried 2010, Physica A 389, 1902–1910): with
//     V_i person i's Voronoi cell (cut by the walkable area and optionally by a disk of radius R
//     around the person), ρ_V = Σ_i |V_i ∩ A| / (|V_i| |A|) and v_V = Σ_i v_i |V_i ∩ A| / |A|;
//   - a measurement line's crossings in the walking direction, their times, and the flow
//     J = N / Δt and the specific flow J / w per metre of line (the line-crossing flow, "method
//     A").
//
// Polygons are lists of vertices (not closed: the last vertex is not repeated), simple, in
// either orientation unless a function asks for a convex one. Everything here is stateless
// maths: points in, numbers out.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace moreau::crowds {

using Point = std::array<double, 2>;  // (x, y) in metres
using Polygon = std::vector<Point>;   // vertices in order, the last not repeating the first

// |shoelace area| of a simple polygon (0 for fewer than three vertices).
double PolygonArea(std::span<const Point> polygon);
// Whether p lies in the polygon (crossing number: a point on an edge may go either way, so
// nobody standing exactly on the boundary is counted twice by two areas sharing that edge).
bool Contains(std::span<const Point> polygon, Point p);
// Whether the polygon is convex with a positive area (collinear vertices allowed).
bool IsConvex(std::span<const Point> polygon);
// The rectangle [lo, hi] counter-clockwise, and a regular polygon of `vertices` vertices on the
// circle of `radius` about `center`, the first at angle 0 (counter-clockwise).
Polygon Rectangle(Point lo, Point hi);
Polygon RegularPolygon(Point center, double radius, int vertices);

// The part of `polygon` where ⟨normal, p⟩ ≤ offset (Sutherland–Hodgman against one half-plane;
// a non-convex polygon may come back with zero-width bridges, its area is right).
Polygon ClipByHalfPlane(std::span<const Point> polygon, Point normal, double offset);
// subject ∩ convex (Sutherland–Hodgman): the area is exact for any simple subject; `convex`
// must be convex, either orientation.
Polygon ClipByConvex(std::span<const Point> subject, std::span<const Point> convex);

// How Voronoi cells are bounded.
struct VoronoiOptions {
  // The walkable area that bounds every cell: convex, at least three vertices (a room, a
  // corridor's box). Cells of people outside it may be empty.
  Polygon bound;
  // R > 0: each cell is also cut by the regular polygon of `cutoff_vertices` vertices inscribed
  // in the circle of radius R about the person (12 vertices: PedPy's Cutoff with quad_segments =
  // 3); none: the cells reach the bound.
  std::optional<double> cutoff_radius;
  int cutoff_vertices = 12;  // ≥ 3

  // Throws InputError(key, reason): ("bound", "must be a convex polygon of positive area"),
  // ("cutoff_radius", "must be > 0 (got 0)"), ("cutoff_vertices", "must be ≥ 3 (got 2)").
  void Validate() const;
};

// Person i's Voronoi cell {p : |p − x_i| ≤ |p − x_j| for every j} ∩ bound (∩ the cutoff
// polygon), counter-clockwise, one per point, by clipping the bound with the perpendicular
// bisectors of the neighbours, nearest first, until no farther neighbour can cut the cell
// (distance ≥ twice the cell's farthest vertex). People at the same position as another do not
// cut each other's cells (both get the same cell). O(N² log N) for N points.
// Throws InputError from options.Validate().
std::vector<Polygon> VoronoiCells(std::span<const Point> points, const VoronoiOptions& options);

// One frame's measurements in one area.
struct AreaMeasurement {
  int count = 0;                 // N_A: people whose position lies in A
  double density_classic = 0.0;  // N_A / |A|, 1/m²
  double density_voronoi = 0.0;  // Σ_i |V_i ∩ A| / (|V_i| |A|), 1/m²
  double speed_voronoi = 0.0;    // Σ_i v_i |V_i ∩ A| / |A|, m/s (0 without speeds)
};

// N_A / |A|. Throws InputError("area", …) for an area of no positive area.
double ClassicDensity(std::span<const Point> points, std::span<const Point> area);
// The measurements in `area` of N people: positions, their cells (VoronoiCells) and speeds |v_i|
// (m/s; empty: no speed). Cells of zero area are skipped. Throws InputError("area", …) for an area
// of no positive area, InputError for sizes that differ.
AreaMeasurement MeasureArea(std::span<const Point> points, std::span<const Polygon> cells,
                            std::span<const double> speeds, std::span<const Point> area);

// Velocities of one person's track by central differences, v_k = (x_{k+1} − x_{k−1}) /
// (t_{k+1} − t_{k−1}), one-sided at the first and the last sample, zero for a single sample.
// times: strictly increasing. Throws InputError for sizes that differ or times not increasing.
std::vector<Point> TrackVelocities(std::span<const double> times, std::span<const Point> x);

// A measurement line from a to b. The walking direction it counts is n = (b − a) turned
// clockwise: people passing from the left of a → b to its right (from (x, 0) to (x, 1): walking
// toward +x).
struct MeasurementLine {
  Point a{0.0, 0.0};
  Point b{0.0, 1.0};
  double length() const;
  Point direction() const;  // n / |n|
};

// The fraction s ∈ [0, 1) of the step p → q at which it crosses `line` in the walking direction,
// none if it does not: p on the line's side behind or on it, q strictly ahead, and the crossing
// point on the segment a–b (a step that ends on the line has not crossed yet; PedPy's rule).
std::optional<double> CrossingFraction(const MeasurementLine& line, Point p, Point q);
// The time of a track's first crossing in the walking direction, t_k + s (t_{k+1} − t_k) on the
// step k → k+1 that crosses; none if it never does. Crossings back are not counted.
std::optional<double> FirstCrossingTime(const MeasurementLine& line, std::span<const double> times,
                                        std::span<const Point> x);

// The flow through a line from its crossing times.
struct LineFlow {
  int crossings = 0;           // N
  double first = 0.0;          // t_1, s (0 when N = 0)
  double last = 0.0;           // t_N, s
  double flow = 0.0;           // J = (N − 1) / (t_N − t_1), 1/s (0 when N < 2 or t_N = t_1)
  double specific_flow = 0.0;  // J / w, 1/(m s), w the line's length
};
// J from the first to the last crossing (the N − 1 time headways between them); the times in any
// order.
LineFlow FlowThroughLine(std::span<const double> crossing_times, double line_length);
// N_[t0, t1) / (t1 − t0): the crossings in a window. Throws InputError unless t1 > t0.
double FlowInWindow(std::span<const double> crossing_times, double t0, double t1);

}  // namespace moreau::crowds
