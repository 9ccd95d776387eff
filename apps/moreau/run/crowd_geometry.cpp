#include "run/crowd_geometry.h"

#include <cmath>
#include <filesystem>

#include <fmt/format.h>

#include "moreau/common/error.h"

namespace moreau::cli {
namespace {

using PS = ParticleScenario;
using particles::Point2;
using particles::Polygon2;

// An array of [x, y] pairs (a polygon, or an exit's two ends).
Polygon2 PointsFromNode(const Scenario& sc, const std::string& key, const toml::node& node) {
  const toml::array* arr = node.as_array();
  if (arr == nullptr) sc.Fail(key, "expected an array of [x, y] points");
  Polygon2 p;
  for (const toml::node& item : *arr) {
    const toml::array* xy = item.as_array();
    if (xy == nullptr || xy->size() != 2) sc.Fail(key, "expected an array of [x, y] points");
    const auto x = (*xy)[0].value<double>();
    const auto y = (*xy)[1].value<double>();
    if (!x || !y || !std::isfinite(*x) || !std::isfinite(*y)) {
      sc.Fail(key, "entries must be finite numbers");
    }
    p.push_back({*x, *y});
  }
  return p;
}

// An array of point arrays (obstacles, exits); empty when absent.
std::vector<Polygon2> PolygonsFromNode(Scenario& sc, const std::string& key) {
  std::vector<Polygon2> out;
  const toml::node* node = sc.GetNode(key);
  if (node == nullptr) return out;
  const toml::array* arr = node->as_array();
  if (arr == nullptr) sc.Fail(key, "expected an array of point arrays");
  for (std::size_t i = 0; i < arr->size(); ++i) {
    out.push_back(PointsFromNode(sc, fmt::format("{}[{}]", key, i), (*arr)[i]));
  }
  return out;
}

// geometry.file: the path relative to the scenario file's folder.
void ReadGeometryFile(Scenario& sc, PS& s, const std::string& key) {
  if (!sc.Has(key)) return;
  s.geometry_file = sc.RequireString(key);
  std::filesystem::path path(s.geometry_file);
  if (path.is_relative()) path = std::filesystem::path(sc.path()).parent_path() / path;
  try {
    s.geometry = particles::ReadCrowdGeometry(path.string(), s.geometry_file);
  } catch (const InputError& e) {
    sc.Fail(key, e.what());
  }
}

// geometry.walkable, geometry.obstacles, geometry.exits (inline, read last), then the distance
// field of either geometry.
void ReadInlineGeometry(Scenario& sc, PS& s, const std::string& key) {
  const std::string prefix = key.substr(0, key.rfind('.'));
  const toml::node* walkable = sc.GetNode(prefix + ".walkable");
  const std::vector<Polygon2> obstacles = PolygonsFromNode(sc, prefix + ".obstacles");
  const std::vector<Polygon2> exits = PolygonsFromNode(sc, key);
  if (walkable != nullptr || !obstacles.empty() || !exits.empty()) {
    if (s.geometry) sc.Fail(prefix, "give geometry.file or the polygons inline, not both");
    if (walkable == nullptr) sc.Fail(prefix + ".walkable", "required key is missing");
    particles::CrowdGeometry g;
    g.walkable = PointsFromNode(sc, prefix + ".walkable", *walkable);
    g.obstacles = obstacles;
    for (std::size_t k = 0; k < exits.size(); ++k) {
      if (exits[k].size() != 2) {
        sc.Fail(fmt::format("{}[{}]", key, k), "an exit is a segment: two [x, y] points");
      }
      g.exits.push_back({exits[k][0], exits[k][1]});
    }
    try {
      g.Validate();
    } catch (const InputError& e) {
      sc.Fail(prefix, e.what());
    }
    s.geometry = std::move(g);
  }
  if (!s.geometry) return;
  try {
    s.route = std::make_shared<const particles::DistanceField>(*s.geometry, s.routing);
  } catch (const InputError& e) {
    sc.Fail(e.key().empty() ? prefix : prefix + "." + e.key(), e.reason());
  }
}

bool Inline(const PS& s) { return s.geometry && s.geometry_file.empty(); }

nlohmann::json EchoPolygon(const Polygon2& p) {
  nlohmann::json j = nlohmann::json::array();
  for (const Point2& v : p) j.push_back({v[0], v[1]});
  return j;
}

// The start inside the walkable area: every given position, or the random start's box.
void CheckStartInTheGeometry(const PS& s) {
  if (!s.geometry) return;
  if (s.positions) {
    const std::vector<double>& x = *s.positions;
    for (std::size_t i = 0; 2 * i + 1 < x.size(); ++i) {
      if (!s.geometry->Walkable(x[2 * i], x[2 * i + 1])) {
        throw InputError(fmt::format("position {} ({}, {}) is outside the walkable area", i,
                                     x[2 * i], x[2 * i + 1]));
      }
    }
    return;
  }
  const particles::Vec3 lo = s.initial_lo.value_or(s.domain_lo);
  const particles::Vec3 hi = s.initial_hi.value_or(s.domain_hi);
  if (!s.geometry->BoxWalkable({lo[0], lo[1]}, {hi[0], hi[1]})) {
    throw InputError(
        fmt::format("the start box (initial.lo/hi, else the domain) [{}, {}] × [{}, {}] is not "
                    "inside the walkable "
                    "area (a wall or an obstacle crosses it)",
                    lo[0], hi[0], lo[1], hi[1]));
  }
}

}  // namespace

void AddGeometryFields(FieldTable<PS>& t) {
  t.Mount("geometry", &PS::routing, particles::RoutingOptions::Fields())
      .Custom(
          "geometry.file", "string", ReadGeometryFile,
          [](const PS& s) {
            return s.geometry_file.empty() ? nlohmann::json() : nlohmann::json(s.geometry_file);
          },
          "walkable polygon, obstacles, exits (path relative to the scenario)")
      .Custom(
          "geometry.walkable", "array of [x, y]", [](Scenario&, PS&, const std::string&) {},
          [](const PS& s) { return Inline(s) ? EchoPolygon(s.geometry->walkable) : nullptr; },
          "the walkable polygon, inline")
      .Custom(
          "geometry.obstacles", "array of polygons", [](Scenario&, PS&, const std::string&) {},
          [](const PS& s) {
            if (!Inline(s)) return nlohmann::json();
            nlohmann::json j = nlohmann::json::array();
            for (const Polygon2& p : s.geometry->obstacles) j.push_back(EchoPolygon(p));
            return j;
          },
          "holes in it (pillars), inline")
      .Custom(
          "geometry.exits", "array of [[x0, y0], [x1, y1]]", ReadInlineGeometry,
          [](const PS& s) {
            if (!Inline(s)) return nlohmann::json();
            nlohmann::json j = nlohmann::json::array();
            for (const particles::CrowdExit& e : s.geometry->exits) {
              j.push_back(EchoPolygon({e.a, e.b}));
            }
            return j;
          },
          "exit segments on the walkable polygon's edges, inline")
      .Check("geometry", [](const PS& s) {
        if (!s.geometry) {
          const particles::RoutingOptions defaults;
          if (s.routing.spacing != defaults.spacing || s.routing.clearance != defaults.clearance) {
            throw InputError("geometry.spacing and geometry.clearance need a geometry");
          }
          return;
        }
        if (s.dimension != 2) throw InputError("a geometry needs dimension 2");
        if (s.room) throw InputError("give [room] or [geometry], not both");
        if (s.forces.target || s.forces.target_end || s.forces.direction) {
          throw InputError("does not go with forces.target or forces.direction");
        }
        CheckStartInTheGeometry(s);
      });
}

}  // namespace moreau::cli
