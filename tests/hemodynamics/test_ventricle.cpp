// The ventricle's figures of a cycle (hemodynamics/ventricle.hpp) on loops whose answers are known: a
// rectangular pressure-volume loop (isovolumic contraction to 100 mmHg, ejection from 120 to 50 mL,
// isovolumic relaxation to 10 mmHg, filling back to 120 mL) has SW = (100 - 10) x 70 mmHg mL exactly
// (its sides are straight, so the trapezoidal rule is exact), EDV 120, ESV 50, SV 70, EF 58.33 %; a
// loop traversed the other way has the opposite work; a compartment that drifts over the cycle has the
// periodicity error of its drift over its swing.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "hemodynamics/metrics.hpp"
#include "hemodynamics/ventricle.hpp"

namespace ibvalve::hemodynamics {
namespace {

/// A series of 401 rows over [0, 0.8] s: the rectangle's corners at 0.1, 0.4, 0.5 s, V_LV and P_LV along
/// it, and p_VEN_SYS rising by `drift` over the cycle on a swing of 2 mmHg.
std::filesystem::path write_loop(const std::string& name, bool reversed, double drift)
{
  const std::filesystem::path file = std::filesystem::temp_directory_path() / (name + "_timeseries.csv");
  std::ofstream out(file);
  out.precision(17); // every digit: the figures below are those of these very samples
  out << "t,Q_valve,P_LV,P_Ao,P_nlv,P_nao,V_LV,p_VEN_SYS\n# units: s,mL/s,mmHg,mmHg,mmHg,mmHg,mL,mmHg\n";
  for (int i = 0; i <= 400; ++i) {
    const double t = 0.002 * i;
    double v = 120.0, p = 10.0;
    if (t <= 0.1) {
      p = 10.0 + 90.0 * t / 0.1; // isovolumic contraction
    } else if (t <= 0.4) {
      p = 100.0;
      v = 120.0 - 70.0 * (t - 0.1) / 0.3; // ejection
    } else if (t <= 0.5) {
      v = 50.0;
      p = 100.0 - 90.0 * (t - 0.4) / 0.1; // isovolumic relaxation
    } else {
      v = 50.0 + 70.0 * (t - 0.5) / 0.3; // filling
    }
    if (reversed) v = 170.0 - v;
    const double venous = 10.0 + std::sin(2.0 * M_PI * t / 0.8) + drift * t / 0.8;
    out << t << ",0," << p << ",80,0,0," << v << "," << venous << "\n";
  }
  return file;
}

double value(const nlohmann::ordered_json& m, const char* key)
{
  return m.at(key).at("value").get<double>();
}

TEST(Ventricle, RectangularLoopHasItsAreaAsStrokeWork)
{
  const auto file = write_loop("ventricle_rectangle", false, 0.0);
  const auto m = ventricle_metrics(file, 0.0, 0.8, 100.0);
  EXPECT_DOUBLE_EQ(value(m, "end_diastolic_volume"), 120.0);
  EXPECT_DOUBLE_EQ(value(m, "end_systolic_volume"), 50.0);
  EXPECT_DOUBLE_EQ(value(m, "stroke_volume"), 70.0);
  EXPECT_NEAR(value(m, "ejection_fraction"), 100.0 * 70.0 / 120.0, 1e-12);
  const double work = 90.0 * 70.0 * mmHg_mL_in_mJ();
  EXPECT_NEAR(value(m, "stroke_work"), work, 1e-9 * work);
  EXPECT_NEAR(value(m, "valve_share_of_stroke_work"), 100.0 * 100.0 / work, 1e-9);
  EXPECT_NEAR(value(m, "periodicity_V_LV"), 0.0, 1e-12);
  EXPECT_NEAR(value(m, "periodicity_p_VEN_SYS"), 0.0, 1e-9);
  std::filesystem::remove(file);
}

TEST(Ventricle, ReversedLoopHasNegativeWorkAndADriftIsItsPeriodicityError)
{
  const auto file = write_loop("ventricle_reversed", true, 0.5);
  const auto m = ventricle_metrics(file, 0.0, 0.8, std::nullopt);
  EXPECT_NEAR(value(m, "stroke_work"), -90.0 * 70.0 * mmHg_mL_in_mJ(), 1e-9);
  EXPECT_TRUE(m.at("valve_share_of_stroke_work").at("value").is_null());
  // p_VEN_SYS: sin over a cycle plus 0.5 mmHg: it ends 0.5 above its start; its swing, the sampled
  // extremes of sin(2 pi t / 0.8) + 0.5 t / 0.8, is found from the same samples.
  double lo = 1e300, hi = -1e300;
  for (int i = 0; i <= 400; ++i) {
    const double t = 0.002 * i, y = std::sin(2.0 * M_PI * t / 0.8) + 0.5 * t / 0.8;
    lo = std::min(lo, y);
    hi = std::max(hi, y);
  }
  EXPECT_NEAR(value(m, "periodicity_p_VEN_SYS"), 0.5 / (hi - lo), 1e-9);
  EXPECT_EQ(m.at("loop_periodicity").at("note").get<std::string>(), "largest: p_VEN_SYS");
  std::filesystem::remove(file);
}

TEST(Ventricle, ARunWithoutTheLoopGetsNothing)
{
  const std::filesystem::path file = std::filesystem::temp_directory_path() / "ventricle_none_timeseries.csv";
  {
    std::ofstream out(file);
    out << "t,Q_valve,P_LV\n0,0,0\n0.4,1,1\n0.8,0,0\n";
  }
  EXPECT_TRUE(ventricle_metrics(file, 0.0, 0.8, 1.0).empty());
  std::filesystem::remove(file);
}

} // namespace
} // namespace ibvalve::hemodynamics
