// Grid: its field list, validation and the voxel geometry.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "moreau/common/error.h"
#include "moreau/fields/field_set.h"

namespace moreau::fields {
namespace {

constexpr const char* kAxisNames[3] = {"x", "y", "z"};

// A field of 2 or 3 numbers (the box's corners); 2 leave z as it is.
FieldList<Grid>::Field Corner(std::string key, std::array<double, 3> Grid::*member,
                              std::string help) {
  return {std::move(key),
          "numbers",
          "2 or 3 finite",
          "length",
          std::move(help),
          [member](const Grid& g) {
            nlohmann::json j = nlohmann::json::array();
            for (int a = 0; a < g.dimension && a < 3; ++a) j.push_back((g.*member)[a]);
            return j;
          },
          [member](Grid& g, const nlohmann::json& j) -> std::string {
            if (!j.is_array() || j.size() < 2 || j.size() > 3) {
              return ExpectedType("an array of 2 or 3 numbers", j);
            }
            std::array<double, 3> v = g.*member;
            for (std::size_t a = 0; a < j.size(); ++a) {
              if (!j[a].is_number()) return ExpectedType("an array of 2 or 3 numbers", j);
              v[a] = j[a].get<double>();
              std::string why = NumberViolation(Range::Any(), v[a]);
              if (!why.empty()) return why;
            }
            g.*member = v;
            return "";
          },
          [member](const Grid& g) {
            for (int a = 0; a < 3; ++a) {
              if (!std::isfinite((g.*member)[a])) return std::string("must be finite");
            }
            return std::string();
          }};
}

// "" when the extent of every axis is a whole number of voxels, else the reason.
std::string ExtentViolation(const Grid& g) {
  for (int a = 0; a < g.dimension; ++a) {
    const double extent = g.upper[a] - g.lower[a];
    if (!(extent > 0.0)) {
      return fmt::format("must exceed lower along {} (got {} ≤ {})", kAxisNames[a], g.upper[a],
                         g.lower[a]);
    }
    const double n = std::round(extent / g.spacing);
    if (n < 1.0 || n > 1e9) {
      return fmt::format("the extent {} along {} holds {} voxels of edge {} (needs 1 to 10⁹)",
                         extent, kAxisNames[a], extent / g.spacing, g.spacing);
    }
    if (std::abs(n * g.spacing - extent) > 1e-9 * extent) {
      return fmt::format("the extent {} along {} is not a whole number of voxels of edge {} ({})",
                         extent, kAxisNames[a], g.spacing, extent / g.spacing);
    }
  }
  return "";
}

}  // namespace

const FieldList<Grid>& Grid::Fields() {
  static const FieldList<Grid> list = [] {
    FieldList<Grid> t;
    t.Integer("dimension", &Grid::dimension, Range::Closed(2, 3), "", "k: 2 or 3")
        .Custom(Corner("lower", &Grid::lower, "the box's lower corner"))
        .Custom(Corner("upper", &Grid::upper, "the box's upper corner"))
        .Number("spacing", &Grid::spacing, Range::Positive(), "length", "h: the voxels' edge")
        .Rule("upper", ExtentViolation);
    return t;
  }();
  return list;
}

void Grid::Validate() const { Fields().Validate(*this); }

std::array<int, 3> Grid::cells() const {
  std::array<int, 3> n{1, 1, 1};
  for (int a = 0; a < dimension; ++a) {
    n[a] = std::max(1, static_cast<int>(std::lround((upper[a] - lower[a]) / spacing)));
  }
  return n;
}

std::int64_t Grid::voxel_count() const {
  const std::array<int, 3> n = cells();
  return std::int64_t{n[0]} * n[1] * n[2];
}

double Grid::voxel_volume() const {
  return dimension == 3 ? spacing * spacing * spacing : spacing * spacing;
}

std::int64_t Grid::VoxelOf(const double* x) const {
  const std::array<int, 3> n = cells();
  std::int64_t index = 0;
  std::int64_t stride = 1;
  for (int a = 0; a < dimension; ++a) {
    const double u = std::floor((x[a] - lower[a]) / spacing);
    const double clamped = std::clamp(u, 0.0, static_cast<double>(n[a] - 1));  // NaN → 0
    index += stride * (std::isnan(u) ? 0 : static_cast<std::int64_t>(clamped));
    stride *= n[a];
  }
  return index;
}

void Grid::Centre(std::int64_t index, double* centre) const {
  const std::array<int, 3> n = cells();
  for (int a = 0; a < dimension; ++a) {
    centre[a] = lower[a] + spacing * (static_cast<double>(index % n[a]) + 0.5);
    index /= n[a];
  }
}

}  // namespace moreau::fields
