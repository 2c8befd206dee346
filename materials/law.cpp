#include "materials/law.hpp"

#include <array>
#include <cmath>
#include <fmt/format.h>
#include <stdexcept>

namespace ibvalve::materials {

namespace {

const std::array<LawInfo, 5>& law_table()
{
  static const std::array<LawInfo, 5> table{{
      {LawKind::neo_hookean,
       "neo-hookean",
       "mu/2 (I1-3)",
       "mu/2*(I1 - 3)",
       {{"mu", true, 1e300, "isotropic modulus"}},
       false},
      {LawKind::W1,
       "W1",
       "C10 (exp(C01 (I1-3)) - 1) + k1/(2 k2) (exp(k2 (I4-1)^2) - 1)",
       "C10*(exp(C01*(I1 - 3)) - 1) + k1/(2*k2)*(exp(k2*(I4 - 1)^2) - 1)",
       {{"C10", true, 1e300, "isotropic modulus"},
        {"C01", false, 1e300, "isotropic exponent"},
        {"k1", true, 1e300, "fiber modulus"},
        {"k2", false, 1e300, "fiber exponent"}},
       false},
      {LawKind::W2,
       "W2",
       "mu (I1-3) + c0 (exp(c1 (I1-3)^2 + c2 (I4-1)^4) - 1)",
       "mu*(I1 - 3) + c0*(exp(c1*(I1 - 3)^2 + c2*(I4 - 1)^4) - 1)",
       {{"mu", true, 1e300, "isotropic modulus"},
        {"c0", true, 1e300, "exponential modulus"},
        {"c1", false, 1e300, "isotropic exponent"},
        {"c2", false, 1e300, "fiber exponent"}},
       false},
      {LawKind::W3,
       "W3",
       "C1 (I1-3) + a/(2 b) (exp(b (I4-1)^2) - 1)",
       "C1*(I1 - 3) + a/(2*b)*(exp(b*(I4 - 1)^2) - 1)",
       {{"C1", true, 1e300, "isotropic modulus"},
        {"a", true, 1e300, "fiber modulus"},
        {"b", false, 1e300, "fiber exponent"}},
       false},
      {LawKind::hgo,
       "hgo",
       "mu/2 (I1-3) + sum_{i=4,6} k1/(2 k2) (exp(k2 E_i^2) - 1), E_i = kappa (I1-3) + (1-3 kappa)(I_i-1)",
       // The built-in drops a compressed family's whole term; with fibers off the formula clamps I_i
       // to 1 instead, which is the same term only when kappa = 0.
       "mu/2*(I1 - 3) + k1/(2*k2)*(exp(k2*(kappa*(I1 - 3) + (1 - 3*kappa)*(I4 - 1))^2) - 1) + "
       "k1/(2*k2)*(exp(k2*(kappa*(I1 - 3) + (1 - 3*kappa)*(I6 - 1))^2) - 1)",
       {{"mu", true, 1e300, "shear modulus of the matrix"},
        {"k1", true, 1e300, "fiber modulus"},
        {"k2", false, 1e300, "fiber exponent"},
        {"kappa", false, 1.0 / 3.0, "fiber dispersion (0: aligned, 1/3: isotropic)"}},
       true},
  }};
  return table;
}

using Vec9 = Eigen::Matrix<double, 9, 1>;

Vec9 flat(const Mat3& A)
{
  return Eigen::Map<const Vec9>(A.data());
}

} // namespace

const LawInfo& law_info(LawKind kind)
{
  for (const auto& info : law_table())
    if (info.kind == kind) return info;
  throw std::logic_error("law_info: unknown law");
}

std::span<const LawInfo> all_laws()
{
  return law_table();
}

std::optional<LawKind> find_law(std::string_view name)
{
  for (const auto& info : law_table())
    if (info.name == name) return info.kind;
  return std::nullopt;
}

std::string law_names()
{
  std::string names;
  for (const auto& info : law_table()) names += (names.empty() ? "" : ", ") + info.name;
  return names;
}

InvariantLaw::InvariantLaw(LawKind kind, std::vector<double> parameters, LawOptions options)
    : kind_(kind), parameters_(std::move(parameters)), options_(options)
{
  const LawInfo& info = law_info(kind);
  if (parameters_.size() != info.parameters.size())
    throw std::invalid_argument(fmt::format("{}: expected {} parameters, got {}", info.name,
                                            info.parameters.size(), parameters_.size()));
  for (std::size_t i = 0; i < parameters_.size(); ++i)
    if (!(parameters_[i] >= 0.0) || parameters_[i] > info.parameters[i].upper)
      throw std::invalid_argument(info.name + ": parameter " + info.parameters[i].name + " out of range");
  if (options_.reference_state == ReferenceState::pressure_like &&
      options_.isotropic_invariant == IsotropicInvariant::I1)
    reference_d1_ = evaluate_invariants<double>(kind_, parameters_.data(), 3.0, 1.0, 1.0, true).d1;
}

std::string InvariantLaw::name() const
{
  return law_info(kind_).name;
}

InvariantLaw::Kinematics InvariantLaw::kinematics(const Mat3& F) const
{
  Kinematics k;
  k.C = F.transpose() * F;
  k.trace_C = k.C.trace();
  if (options_.isotropic_invariant == IsotropicInvariant::I1) {
    k.gradient = 2.0 * F;
    return k;
  }
  // d(J^{-2/3} tr C)/dF = J^{-2/3} (2 F - 2/3 tr C F^{-T}).
  k.j = std::pow(F.determinant(), -2.0 / 3.0);
  k.H = F.inverse().transpose();
  k.gradient = k.j * (2.0 * F - (2.0 / 3.0) * k.trace_C * k.H);
  return k;
}

InvariantResponse<double> InvariantLaw::invariants(const Kinematics& k, const FiberFrame& fibers) const
{
  const double I1 = k.j * k.trace_C; // j = 1 for the invariant I1
  const double I4 = fibers.f0.dot(k.C * fibers.f0);
  const double I6 = fibers.s0.dot(k.C * fibers.s0);
  return evaluate_invariants<double>(kind_, parameters_.data(), I1, I4, I6,
                                     options_.fiber_compression == FiberCompression::included);
}

InvariantResponse<double> InvariantLaw::invariants(const Mat3& F, const FiberFrame& fibers) const
{
  return invariants(kinematics(F), fibers);
}

double InvariantLaw::energy(const Mat3& F, const FiberFrame& fibers) const
{
  double W = invariants(F, fibers).psi;
  if (reference_d1_ != 0.0) W -= 2.0 * reference_d1_ * std::log(F.determinant());
  return W;
}

Mat3 InvariantLaw::invariant_stress(const Mat3& F, const FiberFrame& fibers) const
{
  const Kinematics k = kinematics(F);
  const auto r = invariants(k, fibers);
  // dI1/dF = 2 F (or dI1bar/dF), dI4/dF = 2 F f0 (x) f0, dI6/dF = 2 F s0 (x) s0.
  Mat3 P = r.d1 * k.gradient;
  if (r.d4 != 0.0) P.noalias() += (2.0 * r.d4) * (F * fibers.f0) * fibers.f0.transpose();
  if (r.d6 != 0.0) P.noalias() += (2.0 * r.d6) * (F * fibers.s0) * fibers.s0.transpose();
  return P;
}

Mat3 InvariantLaw::stress(const Mat3& F, const FiberFrame& fibers) const
{
  Mat3 P = invariant_stress(F, fibers);
  if (reference_d1_ != 0.0) P -= 2.0 * reference_d1_ * F.inverse().transpose();
  return P;
}

Tangent InvariantLaw::tangent(const Mat3& F, const FiberFrame& fibers) const
{
  Mat3 P;
  Tangent T;
  stress_and_tangent(F, fibers, P, T);
  return T;
}

void add_volumetric_tangent(const Mat3& F, double g, double g_prime_J, Tangent& T)
{
  add_volumetric_tangent_given_inverse(F.inverse().transpose(), g, g_prime_J, T);
}

void add_volumetric_tangent_given_inverse(const Mat3& H, double g, double g_prime_J, Tangent& T)
{
  // P_ab = g(J) H_ab, H = F^{-T}:  dP_ab/dF_cd = J g'(J) H_ab H_cd - g H_ad H_cb.
  for (int d = 0; d < 3; ++d)
    for (int c = 0; c < 3; ++c)
      for (int b = 0; b < 3; ++b)
        for (int a = 0; a < 3; ++a)
          T(a + 3 * b, c + 3 * d) += g_prime_J * H(a, b) * H(c, d) - g * H(a, d) * H(c, b);
}

void InvariantLaw::stress_and_tangent(const Mat3& F, const FiberFrame& fibers, Mat3& P, Tangent& T) const
{
  invariant_stress_and_tangent(F, fibers, P, T);
  if (reference_d1_ != 0.0) {
    // W_ref = -2 d1_ref ln J: g = J U' = -2 d1_ref (constant), J g' = 0.
    const Mat3 H = F.inverse().transpose();
    P -= 2.0 * reference_d1_ * H;
    add_volumetric_tangent_given_inverse(H, -2.0 * reference_d1_, 0.0, T);
  }
}

void InvariantLaw::invariant_stress_and_tangent(const Mat3& F, const FiberFrame& fibers, Mat3& P,
                                                Tangent& T) const
{
  const Kinematics k = kinematics(F);
  const auto r = invariants(k, fibers);
  const Mat3 A = fibers.f0 * fibers.f0.transpose();
  const Mat3 B = fibers.s0 * fibers.s0.transpose();
  const Mat3& G1 = k.gradient;
  const Mat3 G4 = 2.0 * F * A, G6 = 2.0 * F * B; // dI_k/dF
  P = r.d1 * G1 + r.d4 * G4 + r.d6 * G6;

  // T = sum_k d_k d2I_k/dF2 + sum_kl d_kl dI_k/dF (x) dI_l/dF, with (column-major flattening)
  // d2I1/dF2 = 2 I_9, d2I4/dF2 = 2 A (x)_kron I_3 (entry (a+3b, c+3d) = 2 delta_ac A_bd).
  T.setZero();
  const bool isochoric = options_.isotropic_invariant == IsotropicInvariant::isochoric;
  const Mat3 M = (r.d1 * k.j) * Mat3::Identity() + r.d4 * A + r.d6 * B; // j: d2I1bar/dF2's 2 I_9 part
  for (int d = 0; d < 3; ++d)
    for (int b = 0; b < 3; ++b)
      for (int a = 0; a < 3; ++a) T(a + 3 * b, a + 3 * d) = 2.0 * M(b, d);
  if (isochoric && r.d1 != 0.0) {
    // I1bar = j I1, j = J^{-2/3}, H = F^{-T}: dI1bar/dF = j (2 F - 2/3 I1 H) and
    // d2I1bar/dF_ab dF_cd = j [2 d_ac d_bd - 4/3 (F_ab H_cd + H_ab F_cd) + 4/9 I1 H_ab H_cd
    //                          + 2/3 I1 H_ad H_cb]; the first term is in M above.
    const Mat3& H = k.H;
    const double I1 = k.trace_C;
    const Vec9 f = flat(F), h = flat(H);
    const double c = r.d1 * k.j;
    T.noalias() +=
        c * (-4.0 / 3.0 * (f * h.transpose() + h * f.transpose()) + 4.0 / 9.0 * I1 * h * h.transpose());
    for (int d = 0; d < 3; ++d)
      for (int c2 = 0; c2 < 3; ++c2)
        for (int b = 0; b < 3; ++b)
          for (int a = 0; a < 3; ++a) T(a + 3 * b, c2 + 3 * d) += c * 2.0 / 3.0 * I1 * H(a, d) * H(c2, b);
  }
  const Vec9 g1 = flat(G1), g4 = flat(G4), g6 = flat(G6);
  T.noalias() += r.d11 * g1 * g1.transpose();
  if (r.d44 != 0.0 || r.d14 != 0.0) {
    T.noalias() += r.d44 * g4 * g4.transpose();
    T.noalias() += r.d14 * (g1 * g4.transpose() + g4 * g1.transpose());
  }
  if (r.d66 != 0.0 || r.d16 != 0.0 || r.d46 != 0.0) {
    T.noalias() += r.d66 * g6 * g6.transpose();
    T.noalias() += r.d16 * (g1 * g6.transpose() + g6 * g1.transpose());
    T.noalias() += r.d46 * (g4 * g6.transpose() + g6 * g4.transpose());
  }
}

} // namespace ibvalve::materials
