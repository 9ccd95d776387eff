// Reading the structured fields of a network scenario: [[network.nodes]], [[network.springs]]
// and the reference matrices.
#include <cmath>

#include <fmt/format.h>

#include "control/control_scenario.h"

namespace moreau::cli {
namespace {

double NodeNumber(const Scenario& s, const toml::node& node, const std::string& key) {
  if (auto v = node.value<double>()) {
    if (!std::isfinite(*v)) s.Fail(key, "must be a finite number");
    return *v;
  }
  s.Fail(key, "expected a number");
}

std::vector<double> NodeNumbers(const Scenario& s, const toml::node& node, const std::string& key) {
  const toml::array* arr = node.as_array();
  if (arr == nullptr) s.Fail(key, "expected an array of numbers");
  std::vector<double> out;
  std::size_t i = 0;
  for (const toml::node& item : *arr) {
    out.push_back(NodeNumber(s, item, fmt::format("{}[{}]", key, i++)));
  }
  return out;
}

// The entries of an array of tables, each checked for unknown fields.
std::vector<const toml::table*> Entries(Scenario& s, const std::string& key,
                                        std::initializer_list<std::string_view> allowed) {
  const toml::node* node = s.GetNode(key);
  const toml::array* arr = node == nullptr ? nullptr : node->as_array();
  if (arr == nullptr) s.Fail(key, "expected an array of tables");
  std::vector<const toml::table*> out;
  for (const toml::node& item : *arr) {
    const std::string entry = fmt::format("{}[{}]", key, out.size());
    const toml::table* t = item.as_table();
    if (t == nullptr) s.Fail(entry, "expected a table");
    s.CheckTableKeys(entry, *t, allowed);
    out.push_back(t);
  }
  return out;
}

// d numbers into the first d entries of `out`.
void ReadPoint(const Scenario& s, const toml::node& node, const std::string& key, int d,
               Eigen::Vector3d& out) {
  const std::vector<double> v = NodeNumbers(s, node, key);
  if (static_cast<int>(v.size()) != d) {
    s.Fail(key, fmt::format("expected {} numbers (network.dimension), got {}", d, v.size()));
  }
  for (int i = 0; i < d; ++i) out[i] = v[static_cast<std::size_t>(i)];
}

}  // namespace

void ReadNetworkNodes(Scenario& s, ControlScenario& c, const std::string& key) {
  const int d = c.network.dimension;
  const auto entries = Entries(s, key, {"mass", "position", "velocity", "fixed"});
  for (std::size_t j = 0; j < entries.size(); ++j) {
    const toml::table& t = *entries[j];
    const std::string entry = fmt::format("{}[{}]", key, j);
    control::NetworkNode node;
    if (const toml::node* f = t.get("fixed")) {
      auto b = f->value_exact<bool>();
      if (!b) s.Fail(entry + ".fixed", "expected true or false");
      node.fixed = *b;
    }
    if (const toml::node* m = t.get("mass")) {
      node.mass = NodeNumber(s, *m, entry + ".mass");
    } else if (!node.fixed) {
      s.Fail(entry + ".mass", "required for a free node");
    }
    const toml::node* p = t.get("position");
    if (p == nullptr) s.Fail(entry + ".position", "required key is missing");
    ReadPoint(s, *p, entry + ".position", d, node.position);
    if (const toml::node* v = t.get("velocity")) {
      ReadPoint(s, *v, entry + ".velocity", d, node.velocity);
    }
    c.network.nodes.push_back(node);
  }
}

void ReadNetworkSprings(Scenario& s, ControlScenario& c, const std::string& key) {
  const auto entries = Entries(s, key, {"nodes", "stiffness", "damping", "rest_min", "rest_max"});
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const toml::table& t = *entries[k];
    const std::string entry = fmt::format("{}[{}]", key, k);
    auto field = [&](const char* name) -> const toml::node& {
      const toml::node* n = t.get(name);
      if (n == nullptr) s.Fail(fmt::format("{}.{}", entry, name), "required key is missing");
      return *n;
    };
    control::NetworkSpring sp;
    const std::vector<double> e = NodeNumbers(s, field("nodes"), entry + ".nodes");
    if (e.size() != 2 || e[0] != std::floor(e[0]) || e[1] != std::floor(e[1])) {
      s.Fail(entry + ".nodes", "expected two node indices [a, b]");
    }
    const auto nodes = static_cast<double>(c.network.nodes.size());
    for (const double index : e) {
      if (!(index >= 0.0 && index < nodes)) {
        s.Fail(entry + ".nodes",
               fmt::format("node index {} is out of range [0, {})", index, nodes));
      }
    }
    sp.a = static_cast<int>(e[0]);
    sp.b = static_cast<int>(e[1]);
    sp.stiffness = NodeNumber(s, field("stiffness"), entry + ".stiffness");
    sp.damping = NodeNumber(s, field("damping"), entry + ".damping");
    sp.rest_min = NodeNumber(s, field("rest_min"), entry + ".rest_min");
    sp.rest_max = NodeNumber(s, field("rest_max"), entry + ".rest_max");
    c.network.springs.push_back(sp);
  }
}

void ReadReferenceMatrix(Scenario& s, const std::string& key, Eigen::MatrixXd* out) {
  const toml::node* node = s.GetNode(key);
  if (node == nullptr) return;
  const toml::array* arr = node->as_array();
  if (arr == nullptr) s.Fail(key, "expected an array of frames (arrays of numbers)");
  std::vector<std::vector<double>> rows;
  for (const toml::node& item : *arr) {
    rows.push_back(NodeNumbers(s, item, fmt::format("{}[{}]", key, rows.size())));
  }
  const std::size_t cols = rows.empty() ? 0 : rows.front().size();
  out->resize(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(cols));
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (rows[i].size() != cols) {
      s.Fail(fmt::format("{}[{}]", key, i),
             fmt::format("reference of the wrong length: frame has {} values, frame 0 has {}",
                         rows[i].size(), cols));
    }
    for (std::size_t j = 0; j < cols; ++j) {
      (*out)(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = rows[i][j];
    }
  }
}

}  // namespace moreau::cli
