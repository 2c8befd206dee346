#pragma once
// Fitting a law's parameters to planar biaxial data (docs/reference.md, "Constitutive fitting").
//
// Data: one CSV file per sample with the columns (any order, more columns ignored, '#' comments)
//   lambda1, lambda2, sigma11_kPa, sigma22_kPa
// (stretches along the fiber and cross-fiber axes, measured Cauchy stresses in kPa).
// Fit: minimise sum_i (sigma11_model - sigma11_exp)^2 + (sigma22_model - sigma22_exp)^2 over the
// law's parameters, all >= 0 (kappa <= 1/3), with Ceres' bounded Levenberg–Marquardt and automatic
// derivatives through the same kernels the finite elements use (law_kernels.hpp).
// Starting values: every law here is linear in its moduli once its exponents are fixed, so on a
// log-spaced grid of the exponents the moduli are found by non-negative linear least squares
// (exactly), and the best few grid points start full nonlinear solves (multi-start); the best end
// point wins. Quality: MAE = mean |model - data| over all 2N stresses (kPa) and
// R^2 = 1 - SSE/SST with SST about the mean of all 2N measured stresses.
#include <array>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "materials/biaxial.hpp"

namespace ibvalve::materials {

struct BiaxialPoint {
  double lambda1 = 1.0, lambda2 = 1.0;
  double sigma11 = 0.0, sigma22 = 0.0; ///< kPa
};

struct BiaxialSample {
  std::string name; ///< the file name, for reports
  std::vector<BiaxialPoint> points;
};

/// Reads one sample; any problem throws InputError "file:line: message".
BiaxialSample read_biaxial_csv(const std::filesystem::path& file);

struct FitQuality {
  double mae = 0.0;       ///< kPa
  double r_squared = 0.0; ///< 1 - SSE/SST
  double sse = 0.0;       ///< kPa^2
};

/// The model's stresses for `parameters` (user units: kPa moduli) against the sample.
FitQuality fit_quality(const BiaxialSample& sample, const BiaxialSetup& setup,
                       std::span<const double> parameters);

/// The same for any model of the stresses: `model(point)` = (sigma11, sigma22) in kPa.
FitQuality fit_quality(const BiaxialSample& sample,
                       const std::function<std::array<double, 2>(const BiaxialPoint&)>& model);

/// The same for any law, through its 3-D stress (biaxial_cauchy_through_stress) with fibers `frame`.
FitQuality fit_quality(const BiaxialSample& sample, const StrainEnergy& law, const FiberFrame& frame);

struct FitOptions {
  BiaxialSetup setup;
  int starts = 4;            ///< nonlinear solves from the best grid points
  int max_iterations = 1000; ///< per solve
};

struct FitResult {
  std::vector<double> parameters; ///< user units: kPa for moduli
  FitQuality quality;
  int solves = 0;         ///< nonlinear solves run
  bool converged = false; ///< the best solve ended on a convergence criterion
};

FitResult fit_biaxial(const BiaxialSample& sample, const FitOptions& options);

} // namespace ibvalve::materials
