#include "ib/kernels.hpp"

#include <algorithm>

#include <cmath>
#include <stdexcept>

namespace ibvalve::ib {

namespace {

struct NamedKernel {
  KernelKind kind;
  const char* name;
  int support;
};
constexpr NamedKernel kernels[] = {{KernelKind::piecewise_linear, "piecewise-linear", 2},
                                   {KernelKind::ib_3, "ib-3", 3},
                                   {KernelKind::ib_4, "ib-4", 4},
                                   {KernelKind::ib_6, "ib-6", 6},
                                   {KernelKind::bspline_3, "bspline-3", 4}};

double linear(double r)
{
  const double a = std::abs(r);
  return a < 1.0 ? 1.0 - a : 0.0;
}

// Roma, Peskin & Berger (1999), eq. (22).
double ib3(double r)
{
  const double a = std::abs(r);
  if (a < 0.5) return (1.0 + std::sqrt(1.0 - 3.0 * a * a)) / 3.0;
  if (a < 1.5) return (5.0 - 3.0 * a - std::sqrt(1.0 - 3.0 * (1.0 - a) * (1.0 - a))) / 6.0;
  return 0.0;
}

// Peskin (2002), eq. (6.27).
double ib4(double r)
{
  const double a = std::abs(r);
  if (a < 1.0) return (3.0 - 2.0 * a + std::sqrt(1.0 + 4.0 * a - 4.0 * a * a)) / 8.0;
  if (a < 2.0) return (5.0 - 2.0 * a - std::sqrt(-7.0 + 12.0 * a - 4.0 * a * a)) / 8.0;
  return 0.0;
}

double bspline3(double r)
{
  const double a = std::abs(r);
  if (a < 1.0) return 2.0 / 3.0 - a * a + 0.5 * a * a * a;
  if (a < 2.0) return (2.0 - a) * (2.0 - a) * (2.0 - a) / 6.0;
  return 0.0;
}

// Bao, Kaye & Peskin (2016). For r in [0, 1) the six values a_m = phi(r + 2 - m), m = 0..5, satisfy
// five linear conditions (even and odd sums 1/2, moments 1 and 3 zero, moment 2 equal to
// K = 59/60 - sqrt(29)/20) and one quadratic one (sum of squares C, fixed by phi(-3) = 0 at r = 0).
// Solving the linear ones for a_0..a_4 in terms of a_5 = phi(r - 3) leaves the quadratic
// 28 a_5^2 + b(r) a_5 + c(r) = 0, whose root with the + sign is the kernel (it vanishes at r = 0 and
// joins the neighbouring pieces continuously). The coefficients were derived by hand (with a
// computer-algebra check) from those conditions.
void ib6_pieces(double r, std::array<double, max_kernel_support>& a)
{
  const double s29 = std::sqrt(29.0);
  const double r2 = r * r, r3 = r2 * r, r4 = r2 * r2, r6 = r3 * r3;
  const double b =
      -7.0 / 3.0 * r3 - 1.5 * r2 + (9.0 / 20.0 + 7.0 * s29 / 20.0) * r + 3.0 * s29 / 40.0 + 31.0 / 40.0;
  const double c = 5.0 / 72.0 * r6 + (1.0 / 32.0 - s29 / 48.0) * r4;
  const double discriminant = std::max(0.0, b * b - 112.0 * c);
  const double a5 = (-b + std::sqrt(discriminant)) / 56.0;
  a[5] = a5;
  a[0] = a5 - r3 / 12.0 + r2 / 8.0 + (s29 - 13.0) / 80.0 * r + 29.0 / 480.0 - s29 / 160.0;
  a[1] = -3.0 * a5 + r3 / 6.0 - (7.0 + s29) / 40.0 * r + 0.25;
  a[2] = 2.0 * a5 - r2 / 4.0 + s29 / 80.0 + 91.0 / 240.0;
  a[3] = 2.0 * a5 - r3 / 6.0 + (7.0 + s29) / 40.0 * r + 0.25;
  a[4] = -3.0 * a5 + r3 / 12.0 + r2 / 8.0 + (13.0 - s29) / 80.0 * r + 29.0 / 480.0 - s29 / 160.0;
}

double ib6(double r)
{
  if (!(std::abs(r) < 3.0)) return 0.0;
  const double f = std::floor(r);
  std::array<double, max_kernel_support> a{};
  ib6_pieces(r - f, a);
  // phi(r) = a_m(r - floor r) with r - floor(r) + 2 - m = r, i.e. m = 2 - floor(r).
  return a[static_cast<int>(2.0 - f)];
}

} // namespace

std::string kernel_name(KernelKind kind)
{
  for (const NamedKernel& k : kernels)
    if (k.kind == kind) return k.name;
  return "unknown";
}

std::optional<KernelKind> find_kernel(std::string_view name)
{
  for (const NamedKernel& k : kernels)
    if (name == k.name) return k.kind;
  return std::nullopt;
}

std::vector<KernelKind> every_kernel()
{
  std::vector<KernelKind> all;
  for (const NamedKernel& k : kernels) all.push_back(k.kind);
  return all;
}

std::string kernel_names()
{
  std::string names;
  for (const NamedKernel& k : kernels) names += (names.empty() ? "" : ", ") + std::string(k.name);
  return names;
}

DeltaKernel::DeltaKernel(KernelKind kind) : kind_(kind), support_(0)
{
  for (const NamedKernel& k : kernels)
    if (k.kind == kind) support_ = k.support;
  if (support_ == 0) throw std::invalid_argument("unknown delta kernel");
}

double DeltaKernel::phi(double r) const
{
  switch (kind_) {
  case KernelKind::piecewise_linear:
    return linear(r);
  case KernelKind::ib_3:
    return ib3(r);
  case KernelKind::ib_4:
    return ib4(r);
  case KernelKind::ib_6:
    return ib6(r);
  case KernelKind::bspline_3:
    return bspline3(r);
  }
  return 0.0;
}

int DeltaKernel::weights_of_other_kernels(double s, double* w) const
{
  // The grid points within half the support of s: first = floor(s - support/2) + 1.
  const int first = static_cast<int>(std::floor(s - 0.5 * support_)) + 1;
  if (kind_ == KernelKind::ib_6) {
    // first = floor(s) - 2 and the weights are the six pieces at r = s - floor(s) directly.
    std::array<double, max_kernel_support> pieces{};
    ib6_pieces(s - std::floor(s), pieces);
    std::copy(pieces.begin(), pieces.end(), w);
    return first;
  }
  for (int m = 0; m < support_; ++m) w[m] = phi(s - static_cast<double>(first + m));
  return first;
}

} // namespace ibvalve::ib
