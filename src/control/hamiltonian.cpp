#include "moreau/control/hamiltonian.h"

#include <algorithm>
#include <cmath>

#include "control/hamiltonian_internal.h"
#include "control/spring_term.h"

namespace moreau::control {
namespace {

double LogCosh(double y) {
  const double a = std::abs(y);
  return a + std::log1p(std::exp(-2.0 * a)) - std::log(2.0);
}

// One spring's local variables Δx, Δv, e (hamiltonian.h) and where its free ends sit in z and ρ.
template <int D>
struct SpringGather {
  using Vec = Eigen::Matrix<double, D, 1>;
  Vec dx = Vec::Zero(), dv = Vec::Zero(), e = Vec::Zero();
  int ends = 0;                  // free ends (1 or 2)
  int base[2] = {0, 0};          // 2 d k: the ends' x block; v (and ζ) at base + d
  double sign[2] = {0.0, 0.0};   // −1 for node a, +1 for node b
  double scale[2] = {0.0, 0.0};  // sign / mass: ∂e/∂ζ
};

template <int D>
void Gather(const SpringNetwork& net, const Instant& instant, const Eigen::VectorXd& z,
            const Eigen::VectorXd& rho, const NetworkSpring& sp, SpringGather<D>& g) {
  const int ends[2] = {sp.a, sp.b};
  for (int side = 0; side < 2; ++side) {
    const int j = ends[side];
    const int k = net.free_index(j);
    const double s = side == 0 ? -1.0 : 1.0;
    if (k < 0) {
      g.dx += s * instant.fixed_position.segment<D>(D * j);
      g.dv += s * instant.fixed_velocity.segment<D>(D * j);
      continue;
    }
    const int base = 2 * D * k;
    const double scale = s / net.node(j).mass;
    g.dx += s * z.segment<D>(base);
    g.dv += s * z.segment<D>(base + D);
    g.e += scale * rho.segment<D>(base + D);
    g.base[g.ends] = base;
    g.sign[g.ends] = s;
    g.scale[g.ends] = scale;
    ++g.ends;
  }
}

// Adds one spring's φ (spring_term.h) and its derivatives, mapped to (z, ρ) through
// Δx = Σ ±x, Δv = Σ ±v, e = Σ ±ζ/m, into `out`.
template <int D>
void ScatterSpring(const SpringGather<D>& g, const internal::SpringTerm<D>& t, bool hessian,
                   HamiltonianEval& out) {
  out.value += t.value;
  for (int i = 0; i < g.ends; ++i) {
    const int xi = g.base[i], vi = g.base[i] + D;
    out.dz.segment<D>(xi) += g.sign[i] * t.gx;
    out.dz.segment<D>(vi) += g.sign[i] * t.gv;
    out.drho.segment<D>(vi) += g.scale[i] * t.ge;
    if (!hessian) continue;
    for (int j = 0; j < g.ends; ++j) {
      const int xj = g.base[j], vj = g.base[j] + D;
      const double ss = g.sign[i] * g.sign[j];
      out.zz.block<D, D>(xi, xj) += ss * t.xx;
      out.zz.block<D, D>(xi, vj) += ss * t.xv;
      out.zz.block<D, D>(vi, xj) += ss * t.xv.transpose();
      const double es = g.scale[i] * g.sign[j];
      out.rho_z.block<D, D>(vi, xj) += es * t.xe.transpose();
      out.rho_z.block<D, D>(vi, vj) += es * t.ve.transpose();
      out.rho_rho.block<D, D>(vi, vj) += g.scale[i] * g.scale[j] * t.ee;
    }
  }
}

template <int D>
void AddSprings(const TrackingProblem& problem, const Instant& instant, const Eigen::VectorXd& z,
                const Eigen::VectorXd& rho, HamiltonianOrder order, HamiltonianEval& out) {
  const bool hessian = order == HamiltonianOrder::kHessian;
  internal::SpringTerm<D> term;
  for (const NetworkSpring& sp : problem.network().springs()) {
    SpringGather<D> g;
    Gather<D>(problem.network(), instant, z, rho, sp, g);
    internal::EvaluateSpringTerm<D>(g.dx, g.dv, g.e, sp, problem.gamma(), hessian, term);
    ScatterSpring<D>(g, term, hessian, out);
  }
}

template <int D>
void SwitchingFunctionsOf(const TrackingProblem& problem, const Instant& instant,
                          const Eigen::VectorXd& z, const Eigen::VectorXd& rho,
                          Eigen::VectorXd& p) {
  const SpringNetwork& net = problem.network();
  p.setZero(net.num_springs());
  for (int s = 0; s < net.num_springs(); ++s) {
    SpringGather<D> g;
    Gather<D>(net, instant, z, rho, net.spring(s), g);
    p[s] = net.spring(s).stiffness * g.e.dot(g.dx) / g.dx.norm();
  }
}

}  // namespace

Instant MakeInstant(const TrackingProblem& problem, double t) {
  const SpringNetwork& net = problem.network();
  const int d = net.dimension();
  const int m = net.num_free();
  Instant in;
  in.t = t;
  in.fixed_position.setZero(d * net.num_nodes());
  in.fixed_velocity.setZero(d * net.num_nodes());
  for (int j = 0; j < net.num_nodes(); ++j) {
    if (net.free_index(j) < 0) {
      net.FixedNodeState(j, t, in.fixed_position.data() + d * j, in.fixed_velocity.data() + d * j);
    }
  }
  in.ref_position.setZero(d * m);
  in.ref_velocity.setZero(d * m);
  in.ref_weight.setZero(m);
  problem.reference()(t, in.ref_position.data(), in.ref_velocity.data(), in.ref_weight.data());
  return in;
}

SmoothMin RegularizedSpringMin(double p, double rest_min, double rest_max, double gamma) {
  const double a = 0.5 * (rest_min - rest_max);
  const double b = 0.5 * (rest_min + rest_max);
  const double y = p / gamma;
  const double th = std::tanh(y);
  SmoothMin s;
  s.value = a * gamma * LogCosh(y) + b * p;
  s.slope = a * th + b;
  // 1 − tanh² computed without cancellation for large |y|: 4 e^{−2|y|} / (1 + e^{−2|y|})².
  const double ex = std::exp(-2.0 * std::abs(y));
  const double sech2 = 4.0 * ex / ((1.0 + ex) * (1.0 + ex));
  s.curvature = a * sech2 / gamma;
  return s;
}

namespace internal {

void AddTransportAndCost(const TrackingProblem& problem, const Instant& instant,
                         const Eigen::VectorXd& z, const Eigen::VectorXd& rho,
                         HamiltonianOrder order, HamiltonianEval& out) {
  const SpringNetwork& net = problem.network();
  const int d = net.dimension();
  const int n = net.state_size();
  const CostWeights& w = problem.weights();
  out.value = 0.0;
  out.dz.setZero(n);
  out.drho.setZero(n);
  if (order == HamiltonianOrder::kHessian) {
    out.zz.setZero(n, n);
    out.rho_z.setZero(n, n);
    out.rho_rho.setZero(n, n);
  }
  for (int k = 0; k < net.num_free(); ++k) {
    const int base = 2 * d * k;
    const double wk = instant.ref_weight[k];
    for (int i = 0; i < d; ++i) {
      const int ix = base + i, iv = base + d + i;
      // λ · v
      out.value += rho[ix] * z[iv];
      out.dz[iv] += rho[ix];
      out.drho[ix] += z[iv];
      // running cost h
      const double ex = z[ix] - instant.ref_position[d * k + i];
      const double ev = z[iv] - instant.ref_velocity[d * k + i];
      out.value += wk * (w.position * ex * ex + w.velocity * ev * ev);
      out.dz[ix] += 2.0 * wk * w.position * ex;
      out.dz[iv] += 2.0 * wk * w.velocity * ev;
      if (order == HamiltonianOrder::kHessian) {
        out.rho_z(ix, iv) += 1.0;
        out.zz(ix, ix) += 2.0 * wk * w.position;
        out.zz(iv, iv) += 2.0 * wk * w.velocity;
      }
    }
  }
}

}  // namespace internal

void EvaluateRegularizedHamiltonian(const TrackingProblem& problem, const Instant& instant,
                                    const Eigen::VectorXd& z, const Eigen::VectorXd& rho,
                                    HamiltonianOrder order, HamiltonianEval& out) {
  internal::AssembleRegularizedHamiltonian(problem, instant, z, rho, order, out, [&](auto d) {
    AddSprings<decltype(d)::value>(problem, instant, z, rho, order, out);
  });
}

void SwitchingFunctions(const TrackingProblem& problem, const Instant& instant,
                        const Eigen::VectorXd& z, const Eigen::VectorXd& rho, Eigen::VectorXd& p) {
  switch (problem.network().dimension()) {
    case 1:
      SwitchingFunctionsOf<1>(problem, instant, z, rho, p);
      break;
    case 2:
      SwitchingFunctionsOf<2>(problem, instant, z, rho, p);
      break;
    default:
      SwitchingFunctionsOf<3>(problem, instant, z, rho, p);
      break;
  }
}

void EffectiveRestLengths(const TrackingProblem& problem, const Instant& instant,
                          const Eigen::VectorXd& z, const Eigen::VectorXd& rho,
                          Eigen::VectorXd& rest_lengths) {
  SwitchingFunctions(problem, instant, z, rho, rest_lengths);
  const SpringNetwork& net = problem.network();
  for (int s = 0; s < net.num_springs(); ++s) {
    const NetworkSpring& sp = net.spring(s);
    rest_lengths[s] =
        RegularizedSpringMin(rest_lengths[s], sp.rest_min, sp.rest_max, problem.gamma()).slope;
  }
}

double EvaluateHamiltonian(const TrackingProblem& problem, const Instant& instant,
                           const Eigen::VectorXd& z, const Eigen::VectorXd& rho,
                           Eigen::VectorXd* minimiser) {
  const SpringNetwork& net = problem.network();
  Eigen::VectorXd p;
  SwitchingFunctions(problem, instant, z, rho, p);
  Eigen::VectorXd rest(net.num_springs());
  for (int s = 0; s < net.num_springs(); ++s) {
    const NetworkSpring& sp = net.spring(s);
    rest[s] = p[s] < 0.0 ? sp.rest_max : sp.rest_min;
  }
  // H = ρ · f(z, L*) + h(z, t) with the bang-bang minimiser L*.
  Eigen::VectorXd rate;
  EvaluateDynamics(net, instant.t, z, rest, rate);
  if (minimiser != nullptr) *minimiser = rest;
  return rho.dot(rate) + RunningCost(problem, instant, z);
}

double RunningCost(const TrackingProblem& problem, const Instant& instant,
                   const Eigen::VectorXd& z) {
  const SpringNetwork& net = problem.network();
  const int d = net.dimension();
  const CostWeights& w = problem.weights();
  double h = 0.0;
  for (int k = 0; k < net.num_free(); ++k) {
    const int base = 2 * d * k;
    for (int i = 0; i < d; ++i) {
      const double ex = z[base + i] - instant.ref_position[d * k + i];
      const double ev = z[base + d + i] - instant.ref_velocity[d * k + i];
      h += instant.ref_weight[k] * (w.position * ex * ex + w.velocity * ev * ev);
    }
  }
  return h;
}

double TerminalCost(const TrackingProblem& problem, const Instant& terminal,
                    const Eigen::VectorXd& z, Eigen::VectorXd* gradient,
                    Eigen::VectorXd* hessian_diagonal) {
  const SpringNetwork& net = problem.network();
  const int d = net.dimension();
  const CostWeights& w = problem.weights();
  if (gradient != nullptr) gradient->setZero(net.state_size());
  if (hessian_diagonal != nullptr) hessian_diagonal->setZero(net.state_size());
  double g = 0.0;
  for (int k = 0; k < net.num_free(); ++k) {
    const int base = 2 * d * k;
    const double wk = terminal.ref_weight[k];
    for (int i = 0; i < d; ++i) {
      const double ex = z[base + i] - terminal.ref_position[d * k + i];
      const double ev = z[base + d + i] - terminal.ref_velocity[d * k + i];
      g += wk * (w.terminal_position * ex * ex + w.terminal_velocity * ev * ev);
      if (gradient != nullptr) {
        (*gradient)[base + i] = 2.0 * wk * w.terminal_position * ex;
        (*gradient)[base + d + i] = 2.0 * wk * w.terminal_velocity * ev;
      }
      if (hessian_diagonal != nullptr) {
        (*hessian_diagonal)[base + i] = 2.0 * wk * w.terminal_position;
        (*hessian_diagonal)[base + d + i] = 2.0 * wk * w.terminal_velocity;
      }
    }
  }
  return g;
}

}  // namespace moreau::control
