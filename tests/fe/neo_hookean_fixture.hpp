#pragma once
// A compressible neo-Hookean law written out in full for the fe/ tests, so the assembly is checked
// against a law whose stress and tangent are derived here independently of materials/:
//   W = mu/2 (I1 - 3) - mu ln J + lambda/2 (ln J)^2      (Ogden 1984; Bonet & Wood 2008, eq. 6.27)
//   P = mu (F - F^{-T}) + lambda ln J F^{-T}
//   dP_ab/dF_cd = mu d_ac d_bd + (mu - lambda ln J) Finv_bc Finv_da + lambda Finv_ba Finv_dc
#include <cmath>

#include <Eigen/LU>

#include "materials/strain_energy.hpp"

namespace ibvalve::fe::fixtures {

class NeoHookeanFixture final : public materials::StrainEnergy {
 public:
  NeoHookeanFixture(double mu, double lambda) : mu_(mu), lambda_(lambda) {}
  std::string name() const override { return "neo-Hookean (test fixture)"; }
  double energy(const materials::Mat3& F, const materials::FiberFrame&) const override
  {
    const double J = F.determinant(), logJ = std::log(J);
    return 0.5 * mu_ * ((F.transpose() * F).trace() - 3) - mu_ * logJ + 0.5 * lambda_ * logJ * logJ;
  }
  materials::Mat3 stress(const materials::Mat3& F, const materials::FiberFrame&) const override
  {
    const materials::Mat3 FinvT = F.inverse().transpose();
    return mu_ * (F - FinvT) + lambda_ * std::log(F.determinant()) * FinvT;
  }
  materials::Tangent tangent(const materials::Mat3& F, const materials::FiberFrame&) const override
  {
    const materials::Mat3 Finv = F.inverse();
    const double logJ = std::log(F.determinant());
    materials::Tangent T;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        for (int c = 0; c < 3; ++c)
          for (int d = 0; d < 3; ++d)
            T(a + 3 * b, c + 3 * d) = mu_ * (a == c) * (b == d) +
                                      (mu_ - lambda_ * logJ) * Finv(b, c) * Finv(d, a) +
                                      lambda_ * Finv(b, a) * Finv(d, c);
    return T;
  }
  double mu() const { return mu_; }
  double lambda() const { return lambda_; }

 private:
  double mu_, lambda_;
};

} // namespace ibvalve::fe::fixtures
