#include "hemodynamics/grid_convergence.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ibvalve::hemodynamics {

std::string_view to_string(ConvergenceClass c)
{
  switch (c) {
  case ConvergenceClass::monotone:
    return "monotone";
  case ConvergenceClass::oscillatory:
    return "oscillatory";
  case ConvergenceClass::divergent:
    return "divergent";
  case ConvergenceClass::indeterminate:
    return "indeterminate";
  case ConvergenceClass::unchanged:
    return "unchanged";
  case ConvergenceClass::two_grids:
    return "two_grids";
  }
  return "";
}

std::string_view to_string(UncertaintyRule rule)
{
  switch (rule) {
  case UncertaintyRule::richardson:
    return "richardson";
  case UncertaintyRule::assumed_order:
    return "assumed_order";
  case UncertaintyRule::range:
    return "range";
  case UncertaintyRule::none:
    return "none";
  }
  return "";
}

ObservedOrder observed_order(double phi1, double phi2, double phi3, double r21, double r32)
{
  const double eps21 = phi2 - phi1, eps32 = phi3 - phi2;
  ObservedOrder result;
  if (eps21 == 0.0 || eps32 == 0.0) return result; // ln|eps32/eps21| is infinite or undefined
  const double s = eps32 / eps21 > 0.0 ? 1.0 : -1.0;
  const double log_ratio = std::log(std::abs(eps32 / eps21)), log_r21 = std::log(r21);
  double p = 1.0;
  for (int k = 1; k <= order_max_iterations; ++k) {
    const double q = std::log((std::pow(r21, p) - s) / (std::pow(r32, p) - s));
    const double next = std::abs(log_ratio + q) / log_r21;
    result.iterations = k;
    // An iterate of 0 would make q 0/0 next; an overflowing one (r32 much larger than r21^2 makes the
    // map expanding) ends as inf/inf. Either way the iteration has failed.
    if (!std::isfinite(next) || next <= 0.0) return result;
    if (std::abs(next - p) <= order_tolerance * std::max(1.0, next)) {
      result.p = next;
      return result;
    }
    p = next;
  }
  return result;
}

RichardsonEstimate richardson_estimate(double phi1, double phi2, double r21, double p, double safety_factor)
{
  const double rp = std::pow(r21, p);
  RichardsonEstimate e;
  e.extrapolated = (rp * phi1 - phi2) / (rp - 1.0);
  e.gci_in_unit = safety_factor * std::abs(phi1 - phi2) / (rp - 1.0);
  if (phi1 != 0.0) {
    e.e_a = std::abs((phi1 - phi2) / phi1);
    e.gci = safety_factor * *e.e_a / (rp - 1.0);
  }
  if (e.extrapolated != 0.0) e.e_ext = std::abs((e.extrapolated - phi1) / e.extrapolated);
  return e;
}

namespace {

void check_grids(std::span<const double> spacings, std::span<const double> values)
{
  if (spacings.size() != values.size())
    throw std::invalid_argument("grid_convergence: one value per spacing is needed");
  if (spacings.size() < 2) throw std::invalid_argument("grid_convergence: at least two grids are needed");
  if (!(spacings[0] > 0.0)) throw std::invalid_argument("grid_convergence: spacings must be positive");
  for (std::size_t i = 1; i < spacings.size(); ++i)
    if (!(spacings[i] > spacings[i - 1]))
      throw std::invalid_argument("grid_convergence: spacings must increase (finest first), all different");
}

ConvergenceClass classify(double eps21, double eps32, double r21, double r32)
{
  if (eps21 == 0.0 && eps32 == 0.0) return ConvergenceClass::unchanged;
  if (eps21 == 0.0) return ConvergenceClass::indeterminate;
  if (eps32 == 0.0) return ConvergenceClass::divergent; // |R| infinite: the change grew with refinement
  const double R = eps21 / eps32;
  if (R < 0.0) return ConvergenceClass::oscillatory;
  return R < std::log(r21) / std::log(r32) ? ConvergenceClass::monotone : ConvergenceClass::divergent;
}

/// Fs times the largest change of the finest value over the three finest grids, for a study without an
/// observed order (docs/hemodynamics.md, "Grid convergence").
void set_range_uncertainty(GridConvergence& g, std::span<const double> phi)
{
  g.rule = UncertaintyRule::range;
  g.safety_factor = conservative_safety_factor;
  g.uncertainty = conservative_safety_factor * std::max(std::abs(phi[1] - phi[0]), std::abs(phi[2] - phi[0]));
}

} // namespace

GridConvergence grid_convergence(std::span<const double> spacings, std::span<const double> values)
{
  check_grids(spacings, values);
  GridConvergence g;
  const double phi1 = values[0], phi2 = values[1];
  const double r21 = spacings[1] / spacings[0];
  if (phi1 != 0.0) g.e_a = std::abs((phi2 - phi1) / phi1);
  if (spacings.size() == 2) {
    g.kind = ConvergenceClass::two_grids;
    g.rule = UncertaintyRule::assumed_order;
    g.safety_factor = conservative_safety_factor;
    g.uncertainty =
        richardson_estimate(phi1, phi2, r21, two_grid_assumed_order, conservative_safety_factor).gci_in_unit;
  } else {
    const double phi3 = values[2], r32 = spacings[2] / spacings[1];
    const double eps21 = phi2 - phi1, eps32 = phi3 - phi2;
    if (eps32 != 0.0) g.R = eps21 / eps32;
    g.kind = classify(eps21, eps32, r21, r32);
    if (g.kind == ConvergenceClass::unchanged) {
      g.rule = UncertaintyRule::none;
      g.safety_factor = celik_safety_factor;
      g.uncertainty = 0.0;
    } else if (g.kind == ConvergenceClass::monotone) {
      const ObservedOrder order = observed_order(phi1, phi2, phi3, r21, r32);
      g.order_iterations = order.iterations;
      g.order_converged = order.p.has_value();
      if (order.p) {
        const RichardsonEstimate e = richardson_estimate(phi1, phi2, r21, *order.p);
        g.rule = UncertaintyRule::richardson;
        g.safety_factor = celik_safety_factor;
        g.p = order.p;
        g.phi_ext = e.extrapolated;
        g.e_ext = e.e_ext;
        g.uncertainty = e.gci_in_unit;
      } else {
        set_range_uncertainty(g, values);
      }
    } else {
      set_range_uncertainty(g, values);
    }
  }
  if (phi1 != 0.0) g.gci = g.uncertainty / std::abs(phi1);
  return g;
}

} // namespace ibvalve::hemodynamics
