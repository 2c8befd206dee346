#pragma once
// The exact pressure Poisson solve K phi = r by transforms on a box whose z sides are traction sides
// walled in part (the valve case's inlet and outlet: the pressure in a lumen disk, a no-slip wall
// around it; fluid/boundary.hpp).
//
// The transforms diagonalise K0, the operator with the whole side a traction side (Dirichlet for the
// pressure: the one-sided gradient (p_0 - p_b)/(h/2) adds 2/h^2 to the first cell's diagonal). On a
// walled face G has no row (the normal velocity is fixed), so there K is closed by the homogeneous
// Neumann condition instead, and
//
//   K = K0 - a U U^T,  a = 2 / h_z^2,
//
// U the columns of the identity at the cells next to the walled faces. The Sherman-Morrison-Woodbury
// identity, in the capacitance-matrix form of Buzbee, Dorr, George & Golub (1971, SIAM J. Numer. Anal.
// 8:722, "The direct solution of the discrete Poisson equation on irregular regions"), gives
//
//   phi = K0^-1 (r + U s),  C s = U^T K0^-1 r,  C = (1/a) I - U^T K0^-1 U,
//
// two transform solves and one solve with the capacitance matrix C, whose size is the number of walled
// boundary cells. C is symmetric positive definite when K is (some face of the box carries a traction),
// and applying U^T K0^-1 U needs only the two boundary planes: K0 is separable, so in the transform
// basis of x and y each coefficient (kx, ky) couples the planes z = 0 and z = N-1 through the 2x2 end
// block of the inverse of the tridiagonal 1-D operator along z, (T + mu I)^-1 with mu = lambda_x(kx) +
// lambda_y(ky). So C is applied by 2-D transforms of the planes and solved by conjugate gradients,
// replicated on every rank (the planes are small; every rank computes the same s, so 1 and 2 ranks give
// the same answer).
//
// Walled parts along x or y are not corrected (the transform solve then stays a preconditioner only,
// and FGMRES takes a few more iterations); the valve case walls its z sides only.
#include <array>
#include <memory>
#include <vector>

#include <fftw3.h>
#include <mpi.h>

#include "fluid/boundary.hpp"
#include "fluid/fftw_handles.hpp"
#include "fluid/grid.hpp"
#include "fluid/transform_solver.hpp"

namespace ibvalve::fluid {

class WalledSideCapacitance {
 public:
  /// Null when no z side is a traction side walled in part (the transform solve is exact as it is).
  /// `poisson` is the pressure transform solver of the grid's cells (K0).
  static std::unique_ptr<WalledSideCapacitance> make(const StaggeredGrid& grid, const BoundaryConditions& bc,
                                                     const SeparableTransformSolver& poisson);
  WalledSideCapacitance(const StaggeredGrid& grid, const SeparableTransformSolver& poisson,
                        std::array<std::vector<double>, 2> walled);
  WalledSideCapacitance(const WalledSideCapacitance&) = delete;
  WalledSideCapacitance& operator=(const WalledSideCapacitance&) = delete;

  /// Replaces r in `poisson`'s slab by phi = K^-1 r. Collective.
  void solve(SeparableTransformSolver& poisson);

  /// Conjugate-gradient iterations of the last capacitance solve.
  int last_iterations() const { return last_iterations_; }
  /// Walled boundary cells (the size of C).
  std::size_t size() const { return walled_count_; }

 private:
  void apply_capacitance(const std::vector<double>& v, std::vector<double>& out);
  /// v -> U^T K0^-1 U v on the corrected planes (v zero off the walled cells).
  void apply_plane_green(const std::vector<double>& v, std::vector<double>& out);
  /// Corrected plane p in `poisson`'s local slab, or null where another rank holds it.
  double* slab_plane(SeparableTransformSolver& poisson, std::size_t p) const;

  MPI_Comm comm_;
  std::ptrdiff_t nx_ = 0, ny_ = 0, nz_ = 0;
  std::vector<int> planes_;  // the corrected ends: 0 (z = 0), 1 (z = N-1)
  std::vector<double> mask_; // 1 at the walled cells of each corrected plane, planes_.size() planes
  std::size_t walled_count_ = 0;
  double a_ = 0.0;                              // 2 / h_z^2
  double normalisation_ = 1.0;                  // of the x and y transform pairs
  std::vector<double> g00_, g01_, g11_;         // per (kx, ky): the end block of (T + mu I)^-1
  std::vector<double> rhs_, g_, s_, r_, p_, q_; // slab copy of r; CG vectors on the planes
  FftwBuffer buffer_;                           // the planes for the 2-D transforms
  FftwPlan forward_, backward_;
  int last_iterations_ = 0;
};

} // namespace ibvalve::fluid
