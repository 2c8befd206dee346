#include "materials/expression_law.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "materials/formula_program.hpp"

namespace ibvalve::materials {

namespace {

/// The formula's symbols in order: the invariants, then the parameters.
enum Symbol { sI1, sI1bar, sI2, sI4, sI6, sI8, sJ, invariant_symbols };

std::vector<std::string> symbol_names(const std::vector<ExpressionParameter>& parameters)
{
  std::vector<std::string> names(expression_invariants.begin(), expression_invariants.end());
  for (const auto& p : parameters) names.push_back(p.name);
  return names;
}

using Vec9 = Eigen::Matrix<double, 9, 1>;

Vec9 flat(const Mat3& A)
{
  return Eigen::Map<const Vec9>(A.data());
}

} // namespace

ExpressionLaw::ExpressionLaw(std::string energy, std::vector<ExpressionParameter> parameters,
                             LawOptions options)
    : formula_(std::move(energy), symbol_names(parameters)), parameters_(std::move(parameters)),
      options_(options)
{
  const bool isochoric = options_.isotropic_invariant == IsotropicInvariant::isochoric;
  // Which independent invariants W depends on (I1bar = J^(-2/3) I1 reads I1 and J).
  std::array<bool, kinematic_count> reads{};
  reads[kI1] = formula_.uses(sI1) || formula_.uses(sI1bar);
  reads[kI2] = formula_.uses(sI2);
  reads[kI4] = formula_.uses(sI4);
  reads[kI6] = formula_.uses(sI6);
  reads[kI8] = formula_.uses(sI8);
  reads[kJ] = formula_.uses(sJ) || formula_.uses(sI1bar) || (isochoric && formula_.uses(sI1));
  reads_isochoric_ = formula_.uses(sI1bar) || (isochoric && formula_.uses(sI1));
  slot_.fill(-1);
  for (int k = 0; k < kinematic_count; ++k)
    if (reads[k]) {
      slot_[k] = static_cast<int>(active_.size());
      active_.push_back(k);
    }

  // The parameters' part of the formula, once.
  std::vector<double> values(formula_.symbols().size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 0; i < parameters_.size(); ++i) values[invariant_symbols + i] = parameters_[i].value;
  std::vector<int> invariant_symbol_list;
  for (int s = 0; s < invariant_symbols; ++s) invariant_symbol_list.push_back(s);
  const std::vector<bool> varying = formula_.depends_on(invariant_symbol_list);
  std::vector<double> nodes;
  formula_.evaluate<double>(values, nodes);
  fixed_.assign(nodes.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (!varying[i]) fixed_[i] = nodes[i];
  program_ = FormulaProgram(formula_, fixed_);

  if (options_.reference_state == ReferenceState::pressure_like) {
    // P(I) = (2 d1 + 4 d2 + dJ) I + fiber terms (dI1/dF = 2 I, dI2/dF = 4 I, dJ/dF = I at F = I).
    const ExpressionResponse r = response({3.0, 3.0, 1.0, 1.0, 0.0, 1.0});
    reference_pressure_ = 2.0 * r.d[kI1] + 4.0 * r.d[kI2] + r.d[kJ];
  }
  assembled_ = active_;
  if (slot_[kJ] < 0 && reference_pressure_ != 0.0) assembled_.push_back(kJ);
}

int ExpressionLaw::fiber_families() const
{
  if (formula_.uses(sI6) || formula_.uses(sI8)) return 2;
  return formula_.uses(sI4) ? 1 : 0;
}

std::array<double, kinematic_count> ExpressionLaw::invariants_of(const Mat3& F, const FiberFrame& fibers)
{
  const Mat3 C = F.transpose() * F;
  const double I1 = C.trace();
  const Vec3 Cf = C * fibers.f0;
  return {I1,
          0.5 * (I1 * I1 - C.squaredNorm()), // tr C^2 = C:C for symmetric C
          fibers.f0.dot(Cf),
          fibers.s0.dot(C * fibers.s0),
          fibers.s0.dot(Cf),
          F.determinant()};
}

std::array<double, kinematic_count> ExpressionLaw::switched(std::array<double, kinematic_count> values) const
{
  if (options_.fiber_compression == FiberCompression::excluded) {
    if (values[kI4] < 1.0) values[kI4] = 1.0;
    if (values[kI6] < 1.0) values[kI6] = 1.0;
  }
  return values;
}

template <int N, int Order>
ExpressionResponse ExpressionLaw::response_in(const std::array<double, kinematic_count>& raw) const
{
  using Number = Dual2<double, N, Order>;
  thread_local std::vector<Number> symbols, scratch;
  const std::array<double, kinematic_count> x = switched(raw);
  auto invariant = [&](int k) {
    const int slot = slot_[k];
    const double value = x[k];
    // A slack fiber (switched to 1) is a constant: every derivative in it is zero.
    if (slot < 0 || value != raw[k]) return Number(value);
    return Number::variable(value, slot);
  };
  symbols.resize(invariant_symbols);
  const Number I1 = invariant(kI1), J = invariant(kJ);
  const bool isochoric = options_.isotropic_invariant == IsotropicInvariant::isochoric;
  if (reads_isochoric_) {
    symbols[sI1bar] = I1 * formula_power(J, -2.0 / 3.0);
    symbols[sI1] = isochoric ? symbols[sI1bar] : I1;
  } else {
    symbols[sI1] = I1;
  }
  symbols[sI2] = invariant(kI2);
  symbols[sI4] = invariant(kI4);
  symbols[sI6] = invariant(kI6);
  symbols[sI8] = invariant(kI8);
  symbols[sJ] = J;
  // The parameters are in the program (they depend on no invariant); their symbols stay unused.
  const Number W = program_.run<N, Order>(symbols, scratch);

  ExpressionResponse r;
  r.psi = W.v;
  for (int i = 0; i < N; ++i) {
    const auto ki = static_cast<std::size_t>(active_[static_cast<std::size_t>(i)]);
    r.d[ki] = W.g[static_cast<std::size_t>(i)];
    if constexpr (Order == 2)
      for (int j = i; j < N; ++j) {
        const auto kj = static_cast<std::size_t>(active_[static_cast<std::size_t>(j)]);
        r.dd[ki][kj] = r.dd[kj][ki] = W.h[static_cast<std::size_t>(Number::at(i, j))];
      }
  }
  return r;
}

ExpressionResponse ExpressionLaw::response(const std::array<double, kinematic_count>& values, int order) const
{
  const bool second = order == 2;
  switch (active_.size()) {
  case 0:
    return response_in<0, 2>(values);
  case 1:
    return second ? response_in<1, 2>(values) : response_in<1, 1>(values);
  case 2:
    return second ? response_in<2, 2>(values) : response_in<2, 1>(values);
  case 3:
    return second ? response_in<3, 2>(values) : response_in<3, 1>(values);
  case 4:
    return second ? response_in<4, 2>(values) : response_in<4, 1>(values);
  case 5:
    return second ? response_in<5, 2>(values) : response_in<5, 1>(values);
  default:
    return second ? response_in<6, 2>(values) : response_in<6, 1>(values);
  }
}

double ExpressionLaw::energy_with(std::span<const double> parameter_values,
                                  const std::array<double, kinematic_count>& raw) const
{
  const std::array<double, kinematic_count> x = switched(raw);
  const bool isochoric = options_.isotropic_invariant == IsotropicInvariant::isochoric;
  std::vector<double> symbols{x[kI1], x[kI1] * std::pow(x[kJ], -2.0 / 3.0), x[kI2], x[kI4], x[kI6], x[kI8],
                              x[kJ]};
  if (isochoric) symbols[sI1] = symbols[sI1bar];
  symbols.insert(symbols.end(), parameter_values.begin(), parameter_values.end());
  return formula_.evaluate<double>(symbols);
}

double ExpressionLaw::energy(const Mat3& F, const FiberFrame& fibers) const
{
  std::vector<double> values;
  for (const auto& p : parameters_) values.push_back(p.value);
  const auto x = invariants_of(F, fibers);
  return energy_with(values, x) - reference_pressure_ * std::log(x[kJ]);
}

Mat3 ExpressionLaw::stress(const Mat3& F, const FiberFrame& fibers) const
{
  Mat3 P;
  assemble(F, fibers, P, nullptr, true);
  return P;
}

Mat3 ExpressionLaw::invariant_stress(const Mat3& F, const FiberFrame& fibers) const
{
  Mat3 P;
  assemble(F, fibers, P, nullptr, false);
  return P;
}

void ExpressionLaw::invariant_stress_and_tangent(const Mat3& F, const FiberFrame& fibers, Mat3& P,
                                                 Tangent& T) const
{
  assemble(F, fibers, P, &T, false);
}

Tangent ExpressionLaw::tangent(const Mat3& F, const FiberFrame& fibers) const
{
  Mat3 P;
  Tangent T;
  assemble(F, fibers, P, &T, true);
  return T;
}

void ExpressionLaw::stress_and_tangent(const Mat3& F, const FiberFrame& fibers, Mat3& P, Tangent& T) const
{
  assemble(F, fibers, P, &T, true);
}

void ExpressionLaw::assemble(const Mat3& F, const FiberFrame& fibers, Mat3& P, Tangent* T,
                             bool reference) const
{
  const Mat3 C = F.transpose() * F;
  const double I1 = C.trace();
  const Vec3& f = fibers.f0;
  const Vec3& s = fibers.s0;
  const double J = F.determinant();
  const std::array<double, kinematic_count> x{
      I1, 0.5 * (I1 * I1 - C.squaredNorm()), f.dot(C * f), s.dot(C * s), s.dot(C * f), J};
  ExpressionResponse r = response(x, T ? 2 : 1);
  // The reference term -p_ref ln J: dW/dJ = -p_ref / J, d2W/dJ2 = p_ref / J^2.
  const double p_ref = reference ? reference_pressure_ : 0.0;
  r.d[kJ] -= p_ref / J;
  r.dd[kJ][kJ] += p_ref / (J * J);

  // dI_k/dF over the invariants assembled (H = F^{-T}); J only when W reads it or for the reference.
  const bool volumetric = slot_[kJ] >= 0 || p_ref != 0.0;
  const Mat3 H = volumetric ? Mat3(F.inverse().transpose()) : Mat3::Zero();
  std::array<Mat3, kinematic_count> G;
  P.setZero();
  for (const int k : assembled_) {
    if (k == kJ && !volumetric) continue;
    switch (k) {
    case kI1:
      G[k] = 2.0 * F;
      break;
    case kI2:
      G[k] = 2.0 * (I1 * F - F * C);
      break;
    case kI4:
      G[k] = 2.0 * (F * f) * f.transpose();
      break;
    case kI6:
      G[k] = 2.0 * (F * s) * s.transpose();
      break;
    case kI8:
      G[k] = (F * f) * s.transpose() + (F * s) * f.transpose();
      break;
    default:
      G[k] = J * H;
    }
    P += r.d[k] * G[k];
  }
  if (!T) return;

  // sum_k d_k d2I_k/dF2. The parts delta_ac X_bd go into M (entry (a+3b, a+3d) += 2 M_bd):
  //   I1: 2 d_ac d_bd;  I4: 2 d_ac f_b f_d;  I6: 2 d_ac s_b s_d;  I8: d_ac (f_b s_d + s_b f_d);
  //   I2: 2 I1 d_ac d_bd - 2 d_ac C_bd + 4 F_ab F_cd - 2 F_ad F_cb - 2 B_ac d_bd  (B = F F^T);
  //   J:  J (H_ab H_cd - H_ad H_cb).
  const auto& d = r.d;
  const Mat3 M = (d[kI1] + d[kI2] * I1) * Mat3::Identity() - d[kI2] * C + d[kI4] * f * f.transpose() +
                 d[kI6] * s * s.transpose() + 0.5 * d[kI8] * (f * s.transpose() + s * f.transpose());
  T->setZero();
  for (int dd = 0; dd < 3; ++dd)
    for (int b = 0; b < 3; ++b)
      for (int a = 0; a < 3; ++a) (*T)(a + 3 * b, a + 3 * dd) = 2.0 * M(b, dd);
  const Vec9 vF = flat(F), vH = flat(H);
  if (d[kI2] != 0.0 || d[kJ] != 0.0) {
    const Mat3 B = F * F.transpose();
    const double cJ = d[kJ] * J;
    T->noalias() += (4.0 * d[kI2]) * vF * vF.transpose() + cJ * vH * vH.transpose();
    for (int dd = 0; dd < 3; ++dd)
      for (int c = 0; c < 3; ++c)
        for (int b = 0; b < 3; ++b)
          for (int a = 0; a < 3; ++a)
            (*T)(a + 3 * b, c + 3 * dd) -=
                2.0 * d[kI2] * (F(a, dd) * F(c, b) + (b == dd ? B(a, c) : 0.0)) + cJ * H(a, dd) * H(c, b);
  }
  // sum_kl d_kl dI_k/dF (x) dI_l/dF.
  std::array<Vec9, kinematic_count> g;
  for (const int k : assembled_)
    if (k != kJ || volumetric) g[k] = flat(G[k]);
  for (const int k : assembled_)
    for (const int l : assembled_)
      if (const double c = r.dd[k][l]; c != 0.0) T->noalias() += c * g[k] * g[l].transpose();
}

} // namespace ibvalve::materials
