#pragma once
// When Jacobi is enough: for a matrix A whose diagonal dominates, one Jacobi sweep multiplies the error
// by at most q = max_i sum_{j != i} |A_ij| / |A_ii| (the infinity norm of I - D^{-1} A). The viscous
// (Helmholtz) matrix rho/dt - mu/2 L has q = mu sum_e h_e^-2 / (rho/dt + mu sum_e h_e^-2) on its interior
// rows: 1.5e-4 in the default valve case, 6e-5 on the study's grid. Both fluid solvers then invert it
// with Jacobi (sweeps, or as GMRES's preconditioner) instead of transforms or BoomerAMG (docs/fluid.md,
// docs/nested.md).
#include <petscmat.h>

namespace ibvalve::fluid {

/// q at most this: Jacobi for the viscous solve (two sweeps leave q^2 = 1e-6 of the error).
constexpr double jacobi_ratio_limit = 1e-3;

/// q of an assembled matrix, the largest over all ranks' rows (collective).
double jacobi_ratio(Mat a);

} // namespace ibvalve::fluid
