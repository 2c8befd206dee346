#pragma once
// Planar biaxial test of a thin incompressible sample (docs/reference.md, "Constitutive fitting").
//
// The sample is stretched by lambda1 along axis 1 (the fiber direction) and lambda2 along axis 2,
// F = diag(l1, l2, l3) with l3 = 1/(l1 l2) (incompressible). With the invariant derivatives
// d_k = dPsi/dI_k the Cauchy stress is sigma = -p I + 2 d1 B + 2 d4 f (x) f + 2 d6 s (x) s, and the
// traction-free faces, sigma33 = 0, give p = 2 d1 l3^2 (the fibers lie in the 1-2 plane). Hence
//   sigma11 = 2 d1 (l1^2 - l3^2) + 2 (d4 + d6) l1^2 cos^2(theta)
//   sigma22 = 2 d1 (l2^2 - l3^2) + 2 (d4 + d6) l2^2 sin^2(theta)
// with I1 = l1^2 + l2^2 + l3^2 and I4 = I6 = l1^2 cos^2 + l2^2 sin^2. For W1, W2, W3 and neo-Hookean
// the single family lies along axis 1 (theta = 0; d6 = 0). For HGO the two families lie at
// +-theta from axis 1, so that the shear stresses cancel and the diagonal F is consistent.
// The hydrostatic reference term and any volumetric penalty drop out (they only shift p).
#include <array>
#include <cmath>

#include "materials/law.hpp"
#include "materials/law_kernels.hpp"

namespace ibvalve::materials {

struct BiaxialSetup {
  LawKind law = LawKind::W1;
  FiberCompression fiber_compression = FiberCompression::excluded;
  /// Angle of the HGO families from axis 1 (radians); must be 0 for the single-family laws.
  double fiber_angle = 0.0;
};

/// (sigma11, sigma22) for parameters `p` (moduli in any stress unit; stresses come out in that unit).
template <class T>
std::array<T, 2> biaxial_cauchy(const BiaxialSetup& setup, const T* p, double lambda1, double lambda2)
{
  const double l3 = 1.0 / (lambda1 * lambda2);
  const double c = std::cos(setup.fiber_angle), s = std::sin(setup.fiber_angle);
  const double l1s = lambda1 * lambda1, l2s = lambda2 * lambda2, l3s = l3 * l3;
  const double I1 = l1s + l2s + l3s;
  const double I4 = l1s * c * c + l2s * s * s;
  const bool two_families = setup.law == LawKind::hgo;
  const auto r = evaluate_invariants<T>(setup.law, p, T(I1), T(I4), T(two_families ? I4 : 0.0),
                                        setup.fiber_compression == FiberCompression::included);
  const T fiber = T(2.0) * (r.d4 + r.d6);
  return {T(2.0) * r.d1 * T(l1s - l3s) + fiber * T(l1s * c * c),
          T(2.0) * r.d1 * T(l2s - l3s) + fiber * T(l2s * s * s)};
}

/// The fiber frame of the biaxial sample for `setup` (f0 = (cos, sin, 0); HGO: s0 = (cos, -sin, 0)).
FiberFrame biaxial_frame(const BiaxialSetup& setup);

/// The same test evaluated through a law's 3-D stress: P at F = diag(l1, l2, 1/(l1 l2)), sigma = P F^T / J,
/// and sigma33 = 0 imposed by subtracting sigma33 from the normal stresses. Works for any StrainEnergy.
std::array<double, 2> biaxial_cauchy_through_stress(const StrainEnergy& law, const FiberFrame& frame,
                                                    double lambda1, double lambda2);

} // namespace ibvalve::materials
