#include "windkessel/waveform.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <stdexcept>

#include "base/errors.hpp"
#include "io/files.hpp"

namespace ibvalve::windkessel {

Interpolation interpolation_from_name(std::string_view name)
{
  if (name == "linear") return Interpolation::linear;
  if (name == "monotone-cubic") return Interpolation::monotone_cubic;
  throw std::invalid_argument("unknown interpolation '" + std::string(name) + "'");
}

PeriodicWaveform::PeriodicWaveform(std::vector<double> times, std::vector<double> values,
                                   Interpolation interpolation)
    : times_(std::move(times)), values_(std::move(values)), interpolation_(interpolation)
{
  if (times_.size() != values_.size())
    throw std::invalid_argument("waveform: times and values differ in length");
  if (times_.size() < 2) throw std::invalid_argument("waveform: needs at least 2 points");
  for (std::size_t i = 0; i < times_.size(); ++i) {
    if (!std::isfinite(times_[i]) || !std::isfinite(values_[i]))
      throw std::invalid_argument(fmt::format("waveform: point {} is not finite", i));
    if (i > 0 && !(times_[i] > times_[i - 1]))
      throw std::invalid_argument(fmt::format("waveform: times must increase strictly (point {})", i));
  }
  double largest = 0.0;
  for (double v : values_) largest = std::max(largest, std::abs(v));
  if (std::abs(values_.front() - values_.back()) > 1.0e-9 * std::max(largest, 1.0e-300))
    throw std::invalid_argument(
        "waveform: not periodic: the first and last values differ (the last row must be "
        "the first point one period later)");
  values_.back() = values_.front();
  if (interpolation_ == Interpolation::monotone_cubic) {
    compute_monotone_slopes();
  } else {
    slopes_.resize(times_.size());
    for (std::size_t k = 0; k + 1 < times_.size(); ++k)
      slopes_[k] = (values_[k + 1] - values_[k]) / (times_[k + 1] - times_[k]);
    slopes_.back() = slopes_.front();
  }
}

void PeriodicWaveform::compute_monotone_slopes()
{
  // Fritsch & Carlson (1980): (1) three-point slopes, set to zero at local extrema of the data;
  // (2) on each interval, scale the two end slopes back into the circle alpha^2 + beta^2 <= 9, a
  // sufficient condition for a monotone cubic.
  const std::size_t n = times_.size() - 1; // intervals; point n is point 0 one period later
  std::vector<double> h(n), secant(n);
  for (std::size_t k = 0; k < n; ++k) {
    h[k] = times_[k + 1] - times_[k];
    secant[k] = (values_[k + 1] - values_[k]) / h[k];
  }
  slopes_.assign(n + 1, 0.0);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t before = (k + n - 1) % n; // the interval ending at point k (wraps for k = 0)
    const double d0 = secant[before], d1 = secant[k];
    if (d0 * d1 <= 0.0) continue; // an extremum (or a flat side): zero slope
    // Second-order three-point derivative on a non-uniform grid.
    slopes_[k] = (h[k] * d0 + h[before] * d1) / (h[before] + h[k]);
  }
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t next = (k + 1) % n;
    if (secant[k] == 0.0) {
      slopes_[k] = slopes_[next] = 0.0;
      continue;
    }
    const double alpha = slopes_[k] / secant[k], beta = slopes_[next] / secant[k];
    const double radius2 = alpha * alpha + beta * beta;
    if (radius2 > 9.0) {
      const double tau = 3.0 / std::sqrt(radius2);
      slopes_[k] = tau * alpha * secant[k];
      slopes_[next] = tau * beta * secant[k];
    }
  }
  slopes_[n] = slopes_[0];
}

void PeriodicWaveform::locate(double t, std::size_t& k, double& s) const
{
  const double T = period();
  double local = std::fmod(t - times_.front(), T);
  if (local < 0.0) local += T;
  const double folded = times_.front() + local;
  const auto upper = std::upper_bound(times_.begin(), times_.end(), folded);
  k = static_cast<std::size_t>(std::clamp<std::ptrdiff_t>(upper - times_.begin() - 1, 0,
                                                          static_cast<std::ptrdiff_t>(times_.size()) - 2));
  s = (folded - times_[k]) / (times_[k + 1] - times_[k]);
}

double PeriodicWaveform::value(double t) const
{
  std::size_t k = 0;
  double s = 0.0;
  locate(t, k, s);
  const double y0 = values_[k], y1 = values_[k + 1];
  if (interpolation_ == Interpolation::linear) return y0 + s * (y1 - y0);
  const double h = times_[k + 1] - times_[k];
  // Cubic Hermite basis.
  const double s2 = s * s, s3 = s2 * s;
  return (2 * s3 - 3 * s2 + 1) * y0 + (s3 - 2 * s2 + s) * h * slopes_[k] + (-2 * s3 + 3 * s2) * y1 +
         (s3 - s2) * h * slopes_[k + 1];
}

double PeriodicWaveform::derivative(double t) const
{
  std::size_t k = 0;
  double s = 0.0;
  locate(t, k, s);
  const double h = times_[k + 1] - times_[k];
  const double y0 = values_[k], y1 = values_[k + 1];
  if (interpolation_ == Interpolation::linear) return (y1 - y0) / h;
  const double s2 = s * s;
  return ((6 * s2 - 6 * s) * y0 + (6 * s - 6 * s2) * y1) / h + (3 * s2 - 4 * s + 1) * slopes_[k] +
         (3 * s2 - 2 * s) * slopes_[k + 1];
}

PeriodicWaveform PeriodicWaveform::from_csv(const std::filesystem::path& file, std::string_view time_column,
                                            std::string_view value_column, double value_factor,
                                            Interpolation interpolation)
{
  const io::CsvTable table = io::read_csv(file, true, io::max_input_table_bytes);
  std::vector<double> times = table.values(time_column);
  std::vector<double> values = table.values(value_column);
  for (double& v : values) v *= value_factor;
  try {
    return PeriodicWaveform(std::move(times), std::move(values), interpolation);
  } catch (const std::invalid_argument& error) {
    throw InputError(file.string() + ": " + error.what());
  }
}

} // namespace ibvalve::windkessel
