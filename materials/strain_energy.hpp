#pragma once
// The interface every hyperelastic law implements: strain energy W(F), first Piola–Kirchhoff stress
// P = dW/dF and the consistent tangent dP/dF, at one material point with its fiber directions.
#include <string>

#include <Eigen/Core>
#include <Eigen/LU> // determinant() and inverse() of 3x3 F

namespace ibvalve::materials {

using Mat3 = Eigen::Matrix3d;
using Vec3 = Eigen::Vector3d;
/// dP/dF with P and F flattened column-major (index i + 3 j for entry (i, j)):
/// T(a + 3 b, c + 3 d) = dP_ab / dF_cd.
using Tangent = Eigen::Matrix<double, 9, 9>;

/// Reference (unit) fiber directions at a material point. `f0` is the main family; `s0` a second
/// family (Holzapfel–Gasser–Ogden) or the sheet/cross-fiber direction; zero where unused.
struct FiberFrame {
  Vec3 f0 = Vec3::Zero();
  Vec3 s0 = Vec3::Zero();
};

class StrainEnergy {
 public:
  virtual ~StrainEnergy() = default;
  virtual std::string name() const = 0;
  /// W(F) in erg/cm^3 (dyn/cm^2).
  virtual double energy(const Mat3& F, const FiberFrame& fibers) const = 0;
  /// P = dW/dF in dyn/cm^2.
  virtual Mat3 stress(const Mat3& F, const FiberFrame& fibers) const = 0;
  /// dP/dF (see Tangent for the layout).
  virtual Tangent tangent(const Mat3& F, const FiberFrame& fibers) const = 0;
  /// P and dP/dF together (a law may share work between them; the default calls both).
  virtual void stress_and_tangent(const Mat3& F, const FiberFrame& fibers, Mat3& P, Tangent& T) const
  {
    P = stress(F, fibers);
    T = tangent(F, fibers);
  }
};

} // namespace ibvalve::materials
