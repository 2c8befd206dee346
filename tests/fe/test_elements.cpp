// Quadrature rules integrate the polynomials they promise exactly; shape functions are a partition of
// unity, interpolate the nodes, and their gradients match finite differences.
#include <cmath>

#include <gtest/gtest.h>

#include "fe/element.hpp"
#include "fe/quadrature.hpp"

using namespace ibvalve::fe;

namespace {

double factorial(int n)
{
  return n <= 1 ? 1.0 : n * factorial(n - 1);
}

// Integral of x^a y^b z^c over the unit reference tetrahedron: a! b! c! / (a + b + c + 3)!.
double tetrahedron_monomial(int a, int b, int c)
{
  return factorial(a) * factorial(b) * factorial(c) / factorial(a + b + c + 3);
}
double triangle_monomial(int a, int b)
{
  return factorial(a) * factorial(b) / factorial(a + b + 2);
}
// Integral of x^a over [-1, 1].
double interval_monomial(int a)
{
  return a % 2 ? 0.0 : 2.0 / (a + 1);
}

} // namespace

TEST(Quadrature, GaussLegendreIsExactToDegreeTwoNMinusOne)
{
  for (int n = 1; n <= 12; ++n) {
    std::vector<double> x, w;
    gauss_legendre(n, x, w);
    for (int degree = 0; degree <= 2 * n - 1; ++degree) {
      double sum = 0;
      for (int i = 0; i < n; ++i) sum += w[i] * std::pow(x[i], degree);
      EXPECT_NEAR(sum, interval_monomial(degree), 1e-14) << "n = " << n << ", degree " << degree;
    }
    // ... and not beyond: x^(2n) is integrated with an error.
    double sum = 0;
    for (int i = 0; i < n; ++i) sum += w[i] * std::pow(x[i], 2 * n);
    EXPECT_GT(std::abs(sum - interval_monomial(2 * n)), 1e-12);
  }
}

TEST(Quadrature, HexahedronRuleIsExactPerVariable)
{
  for (int degree = 1; degree <= 9; ++degree) {
    const QuadratureRule rule = hexahedron_rule(degree);
    for (int a = 0; a <= degree; ++a)
      for (int b = 0; b <= degree; b += 2)
        for (int c = 0; c <= degree; c += 3) {
          double sum = 0;
          for (std::size_t q = 0; q < rule.size(); ++q)
            sum += rule.weights[q] * std::pow(rule.points[q][0], a) * std::pow(rule.points[q][1], b) *
                   std::pow(rule.points[q][2], c);
          EXPECT_NEAR(sum, interval_monomial(a) * interval_monomial(b) * interval_monomial(c), 1e-13);
        }
  }
}

TEST(Quadrature, SimplexRulesAreExactForTotalDegree)
{
  for (int degree = 0; degree <= 8; ++degree) {
    const QuadratureRule tet = tetrahedron_rule(degree), tri = triangle_rule(degree);
    for (int a = 0; a <= degree; ++a)
      for (int b = 0; a + b <= degree; ++b) {
        for (int c = 0; a + b + c <= degree; ++c) {
          double sum = 0;
          for (std::size_t q = 0; q < tet.size(); ++q)
            sum += tet.weights[q] * std::pow(tet.points[q][0], a) * std::pow(tet.points[q][1], b) *
                   std::pow(tet.points[q][2], c);
          EXPECT_NEAR(sum, tetrahedron_monomial(a, b, c), 1e-15) << a << b << c;
        }
        double sum = 0;
        for (std::size_t q = 0; q < tri.size(); ++q)
          sum += tri.weights[q] * std::pow(tri.points[q][0], a) * std::pow(tri.points[q][1], b);
        EXPECT_NEAR(sum, triangle_monomial(a, b), 1e-15) << a << b;
      }
  }
}

class ShapeFunctions : public ::testing::TestWithParam<CellShape> {};

TEST_P(ShapeFunctions, InterpolateNodesAndSumToOne)
{
  const ElementType& type = element_type(GetParam());
  const auto nodes = type.reference_nodes();
  std::vector<double> N(type.num_nodes());
  for (int a = 0; a < type.num_nodes(); ++a) {
    type.values(nodes[a], N);
    for (int b = 0; b < type.num_nodes(); ++b) EXPECT_NEAR(N[b], a == b ? 1.0 : 0.0, 1e-15);
  }
  const QuadratureRule rule = type.quadrature(3);
  for (const Vec3& xi : rule.points) {
    type.values(xi, N);
    double sum = 0;
    for (double n : N) sum += n;
    EXPECT_NEAR(sum, 1.0, 1e-15);
  }
}

TEST_P(ShapeFunctions, GradientsMatchCentralDifferences)
{
  const ElementType& type = element_type(GetParam());
  const int n = type.num_nodes();
  std::vector<double> plus(n), minus(n);
  std::vector<Vec3> dN(n);
  const double h = 1e-6;
  for (const Vec3& xi : type.quadrature(3).points) {
    type.gradients(xi, dN);
    for (int d = 0; d < type.dimension(); ++d) {
      type.values(xi + h * Vec3::Unit(d), plus);
      type.values(xi - h * Vec3::Unit(d), minus);
      for (int a = 0; a < n; ++a) EXPECT_NEAR(dN[a][d], (plus[a] - minus[a]) / (2 * h), 1e-9);
    }
  }
}

TEST_P(ShapeFunctions, FacesPointOutward)
{
  const ElementType& type = element_type(GetParam());
  if (type.dimension() != 3) GTEST_SKIP() << "faces of 2-D cells are edges";
  const auto nodes = type.reference_nodes();
  Vec3 centre = Vec3::Zero();
  for (const Vec3& x : nodes) centre += x / nodes.size();
  for (const auto& face : type.faces()) {
    const Vec3 normal = (nodes[face[1]] - nodes[face[0]]).cross(nodes[face[2]] - nodes[face[0]]);
    EXPECT_GT(normal.dot(nodes[face[0]] - centre), 0.0);
  }
}

INSTANTIATE_TEST_SUITE_P(AllCells, ShapeFunctions,
                         ::testing::Values(CellShape::hexahedron, CellShape::tetrahedron,
                                           CellShape::quadrilateral, CellShape::triangle));
