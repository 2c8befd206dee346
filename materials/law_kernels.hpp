#pragma once
// The leaflet and wall laws written once, as functions of the invariants I1 = tr C, I4 = f0.C f0 and
// I6 = s0.C s0, templated on the scalar so that the same code gives double stresses/tangents to the
// finite elements and Ceres Jets (automatic derivatives in the parameters) to the biaxial fit.
//
// Each kernel returns Psi and its first and second partial derivatives in the invariants; the tensors
// P = dW/dF and dP/dF are assembled from them in law.cpp (chain rule through dI/dF), and the planar
// biaxial Cauchy stresses in biaxial.hpp.
//
// Laws (docs/reference.md, "Constitutive laws"; Zhu et al. 2021, Front. Physiol. 12:682893, eqs. for
// W1-W3):
//   neo-Hookean  Psi = mu/2 (I1 - 3)
//   W1           Psi = C10 (exp(C01 (I1-3)) - 1) + k1/(2 k2) (exp(k2 (I4-1)^2) - 1)
//   W2           Psi = mu (I1-3) + c0 (exp(c1 (I1-3)^2 + c2 (I4-1)^4) - 1)
//   W3           Psi = C1 (I1-3) + a/(2 b) (exp(b (I4-1)^2) - 1)
//   HGO          Psi = mu/2 (I1-3) + sum_{i=4,6} k1/(2 k2) (exp(k2 E_i^2) - 1),
//                E_i = kappa (I1-3) + (1 - 3 kappa)(I_i - 1)
//                (Holzapfel, Gasser & Ogden 2000, J. Elasticity 61:1; dispersion kappa in [0, 1/3]:
//                 Gasser, Ogden & Holzapfel 2006, J. R. Soc. Interface 3:15).
// Fibers in compression: when `fibers_bear_compression` is false, a family with I_i < 1 contributes
// nothing (its term is removed, for W2 its part of the exponent), the usual choice for collagen,
// which buckles (Holzapfel & Ogden 2015, Eur. J. Mech. A/Solids 49:561, discuss the switch).
#include <cmath>

namespace ibvalve::materials {

enum class LawKind { neo_hookean, W1, W2, W3, hgo };

/// Psi and its partial derivatives d_k = dPsi/dI_k, d_kl = d2Psi/dI_k dI_l (k, l in {1, 4, 6}).
template <class T>
struct InvariantResponse {
  T psi{0.0};
  T d1{0.0}, d4{0.0}, d6{0.0};
  T d11{0.0}, d14{0.0}, d16{0.0}, d44{0.0}, d46{0.0}, d66{0.0};
};

namespace kernels {

/// k/(2 b) (exp(b s) - 1) for s >= 0, well defined as b -> 0 (limit k s / 2), so that a fit may
/// reach the bound b = 0 without a division by zero.
template <class T>
T exp_quadratic_energy(const T& k, const T& b, const T& s)
{
  using std::expm1;
  const T z = b * s;
  if (z < T(1e-12) && z > T(-1e-12)) return k * s * (T(1.0) + z * T(0.5)) * T(0.5);
  return k * expm1(z) / (T(2.0) * b);
}

/// One exponential fiber family k1/(2 k2)(exp(k2 E^2) - 1) added to `r`, with E = alpha (I1-3) + beta (Ii-1).
/// `first` is d_i, `second` d_ii, `mixed` d_1i of the family's invariant Ii.
template <class T>
void add_exponential_family(InvariantResponse<T>& r, T& first, T& second, T& mixed, const T& k1, const T& k2,
                            const T& alpha, const T& beta, const T& I1, const T& Ii)
{
  using std::exp;
  const T E = alpha * (I1 - T(3.0)) + beta * (Ii - T(1.0));
  const T E2 = E * E;
  const T e = exp(k2 * E2);
  const T dE = k1 * E * e;                            // dPsi/dE
  const T ddE = k1 * (T(1.0) + T(2.0) * k2 * E2) * e; // d2Psi/dE2
  r.psi += exp_quadratic_energy(k1, k2, E2);
  r.d1 += alpha * dE;
  first += beta * dE;
  r.d11 += alpha * alpha * ddE;
  mixed += alpha * beta * ddE;
  second += beta * beta * ddE;
}

} // namespace kernels

/// Number of parameters of each law (order as in law_info()).
constexpr int parameter_count(LawKind kind)
{
  switch (kind) {
  case LawKind::neo_hookean:
    return 1;
  case LawKind::W1:
    return 4;
  case LawKind::W2:
    return 4;
  case LawKind::W3:
    return 3;
  case LawKind::hgo:
    return 4;
  }
  return 0;
}

/// Psi(I1, I4, I6) and derivatives for `kind` with parameters `p` (moduli in any consistent stress
/// unit; the result is in that unit).
template <class T>
InvariantResponse<T> evaluate_invariants(LawKind kind, const T* p, const T& I1, const T& I4, const T& I6,
                                         bool fibers_bear_compression)
{
  using std::exp;
  InvariantResponse<T> r;
  const T one(1.0), two(2.0), three(3.0);
  const T u = I1 - three;
  const bool family4 = fibers_bear_compression || !(I4 < one);
  const bool family6 = fibers_bear_compression || !(I6 < one);
  switch (kind) {
  case LawKind::neo_hookean: {
    const T& mu = p[0];
    r.psi = mu * u / two;
    r.d1 = mu / two;
    break;
  }
  case LawKind::W1: {
    const T &C10 = p[0], &C01 = p[1], &k1 = p[2], &k2 = p[3];
    const T e1 = exp(C01 * u);
    r.psi = C10 * (e1 - one);
    r.d1 = C10 * C01 * e1;
    r.d11 = C10 * C01 * C01 * e1;
    if (family4) {
      T unused_mixed(0.0);
      kernels::add_exponential_family(r, r.d4, r.d44, unused_mixed, k1, k2, T(0.0), one, I1, I4);
    }
    break;
  }
  case LawKind::W2: {
    const T &mu = p[0], &c0 = p[1], &c1 = p[2], &c2 = p[3];
    const T x = family4 ? I4 - one : T(0.0);
    const T x2 = x * x, x3 = x2 * x;
    const T E = exp(c1 * u * u + c2 * x2 * x2);
    const T g1 = two * c1 * u;     // d(exponent)/dI1
    const T g4 = T(4.0) * c2 * x3; // d(exponent)/dI4
    r.psi = mu * u + c0 * (E - one);
    r.d1 = mu + c0 * g1 * E;
    r.d4 = c0 * g4 * E;
    r.d11 = c0 * E * (two * c1 + g1 * g1);
    r.d14 = c0 * E * g1 * g4;
    r.d44 = family4 ? c0 * E * (T(12.0) * c2 * x2 + g4 * g4) : T(0.0);
    break;
  }
  case LawKind::W3: {
    const T &C1 = p[0], &a = p[1], &b = p[2];
    r.psi = C1 * u;
    r.d1 = C1;
    if (family4) {
      T unused_mixed(0.0);
      kernels::add_exponential_family(r, r.d4, r.d44, unused_mixed, a, b, T(0.0), one, I1, I4);
    }
    break;
  }
  case LawKind::hgo: {
    const T &mu = p[0], &k1 = p[1], &k2 = p[2], &kappa = p[3];
    r.psi = mu * u / two;
    r.d1 = mu / two;
    const T beta = one - three * kappa;
    if (family4) kernels::add_exponential_family(r, r.d4, r.d44, r.d14, k1, k2, kappa, beta, I1, I4);
    if (family6) kernels::add_exponential_family(r, r.d6, r.d66, r.d16, k1, k2, kappa, beta, I1, I6);
    break;
  }
  }
  return r;
}

} // namespace ibvalve::materials
