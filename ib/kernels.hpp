#pragma once
// Regularized delta functions of the immersed boundary method (Peskin 2002, Acta Numerica 11:479).
//
// The 3-D kernel is a tensor product, delta_h(x) = phi(x/hx) phi(y/hy) phi(z/hz) / (hx hy hz), of a
// 1-D function phi of compact support. Each kernel here is a published phi:
//   piecewise linear   support 2, first moment                       (hat function)
//   IB 3-point         support 3, first moment, sum phi^2 = 1/2      (Roma, Peskin & Berger 1999, JCP
//   153:509) IB 4-point         support 4, even/odd sums, first moment,       (Peskin 2002, eq. 6.27)
//                      sum phi^2 = 3/8
//   IB 6-point         support 6, even/odd sums, moments 1, 2 (= K), (Bao, Kaye & Peskin 2016, JCP 316:139)
//                      3, sum phi^2 = C, three continuous derivatives
//   B-spline 3rd order support 4, first moment, C2                  (the cubic B-spline)
// The default is IB 4-point: it has the even/odd condition (sum over even and over odd grid points
// each 1/2), which keeps the staggered grid's checkerboard modes from decoupling from the structure,
// and the first moment, so a linear velocity field is interpolated exactly and spreading conserves
// angular momentum; with 4 points per direction it needs 2 ghost layers and 64 grid points per
// structure point, against 216 and 3 layers for the 6-point kernel (whose better translation
// invariance matters less than cost for valve runs; docs/ib.md).
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ibvalve::ib {

enum class KernelKind { piecewise_linear, ib_3, ib_4, ib_6, bspline_3 };

/// The largest support (grid points per direction) of any kernel.
inline constexpr int max_kernel_support = 6;

/// "piecewise-linear", "ib-3", "ib-4", "ib-6", "bspline-3".
std::string kernel_name(KernelKind kind);
std::optional<KernelKind> find_kernel(std::string_view name);
/// All names, comma separated (for error messages and the schema).
/// Every kernel, in the order kernel_names() lists them.
std::vector<KernelKind> every_kernel();
std::string kernel_names();
inline constexpr KernelKind default_kernel = KernelKind::ib_4;

/// floor(s) for a finite s with |s| < 2^62 (a grid coordinate), the same value as std::floor: the
/// baseline x86-64 instruction set has no rounding instruction, so std::floor is a library call, nine
/// per coupling point and placement.
inline double grid_floor(double s)
{
  const auto truncated = static_cast<double>(static_cast<std::int64_t>(s));
  return truncated > s ? truncated - 1.0 : truncated;
}

class DeltaKernel {
 public:
  explicit DeltaKernel(KernelKind kind = default_kernel);

  KernelKind kind() const { return kind_; }
  std::string name() const { return kernel_name(kind_); }
  /// Grid points per direction the kernel touches.
  int support() const { return support_; }
  /// Ghost layers a grid needs so that every point of an owned cell reaches only owned or ghost
  /// points, on cell-centred and face-centred index sets alike.
  int ghost_width() const { return (support_ + 1) / 2; }
  /// True for kernels whose even and odd grid points each carry half the weight.
  bool has_even_odd_condition() const { return kind_ == KernelKind::ib_4 || kind_ == KernelKind::ib_6; }

  /// phi(r), r in units of the grid spacing.
  double phi(double r) const;

  /// The support() weights phi(s - (first + m)), m = 0 .. support()-1, for a point at grid coordinate
  /// s (index units: grid point i sits at s = i; finite), written to w[0 .. support()-1]. Returns `first`.
  /// The weights are evaluated per piece so that their sum and moments hold to round-off.
  int weights(double s, double* w) const
  {
    if (kind_ != KernelKind::ib_4) return weights_of_other_kernels(s, w);
    // With r = s - floor(s) the four distances are 1 + r, r, 1 - r and 2 - r, and both pieces of
    // Peskin (2002), eq. (6.27), take the same root sqrt(1 + 4r - 4r^2) there: one square root. Inline,
    // and written where the caller keeps them: the default kernel's weights are evaluated 24 times per
    // coupling point and placement.
    const double f = grid_floor(s), r = s - f;
    const double q = std::sqrt(1.0 + 4.0 * r - 4.0 * r * r);
    w[0] = (3.0 - 2.0 * r - q) / 8.0;
    w[1] = (3.0 - 2.0 * r + q) / 8.0;
    w[2] = (1.0 + 2.0 * r + q) / 8.0;
    w[3] = (1.0 + 2.0 * r - q) / 8.0;
    return static_cast<int>(f) - 1;
  }
  int weights(double s, std::array<double, max_kernel_support>& w) const { return weights(s, w.data()); }

 private:
  int weights_of_other_kernels(double s, double* w) const;

  KernelKind kind_;
  int support_;
};

} // namespace ibvalve::ib
