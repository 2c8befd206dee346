#pragma once
// Gauss quadrature on the reference cells of fe/ (docs/fe.md). A rule is given by the polynomial
// degree it must integrate exactly; any degree is available.
//
// Reference cells: the hexahedron and quadrilateral are [-1, 1]^d; the tetrahedron is
// {xi, eta, zeta >= 0, xi + eta + zeta <= 1} and the triangle {xi, eta >= 0, xi + eta <= 1}.
#include <vector>

#include <Eigen/Dense>

namespace ibvalve::fe {

using Vec3 = Eigen::Vector3d;

/// Points (unused coordinates are zero) and weights on a reference cell.
struct QuadratureRule {
  std::vector<Vec3> points;
  std::vector<double> weights;
  std::size_t size() const { return points.size(); }
};

/// n-point Gauss–Legendre rule on [-1, 1] (exact for degree 2n - 1): nodes are the roots of P_n,
/// found by Newton's method from Tricomi's initial guesses (Abramowitz & Stegun 25.4.29).
void gauss_legendre(int n, std::vector<double>& nodes, std::vector<double>& weights);

/// Tensor Gauss rules on [-1, 1]^3 and [-1, 1]^2, exact for polynomials of degree <= `degree` in each
/// variable.
QuadratureRule hexahedron_rule(int degree);
QuadratureRule quadrilateral_rule(int degree);

/// Rules on the reference tetrahedron / triangle, exact for total degree <= `degree`. Degrees 1 and 2
/// use the classical symmetric rules (centroid; 4 points, Hammer–Marlowe–Stroud 1956 / 3 points);
/// higher degrees use the conical (collapsed) Gauss product rule of Stroud (1971), Duffy's map.
QuadratureRule tetrahedron_rule(int degree);
QuadratureRule triangle_rule(int degree);

} // namespace ibvalve::fe
