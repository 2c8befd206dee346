#include "fe/quadrature.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace ibvalve::fe {

void gauss_legendre(int n, std::vector<double>& nodes, std::vector<double>& weights)
{
  if (n < 1) throw std::invalid_argument("gauss_legendre: need at least one point");
  nodes.assign(n, 0.0);
  weights.assign(n, 0.0);
  for (int i = 0; i < (n + 1) / 2; ++i) {
    double x = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5));
    double derivative = 1.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      // Three-term recurrence for P_n(x) and P_n'(x).
      double p0 = 1.0, p1 = x;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      derivative = n * (x * p1 - p0) / (x * x - 1.0);
      const double step = p1 / derivative;
      x -= step;
      if (std::abs(step) < 1e-16) break;
    }
    // Recompute the derivative at the converged root for the weight 2 / ((1 - x^2) P_n'(x)^2).
    double p0 = 1.0, p1 = x;
    for (int k = 2; k <= n; ++k) {
      const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
      p0 = p1;
      p1 = p2;
    }
    derivative = n == 1 ? 1.0 : n * (x * p1 - p0) / (x * x - 1.0);
    const double w = 2.0 / ((1.0 - x * x) * derivative * derivative);
    nodes[i] = -x;
    nodes[n - 1 - i] = x;
    weights[i] = weights[n - 1 - i] = w;
  }
  if (n % 2 == 1) nodes[n / 2] = 0.0;
}

namespace {

int points_for_degree(int degree)
{
  return std::max(1, (degree + 2) / 2);
}

} // namespace

QuadratureRule hexahedron_rule(int degree)
{
  std::vector<double> x, w;
  gauss_legendre(points_for_degree(degree), x, w);
  QuadratureRule rule;
  for (std::size_t k = 0; k < x.size(); ++k)
    for (std::size_t j = 0; j < x.size(); ++j)
      for (std::size_t i = 0; i < x.size(); ++i) {
        rule.points.emplace_back(x[i], x[j], x[k]);
        rule.weights.push_back(w[i] * w[j] * w[k]);
      }
  return rule;
}

QuadratureRule quadrilateral_rule(int degree)
{
  std::vector<double> x, w;
  gauss_legendre(points_for_degree(degree), x, w);
  QuadratureRule rule;
  for (std::size_t j = 0; j < x.size(); ++j)
    for (std::size_t i = 0; i < x.size(); ++i) {
      rule.points.emplace_back(x[i], x[j], 0.0);
      rule.weights.push_back(w[i] * w[j]);
    }
  return rule;
}

QuadratureRule tetrahedron_rule(int degree)
{
  QuadratureRule rule;
  if (degree <= 1) {
    rule.points.emplace_back(0.25, 0.25, 0.25);
    rule.weights.push_back(1.0 / 6.0);
    return rule;
  }
  if (degree == 2) {
    const double a = 0.5854101966249685, b = 0.1381966011250105; // (5 +- 3 sqrt 5) / 20
    rule.points = {Vec3(b, b, b), Vec3(a, b, b), Vec3(b, a, b), Vec3(b, b, a)};
    rule.weights.assign(4, 1.0 / 24.0);
    return rule;
  }
  // Duffy: xi = u, eta = v (1 - u), zeta = w (1 - u)(1 - v) on [0, 1]^3, Jacobian (1 - u)^2 (1 - v).
  // A polynomial of total degree p becomes degree <= p + 2 in each of u, v, w.
  std::vector<double> x, w;
  gauss_legendre(points_for_degree(degree + 2), x, w);
  for (std::size_t i = 0; i < x.size(); ++i)
    for (std::size_t j = 0; j < x.size(); ++j)
      for (std::size_t k = 0; k < x.size(); ++k) {
        const double u = 0.5 * (x[i] + 1), v = 0.5 * (x[j] + 1), s = 0.5 * (x[k] + 1);
        rule.points.emplace_back(u, v * (1 - u), s * (1 - u) * (1 - v));
        rule.weights.push_back(0.125 * w[i] * w[j] * w[k] * (1 - u) * (1 - u) * (1 - v));
      }
  return rule;
}

QuadratureRule triangle_rule(int degree)
{
  QuadratureRule rule;
  if (degree <= 1) {
    rule.points.emplace_back(1.0 / 3.0, 1.0 / 3.0, 0.0);
    rule.weights.push_back(0.5);
    return rule;
  }
  if (degree == 2) {
    rule.points = {Vec3(1.0 / 6, 1.0 / 6, 0), Vec3(2.0 / 3, 1.0 / 6, 0), Vec3(1.0 / 6, 2.0 / 3, 0)};
    rule.weights.assign(3, 1.0 / 6.0);
    return rule;
  }
  std::vector<double> x, w;
  gauss_legendre(points_for_degree(degree + 1), x, w);
  for (std::size_t i = 0; i < x.size(); ++i)
    for (std::size_t j = 0; j < x.size(); ++j) {
      const double u = 0.5 * (x[i] + 1), v = 0.5 * (x[j] + 1);
      rule.points.emplace_back(u, v * (1 - u), 0.0);
      rule.weights.push_back(0.25 * w[i] * w[j] * (1 - u));
    }
  return rule;
}

} // namespace ibvalve::fe
