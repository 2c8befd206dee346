// The three-element Windkessel against its closed-form solutions: exact exponential approach under a
// constant inflow, steady sinusoidal response equal to the analytic input impedance, second-order
// convergence, stability for any time step; the preset and the case-file keys.
#include <cmath>
#include <complex>
#include <fstream>
#include <iostream>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "base/errors.hpp"
#include "base/units.hpp"
#include "windkessel/keys.hpp"
#include "windkessel/windkessel.hpp"

namespace wk = ibvalve::windkessel;
namespace units = ibvalve::units;

namespace {

wk::WindkesselParameters study_parameters()
{
  return *wk::preset("stergiopulos-typeA");
}

/// P_Wk(t) for Q = q_mean + q_amp sin(omega t), from P_Wk(0) = p0 (variation of constants).
double exact_sinusoidal(const wk::WindkesselParameters& p, double q_mean, double q_amp, double omega,
                        double p0, double t)
{
  const double tau = p.time_constant();
  const double a = q_amp * p.distal_resistance / (1.0 + omega * omega * tau * tau);
  auto particular = [&](double s) {
    return p.distal_pressure + p.distal_resistance * q_mean +
           a * (std::sin(omega * s) - omega * tau * std::cos(omega * s));
  };
  return particular(t) + (p0 - particular(0.0)) * std::exp(-t / tau);
}

} // namespace

TEST(Windkessel, PresetIsTheStudysTypeABeatInCgs)
{
  const auto p = study_parameters();
  EXPECT_NEAR(p.proximal_resistance, 0.033 * 1333.22, 1e-9);
  EXPECT_NEAR(p.distal_resistance, 0.79 * 1333.22, 1e-9);
  EXPECT_NEAR(p.compliance, 1.75 / 1333.22, 1e-15);
  EXPECT_EQ(p.distal_pressure, 0.0);
  EXPECT_NEAR(p.initial_pressure, 85.0 * 1333.22, 1e-9);
  EXPECT_NEAR(p.time_constant(), 0.79 * 1.75, 1e-12); // R_p C in seconds, unit-free check
  EXPECT_FALSE(wk::preset("no-such-preset"));
  // P_Ao(0) = P_Wk(0) (docs/reference.md, "Boundary conditions"): no flow before the first step by default.
  wk::ThreeElementWindkessel w(p);
  EXPECT_DOUBLE_EQ(w.outlet_pressure(), p.initial_pressure);
}

TEST(Windkessel, ConstantInflowGivesTheExactExponentialForAnyTimeStep)
{
  auto p = study_parameters();
  p.distal_pressure = 5.0 * units::mmHg;
  const double q = 90.0; // mL/s
  const double tau = p.time_constant();
  for (double dt : {1.0e-4, 0.01, 0.3 * tau, 2.0 * tau}) {
    wk::ThreeElementWindkessel w(p);
    double worst = 0.0;
    for (int n = 1; n * dt <= 4.0 * tau + 1e-12; ++n) {
      const double p_ao = w.advance(dt, q, q);
      const double t = n * dt;
      const double exact =
          p.distal_pressure + p.distal_resistance * q +
          (p.initial_pressure - p.distal_pressure - p.distal_resistance * q) * std::exp(-t / tau);
      worst = std::max(worst, std::abs(w.reservoir_pressure() - exact) / exact);
      EXPECT_NEAR(p_ao, w.reservoir_pressure() + p.proximal_resistance * q, 1e-9 * p_ao);
    }
    EXPECT_LT(worst, 1e-12) << "dt = " << dt;
  }
}

TEST(Windkessel, SinusoidalInflowReachesTheAnalyticImpedance)
{
  // Steady state of P_Ao for Q = Q_m + Q_a sin(omega t): amplitude |Z| Q_a and phase arg Z with
  // Z(omega) = R_c + R_p / (1 + i omega R_p C), mean R_p Q_m. Measured by projecting the last
  // period onto sin and cos (exact for a periodic signal sampled uniformly over whole periods).
  const auto p = study_parameters();
  const double period = 0.8, omega = 2.0 * std::numbers::pi / period;
  const double q_mean = 80.0, q_amp = 150.0;
  const std::complex<double> z =
      p.proximal_resistance + p.distal_resistance / std::complex<double>(1.0, omega * p.time_constant());
  for (int steps_per_period : {800, 8000}) {
    const double dt = period / steps_per_period;
    auto q = [&](double t) { return q_mean + q_amp * std::sin(omega * t); };
    wk::ThreeElementWindkessel w(p, 0.0, q(0.0));
    const int periods = 40; // 32 s = 23 time constants: the transient is below 1e-10
    double sum_sin = 0, sum_cos = 0, sum = 0;
    for (int n = 0; n < periods * steps_per_period; ++n) {
      const double t1 = (n + 1) * dt;
      const double p_ao = w.advance(dt, q(t1));
      if (n >= (periods - 1) * steps_per_period) {
        sum += p_ao;
        sum_sin += p_ao * std::sin(omega * t1);
        sum_cos += p_ao * std::cos(omega * t1);
      }
    }
    const double mean = sum / steps_per_period;
    const std::complex<double> response(2.0 * sum_sin / steps_per_period, 2.0 * sum_cos / steps_per_period);
    // P_Ao ~ Re(Z Q_a e^{i omega t}) rotated: response = (in-phase, quadrature) = Q_a |Z| (cos phi, sin phi).
    const double amplitude = std::abs(response), phase = std::atan2(response.imag(), response.real());
    EXPECT_NEAR(mean / ((p.distal_resistance + p.proximal_resistance) * q_mean), 1.0, 1e-4)
        << steps_per_period;
    EXPECT_NEAR(amplitude / (std::abs(z) * q_amp), 1.0, 1e-4) << steps_per_period;
    EXPECT_NEAR(phase, std::arg(z), 1e-4) << steps_per_period;
    std::cout << "  " << steps_per_period << " steps/period: amplitude rel. error "
              << amplitude / (std::abs(z) * q_amp) - 1.0 << ", phase error " << phase - std::arg(z)
              << " rad\n";
  }
}

TEST(Windkessel, ObservedOrderIsTwo)
{
  const auto p = study_parameters();
  const double omega = 2.0 * std::numbers::pi / 0.8;
  const double q_mean = 80.0, q_amp = 150.0, t_end = 1.0;
  std::vector<double> errors;
  for (int n : {25, 50, 100, 200, 400}) {
    const double dt = t_end / n;
    wk::ThreeElementWindkessel w(p, 0.0, q_mean); // Q(0) = q_mean
    for (int i = 1; i <= n; ++i) w.advance(dt, q_mean + q_amp * std::sin(omega * i * dt));
    errors.push_back(std::abs(w.reservoir_pressure() -
                              exact_sinusoidal(p, q_mean, q_amp, omega, p.initial_pressure, t_end)));
  }
  for (std::size_t i = 1; i < errors.size(); ++i) {
    const double order = std::log2(errors[i - 1] / errors[i]);
    std::cout << "  error " << errors[i] / units::mmHg << " mmHg, observed order " << order << "\n";
    EXPECT_GE(order, 1.9);
    EXPECT_LE(order, 2.1);
  }
}

TEST(Windkessel, StableAndConsistentForHugeSteps)
{
  const auto p = study_parameters();
  wk::ThreeElementWindkessel w(p);
  const double q = 50.0;
  for (int i = 0; i < 10; ++i) w.advance(100.0 * p.time_constant(), q);
  EXPECT_NEAR(w.reservoir_pressure(), p.distal_resistance * q, 1e-9 * p.distal_resistance * q);
  // The state can be restored exactly (predictor-corrector couplings, checkpoints).
  const wk::WindkesselState saved = w.state();
  const double predicted = w.reservoir_pressure_after(1e-3, q, 2 * q);
  w.advance(1e-3, 2 * q);
  EXPECT_DOUBLE_EQ(w.reservoir_pressure(), predicted);
  w.restore(saved);
  EXPECT_DOUBLE_EQ(w.reservoir_pressure(), saved.reservoir_pressure);
  // The ODE's right-hand side agrees with a small exact step.
  const double rate = w.reservoir_rate(w.reservoir_pressure(), 2 * q);
  const double h = 1e-6;
  EXPECT_NEAR((w.reservoir_pressure_after(h, 2 * q, 2 * q) - w.reservoir_pressure()) / h, rate,
              1e-5 * std::abs(rate));
}

TEST(Windkessel, CaseKeysInUserUnitsOverrideThePreset)
{
  ibvalve::io::Schema schema;
  {
    ibvalve::io::KeyBinder declaring(schema);
    wk::WindkesselKeys unused;
    wk::bind(declaring, unused, "windkessel");
  }
  // The parameters a case gives, each over the preset's, checked as a model that uses them checks them.
  const auto parameters = [&](const std::filesystem::path& file) {
    const ibvalve::io::Config config = ibvalve::io::Config::load(file, schema);
    ibvalve::io::KeyBinder keys(config);
    wk::WindkesselKeys k;
    wk::bind(keys, k, "windkessel");
    wk::check(keys, k);
    return k.parameters;
  };
  const auto dir = std::filesystem::temp_directory_path() / "ibvalve_test_windkessel";
  std::filesystem::create_directories(dir);
  const auto file = dir / "case.toml";
  {
    std::ofstream out(file);
    out << "[windkessel]\ncompliance = 2.0\ninitial_pressure = 80\n";
  }
  auto p = parameters(file);
  EXPECT_NEAR(p.compliance, 2.0 / units::mmHg, 1e-15);
  EXPECT_NEAR(p.initial_pressure, 80.0 * units::mmHg, 1e-9);
  EXPECT_NEAR(p.distal_resistance, 0.79 * units::mmHg, 1e-9);
  {
    std::ofstream out(file);
    out << "[windkessel]\npreset = \"none\"\ncompliance = 2.0\n";
  }
  EXPECT_THROW(parameters(file), ibvalve::InputError);
  {
    std::ofstream out(file);
    out << "[windkessel]\ncompliance = -1.0\n";
  }
  EXPECT_THROW(ibvalve::io::Config::load(file, schema), ibvalve::InputError);
  std::filesystem::remove_all(dir);
}

TEST(Windkessel, ABoundTableReadsWhatIsGivenAndCheckNamesTheFirstParameterMissing)
{
  ibvalve::io::Schema schema;
  {
    ibvalve::io::KeyBinder declaring(schema);
    wk::WindkesselKeys unused;
    wk::bind(declaring, unused, "outlet");
  }
  const auto dir = std::filesystem::temp_directory_path() / "ibvalve_test_windkessel_bind";
  std::filesystem::create_directories(dir);
  const auto file = dir / "case.toml";
  std::ofstream(file) << "[outlet]\npreset = \"none\"\ncompliance = 2.0\n";
  const ibvalve::io::Config config = ibvalve::io::Config::load(file, schema);
  ibvalve::io::KeyBinder keys(config);
  wk::WindkesselKeys k;
  wk::bind(keys, k, "outlet"); // binding alone asks for nothing: a model may use the table in one mode only
  EXPECT_NEAR(k.parameters.compliance, 2.0 / units::mmHg, 1e-15);
  try {
    wk::check(keys, k);
    ADD_FAILURE() << "no parameter reported missing";
  } catch (const ibvalve::InputError& e) {
    EXPECT_EQ(std::string(e.what()), file.string() +
                                         ": outlet.proximal_resistance: missing (no preset given: set "
                                         "outlet.preset or this key)");
  }
  std::ofstream(file) << "[outlet]\ncompliance = 2.0\n";
  const ibvalve::io::Config with_preset = ibvalve::io::Config::load(file, schema);
  ibvalve::io::KeyBinder preset_keys(with_preset);
  wk::WindkesselKeys p;
  wk::bind(preset_keys, p, "outlet");
  EXPECT_NO_THROW(wk::check(preset_keys, p));
  EXPECT_NEAR(p.parameters.distal_resistance, 0.79 * units::mmHg, 1e-9);
  std::filesystem::remove_all(dir);
}
