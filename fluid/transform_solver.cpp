#include "fluid/transform_solver.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "fluid/fft_stokes.hpp"

namespace ibvalve::fluid {

TransformAxis TransformAxis::make(Placement placement, EndCondition lower, EndCondition upper,
                                  std::ptrdiff_t cells, double h)
{
  if ((lower == EndCondition::periodic) != (upper == EndCondition::periodic))
    throw std::invalid_argument("transform solver: a periodic direction is periodic at both ends");
  if (cells < 2) throw std::invalid_argument("transform solver: at least 2 cells per direction");
  TransformAxis axis;
  // Eigenvalue k of minus the second difference: (4/h^2) sin^2(pi (k + shift) / period).
  double shift = 0.0, period = 0.0;
  const bool dirichlet_lower = lower == EndCondition::dirichlet,
             dirichlet_upper = upper == EndCondition::dirichlet;
  if (lower == EndCondition::periodic) {
    axis.unknowns = cells;
    axis.forward = FFTW_R2HC;
    axis.backward = FFTW_HC2R;
    axis.normalisation = static_cast<double>(cells);
    period = static_cast<double>(cells);
  } else if (placement == Placement::cell) {
    axis.unknowns = cells;
    axis.normalisation = 2.0 * static_cast<double>(cells);
    period = 2.0 * static_cast<double>(cells);
    if (!dirichlet_lower && !dirichlet_upper) {
      axis.forward = FFTW_REDFT10;
      axis.backward = FFTW_REDFT01;
    } else if (dirichlet_lower && dirichlet_upper) {
      axis.forward = FFTW_RODFT10;
      axis.backward = FFTW_RODFT01;
      shift = 1.0;
    } else {
      axis.forward = axis.backward = dirichlet_upper ? FFTW_REDFT11 : FFTW_RODFT11;
      shift = 0.5;
    }
  } else {
    axis.first = dirichlet_lower ? 1 : 0;
    axis.unknowns = cells + 1 - (dirichlet_lower ? 1 : 0) - (dirichlet_upper ? 1 : 0);
    const auto n = static_cast<double>(axis.unknowns);
    if (dirichlet_lower && dirichlet_upper) {
      axis.forward = axis.backward = FFTW_RODFT00;
      axis.normalisation = period = 2.0 * (n + 1.0);
      shift = 1.0;
    } else if (!dirichlet_lower && !dirichlet_upper) {
      axis.forward = axis.backward = FFTW_REDFT00;
      axis.normalisation = period = 2.0 * (n - 1.0);
    } else {
      // Odd about one end node, even about the other: the weighted analysis (type III) and the
      // synthesis in the same basis (type II) are each other's inverses.
      axis.forward = dirichlet_lower ? FFTW_RODFT01 : FFTW_REDFT01;
      axis.backward = dirichlet_lower ? FFTW_RODFT10 : FFTW_REDFT10;
      axis.normalisation = period = 2.0 * n;
      shift = 0.5;
    }
  }
  axis.eigenvalues.resize(static_cast<std::size_t>(axis.unknowns));
  for (std::ptrdiff_t k = 0; k < axis.unknowns; ++k) {
    const double s = std::sin(std::numbers::pi * (static_cast<double>(k) + shift) / period);
    axis.eigenvalues[static_cast<std::size_t>(k)] = 4.0 / (h * h) * s * s;
  }
  return axis;
}

SeparableTransformSolver::SeparableTransformSolver(MPI_Comm comm, const std::array<TransformAxis, 3>& axes)
    : axes_(axes)
{
  initialise_fftw_mpi();
  // FFTW's arrays are row-major with the first dimension split over ranks: (z, y, x).
  const ptrdiff_t n[3] = {axes[2].unknowns, axes[1].unknowns, axes[0].unknowns};
  const fftw_r2r_kind forward[3] = {axes[2].forward, axes[1].forward, axes[0].forward};
  const fftw_r2r_kind backward[3] = {axes[2].backward, axes[1].backward, axes[0].backward};
  int size = 1;
  MPI_Comm_size(comm, &size);
  if (size == 1) {
    // The slab is the whole box: serial transforms, coefficients in the data layout [z][y][x].
    local_n0_ = n[0];
    local_n1_ = n[1];
    data_ = make_fftw_buffer(static_cast<std::size_t>(n[0] * n[1] * n[2]));
    const int m[3] = {static_cast<int>(n[0]), static_cast<int>(n[1]), static_cast<int>(n[2])};
    forward_.reset(fftw_plan_r2r(3, m, data_.get(), data_.get(), forward, fftw_planner_flags()));
    backward_.reset(fftw_plan_r2r(3, m, data_.get(), data_.get(), backward, fftw_planner_flags()));
  } else {
    // Coefficients stay in the transposed layout [y local][z][x] (y split, z whole): one global
    // transpose saved each way.
    transposed_ = true;
    const ptrdiff_t alloc =
        fftw_mpi_local_size_transposed(3, n, comm, &local_n0_, &local_0_start_, &local_n1_, &local_1_start_);
    data_ = make_fftw_buffer(static_cast<std::size_t>(alloc));
    forward_.reset(fftw_mpi_plan_r2r(3, n, data_.get(), data_.get(), comm, forward,
                                     fftw_planner_flags() | FFTW_MPI_TRANSPOSED_OUT));
    backward_.reset(fftw_mpi_plan_r2r(3, n, data_.get(), data_.get(), comm, backward,
                                      fftw_planner_flags() | FFTW_MPI_TRANSPOSED_IN));
  }
  if (!forward_ || !backward_)
    throw std::runtime_error("transform solver: FFTW could not plan the real-to-real transforms");
}

void SeparableTransformSolver::solve(double a, double b)
{
  fftw_execute(forward_.get());
  const double scale = 1.0 / (axes_[0].normalisation * axes_[1].normalisation * axes_[2].normalisation);
  const ptrdiff_t nz = axes_[2].unknowns, nx = axes_[0].unknowns;
  const double* lx = axes_[0].eigenvalues.data();
  const double* ly = axes_[1].eigenvalues.data();
  const double* lz = axes_[2].eigenvalues.data();
  const ptrdiff_t ny = axes_[1].unknowns;
  for (ptrdiff_t jy = 0; jy < local_n1_; ++jy)
    for (ptrdiff_t jz = 0; jz < nz; ++jz) {
      double* row = data_.get() + (transposed_ ? (jy * nz + jz) * nx : (jz * ny + jy) * nx);
      const double ayz = a + b * (ly[jy + local_1_start_] + lz[jz]);
      for (ptrdiff_t jx = 0; jx < nx; ++jx) {
        const double factor = ayz + b * lx[jx];
        row[jx] = factor != 0.0 ? row[jx] * scale / factor : 0.0;
      }
    }
  fftw_execute(backward_.get());
}

} // namespace ibvalve::fluid
