#include "materials/biaxial.hpp"

namespace ibvalve::materials {

FiberFrame biaxial_frame(const BiaxialSetup& setup)
{
  const double c = std::cos(setup.fiber_angle), s = std::sin(setup.fiber_angle);
  FiberFrame frame;
  frame.f0 = Vec3(c, s, 0.0);
  if (setup.law == LawKind::hgo) frame.s0 = Vec3(c, -s, 0.0);
  return frame;
}

std::array<double, 2> biaxial_cauchy_through_stress(const StrainEnergy& law, const FiberFrame& frame,
                                                    double lambda1, double lambda2)
{
  const Vec3 stretches(lambda1, lambda2, 1.0 / (lambda1 * lambda2));
  const Mat3 F = stretches.asDiagonal();
  const Mat3 sigma = law.stress(F, frame) * F.transpose() / F.determinant();
  return {sigma(0, 0) - sigma(2, 2), sigma(1, 1) - sigma(2, 2)};
}

} // namespace ibvalve::materials
