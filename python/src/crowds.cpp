// moreau.particles' pedestrian crowds: the walking speeds (desired speeds, Weidmann's density
// law, the collision-free speed model), the walkable area with its exits, and the routing field
// that gives each person the direction toward the nearest exit.
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "bindings.h"
#include "moreau/particles/forces.h"
#include "moreau/particles/geometry.h"
#include "moreau/particles/routing.h"

namespace moreau::python {

using namespace moreau::particles;

namespace {

// The walking speeds and the speed laws.
void BindWalking(py::module_& m) {
  BindOptionsClass<CollisionFreeSpeed>(
      m, "CollisionFreeSpeed",
      "The collision-free speed model of Tordeux, Chraibi & Seyfried (2016): keys of "
      "[forces.collision_free].");
  py::class_<DensitySpeed>(m, "DensitySpeed",
                           "Weidmann's speed–density law: v = v0 φ(ρ) at the local density ρ.")
      .def(py::init(&FromKwargs<DensitySpeed>))
      .def_readwrite("gamma", &DensitySpeed::gamma)
      .def_readwrite("max_density", &DensitySpeed::max_density)
      .def_readwrite("radius", &DensitySpeed::radius);
  py::class_<WalkingSpeeds>(m, "WalkingSpeeds",
                            "Per-person walking speeds of the self-propulsion (a crowd).")
      .def(py::init(&FromKwargs<WalkingSpeeds>))
      .def_readwrite("speed_sd", &WalkingSpeeds::speed_sd)
      .def_readwrite("density", &WalkingSpeeds::density)
      .def_readwrite("collision_free", &WalkingSpeeds::collision_free);
  m.def("collision_free_speed_at", &CollisionFreeSpeedAt, py::arg("model"), py::arg("v0"),
        py::arg("headway"), "V(s) = min(v0, max(0, (s − ℓ) / T)) at headway s.");
  m.def("collision_free_range", &CollisionFreeRange, py::arg("model"), py::arg("max_speed"),
        "R = ℓ + max(T v_max, 10 D): the distance within which neighbours count.");
  m.def("desired_speed", &DesiredSpeed, py::arg("seed"), py::arg("id"), py::arg("mean"),
        py::arg("sd"), "v0,i of person id: mean + sd z, z a normal truncated to [−3, 3].");
  m.def("weidmann_speed_factor", &WeidmannSpeedFactor, py::arg("law"), py::arg("density"),
        "φ(ρ) of Weidmann's law.");
}

// The walkable area and the routing field over it.
void BindGeometry(py::module_& m) {
  py::class_<CrowdGeometry>(m, "CrowdGeometry",
                            "A walkable polygon, obstacles in it and exits on its boundary (2D).")
      .def(py::init(&FromKwargs<CrowdGeometry>))
      .def_readwrite("walkable", &CrowdGeometry::walkable)
      .def_readwrite("obstacles", &CrowdGeometry::obstacles)
      .def_property(
          "exits",
          [](const CrowdGeometry& g) {
            std::vector<std::vector<Point2>> exits;
            for (const CrowdExit& e : g.exits) exits.push_back({e.a, e.b});
            return exits;
          },
          [](CrowdGeometry& g, const std::vector<std::array<Point2, 2>>& exits) {
            g.exits.clear();
            for (const auto& e : exits) g.exits.push_back({e[0], e[1]});
          },
          "The exits as [[a, b], …] segments.")
      .def("validate", &CrowdGeometry::Validate)
      .def("walls", &CrowdGeometry::Walls,
           "The walkable polygon's edges without the exits, then every obstacle's edges "
           "(ParticleModel.segments).")
      .def("walkable_at", &CrowdGeometry::Walkable, py::arg("x"), py::arg("y"))
      .def("exit_normal", &CrowdGeometry::ExitNormal, py::arg("k"))
      .def("nearest_exit", &CrowdGeometry::NearestExit, py::arg("x"), py::arg("y"));
  m.def(
      "parse_crowd_geometry",
      [](const std::string& text, const std::string& name) {
        return ParseCrowdGeometry(text, name);
      },
      py::arg("text"), py::arg("name") = "geometry",
      "A geometry from the text format of docs/crowds.md (walkable, obstacle, exit lines).");
  m.def(
      "read_crowd_geometry", [](const std::string& path) { return ReadCrowdGeometry(path, path); },
      py::arg("path"), "A geometry from a file in that format.");

  BindOptionsClass<RoutingOptions>(m, "RoutingOptions", "Keys of [geometry]: the routing grid.");
  py::class_<DistanceField, std::shared_ptr<DistanceField>>(
      m, "DistanceField",
      "The walking distance to the nearest exit on a grid (fast marching) and its direction −∇d.")
      .def(py::init([](const CrowdGeometry& geometry, const std::optional<RoutingOptions>& options,
                       const py::kwargs& kwargs) {
             return std::make_shared<DistanceField>(geometry, WithKwargs(options, kwargs));
           }),
           py::arg("geometry"), py::arg("options") = std::nullopt)
      .def("distance", &DistanceField::Distance, py::arg("x"), py::arg("y"))
      .def(
          "direction",
          [](const DistanceField& f, double x, double y) {
            const double p[2] = {x, y};
            Point2 e{0.0, 0.0};
            f.Direction(p, e.data());
            return e;
          },
          py::arg("x"), py::arg("y"), "The unit walking direction at (x, y).")
      .def_property_readonly("geometry", &DistanceField::geometry)
      .def_property_readonly("spacing", &DistanceField::spacing);
}

}  // namespace

void BindCrowdTypes(py::module_& m) {
  BindWalking(m);
  BindGeometry(m);
}

}  // namespace moreau::python
