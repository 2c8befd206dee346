#pragma once
// The discretization uncertainty of one quantity computed on several grids: the observed order, the
// Richardson extrapolate and the grid convergence index (GCI) of Celik, Ghia, Roache, Freitas, Coleman &
// Raad (2008), "Procedure for estimation and reporting of uncertainty due to discretization in CFD
// applications", J. Fluids Eng. 130:078001 (their equations 1-10), with a conservative uncertainty where
// the grids do not converge monotonically (docs/hemodynamics.md, "Grid convergence").
//
// Grids are numbered from the finest: h1 < h2 < h3, r21 = h2/h1, r32 = h3/h2, eps21 = phi2 - phi1,
// eps32 = phi3 - phi2 and R = eps21/eps32.
//
// Classes. With phi(h) = phi0 + C h^p and p > 0, R = (r21^p - 1) / (r21^p (r32^p - 1)), which falls
// strictly from ln(r21)/ln(r32) (p -> 0) to 0 (p -> infinity). So the grids converge monotonically
// exactly when 0 < R < ln(r21)/ln(r32), and then one p > 0 fits them. For a constant ratio the bound is
// 1, Celik et al.'s 0 < R < 1; for ratios that differ it is not: on spacings 1/16, 1/8, 3/16 a first-order
// quantity has R = 1 and one of order 0.8 has R = 1.11, both converging. R < 0 is oscillatory, R at or
// beyond the bound divergent (no positive order fits).
#include <optional>
#include <span>
#include <string_view>
#include <vector>

namespace ibvalve::hemodynamics {

/// Celik et al.'s factor of safety of the GCI where the order is observed on three grids (their eq. 10).
inline constexpr double celik_safety_factor = 1.25;
/// Roache's factor of safety where no order is observed (two grids, or grids that do not converge
/// monotonically): Roache (1994), "Perspective: a method for uniform reporting of grid refinement
/// studies", J. Fluids Eng. 116:405.
inline constexpr double conservative_safety_factor = 3.0;
/// The order assumed with two grids: the immersed boundary method's with a regularised delta function
/// where the solution has a sharp interface (Peskin 2002, Acta Numerica 11:479; Griffith & Peskin 2005,
/// J. Comput. Phys. 208:75); also the more conservative of the orders 1 and 2.
inline constexpr double two_grid_assumed_order = 1.0;
/// The fixed-point iteration of the observed order stops when an iterate moves by at most this much
/// (relative to max(1, p)): some hundred times the round-off of one evaluation.
inline constexpr double order_tolerance = 1e-13;
/// ... or gives up after this many iterations.
inline constexpr int order_max_iterations = 1000;

/// How the grids' values of a quantity behave under refinement.
enum class ConvergenceClass {
  monotone,      // 0 < R < ln(r21)/ln(r32)
  oscillatory,   // R < 0
  divergent,     // R >= ln(r21)/ln(r32), including eps32 = 0 with eps21 != 0
  indeterminate, // eps21 = 0, eps32 != 0: the two finest agree exactly, so no order can be observed
  unchanged,     // every grid gives the same value: no discretization error is seen
  two_grids,     // only two grids: no order can be observed
};
/// "monotone", "oscillatory", "divergent", "indeterminate", "unchanged", "two_grids".
std::string_view to_string(ConvergenceClass c);

/// How the uncertainty of the finest grid's value was estimated.
enum class UncertaintyRule {
  richardson,    // Celik et al. eq. 10: 1.25 |eps21| / (r21^p - 1), p observed
  assumed_order, // two grids: 3 |eps21| / (r21^p - 1), p = two_grid_assumed_order
  range,         // no order observed on three grids: 3 max(|phi2 - phi1|, |phi3 - phi1|)
  none,          // unchanged: 0
};
/// "richardson", "assumed_order", "range", "none".
std::string_view to_string(UncertaintyRule rule);

/// The observed order of Celik et al.'s eqs. 5a-5c by their fixed-point iteration
/// p = |ln|eps32/eps21| + q(p)| / ln(r21), q(p) = ln((r21^p - s)/(r32^p - s)), s = sign(eps32/eps21),
/// started from p = 1 (where q vanishes for a constant ratio, so that one step gives the exact p).
struct ObservedOrder {
  std::optional<double> p; // empty: eps21 or eps32 is zero, or the iteration did not converge
  int iterations = 0;
};
ObservedOrder observed_order(double phi1, double phi2, double phi3, double r21, double r32);

/// Celik et al.'s eqs. 6-10 for the two finest grids and an order p.
struct RichardsonEstimate {
  double extrapolated = 0.0;   // phi_ext21 = (r21^p phi1 - phi2) / (r21^p - 1)
  std::optional<double> e_a;   // |(phi1 - phi2) / phi1|; empty when phi1 = 0
  std::optional<double> e_ext; // |(phi_ext21 - phi1) / phi_ext21|; empty when phi_ext21 = 0
  std::optional<double> gci;   // safety_factor e_a / (r21^p - 1); empty when phi1 = 0
  double gci_in_unit = 0.0;    // safety_factor |phi1 - phi2| / (r21^p - 1): gci |phi1|
};
RichardsonEstimate richardson_estimate(double phi1, double phi2, double r21, double p,
                                       double safety_factor = celik_safety_factor);

/// One quantity's grid convergence.
struct GridConvergence {
  ConvergenceClass kind = ConvergenceClass::two_grids;
  UncertaintyRule rule = UncertaintyRule::assumed_order;
  std::optional<double> R;       // eps21/eps32 of the three finest grids (empty with two grids or eps32 = 0)
  std::optional<double> p;       // observed order (monotone only)
  int order_iterations = 0;      // of the fixed point (0 when it did not run)
  bool order_converged = false;  // false for a monotone triple only when the fixed point gave up
  std::optional<double> phi_ext; // Richardson extrapolate (monotone with an observed order only)
  std::optional<double> e_a;     // |eps21 / phi1| (empty when phi1 = 0)
  std::optional<double> e_ext;   // |(phi_ext - phi1) / phi_ext| (with phi_ext, when it is not 0)
  double safety_factor = conservative_safety_factor;
  double uncertainty = 0.0;  // the GCI in the quantity's unit: the finest value's uncertainty
  std::optional<double> gci; // uncertainty / |phi1| (empty when phi1 = 0)
};

/// The study of one quantity: `spacings` increasing (finest first, at least two, all different) and its
/// `values` on them. Three or more grids: the three finest are classified; a monotone triple gets
/// Celik et al.'s estimate (eqs. 5-10), any other a conservative one (UncertaintyRule::range), as does a
/// monotone triple whose fixed point did not converge. Two grids: the assumed order with Fs = 3.
/// std::invalid_argument for spacings that are not increasing and positive or sizes that differ.
GridConvergence grid_convergence(std::span<const double> spacings, std::span<const double> values);

} // namespace ibvalve::hemodynamics
