#pragma once
// Driving waveforms: a table of (time, value) points repeated with its period, read from CSV.
//
// The table's first and last rows are the two ends of one period (t_0 and t_0 + T) and must carry the
// same value, so the repeated waveform is continuous. Between points it is interpolated linearly or by
// the monotone piecewise-cubic Hermite interpolant of Fritsch & Carlson (1980), SIAM J. Numer. Anal.
// 17:238, which is C^1, adds no overshoot (the interpolant is monotone wherever the data are) and, on
// a periodic table, takes its end slopes from the wrapped-around neighbours.
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace ibvalve::windkessel {

enum class Interpolation { linear, monotone_cubic };

/// "linear" or "monotone-cubic"; std::invalid_argument for anything else.
Interpolation interpolation_from_name(std::string_view name);

class PeriodicWaveform {
 public:
  /// `times` strictly increasing (at least 2 points), values.front() == values.back() (to 1e-9 of the
  /// largest |value|); std::invalid_argument otherwise.
  PeriodicWaveform(std::vector<double> times, std::vector<double> values, Interpolation interpolation);

  /// Reads the columns `time_column` (s) and `value_column` from a CSV file with a header; values are
  /// multiplied by `value_factor` (e.g. units::mmHg for a table in mmHg). Bad input (missing file,
  /// missing column, a malformed line, times not increasing, not periodic) is an InputError.
  static PeriodicWaveform from_csv(const std::filesystem::path& file, std::string_view time_column,
                                   std::string_view value_column, double value_factor,
                                   Interpolation interpolation);

  double operator()(double t) const { return value(t); }
  double value(double t) const;
  double derivative(double t) const;
  double period() const { return times_.back() - times_.front(); }
  double start_time() const { return times_.front(); }
  const std::vector<double>& times() const { return times_; }
  const std::vector<double>& values() const { return values_; }
  /// Hermite slopes at the points (monotone cubic); the secants' slopes are used for linear.
  const std::vector<double>& slopes() const { return slopes_; }

 private:
  /// The interval k and the local coordinate s in [0, 1) of time t folded into the first period.
  void locate(double t, std::size_t& k, double& s) const;
  void compute_monotone_slopes();

  std::vector<double> times_;
  std::vector<double> values_;
  std::vector<double> slopes_;
  Interpolation interpolation_;
};

} // namespace ibvalve::windkessel
