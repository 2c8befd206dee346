#include "materials/material.hpp"

#include <array>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "materials/expression_law.hpp"
#include "materials/law.hpp"

namespace ibvalve::materials {

namespace {
constexpr std::array<std::pair<std::string_view, PenaltyKind>, 4> penalty_table{{
    {"none", PenaltyKind::none},
    {"log", PenaltyKind::log},
    {"quadratic-log", PenaltyKind::quadratic_log},
    {"quadratic", PenaltyKind::quadratic},
}};
} // namespace

std::optional<PenaltyKind> find_penalty(std::string_view name)
{
  for (const auto& [n, kind] : penalty_table)
    if (n == name) return kind;
  return std::nullopt;
}

std::string penalty_name(PenaltyKind kind)
{
  for (const auto& [n, k] : penalty_table)
    if (k == kind) return std::string(n);
  return "?";
}

std::string penalty_names()
{
  std::string names;
  for (const auto& [n, kind] : penalty_table) names += (names.empty() ? "" : ", ") + std::string(n);
  return names;
}

VolumetricPenalty::VolumetricPenalty(PenaltyKind kind, double bulk_modulus)
    : kind_(kind), kappa_(bulk_modulus)
{
  if (!(bulk_modulus >= 0.0)) throw std::invalid_argument("volumetric penalty: negative bulk modulus");
  if (kind_ == PenaltyKind::none) kappa_ = 0.0;
}

std::string VolumetricPenalty::name() const
{
  return penalty_name(kind_);
}

double VolumetricPenalty::U(double J) const
{
  switch (kind_) {
  case PenaltyKind::none:
    return 0.0;
  case PenaltyKind::log:
    return 0.5 * kappa_ * std::log(J) * std::log(J);
  case PenaltyKind::quadratic_log:
    return 0.25 * kappa_ * (J * J - 1.0 - 2.0 * std::log(J));
  case PenaltyKind::quadratic:
    return 0.5 * kappa_ * (J - 1.0) * (J - 1.0);
  }
  return 0.0;
}

double VolumetricPenalty::dU(double J) const
{
  switch (kind_) {
  case PenaltyKind::none:
    return 0.0;
  case PenaltyKind::log:
    return kappa_ * std::log(J) / J;
  case PenaltyKind::quadratic_log:
    return 0.5 * kappa_ * (J - 1.0 / J);
  case PenaltyKind::quadratic:
    return kappa_ * (J - 1.0);
  }
  return 0.0;
}

double VolumetricPenalty::d2U(double J) const
{
  switch (kind_) {
  case PenaltyKind::none:
    return 0.0;
  case PenaltyKind::log:
    return kappa_ * (1.0 - std::log(J)) / (J * J);
  case PenaltyKind::quadratic_log:
    return 0.5 * kappa_ * (1.0 + 1.0 / (J * J));
  case PenaltyKind::quadratic:
    return kappa_;
  }
  return 0.0;
}

double VolumetricPenalty::energy(const Mat3& F, const FiberFrame&) const
{
  return U(F.determinant());
}

Mat3 VolumetricPenalty::stress(const Mat3& F, const FiberFrame&) const
{
  if (kind_ == PenaltyKind::none) return Mat3::Zero();
  const double J = F.determinant();
  return J * dU(J) * F.inverse().transpose();
}

Tangent VolumetricPenalty::tangent(const Mat3& F, const FiberFrame&) const
{
  Tangent T = Tangent::Zero();
  if (kind_ == PenaltyKind::none) return T;
  const double J = F.determinant();
  add_volumetric_tangent(F, J * dU(J), J * J * d2U(J) + J * dU(J), T);
  return T;
}

Material::Material(std::shared_ptr<const StrainEnergy> law, VolumetricPenalty penalty)
    : law_(std::move(law)), penalty_(penalty)
{
  if (!law_) throw std::invalid_argument("Material: no law");
  invariant_law_ = dynamic_cast<const InvariantLaw*>(law_.get());
  expression_law_ = dynamic_cast<const ExpressionLaw*>(law_.get());
  if (invariant_law_) reference_g_ = -2.0 * invariant_law_->reference_d1();
  if (expression_law_) reference_g_ = -expression_law_->reference_pressure();
}

std::string Material::name() const
{
  if (penalty_.kind() == PenaltyKind::none) return law_->name();
  return law_->name() + " + " + penalty_.name() + " penalty";
}

double Material::energy(const Mat3& F, const FiberFrame& fibers) const
{
  return law_->energy(F, fibers) + penalty_.energy(F, fibers);
}

Mat3 Material::stress(const Mat3& F, const FiberFrame& fibers) const
{
  if (!invariant_law_ && !expression_law_) return law_->stress(F, fibers) + penalty_.stress(F, fibers);
  // Psi's stress, then every volumetric term at once: (J U'(J) - 2 d1_ref) F^{-T}.
  Mat3 P = invariant_law_ ? invariant_law_->invariant_stress(F, fibers)
                          : expression_law_->invariant_stress(F, fibers);
  double g = reference_g_;
  if (penalty_.kind() != PenaltyKind::none) {
    const double J = F.determinant();
    g += J * penalty_.dU(J);
  }
  if (g != 0.0) P += g * F.inverse().transpose();
  return P;
}

Tangent Material::tangent(const Mat3& F, const FiberFrame& fibers) const
{
  Mat3 P;
  Tangent T;
  stress_and_tangent(F, fibers, P, T);
  return T;
}

void Material::stress_and_tangent(const Mat3& F, const FiberFrame& fibers, Mat3& P, Tangent& T) const
{
  double g = 0.0, g_prime_J = 0.0;
  if (invariant_law_ || expression_law_) {
    if (invariant_law_)
      invariant_law_->invariant_stress_and_tangent(F, fibers, P, T);
    else
      expression_law_->invariant_stress_and_tangent(F, fibers, P, T);
    g = reference_g_; // the reference term: -2 d1_ref ln J or -p_ref ln J (J g' = 0)
  } else {
    law_->stress_and_tangent(F, fibers, P, T);
  }
  if (penalty_.kind() != PenaltyKind::none) {
    const double J = F.determinant();
    const double dU = penalty_.dU(J);
    g += J * dU;
    g_prime_J += J * J * penalty_.d2U(J) + J * dU;
  }
  if (g == 0.0 && g_prime_J == 0.0) return;
  const Mat3 H = F.inverse().transpose();
  P += g * H;
  add_volumetric_tangent_given_inverse(H, g, g_prime_J, T);
}

} // namespace ibvalve::materials
