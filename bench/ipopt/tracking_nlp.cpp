#include "tracking_nlp.h"

#include <algorithm>
#include <cmath>

#include "moreau/control/hamiltonian.h"
#include "spring_terms.h"

namespace moreau::bench {
namespace {

using control::Instant;
using control::SpringNetwork;
using Ipopt::Index;
using Ipopt::Number;

// One end of a spring: its block in z (−1 for a fixed node), sign in Δ = end b − end a, 1 / m.
struct SpringEnd {
  int base = -1;
  double sign = 1.0;
  double inv_mass = 0.0;
};

template <int D>
struct SpringState {
  SpringEnd ends[2];
  Eigen::Matrix<double, D, 1> dx = Eigen::Matrix<double, D, 1>::Zero();
  Eigen::Matrix<double, D, 1> dv = Eigen::Matrix<double, D, 1>::Zero();
};

template <int D>
SpringState<D> GatherSpring(const SpringNetwork& net, const Instant& instant,
                            const Eigen::VectorXd& z, int s) {
  const auto& sp = net.spring(s);
  SpringState<D> st;
  const int nodes[2] = {sp.a, sp.b};
  for (int side = 0; side < 2; ++side) {
    const int j = nodes[side];
    const int k = net.free_index(j);
    SpringEnd& end = st.ends[side];
    end.sign = side == 0 ? -1.0 : 1.0;
    for (int i = 0; i < D; ++i) {
      if (k < 0) {
        st.dx[i] += end.sign * instant.fixed_position[D * j + i];
        st.dv[i] += end.sign * instant.fixed_velocity[D * j + i];
      } else {
        st.dx[i] += end.sign * z[2 * D * k + i];
        st.dv[i] += end.sign * z[2 * D * k + D + i];
      }
    }
    if (k >= 0) {
      end.base = 2 * D * k;
      end.inv_mass = 1.0 / net.node(j).mass;
    }
  }
  return st;
}

template <int D>
void AccumulateJacobian(const SpringNetwork& net, const Instant& instant, const Eigen::VectorXd& z,
                        const Eigen::VectorXd& rest, const std::vector<int>& slot_z,
                        const std::vector<int>& slot_l, int nz, int m, double* vz, double* vl) {
  for (int s = 0; s < net.num_springs(); ++s) {
    const auto& sp = net.spring(s);
    const SpringState<D> st = GatherSpring<D>(net, instant, z, s);
    const auto jac = ForceJacobian<D>(st.dx, st.dv, rest[s], sp.stiffness, sp.damping);
    for (const SpringEnd& r : st.ends) {
      if (r.base < 0) continue;
      const double row_scale = r.sign * r.inv_mass;
      for (int i = 0; i < D; ++i) {
        const int row = r.base + D + i;
        vl[slot_l[static_cast<std::size_t>(row * m + s)]] += row_scale * jac.dl[i];
        for (const SpringEnd& c : st.ends) {
          if (c.base < 0) continue;
          for (int j = 0; j < D; ++j) {
            const double f = row_scale * c.sign;
            vz[slot_z[static_cast<std::size_t>(row * nz + c.base + j)]] += f * jac.dx(i, j);
            vz[slot_z[static_cast<std::size_t>(row * nz + c.base + D + j)]] += f * jac.dv(i, j);
          }
        }
      }
    }
  }
}

template <int D>
void AccumulateHessian(const SpringNetwork& net, const Instant& instant, const Eigen::VectorXd& z,
                       const Eigen::VectorXd& rest, const Number* lambda, double scale,
                       const std::vector<int>& slot_zz, const std::vector<int>& slot_lz, int nz,
                       double* vzz, double* vlz) {
  auto add_zz = [&](int a, int b, double v) {
    const int row = std::max(a, b);
    const int col = std::min(a, b);
    vzz[slot_zz[static_cast<std::size_t>(row * nz + col)]] += v;
  };
  for (int s = 0; s < net.num_springs(); ++s) {
    const auto& sp = net.spring(s);
    const SpringState<D> st = GatherSpring<D>(net, instant, z, s);
    Eigen::Matrix<double, D, 1> e = Eigen::Matrix<double, D, 1>::Zero();
    for (const SpringEnd& r : st.ends) {
      if (r.base < 0) continue;
      for (int i = 0; i < D; ++i) e[i] += r.sign * r.inv_mass * lambda[r.base + D + i];
    }
    const auto h = ForceHessian<D>(st.dx, st.dv, e, rest[s], sp.stiffness, sp.damping);
    for (const SpringEnd& r : st.ends) {
      if (r.base < 0) continue;
      for (int i = 0; i < D; ++i) {
        vlz[slot_lz[static_cast<std::size_t>(s * nz + r.base + i)]] += scale * r.sign * h.xl[i];
        for (const SpringEnd& c : st.ends) {
          if (c.base < 0) continue;
          const double f = scale * r.sign * c.sign;
          for (int j = 0; j < D; ++j) {
            // The (x, x) block is symmetric: keep each unordered pair once (lower triangle).
            if (r.base + i >= c.base + j) add_zz(r.base + i, c.base + j, f * h.xx(i, j));
            add_zz(r.base + i, c.base + D + j, f * h.xv(i, j));
          }
        }
      }
    }
  }
}

}  // namespace

int TrackingNlp::Pattern::Add(int row, int col, int cols_count) {
  int& s = slot[static_cast<std::size_t>(row * cols_count + col)];
  if (s < 0) {
    s = static_cast<int>(rows.size());
    rows.push_back(row);
    cols.push_back(col);
  }
  return s;
}

TrackingNlp::TrackingNlp(const control::PontryaginDiscretization& disc, Eigen::MatrixXd states,
                         Eigen::MatrixXd controls)
    : disc_(disc),
      nz_(disc.state_size()),
      m_(disc.problem().network().num_springs()),
      steps_(disc.steps()),
      block_(nz_ + m_),
      start_states_(std::move(states)),
      start_controls_(std::move(controls)) {
  BuildPatterns();
}

void TrackingNlp::BuildPatterns() {
  const SpringNetwork& net = disc_.problem().network();
  const int d = net.dimension();
  jac_z_.slot.assign(static_cast<std::size_t>(nz_ * nz_), -1);
  jac_l_.slot.assign(static_cast<std::size_t>(nz_ * m_), -1);
  hess_zz_.slot.assign(static_cast<std::size_t>(nz_ * nz_), -1);
  hess_lz_.slot.assign(static_cast<std::size_t>(m_ * nz_), -1);
  for (int i = 0; i < nz_; ++i) {
    jac_z_.Add(i, i, nz_);
    hess_zz_.Add(i, i, nz_);
  }
  for (int k = 0; k < net.num_free(); ++k) {
    for (int i = 0; i < d; ++i) jac_z_.Add(2 * d * k + i, 2 * d * k + d + i, nz_);
  }
  for (int s = 0; s < m_; ++s) {
    const int ends[2] = {net.free_index(net.spring(s).a), net.free_index(net.spring(s).b)};
    for (int r : ends) {
      if (r < 0) continue;
      for (int i = 0; i < d; ++i) {
        const int pos = 2 * d * r + i;
        jac_l_.Add(pos + d, s, m_);
        hess_lz_.Add(s, pos, nz_);
        for (int c : ends) {
          if (c < 0) continue;
          for (int j = 0; j < d; ++j) {
            jac_z_.Add(pos + d, 2 * d * c + j, nz_);
            jac_z_.Add(pos + d, 2 * d * c + d + j, nz_);
            const int other_pos = 2 * d * c + j;
            const int other_vel = other_pos + d;
            hess_zz_.Add(std::max(pos, other_pos), std::min(pos, other_pos), nz_);
            hess_zz_.Add(std::max(pos, other_vel), std::min(pos, other_vel), nz_);
          }
        }
      }
    }
  }
}

void TrackingNlp::Gather(const Number* x, int n, Eigen::VectorXd& z, Eigen::VectorXd& rest) const {
  if (n == 0) {
    z = disc_.initial_state();
  } else {
    z = Eigen::Map<const Eigen::VectorXd>(x + ZIndex(n), nz_);
  }
  rest = Eigen::Map<const Eigen::VectorXd>(x + LIndex(n), m_);
}

void TrackingNlp::DynamicsJacobian(int n, const Eigen::VectorXd& z, const Eigen::VectorXd& rest,
                                   double* vz, double* vl) const {
  const SpringNetwork& net = disc_.problem().network();
  const Instant& instant = disc_.instant(n);
  const int d = net.dimension();
  for (int k = 0; k < net.num_free(); ++k) {
    for (int i = 0; i < d; ++i) {
      vz[jac_z_.slot[static_cast<std::size_t>((2 * d * k + i) * nz_ + 2 * d * k + d + i)]] += 1.0;
    }
  }
  if (d == 1) {
    AccumulateJacobian<1>(net, instant, z, rest, jac_z_.slot, jac_l_.slot, nz_, m_, vz, vl);
  } else if (d == 2) {
    AccumulateJacobian<2>(net, instant, z, rest, jac_z_.slot, jac_l_.slot, nz_, m_, vz, vl);
  } else {
    AccumulateJacobian<3>(net, instant, z, rest, jac_z_.slot, jac_l_.slot, nz_, m_, vz, vl);
  }
}

void TrackingNlp::DynamicsHessian(int n, const Eigen::VectorXd& z, const Eigen::VectorXd& rest,
                                  const Number* lambda, double scale, double* vzz,
                                  double* vlz) const {
  const SpringNetwork& net = disc_.problem().network();
  const Instant& instant = disc_.instant(n);
  const int d = net.dimension();
  if (d == 1) {
    AccumulateHessian<1>(net, instant, z, rest, lambda, scale, hess_zz_.slot, hess_lz_.slot, nz_,
                         vzz, vlz);
  } else if (d == 2) {
    AccumulateHessian<2>(net, instant, z, rest, lambda, scale, hess_zz_.slot, hess_lz_.slot, nz_,
                         vzz, vlz);
  } else {
    AccumulateHessian<3>(net, instant, z, rest, lambda, scale, hess_zz_.slot, hess_lz_.slot, nz_,
                         vzz, vlz);
  }
}

bool TrackingNlp::get_nlp_info(Index& n, Index& m, Index& nnz_jac_g, Index& nnz_h_lag,
                               IndexStyleEnum& index_style) {
  const int jz = static_cast<int>(jac_z_.rows.size());
  const int jl = static_cast<int>(jac_l_.rows.size());
  const int hzz = static_cast<int>(hess_zz_.rows.size());
  const int hlz = static_cast<int>(hess_lz_.rows.size());
  n = steps_ * block_;
  m = steps_ * nz_;
  nnz_jac_g = steps_ * (nz_ + jl) + (steps_ - 1) * jz;
  nnz_h_lag = steps_ * m_ + (steps_ - 1) * (hzz + hlz) + nz_;
  index_style = C_STYLE;
  return true;
}

bool TrackingNlp::get_bounds_info(Index, Number* x_l, Number* x_u, Index, Number* g_l,
                                  Number* g_u) {
  const SpringNetwork& net = disc_.problem().network();
  for (int n = 0; n < steps_; ++n) {
    for (int s = 0; s < m_; ++s) {
      x_l[LIndex(n) + s] = net.spring(s).rest_min;
      x_u[LIndex(n) + s] = net.spring(s).rest_max;
    }
    for (int i = 0; i < nz_; ++i) {
      x_l[ZIndex(n + 1) + i] = -1e20;
      x_u[ZIndex(n + 1) + i] = 1e20;
      g_l[n * nz_ + i] = 0.0;
      g_u[n * nz_ + i] = 0.0;
    }
  }
  return true;
}

bool TrackingNlp::get_starting_point(Index, bool, Number* x, bool, Number*, Number*, Index, bool,
                                     Number*) {
  const SpringNetwork& net = disc_.problem().network();
  for (int n = 0; n < steps_; ++n) {
    for (int s = 0; s < m_; ++s) {
      const double lo = net.spring(s).rest_min;
      const double hi = net.spring(s).rest_max;
      const double margin = 1e-6 * (hi - lo);
      x[LIndex(n) + s] = std::clamp(start_controls_(s, n), lo + margin, hi - margin);
    }
    Eigen::Map<Eigen::VectorXd>(x + ZIndex(n + 1), nz_) = start_states_.col(n + 1);
  }
  return true;
}

bool TrackingNlp::eval_f(Index, const Number* x, bool, Number& obj_value) {
  const control::TrackingProblem& problem = disc_.problem();
  const SpringNetwork& net = problem.network();
  Eigen::VectorXd z, rest;
  double sum = 0.0;
  EntropyPenalty pen;
  for (int n = 0; n < steps_; ++n) {
    Gather(x, n, z, rest);
    double step = control::RunningCost(problem, disc_.instant(n), z);
    for (int s = 0; s < m_; ++s) {
      if (!ControlEntropy(rest[s], net.spring(s).rest_min, net.spring(s).rest_max, pen)) {
        return false;
      }
      step += problem.gamma() * pen.value;
    }
    sum += disc_.dt() * step;
  }
  z = Eigen::Map<const Eigen::VectorXd>(x + ZIndex(steps_), nz_);
  obj_value = sum + control::TerminalCost(problem, disc_.instant(steps_), z);
  return std::isfinite(obj_value);
}

bool TrackingNlp::eval_grad_f(Index n_vars, const Number* x, bool, Number* grad_f) {
  const control::TrackingProblem& problem = disc_.problem();
  const SpringNetwork& net = problem.network();
  const control::CostWeights& w = problem.weights();
  const int d = net.dimension();
  std::fill(grad_f, grad_f + n_vars, 0.0);
  Eigen::VectorXd z, rest, dg;
  EntropyPenalty pen;
  const double dt = disc_.dt();
  for (int n = 0; n < steps_; ++n) {
    Gather(x, n, z, rest);
    for (int s = 0; s < m_; ++s) {
      if (!ControlEntropy(rest[s], net.spring(s).rest_min, net.spring(s).rest_max, pen)) {
        return false;
      }
      grad_f[LIndex(n) + s] = dt * problem.gamma() * pen.slope;
    }
    if (n == 0) continue;
    const Instant& instant = disc_.instant(n);
    for (int k = 0; k < net.num_free(); ++k) {
      for (int i = 0; i < d; ++i) {
        const int p = 2 * d * k + i;
        const double wk = 2.0 * dt * instant.ref_weight[k];
        grad_f[ZIndex(n) + p] = wk * w.position * (z[p] - instant.ref_position[d * k + i]);
        grad_f[ZIndex(n) + p + d] = wk * w.velocity * (z[p + d] - instant.ref_velocity[d * k + i]);
      }
    }
  }
  z = Eigen::Map<const Eigen::VectorXd>(x + ZIndex(steps_), nz_);
  control::TerminalCost(problem, disc_.instant(steps_), z, &dg);
  for (int i = 0; i < nz_; ++i) grad_f[ZIndex(steps_) + i] += dg[i];
  return true;
}

bool TrackingNlp::eval_g(Index, const Number* x, bool, Index, Number* g) {
  const SpringNetwork& net = disc_.problem().network();
  Eigen::VectorXd z, rest, rate(nz_);
  for (int n = 0; n < steps_; ++n) {
    Gather(x, n, z, rest);
    control::EvaluateDynamics(net, disc_.instant(n).t, z, rest, rate);
    Eigen::Map<Eigen::VectorXd>(g + n * nz_, nz_) =
        Eigen::Map<const Eigen::VectorXd>(x + ZIndex(n + 1), nz_) - z - disc_.dt() * rate;
  }
  return rate.allFinite();
}

bool TrackingNlp::eval_jac_g(Index, const Number* x, bool, Index, Index, Index* i_row, Index* j_col,
                             Number* values) {
  const auto jz = static_cast<int>(jac_z_.rows.size());
  const auto jl = static_cast<int>(jac_l_.rows.size());
  int k = 0;
  Eigen::VectorXd z, rest;
  std::vector<double> vz(static_cast<std::size_t>(jz)), vl(static_cast<std::size_t>(jl));
  for (int n = 0; n < steps_; ++n) {
    const int row0 = n * nz_;
    if (values == nullptr) {
      for (int i = 0; i < nz_; ++i, ++k) {
        i_row[k] = row0 + i;
        j_col[k] = ZIndex(n + 1) + i;
      }
      for (int e = 0; n > 0 && e < jz; ++e, ++k) {
        i_row[k] = row0 + jac_z_.rows[static_cast<std::size_t>(e)];
        j_col[k] = ZIndex(n) + jac_z_.cols[static_cast<std::size_t>(e)];
      }
      for (int e = 0; e < jl; ++e, ++k) {
        i_row[k] = row0 + jac_l_.rows[static_cast<std::size_t>(e)];
        j_col[k] = LIndex(n) + jac_l_.cols[static_cast<std::size_t>(e)];
      }
      continue;
    }
    Gather(x, n, z, rest);
    std::fill(vz.begin(), vz.end(), 0.0);
    std::fill(vl.begin(), vl.end(), 0.0);
    DynamicsJacobian(n, z, rest, vz.data(), vl.data());
    const double dt = disc_.dt();
    for (int i = 0; i < nz_; ++i) values[k++] = 1.0;
    for (int e = 0; n > 0 && e < jz; ++e) {
      const auto es = static_cast<std::size_t>(e);
      values[k++] = -dt * vz[es] - (jac_z_.rows[es] == jac_z_.cols[es] ? 1.0 : 0.0);
    }
    for (int e = 0; e < jl; ++e) values[k++] = -dt * vl[static_cast<std::size_t>(e)];
  }
  return true;
}

bool TrackingNlp::eval_h(Index, const Number* x, bool, Number obj_factor, Index,
                         const Number* lambda, bool, Index, Index* i_row, Index* j_col,
                         Number* values) {
  const SpringNetwork& net = disc_.problem().network();
  const control::CostWeights& w = disc_.problem().weights();
  const int d = net.dimension();
  const auto hzz = static_cast<int>(hess_zz_.rows.size());
  const auto hlz = static_cast<int>(hess_lz_.rows.size());
  const double dt = disc_.dt();
  Eigen::VectorXd z, rest, dg, g2;
  EntropyPenalty pen;
  int k = 0;
  for (int n = 0; n < steps_; ++n) {
    if (values == nullptr) {
      for (int s = 0; s < m_; ++s, ++k) i_row[k] = j_col[k] = LIndex(n) + s;
      for (int e = 0; n > 0 && e < hzz; ++e, ++k) {
        i_row[k] = ZIndex(n) + hess_zz_.rows[static_cast<std::size_t>(e)];
        j_col[k] = ZIndex(n) + hess_zz_.cols[static_cast<std::size_t>(e)];
      }
      for (int e = 0; n > 0 && e < hlz; ++e, ++k) {
        i_row[k] = LIndex(n) + hess_lz_.rows[static_cast<std::size_t>(e)];
        j_col[k] = ZIndex(n) + hess_lz_.cols[static_cast<std::size_t>(e)];
      }
      continue;
    }
    Gather(x, n, z, rest);
    for (int s = 0; s < m_; ++s) {
      if (!ControlEntropy(rest[s], net.spring(s).rest_min, net.spring(s).rest_max, pen)) {
        return false;
      }
      values[k++] = obj_factor * dt * disc_.problem().gamma() * pen.curvature;
    }
    if (n == 0) continue;
    double* vzz = values + k;
    double* vlz = values + k + hzz;
    std::fill(vzz, vzz + hzz + hlz, 0.0);
    const Instant& instant = disc_.instant(n);
    for (int f = 0; f < net.num_free(); ++f) {
      for (int i = 0; i < d; ++i) {
        const int p = 2 * d * f + i;
        const double c = 2.0 * obj_factor * dt * instant.ref_weight[f];
        vzz[hess_zz_.slot[static_cast<std::size_t>(p * nz_ + p)]] += c * w.position;
        vzz[hess_zz_.slot[static_cast<std::size_t>((p + d) * nz_ + p + d)]] += c * w.velocity;
      }
    }
    DynamicsHessian(n, z, rest, lambda + n * nz_, -dt, vzz, vlz);
    k += hzz + hlz;
  }
  for (int i = 0; i < nz_; ++i, ++k) {
    if (values == nullptr) {
      i_row[k] = j_col[k] = ZIndex(steps_) + i;
    }
  }
  if (values != nullptr) {
    z = Eigen::Map<const Eigen::VectorXd>(x + ZIndex(steps_), nz_);
    control::TerminalCost(disc_.problem(), disc_.instant(steps_), z, &dg, &g2);
    for (int i = 0; i < nz_; ++i) values[k - nz_ + i] = obj_factor * g2[i];
  }
  return true;
}

void TrackingNlp::finalize_solution(Ipopt::SolverReturn status, Index, const Number* x,
                                    const Number*, const Number*, Index, const Number*,
                                    const Number* lambda, Number obj_value, const Ipopt::IpoptData*,
                                    Ipopt::IpoptCalculatedQuantities*) {
  status_ = status;
  objective_ = obj_value;
  states_.resize(nz_, steps_ + 1);
  controls_.resize(m_, steps_);
  duals_.resize(nz_, steps_);
  states_.col(0) = disc_.initial_state();
  for (int n = 0; n < steps_; ++n) {
    states_.col(n + 1) = Eigen::Map<const Eigen::VectorXd>(x + ZIndex(n + 1), nz_);
    controls_.col(n) = Eigen::Map<const Eigen::VectorXd>(x + LIndex(n), m_);
    duals_.col(n) = -Eigen::Map<const Eigen::VectorXd>(lambda + n * nz_, nz_);
  }
}

}  // namespace moreau::bench
