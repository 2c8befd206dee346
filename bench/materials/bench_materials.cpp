// Throughput of the laws at one material point: P alone and P with dP/dF (what the explicit IB/FE
// step and a Newton solve call at every quadrature point), per law, with the log penalty. Prints
// the median of several repetitions; never passes or fails on time.
//   bench_materials [evaluations per repetition, default 200000]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "base/units.hpp"
#include "materials/expression_law.hpp"
#include "materials/law.hpp"
#include "materials/material.hpp"

using namespace ibvalve;
using namespace ibvalve::materials;

namespace {

template <class Work>
double median_rate(long n, Work&& work)
{
  std::vector<double> rates;
  for (int repetition = 0; repetition < 7; ++repetition) {
    const auto start = std::chrono::steady_clock::now();
    work();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    rates.push_back(static_cast<double>(n) / seconds);
  }
  std::sort(rates.begin(), rates.end());
  return rates[rates.size() / 2];
}

} // namespace

int main(int argc, char** argv)
{
  const long n = argc > 1 ? std::atol(argv[1]) : 200000;
  constexpr double kPa = units::kPa;
  struct Case {
    std::string name;
    LawKind kind;
    std::vector<double> parameters;
    std::string formula; ///< when set, the law written as this formula (parameters in the same order)
  };
  const std::vector<Case> cases{
      {"neo-hookean", LawKind::neo_hookean, {50 * kPa}, ""},
      {"W1", LawKind::W1, {1.21 * kPa, 7.99, 24.23 * kPa, 57.62}, ""},
      {"W2", LawKind::W2, {1.18 * kPa, 55.04 * kPa, 8.08, 54.0}, ""},
      {"W3", LawKind::W3, {19.59 * kPa, 12.94 * kPa, 77.79}, ""},
      {"hgo (kappa 0.226)", LawKind::hgo, {7.64 * kPa, 996.6 * kPa, 524.6, 0.226}, ""},
      // The same W1 written as a formula (docs/materials.md, "Laws written as formulas").
      {"W1 as a formula",
       LawKind::W1,
       {1.21 * kPa, 7.99, 24.23 * kPa, 57.62},
       "C10*(exp(C01*(I1 - 3)) - 1) + k1/(2*k2)*(exp(k2*(I4 - 1)^2) - 1)"},
  };
  // A pool of deformation gradients near the reference (half the fibers stretched, half shortened).
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-0.1, 0.1);
  std::vector<Mat3> Fs(1024);
  for (Mat3& F : Fs) {
    F = Mat3::Identity();
    for (int i = 0; i < 9; ++i) F.data()[i] += u(rng);
  }
  FiberFrame frame;
  frame.f0 = Vec3(1.0, 0.2, 0.0).normalized();
  frame.s0 = Vec3(1.0, -0.2, 0.0).normalized();

  std::printf("materials benchmark: %ld evaluations per repetition, median of 7 (single thread)\n", n);
  std::printf("%-20s %18s %22s %24s\n", "law (+ log penalty)", "P [1e6 /s]", "P + dP/dF [1e6 /s]",
              "ns per P + dP/dF");
  double sink = 0.0;
  for (const auto& c : cases) {
    std::shared_ptr<const StrainEnergy> law;
    if (c.formula.empty()) {
      law = std::make_shared<InvariantLaw>(c.kind, c.parameters);
    } else {
      const auto& info = law_info(c.kind);
      std::vector<ExpressionParameter> parameters;
      for (std::size_t i = 0; i < c.parameters.size(); ++i)
        parameters.push_back({info.parameters[i].name, c.parameters[i], info.parameters[i].is_modulus});
      law = std::make_shared<ExpressionLaw>(c.formula, parameters);
    }
    const Material material(law, VolumetricPenalty(PenaltyKind::log, 1000 * kPa));
    const double stress_rate = median_rate(n, [&] {
      for (long i = 0; i < n; ++i)
        sink += material.stress(Fs[static_cast<std::size_t>(i) & 1023], frame)(0, 0);
    });
    const double tangent_rate = median_rate(n, [&] {
      Mat3 P;
      Tangent T;
      for (long i = 0; i < n; ++i) {
        material.stress_and_tangent(Fs[static_cast<std::size_t>(i) & 1023], frame, P, T);
        sink += T(0, 0);
      }
    });
    std::printf("%-20s %18.2f %22.2f %24.1f\n", c.name.c_str(), stress_rate / 1e6, tangent_rate / 1e6,
                1e9 / tangent_rate);
  }
  std::printf("(checksum %g)\n", sink);
  return 0;
}
