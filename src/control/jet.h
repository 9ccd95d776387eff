// Second-order forward-mode jets: a value with its gradient and Hessian with respect to K
// independent variables. Used for the per-spring part of the Hamiltonian, whose second
// derivatives Newton needs (internal header).
#pragma once

#include <Eigen/Core>

namespace moreau::control::internal {

template <int K>
struct Jet2 {
  using Vec = Eigen::Matrix<double, K, 1>;
  using Mat = Eigen::Matrix<double, K, K>;
  double v = 0.0;
  Vec g = Vec::Zero();
  Mat h = Mat::Zero();

  static Jet2 Variable(double value, int index) {
    Jet2 r;
    r.v = value;
    r.g[index] = 1.0;
    return r;
  }
  static Jet2 Constant(double value) {
    Jet2 r;
    r.v = value;
    return r;
  }
};

// f(a) given f, f', f'' at a.v.
template <int K>
Jet2<K> Apply(const Jet2<K>& a, double f0, double f1, double f2) {
  Jet2<K> r;
  r.v = f0;
  r.g = f1 * a.g;
  r.h = f1 * a.h + f2 * (a.g * a.g.transpose());
  return r;
}

template <int K>
Jet2<K> operator+(const Jet2<K>& a, const Jet2<K>& b) {
  Jet2<K> r;
  r.v = a.v + b.v;
  r.g = a.g + b.g;
  r.h = a.h + b.h;
  return r;
}

template <int K>
Jet2<K> operator-(const Jet2<K>& a, const Jet2<K>& b) {
  Jet2<K> r;
  r.v = a.v - b.v;
  r.g = a.g - b.g;
  r.h = a.h - b.h;
  return r;
}

template <int K>
Jet2<K> operator*(double s, const Jet2<K>& a) {
  Jet2<K> r;
  r.v = s * a.v;
  r.g = s * a.g;
  r.h = s * a.h;
  return r;
}

template <int K>
Jet2<K> operator*(const Jet2<K>& a, const Jet2<K>& b) {
  Jet2<K> r;
  r.v = a.v * b.v;
  r.g = a.v * b.g + b.v * a.g;
  const typename Jet2<K>::Mat outer = a.g * b.g.transpose();
  r.h = a.v * b.h + b.v * a.h + outer + outer.transpose();
  return r;
}

}  // namespace moreau::control::internal
