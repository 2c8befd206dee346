// The delta kernels' defining properties (Peskin 2002, section 6): partition of unity, first moment,
// the even/odd condition, the second moment of the 6-point kernel, and the sum of squares, each to
// round-off at many positions; and that the per-piece weights agree with phi(r) and join continuously.
#include <array>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "ib/kernels.hpp"

using namespace ibvalve::ib;

namespace {

const KernelKind all_kernels[] = {KernelKind::piecewise_linear, KernelKind::ib_3, KernelKind::ib_4,
                                  KernelKind::ib_6, KernelKind::bspline_3};

struct Sums {
  double total = 0, first = 0, second = 0, third = 0, squares = 0, even = 0, odd = 0;
};

Sums sums(const DeltaKernel& k, double s)
{
  std::array<double, max_kernel_support> w{};
  const int first = k.weights(s, w);
  Sums r;
  for (int m = 0; m < k.support(); ++m) {
    const int i = first + m;
    const double d = s - i;
    r.total += w[m];
    r.first += d * w[m];
    r.second += d * d * w[m];
    r.third += d * d * d * w[m];
    r.squares += w[m] * w[m];
    (i % 2 == 0 ? r.even : r.odd) += w[m];
  }
  return r;
}

std::vector<double> sample_positions()
{
  std::vector<double> s{0.0, 0.5, 1.0, 2.25, 3.5, 7.0 - 1e-12, 7.0 + 1e-12};
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> u(-20.0, 20.0);
  for (int n = 0; n < 500; ++n) s.push_back(u(gen));
  return s;
}

} // namespace

TEST(Kernels, PartitionOfUnityAndFirstMomentToRoundOff)
{
  for (KernelKind kind : all_kernels) {
    const DeltaKernel k(kind);
    for (double s : sample_positions()) {
      const Sums r = sums(k, s);
      EXPECT_NEAR(r.total, 1.0, 4e-15) << k.name() << " at s = " << s;
      EXPECT_NEAR(r.first, 0.0, 1e-14) << k.name() << " at s = " << s;
    }
  }
}

TEST(Kernels, EvenAndOddSumsAreOneHalfForIb4AndIb6)
{
  for (KernelKind kind : {KernelKind::ib_4, KernelKind::ib_6}) {
    const DeltaKernel k(kind);
    ASSERT_TRUE(k.has_even_odd_condition());
    for (double s : sample_positions()) {
      const Sums r = sums(k, s);
      EXPECT_NEAR(r.even, 0.5, 4e-15) << k.name() << " at s = " << s;
      EXPECT_NEAR(r.odd, 0.5, 4e-15) << k.name() << " at s = " << s;
    }
  }
  // The hat and the B-spline do not have it: at s = 0 all weight of the hat sits on one point.
  EXPECT_NEAR(sums(DeltaKernel(KernelKind::piecewise_linear), 0.0).even, 1.0, 1e-15);
}

TEST(Kernels, SumOfSquaresIsTheKernelsConstant)
{
  // Roma et al. (1999): 1/2; Peskin (2002): 3/8; Bao et al. (2016): C = 5431/19200 + 51 sqrt(29)/6400.
  const double c6 = 5431.0 / 19200.0 + 51.0 * std::sqrt(29.0) / 6400.0;
  const std::pair<KernelKind, double> cases[] = {
      {KernelKind::ib_3, 0.5}, {KernelKind::ib_4, 0.375}, {KernelKind::ib_6, c6}};
  for (const auto& [kind, constant] : cases) {
    const DeltaKernel k(kind);
    for (double s : sample_positions())
      EXPECT_NEAR(sums(k, s).squares, constant, 2e-15) << k.name() << " at " << s;
  }
}

TEST(Kernels, SixPointKernelHasSecondMomentKAndZeroThirdMoment)
{
  const double K = 59.0 / 60.0 - std::sqrt(29.0) / 20.0;
  const DeltaKernel k(KernelKind::ib_6);
  for (double s : sample_positions()) {
    const Sums r = sums(k, s);
    EXPECT_NEAR(r.second, K, 1e-13) << s;
    EXPECT_NEAR(r.third, 0.0, 1e-12) << s;
  }
}

TEST(Kernels, WeightsAgreeWithPhiAndPhiIsContinuousAndCompact)
{
  for (KernelKind kind : all_kernels) {
    const DeltaKernel k(kind);
    const double half = 0.5 * k.support();
    EXPECT_EQ(k.phi(half), 0.0) << k.name();
    EXPECT_EQ(k.phi(-half - 0.1), 0.0) << k.name();
    EXPECT_NEAR(k.phi(half - 1e-9), 0.0, 1e-8) << k.name();
    for (double s : sample_positions()) {
      std::array<double, max_kernel_support> w{};
      const int first = k.weights(s, w);
      for (int m = 0; m < k.support(); ++m)
        EXPECT_NEAR(w[m], k.phi(s - (first + m)), 1e-14) << k.name() << " " << s;
    }
    // Symmetric and continuous, including across the pieces' joints (integers and half-integers).
    for (double r = -half; r <= half; r += 0.25) {
      EXPECT_NEAR(k.phi(r), k.phi(-r), 1e-14) << k.name() << " " << r;
      EXPECT_NEAR(k.phi(r - 1e-10), k.phi(r + 1e-10), 1e-8) << k.name() << " at " << r;
    }
  }
}

TEST(Kernels, NamesRoundTripAndDefaultIsIb4)
{
  for (KernelKind kind : all_kernels) EXPECT_EQ(find_kernel(kernel_name(kind)), kind);
  EXPECT_FALSE(find_kernel("ib-5").has_value());
  EXPECT_EQ(default_kernel, KernelKind::ib_4);
  EXPECT_EQ(DeltaKernel(KernelKind::ib_6).ghost_width(), 3);
  EXPECT_EQ(DeltaKernel(KernelKind::ib_4).ghost_width(), 2);
}

// grid_floor, which the stencils use instead of the library's floor, is floor: the same value at
// integers, just beside them and between them, negative and positive (the sign of a zero aside).
TEST(Kernels, GridFloorIsFloor)
{
  std::mt19937 random(7);
  std::uniform_real_distribution<double> coordinate(-50.0, 1000.0);
  for (int n = 0; n < 100000; ++n) {
    const double s = coordinate(random);
    for (const double t :
         {s, std::round(s), std::nextafter(std::round(s), -1e9), std::nextafter(std::round(s), 1e9)})
      ASSERT_EQ(grid_floor(t), std::floor(t)) << "at " << t;
  }
}
