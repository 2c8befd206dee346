#pragma once
// Second-order forward-mode automatic differentiation: a number that carries its value, its gradient
// and its Hessian in N independent variables, so that one pass over a formula's tape gives a strain
// energy with its exact first and second derivatives in the invariants (no finite differences).
//
// Every operation applies the chain rule to second order. For u = f(a) with f', f'':
//   u_i = f' a_i,   u_ij = f' a_ij + f'' a_i a_j;
// for u = a b:  u_i = a b_i + b a_i,  u_ij = a b_ij + b a_ij + a_i b_j + a_j b_i
// (e.g. Griewank & Walther 2008, "Evaluating Derivatives", ch. 13, Taylor arithmetic). The Hessian
// is symmetric and stored as its upper triangle, row by row.
//
// The scalar S is double for the finite elements and a Ceres Jet when a fit also needs derivatives in
// the parameters. With Order = 1 the Hessian is left out (what a stress alone needs).
#include <array>
#include <cmath>
#include <type_traits>

namespace ibvalve::materials {

template <class S, int N, int Order = 2>
struct Dual2 {
  static constexpr int hessian_size = Order == 2 ? N * (N + 1) / 2 : 0;

  S v{0.0};
  std::array<S, N> g{};
  std::array<S, hessian_size> h{};

  Dual2() { clear_derivatives(); }
  /// A constant (every derivative zero).
  explicit Dual2(double value) : v(value) { clear_derivatives(); }
  explicit Dual2(const S& value) requires(!std::is_same_v<S, double>) : v(value) { clear_derivatives(); }
  /// The independent variable number `index` (0 <= index < N) at `value`.
  static Dual2 variable(const S& value, int index)
  {
    Dual2 x(value);
    x.g[static_cast<std::size_t>(index)] = S(1.0);
    return x;
  }
  /// Position of (i, j), i <= j, in `h`.
  static constexpr int at(int i, int j) { return i * N - i * (i - 1) / 2 + (j - i); }

  void clear_derivatives()
  {
    g.fill(S(0.0));
    h.fill(S(0.0));
  }
};

/// u = f(a) given f(a), f'(a), f''(a).
template <class S, int N, int O>
Dual2<S, N, O> chain(const Dual2<S, N, O>& a, const S& f0, const S& f1, const S& f2)
{
  Dual2<S, N, O> u;
  u.v = f0;
  for (int i = 0, k = 0; i < N; ++i) {
    u.g[i] = f1 * a.g[i];
    if constexpr (O == 2)
      for (int j = i; j < N; ++j, ++k) u.h[k] = f1 * a.h[k] + f2 * a.g[i] * a.g[j];
  }
  return u;
}

template <class S, int N, int O>
Dual2<S, N, O> operator+(const Dual2<S, N, O>& a, const Dual2<S, N, O>& b)
{
  Dual2<S, N, O> u = a;
  u.v += b.v;
  for (int i = 0; i < N; ++i) u.g[i] += b.g[i];
  for (int k = 0; k < Dual2<S, N, O>::hessian_size; ++k) u.h[k] += b.h[k];
  return u;
}

template <class S, int N, int O>
Dual2<S, N, O> operator-(const Dual2<S, N, O>& a)
{
  Dual2<S, N, O> u;
  u.v = -a.v;
  for (int i = 0; i < N; ++i) u.g[i] = -a.g[i];
  for (int k = 0; k < Dual2<S, N, O>::hessian_size; ++k) u.h[k] = -a.h[k];
  return u;
}

template <class S, int N, int O>
Dual2<S, N, O> operator-(const Dual2<S, N, O>& a, const Dual2<S, N, O>& b)
{
  Dual2<S, N, O> u = a;
  u.v -= b.v;
  for (int i = 0; i < N; ++i) u.g[i] -= b.g[i];
  for (int k = 0; k < Dual2<S, N, O>::hessian_size; ++k) u.h[k] -= b.h[k];
  return u;
}

template <class S, int N, int O>
Dual2<S, N, O> operator*(const Dual2<S, N, O>& a, const Dual2<S, N, O>& b)
{
  Dual2<S, N, O> u;
  u.v = a.v * b.v;
  for (int i = 0, k = 0; i < N; ++i) {
    u.g[i] = a.v * b.g[i] + b.v * a.g[i];
    if constexpr (O == 2)
      for (int j = i; j < N; ++j, ++k)
        u.h[k] = a.v * b.h[k] + b.v * a.h[k] + a.g[i] * b.g[j] + a.g[j] * b.g[i];
  }
  return u;
}

template <class S, int N, int O>
Dual2<S, N, O> operator/(const Dual2<S, N, O>& a, const Dual2<S, N, O>& b)
{
  const S r = S(1.0) / b.v; // 1/b: f' = -1/b^2, f'' = 2/b^3
  return a * chain(b, r, -r * r, S(2.0) * r * r * r);
}

template <class S, int N, int O>
bool operator<(const Dual2<S, N, O>& a, const Dual2<S, N, O>& b)
{
  return a.v < b.v;
}

template <class S, int N, int O>
Dual2<S, N, O> exp(const Dual2<S, N, O>& a)
{
  using std::exp;
  const S e = exp(a.v);
  return chain(a, e, e, e);
}

template <class S, int N, int O>
Dual2<S, N, O> log(const Dual2<S, N, O>& a)
{
  using std::log;
  const S r = S(1.0) / a.v;
  return chain(a, log(a.v), r, -r * r);
}

template <class S, int N, int O>
Dual2<S, N, O> sqrt(const Dual2<S, N, O>& a)
{
  using std::sqrt;
  const S s = sqrt(a.v);
  const S d = S(0.5) / s;
  return chain(a, s, d, -d / (S(2.0) * a.v));
}

/// a^p for a constant p that is not a small integer (formula_power handles those by products).
template <class S, int N, int O>
Dual2<S, N, O> pow(const Dual2<S, N, O>& a, double p)
{
  using std::pow; // three powers rather than quotients, so that a = 0 gives 0, not 0/0, where p > 2
  return chain(a, pow(a.v, p), S(p) * pow(a.v, p - 1.0), S(p * (p - 1.0)) * pow(a.v, p - 2.0));
}

} // namespace ibvalve::materials
