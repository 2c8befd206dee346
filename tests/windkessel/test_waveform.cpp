// Periodic waveform tables: interpolation exactness, periodic folding, monotonicity (no overshoot) and
// C^1 continuity of the Fritsch–Carlson cubic, measured convergence orders, and the CSV reader's
// errors. Also checks the shipped default LV pressure table.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "base/errors.hpp"
#include "base/units.hpp"
#include "windkessel/keys.hpp"
#include "windkessel/waveform.hpp"

namespace wk = ibvalve::windkessel;

namespace {
std::filesystem::path scratch()
{
  const auto dir = std::filesystem::temp_directory_path() / "ibvalve_test_waveform";
  std::filesystem::create_directories(dir);
  return dir;
}
} // namespace

TEST(Waveform, LinearInterpolationIsExactAndFoldsByThePeriod)
{
  const wk::PeriodicWaveform w({0.0, 0.2, 0.5, 0.8}, {1.0, 3.0, -3.0, 1.0}, wk::Interpolation::linear);
  EXPECT_DOUBLE_EQ(w.period(), 0.8);
  EXPECT_DOUBLE_EQ(w(0.1), 2.0);
  EXPECT_NEAR(w(0.35), 0.0, 1e-14);
  EXPECT_NEAR(w(0.1 + 0.8 * 3), 2.0, 1e-12);
  EXPECT_NEAR(w(0.1 - 0.8 * 2), 2.0, 1e-12);
  EXPECT_NEAR(w(0.8), 1.0, 1e-12);
  EXPECT_NEAR(w.derivative(0.6), (1.0 + 3.0) / 0.3, 1e-12);
}

TEST(Waveform, MonotoneCubicInterpolatesWithoutOvershootAndIsC1)
{
  // A step-like table: a cubic spline would overshoot; Fritsch–Carlson must stay within the data
  // range and be monotone on each monotone stretch.
  const std::vector<double> t{0.0, 0.1, 0.2, 0.25, 0.3, 0.5, 0.6, 0.8};
  const std::vector<double> v{5.0, 5.0, 6.0, 100.0, 120.0, 10.0, 5.0, 5.0};
  const wk::PeriodicWaveform w(t, v, wk::Interpolation::monotone_cubic);
  for (std::size_t k = 0; k < t.size(); ++k) EXPECT_NEAR(w(t[k]), v[k], 1e-12);
  double previous = w(0.0);
  for (int i = 1; i <= 8000; ++i) {
    const double s = 0.8 * i / 8000.0;
    const double value = w(s);
    EXPECT_GE(value, 5.0 - 1e-12);
    EXPECT_LE(value, 120.0 + 1e-12);
    if (s > 0.1 && s <= 0.3) {
      EXPECT_GE(value, previous - 1e-12) << s; // rising data
    }
    if (s > 0.3 && s <= 0.6) {
      EXPECT_LE(value, previous + 1e-12) << s; // falling data
    }
    if (s <= 0.1 || s >= 0.6) {
      EXPECT_NEAR(value, 5.0, 1e-12) << s; // flat data stay flat
    }
    previous = value;
  }
  // C^1: the derivative from both sides of each interior point agrees (and across the period's end).
  for (double node : {0.2, 0.25, 0.3, 0.5, 0.8}) {
    const double eps = 1e-9;
    EXPECT_NEAR(w.derivative(node - eps), w.derivative(node + eps),
                1e-4 * (1.0 + std::abs(w.derivative(node))));
  }
}

TEST(Waveform, ConvergenceOrdersOnASmoothPeriodicSignal)
{
  // f(t) = sin(2 pi t / T) + 0.3 cos(6 pi t / T) sampled on n non-uniform points per period. Linear:
  // the maximum error falls with order 2. Monotone cubic: order 3 away from the data's extrema; next
  // to an extremum the limiter sets the slope to zero, which bounds the error by C h^2 with a
  // constant that depends on where the extremum falls between the points, so there the measured
  // figure is the order over the whole refinement (h / 8), not between neighbouring grids.
  const double T = 0.8;
  auto f = [&](double t) {
    return std::sin(2 * std::numbers::pi * t / T) + 0.3 * std::cos(6 * std::numbers::pi * t / T);
  };
  for (auto kind : {wk::Interpolation::linear, wk::Interpolation::monotone_cubic}) {
    std::vector<double> errors, smooth_errors;
    for (int n : {40, 80, 160, 320}) {
      std::vector<double> t, v;
      for (int i = 0; i <= n; ++i) {
        // A smooth non-uniform grid mapped from a uniform one.
        const double u = static_cast<double>(i) / n;
        const double s = T * (u + 0.05 * std::sin(2 * std::numbers::pi * u));
        t.push_back(s);
        v.push_back(f(s));
      }
      v.back() = v.front();
      const wk::PeriodicWaveform w(t, v, kind);
      // Points whose interval or a neighbour's touches a data extremum (sign change of the secants).
      std::vector<bool> near_extremum(t.size(), false);
      for (int i = 1; i < n; ++i)
        if ((v[i] - v[i - 1]) * (v[i + 1] - v[i]) <= 0)
          for (int j = std::max(0, i - 2); j <= std::min(n, i + 2); ++j) near_extremum[j] = true;
      double worst = 0.0, worst_smooth = 0.0;
      for (int i = 0; i < 20000; ++i) {
        const double s = T * i / 20000.0;
        const double error = std::abs(w(s) - f(s));
        worst = std::max(worst, error);
        const auto k = static_cast<std::size_t>(std::upper_bound(t.begin(), t.end(), s) - t.begin() - 1);
        if (!near_extremum[k] && !near_extremum[k + 1]) worst_smooth = std::max(worst_smooth, error);
      }
      errors.push_back(worst);
      smooth_errors.push_back(worst_smooth);
    }
    const char* name = kind == wk::Interpolation::linear ? "linear" : "monotone-cubic";
    if (kind == wk::Interpolation::linear) {
      for (std::size_t i = 1; i < errors.size(); ++i) {
        const double order = std::log2(errors[i - 1] / errors[i]);
        std::cout << "  linear: max error " << errors[i] << ", order " << order << "\n";
        EXPECT_GE(order, 1.9);
      }
    } else {
      for (std::size_t i = 1; i < smooth_errors.size(); ++i) {
        const double order = std::log2(smooth_errors[i - 1] / smooth_errors[i]);
        std::cout << "  " << name << " away from extrema: max error " << smooth_errors[i] << ", order "
                  << order << "\n";
        EXPECT_GE(order, 2.8);
      }
      const double overall = std::log2(errors.front() / errors.back()) / 3.0;
      std::cout << "  " << name << " overall: max error " << errors.front() << " -> " << errors.back()
                << ", mean order " << overall << "\n";
      EXPECT_GE(overall, 1.9);
    }
  }
}

TEST(Waveform, BadTablesAreInputErrors)
{
  const auto dir = scratch();
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return dir / name;
  };
  const double f = ibvalve::units::mmHg;
  const auto good = write("good.csv", "time,pressure\n0,5\n0.4,120\n0.8,5\n");
  const auto w = wk::PeriodicWaveform::from_csv(good, "time", "pressure", f, wk::Interpolation::linear);
  EXPECT_NEAR(w(0.2), 62.5 * f, 1e-9);
  EXPECT_THROW(wk::PeriodicWaveform::from_csv(good, "time", "P", f, wk::Interpolation::linear),
               ibvalve::InputError);
  EXPECT_THROW(wk::PeriodicWaveform::from_csv(write("bad.csv", "time,pressure\n0,5\n0.4,abc\n0.8,5\n"),
                                              "time", "pressure", f, wk::Interpolation::linear),
               ibvalve::InputError);
  EXPECT_THROW(wk::PeriodicWaveform::from_csv(write("order.csv", "time,pressure\n0,5\n0.4,7\n0.3,5\n"),
                                              "time", "pressure", f, wk::Interpolation::linear),
               ibvalve::InputError);
  EXPECT_THROW(wk::PeriodicWaveform::from_csv(write("open.csv", "time,pressure\n0,5\n0.4,120\n0.8,6\n"),
                                              "time", "pressure", f, wk::Interpolation::linear),
               ibvalve::InputError);
  EXPECT_THROW(
      wk::PeriodicWaveform::from_csv(dir / "missing.csv", "time", "pressure", f, wk::Interpolation::linear),
      ibvalve::InputError);
  std::filesystem::remove_all(dir);
}

TEST(Waveform, TheDefaultLvPressureTableIsPhysiological)
{
  const auto file = std::filesystem::path(IBVALVE_SOURCE_DIR) / "examples/waveforms/lv_pressure.csv";
  const auto w =
      wk::PeriodicWaveform::from_csv(file, "time", "pressure", 1.0, wk::Interpolation::monotone_cubic);
  EXPECT_NEAR(w.period(), 0.8, 1e-12);
  double peak = -1e9, low = 1e9, t_peak = 0;
  for (int i = 0; i < 8000; ++i) {
    const double t = 0.8 * i / 8000;
    if (w(t) > peak) {
      peak = w(t);
      t_peak = t;
    }
    low = std::min(low, w(t));
  }
  std::cout << "  default LV table: peak " << peak << " mmHg at " << t_peak << " s, minimum " << low
            << " mmHg\n";
  EXPECT_NEAR(peak, 120.0, 3.0);
  EXPECT_GT(t_peak, 0.1);
  EXPECT_LT(t_peak, 0.35);
  EXPECT_GT(low, 0.0);
  EXPECT_LT(low, 12.0);
}

// The default of examples/lumped: an elastance beat, end-diastolic about 8 mmHg at t = 0,
// a systolic peak of about 125 mmHg in early-to-mid systole (docs/windkessel.md), a few mmHg in diastole.
TEST(Waveform, TheTypeALvPressureTableIsPhysiological)
{
  const auto file = std::filesystem::path(IBVALVE_SOURCE_DIR) / "examples/waveforms/lv_pressure_typeA.csv";
  const auto w =
      wk::PeriodicWaveform::from_csv(file, "time", "pressure", 1.0, wk::Interpolation::monotone_cubic);
  EXPECT_NEAR(w.period(), 0.8, 1e-12);
  double peak = -1e9, low = 1e9, t_peak = 0;
  for (int i = 0; i < 8000; ++i) {
    const double t = 0.8 * i / 8000;
    if (w(t) > peak) {
      peak = w(t);
      t_peak = t;
    }
    low = std::min(low, w(t));
  }
  std::cout << "  Type A LV table: " << w(0.0) << " mmHg at t = 0, peak " << peak << " mmHg at " << t_peak
            << " s, minimum " << low << " mmHg\n";
  EXPECT_NEAR(w(0.0), 8.0, 2.0);
  EXPECT_NEAR(peak, 125.0, 5.0);
  EXPECT_GT(t_peak, 0.1);
  EXPECT_LT(t_peak, 0.25);
  EXPECT_GT(low, 2.0);
  EXPECT_LT(low, 8.0);
  // Flat across the period end: the pressure just before and after t = 0 differs by under 0.1 mmHg.
  EXPECT_LT(std::abs(w(0.799) - w(0.001)), 0.1);
}

TEST(Waveform, CaseKeysNameTheTableRelativeToTheCaseFile)
{
  const auto dir = scratch();
  std::ofstream(dir / "p.csv") << "# a comment\nseconds,kPa\n0,1\n0.5,2\n1.0,1\n";
  std::ofstream(dir / "case.toml")
      << "[drive]\nfile = \"p.csv\"\ntime_column = \"seconds\"\nvalue_column = \"kPa\"\n"
         "interpolation = \"linear\"\n";
  ibvalve::io::Schema schema;
  {
    ibvalve::io::KeyBinder declaring(schema);
    wk::WaveformKeys unused;
    wk::bind(declaring, unused, "drive", "a test waveform");
  }
  const ibvalve::io::Config config = ibvalve::io::Config::load(dir / "case.toml", schema);
  ibvalve::io::KeyBinder keys(config);
  wk::WaveformKeys k;
  wk::bind(keys, k, "drive", "a test waveform");
  const auto w = wk::load_waveform(k, ibvalve::units::kPa);
  EXPECT_NEAR(w.period(), 1.0, 1e-15);
  EXPECT_NEAR(w(0.25), 1.5 * ibvalve::units::kPa, 1e-9);
  std::ofstream(dir / "case.toml") << "[drive]\nfile = \"missing.csv\"\n";
  EXPECT_THROW(ibvalve::io::Config::load(dir / "case.toml", schema), ibvalve::InputError);
  std::ofstream(dir / "case.toml") << "[drive]\nfile = \"p.csv\"\ninterpolation = \"spline\"\n";
  EXPECT_THROW(ibvalve::io::Config::load(dir / "case.toml", schema), ibvalve::InputError);
  std::filesystem::remove_all(dir);
}
