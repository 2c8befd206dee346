#pragma once
// Volumetric penalties and the composite Material = law + penalty used by the finite elements.
//
// In the IB setting the fluid keeps the structure (nearly) incompressible; a volumetric energy U(J)
// with a bulk modulus kappa keeps the discrete structure from drifting in volume and stabilises it
// (Vadala-Roth et al. 2020, CMAME 365:112978). U(1) = U'(1) = 0 for each form, so the stress-free
// reference state of the law is kept. Forms (J = det F):
//   log            U = kappa/2 (ln J)^2                 (e.g. Simo & Taylor 1982 family; Holzapfel 2000, 6.5)
//   quadratic-log  U = kappa/4 (J^2 - 1 - 2 ln J)       (Simo & Taylor 1991, CMAME 85:273)
//   quadratic      U = kappa/2 (J - 1)^2                (Ogden 1972 / Holzapfel 2000, eq. 6.138 family)
// P = J U'(J) F^{-T}.
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "materials/strain_energy.hpp"

namespace ibvalve::materials {

class InvariantLaw;
class ExpressionLaw;

enum class PenaltyKind { none, log, quadratic_log, quadratic };

std::optional<PenaltyKind> find_penalty(std::string_view name);
std::string penalty_name(PenaltyKind kind);
/// "none, log, quadratic-log, quadratic".
std::string penalty_names();

class VolumetricPenalty : public StrainEnergy {
 public:
  /// `bulk_modulus` kappa in dyn/cm^2.
  VolumetricPenalty(PenaltyKind kind, double bulk_modulus);

  std::string name() const override;
  double energy(const Mat3& F, const FiberFrame& fibers) const override;
  Mat3 stress(const Mat3& F, const FiberFrame& fibers) const override;
  Tangent tangent(const Mat3& F, const FiberFrame& fibers) const override;

  PenaltyKind kind() const { return kind_; }
  double bulk_modulus() const { return kappa_; }
  /// U(J), U'(J), U''(J).
  double U(double J) const;
  double dU(double J) const;
  double d2U(double J) const;

 private:
  PenaltyKind kind_;
  double kappa_;
};

/// The law plus its volumetric penalty: what a finite element evaluates at a quadrature point.
class Material : public StrainEnergy {
 public:
  Material(std::shared_ptr<const StrainEnergy> law, VolumetricPenalty penalty);

  std::string name() const override;
  double energy(const Mat3& F, const FiberFrame& fibers) const override;
  Mat3 stress(const Mat3& F, const FiberFrame& fibers) const override;
  Tangent tangent(const Mat3& F, const FiberFrame& fibers) const override;
  void stress_and_tangent(const Mat3& F, const FiberFrame& fibers, Mat3& P, Tangent& T) const override;

  const StrainEnergy& law() const { return *law_; }
  const VolumetricPenalty& penalty() const { return penalty_; }

 private:
  std::shared_ptr<const StrainEnergy> law_;
  VolumetricPenalty penalty_;
  /// The law when it is an InvariantLaw or an ExpressionLaw: its reference term and the penalty then
  /// share one F^{-T}.
  const InvariantLaw* invariant_law_ = nullptr;
  const ExpressionLaw* expression_law_ = nullptr;
  /// The coefficient g of the law's reference term g F^{-T} (-2 d1_ref or -p_ref), 0 for other laws.
  double reference_g_ = 0.0;
};

} // namespace ibvalve::materials
