#pragma once
// Exact solver for separable constant-coefficient problems (a I - b L) x = f on a box of unknowns,
// L = sum over x, y, z of the 1-D second difference (x_{j-1} - 2 x_j + x_{j+1}) / h^2 closed at each
// end by a periodic, Dirichlet or Neumann condition, by FFTW real-to-real transforms (FFTW-MPI,
// slabs in z). Each 1-D closure is diagonalised by one of the trigonometric transforms (Strang 1999,
// SIAM Rev. 41:135, "The discrete cosine transform", which lists all sixteen and their boundary
// conditions; Schumann & Sweet 1988, JCP 75:123 for the staggered-grid Poisson case). On one rank
// the transforms are FFTW's serial ones (the slab is the whole box):
//
//   unknowns at     ends            forward / backward (FFTW kinds)   eigenvalue of -d2 (times h^2/4)
//   cell centres    Neumann-Neumann REDFT10 / REDFT01 (DCT-II/III)     sin^2(pi k / 2n)
//                   Dirichlet-Dir.  RODFT10 / RODFT01 (DST-II/III)     sin^2(pi (k+1) / 2n)
//                   Neumann-Dir.    REDFT11 (DCT-IV, self-inverse)     sin^2(pi (k+1/2) / 2n)
//                   Dir.-Neumann    RODFT11 (DST-IV, self-inverse)     sin^2(pi (k+1/2) / 2n)
//   nodes 0..N      Dirichlet-Dir.  RODFT00 (DST-I) on nodes 1..N-1    sin^2(pi (k+1) / 2(n+1))
//                   Neumann-Neumann REDFT00 (DCT-I) on nodes 0..N      sin^2(pi k / 2(n-1))
//                   Dir.-Neumann    RODFT01 / RODFT10 on nodes 1..N    sin^2(pi (k+1/2) / 2n)
//                   Neumann-Dir.    REDFT01 / REDFT10 on nodes 0..N-1  sin^2(pi (k+1/2) / 2n)
//   periodic        (either)        R2HC / HC2R                        sin^2(pi k / n)
//
// "Dirichlet" is homogeneous and odd about the end (the end node itself, or the face half a cell
// beyond the last centre); "Neumann" is even about it. The backward transform of the forward one is
// the identity times 2n (n for periodic; 2(n+1) for DST-I, 2(n-1) for DCT-I), so the solve is
// forward, divide each coefficient by (a + b sum of eigenvalues) times the normalisations, backward.
#include <array>
#include <cstddef>
#include <vector>

#include <fftw3-mpi.h>

#include "fluid/fftw_handles.hpp"

namespace ibvalve::fluid {

enum class EndCondition { periodic, dirichlet, neumann };
/// Where the unknowns of a direction sit: cell centres (each end is half a cell beyond the outer
/// centre) or the nodes 0..cells (each end is a node: a Dirichlet end node is not an unknown).
enum class Placement { cell, node };

/// One direction of a separable problem: which grid points are unknowns, the transform pair that
/// diagonalises the closed second difference, and its eigenvalues.
struct TransformAxis {
  static TransformAxis make(Placement placement, EndCondition lower, EndCondition upper, std::ptrdiff_t cells,
                            double h);
  std::ptrdiff_t unknowns = 0; // n
  std::ptrdiff_t first = 0;    // grid index (cell or node) of unknown 0
  fftw_r2r_kind forward = FFTW_R2HC, backward = FFTW_HC2R;
  double normalisation = 1.0;      // backward(forward(x)) = normalisation x
  std::vector<double> eigenvalues; // of minus the closed second difference, >= 0, per coefficient
};

class SeparableTransformSolver {
 public:
  /// `axes` in x, y, z order. Collective on `comm`; z is split over its ranks in FFTW's blocks.
  SeparableTransformSolver(MPI_Comm comm, const std::array<TransformAxis, 3>& axes);
  SeparableTransformSolver(const SeparableTransformSolver&) = delete;
  SeparableTransformSolver& operator=(const SeparableTransformSolver&) = delete;

  /// Replaces f in data() by the solution x of (a I - b L) x = f. A coefficient whose factor
  /// a + b lambda is zero (the constant when a = 0 and no end is Dirichlet) is set to zero, which
  /// gives the zero-mean solution; f must then have zero mean for x to solve the system.
  void solve(double a, double b);

  /// The local slab of f / x: z_count() planes from z_begin(), each unknowns(1) rows of unknowns(0)
  /// values (x fastest).
  double* data() const { return data_.get(); }
  std::ptrdiff_t local_size() const { return local_n0_ * axes_[1].unknowns * axes_[0].unknowns; }
  std::ptrdiff_t z_begin() const { return local_0_start_; }
  std::ptrdiff_t z_count() const { return local_n0_; }
  const TransformAxis& axis(int d) const { return axes_[d]; }

 private:
  std::array<TransformAxis, 3> axes_;
  std::ptrdiff_t local_n0_ = 0, local_0_start_ = 0, local_n1_ = 0, local_1_start_ = 0;
  FftwBuffer data_;
  bool transposed_ = false; // coefficients in FFTW-MPI's transposed layout (more than one rank)
  FftwPlan forward_, backward_;
};

} // namespace ibvalve::fluid
