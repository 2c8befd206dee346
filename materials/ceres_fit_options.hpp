#pragma once
// The least-squares solver's settings every constitutive fit takes (materials/fitting.cpp,
// materials/expression_fitting.cpp): a dense QR for a handful of parameters, tolerances at round-off
// so that a fit stops at its minimum and not at a tolerance, silent.
#include <ceres/ceres.h>

namespace ibvalve::materials {

inline ceres::Solver::Options fit_solver_options(int max_iterations)
{
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_QR;
  solver.max_num_iterations = max_iterations;
  solver.function_tolerance = 1e-16;
  solver.gradient_tolerance = 1e-16;
  solver.parameter_tolerance = 1e-14;
  solver.logging_type = ceres::SILENT;
  solver.minimizer_progress_to_stdout = false;
  return solver;
}

} // namespace ibvalve::materials
