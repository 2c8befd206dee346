#pragma once
// A strain energy written by the user as a formula of the invariants (docs/materials.md, "Laws written
// as formulas"), with exact first and second derivatives from second-order forward-mode automatic
// differentiation (formula_ad.hpp), assembled into P = dW/dF and dP/dF by the chain rule.
//
// Invariants the formula may read (C = F^T F, J = det F, f0 and s0 the fiber families):
//   I1 = tr C,  I1bar = J^(-2/3) I1,  I2 = (I1^2 - tr C^2)/2,  I4 = f0.C f0,  I6 = s0.C s0,
//   I8 = f0.C s0,  J.
// With the derivatives d_k = dW/dI_k and d_kl over the independent invariants k in {I1, I2, I4, I6,
// I8, J} (I1bar is differentiated through I1 and J):
//   P = sum_k d_k dI_k/dF,   dP/dF = sum_k d_k d2I_k/dF2 + sum_kl d_kl dI_k/dF (x) dI_l/dF.
// The options are those of the built-in laws (law.hpp):
//  - fiber compression excluded: a fiber invariant I4 or I6 below 1 reads 1 (the family is slack:
//    its stretch, and every derivative in it, is removed). This is the built-in W1, W2, W3 rule; the
//    built-in hgo drops a compressed family's whole term, which an expression writes with step(I4 - 1);
//  - the isochoric isotropic invariant: I1 reads I1bar;
//  - the stress-free reference term: the hydrostatic stress p_ref I that the energy gives at F = I
//    (p_ref = 2 d1 + 4 d2 + dJ there) is removed by adding -p_ref ln J, as the built-in laws add
//    -2 d1_ref ln J. The fiber derivatives must vanish at F = I (checked: check_expression_law).
#include <array>
#include <span>
#include <string>
#include <vector>

#include "materials/formula_program.hpp"
#include "materials/law.hpp"

namespace ibvalve::materials {

/// A named parameter of an expression law, in CGS (a modulus in dyn/cm^2).
struct ExpressionParameter {
  std::string name;
  double value = 0.0;
  bool is_modulus = false;
};

/// The invariants the formula may read, in the order of the formula's first symbols.
inline constexpr std::array<const char*, 7> expression_invariants{"I1", "I1bar", "I2", "I4", "I6", "I8", "J"};

/// The independent invariants the derivatives are taken in.
enum KinematicInvariant { kI1, kI2, kI4, kI6, kI8, kJ, kinematic_count };

/// W and its derivatives in the independent invariants (zero for an invariant the formula does not read).
struct ExpressionResponse {
  double psi = 0.0;
  std::array<double, kinematic_count> d{};
  std::array<std::array<double, kinematic_count>, kinematic_count> dd{};
};

class ExpressionLaw : public StrainEnergy {
 public:
  /// Throws FormulaError for a syntax error or an unknown symbol (the symbols are the invariants and the
  /// parameters' names).
  ExpressionLaw(std::string energy, std::vector<ExpressionParameter> parameters, LawOptions options = {});

  std::string name() const override { return "expression"; }
  double energy(const Mat3& F, const FiberFrame& fibers) const override;
  Mat3 stress(const Mat3& F, const FiberFrame& fibers) const override;
  Tangent tangent(const Mat3& F, const FiberFrame& fibers) const override;
  void stress_and_tangent(const Mat3& F, const FiberFrame& fibers, Mat3& P, Tangent& T) const override;

  /// P and dP/dF of W alone (without the reference term), for a Material that adds every volumetric
  /// term in one pass (as for InvariantLaw).
  Mat3 invariant_stress(const Mat3& F, const FiberFrame& fibers) const;
  void invariant_stress_and_tangent(const Mat3& F, const FiberFrame& fibers, Mat3& P, Tangent& T) const;

  const Formula& formula() const { return formula_; }
  std::span<const ExpressionParameter> parameters() const { return parameters_; }
  const LawOptions& options() const { return options_; }
  /// The coefficient of the reference term -p_ref ln J (0 when as written, or when W gives no stress at I).
  double reference_pressure() const { return reference_pressure_; }
  /// How many fiber families the formula reads: 0, 1 (I4) or 2 (I6 or I8).
  int fiber_families() const;

  /// W (without the reference term) and its derivatives at the invariants' values `values`
  /// (indexed by KinematicInvariant), the fiber switch applied; `order` 1 leaves dd at zero.
  ExpressionResponse response(const std::array<double, kinematic_count>& values, int order = 2) const;
  /// The invariants of F with `fibers`.
  static std::array<double, kinematic_count> invariants_of(const Mat3& F, const FiberFrame& fibers);
  /// W with `parameter_values` (CGS, in the order of parameters()) in place of the law's own: for checks.
  double energy_with(std::span<const double> parameter_values,
                     const std::array<double, kinematic_count>& values) const;

 private:
  /// P and, when T is given, dP/dF, with the reference term or without.
  void assemble(const Mat3& F, const FiberFrame& fibers, Mat3& P, Tangent* T, bool reference) const;
  template <int N, int Order>
  ExpressionResponse response_in(const std::array<double, kinematic_count>& values) const;
  std::array<double, kinematic_count> switched(std::array<double, kinematic_count> values) const;

  Formula formula_;
  std::vector<ExpressionParameter> parameters_;
  LawOptions options_;
  /// The kinematic invariants differentiated (their slot in the AD number), in order.
  std::vector<int> active_;
  std::array<int, kinematic_count> slot_{};
  /// The invariants whose derivatives P and dP/dF sum: active_, and J for the reference term.
  std::vector<int> assembled_;
  bool reads_isochoric_ = false; ///< the formula reads J^(-2/3) I1 (as I1bar, or as I1 when isochoric)
  /// Node values that depend on no invariant (the parameters' part of the formula), computed once;
  /// NaN for the others.
  std::vector<double> fixed_;
  FormulaProgram program_;
  double reference_pressure_ = 0.0;
};

} // namespace ibvalve::materials
