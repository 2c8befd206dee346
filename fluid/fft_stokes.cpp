#include "fluid/fft_stokes.hpp"

#include <cmath>
#include <fmt/format.h>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>

#include "io/petsc_check.hpp"

namespace ibvalve::fluid {

void initialise_fftw_mpi()
{
  static bool initialised = false;
  if (!initialised) {
    fftw_mpi_init();
    initialised = true;
  }
}

unsigned fftw_planner_flags()
{
  char value[32] = "measure";
  PetscBool set = PETSC_FALSE;
  PETSC_CHECK(PetscOptionsGetString(nullptr, nullptr, "-fluid_fftw_planner", value, sizeof value, &set));
  const std::string planner = value;
  if (planner == "estimate") return FFTW_ESTIMATE;
  if (planner == "measure") return FFTW_MEASURE;
  if (planner == "patient") return FFTW_PATIENT;
  throw std::invalid_argument("-fluid_fftw_planner: \"" + planner + "\" is not estimate, measure or patient");
}

std::string export_fftw_wisdom()
{
  // The text's header names FFTW's set of algorithms, which fftw_mpi_init extends: export and import
  // with it called, or FFTW refuses the text of a run that planned nothing (an AMG-only run).
  initialise_fftw_mpi();
  const std::unique_ptr<char, void (*)(void*)> text(fftw_export_wisdom_to_string(), fftw_free);
  return text ? std::string(text.get()) : std::string();
}

bool import_fftw_wisdom(const std::string& wisdom)
{
  initialise_fftw_mpi(); // the MPI plans' wisdom names solvers that fftw_mpi_init registers
  return fftw_import_wisdom_from_string(wisdom.c_str()) != 0;
}

Decomposition fft_decomposition(MPI_Comm comm, const Index3& cells)
{
  initialise_fftw_mpi();
  ptrdiff_t local_n0 = 0, local_0_start = 0;
  fftw_mpi_local_size_3d(cells[2], cells[1], cells[0] / 2 + 1, comm, &local_n0, &local_0_start);
  int size = 1;
  MPI_Comm_size(comm, &size);
  std::vector<long> all(static_cast<std::size_t>(size));
  long mine = static_cast<long>(local_n0);
  MPI_Allgather(&mine, 1, MPI_LONG, all.data(), 1, MPI_LONG, comm);
  Decomposition decomposition;
  decomposition.slabs_in_z = true;
  for (long n : all) {
    if (n < 2)
      throw std::invalid_argument(fmt::format(
          "fluid fft solver: too many ranks for {} cells in z (each rank needs a slab of at least 2 planes)",
          cells[2]));
    decomposition.z_ownership.push_back(static_cast<PetscInt>(n));
  }
  return decomposition;
}

FftStokesSolver::FftStokesSolver(const StaggeredGrid& grid) : grid_(grid)
{
  for (int d = 0; d < 3; ++d)
    if (!grid.periodic(d))
      throw std::invalid_argument("fluid fft solver: the box must be periodic in x, y and z");
  initialise_fftw_mpi();
  const ptrdiff_t nx = grid.cells(0), ny = grid.cells(1), nz = grid.cells(2);
  half_ = nx / 2 + 1;
  padded_ = 2 * half_;
  // Transposed spectra (y distributed, z whole) save one global transpose per transform each way.
  alloc_ = fftw_mpi_local_size_3d_transposed(nz, ny, half_, grid.comm(), &local_n0_, &local_0_start_,
                                             &local_n1_, &local_1_start_);
  if (local_0_start_ != grid.begin(2) || local_n0_ != grid.count(2))
    throw std::invalid_argument("fluid fft solver: the grid is not in FFTW's slab decomposition");
  real_ = make_fftw_buffer(static_cast<std::size_t>(2 * alloc_));
  for (auto& s : spectra_) s = make_fftw_complex_buffer(static_cast<std::size_t>(alloc_));
  forward_.reset(fftw_mpi_plan_dft_r2c_3d(nz, ny, nx, real_.get(), spectra_[0].get(), grid.comm(),
                                          fftw_planner_flags() | FFTW_MPI_TRANSPOSED_OUT));
  backward_.reset(fftw_mpi_plan_dft_c2r_3d(nz, ny, nx, spectra_[0].get(), real_.get(), grid.comm(),
                                           fftw_planner_flags() | FFTW_MPI_TRANSPOSED_IN));
  if (!forward_ || !backward_) throw std::runtime_error("fluid fft solver: FFTW could not plan");
  for (int d = 0; d < 3; ++d) {
    const PetscInt n = grid.cells(d);
    const double h = grid.h(d);
    laplacian_[d].resize(static_cast<std::size_t>(n));
    forward_difference_[d].resize(static_cast<std::size_t>(n));
    for (PetscInt m = 0; m < n; ++m) {
      const double theta = 2.0 * std::numbers::pi * static_cast<double>(m) / static_cast<double>(n);
      laplacian_[d][static_cast<std::size_t>(m)] = (2.0 * std::cos(theta) - 2.0) / (h * h);
      forward_difference_[d][static_cast<std::size_t>(m)] = (std::polar(1.0, theta) - 1.0) / h;
    }
  }
}

void FftStokesSolver::load(Vec local, PetscInt slot, double* real) const
{
  StagArray a(grid_, local, true);
  const PetscInt nx = grid_.cells(0), ny = grid_.cells(1);
  for (PetscInt k = grid_.begin(2); k < grid_.begin(2) + grid_.count(2); ++k)
    for (PetscInt j = 0; j < ny; ++j) {
      double* row = real + ((k - grid_.begin(2)) * ny + j) * padded_;
      for (PetscInt i = 0; i < nx; ++i) row[i] = a(i, j, k, slot);
    }
}

void FftStokesSolver::store(const double* real, Vec local, PetscInt slot) const
{
  StagArray a(grid_, local);
  const PetscInt nx = grid_.cells(0), ny = grid_.cells(1);
  const double scale =
      1.0 / (static_cast<double>(nx) * static_cast<double>(ny) * static_cast<double>(grid_.cells(2)));
  for (PetscInt k = grid_.begin(2); k < grid_.begin(2) + grid_.count(2); ++k)
    for (PetscInt j = 0; j < ny; ++j) {
      const double* row = real + ((k - grid_.begin(2)) * ny + j) * padded_;
      for (PetscInt i = 0; i < nx; ++i) a(i, j, k, slot) = scale * row[i];
    }
}

SolveStatistics FftStokesSolver::solve(Vec rhs, Vec solution)
{
  SolveStatistics stats;
  const double t0 = MPI_Wtime();
  for (int d = 0; d < 3; ++d) {
    load(rhs, grid_.face_slot(d), real_.get());
    fftw_mpi_execute_dft_r2c(forward_.get(), real_.get(), spectra_[static_cast<std::size_t>(d)].get());
  }
  const double t1 = MPI_Wtime();
  using C = std::complex<double>;
  C* s[4];
  for (int d = 0; d < 4; ++d) s[d] = reinterpret_cast<C*>(spectra_[static_cast<std::size_t>(d)].get());
  const double rho_dt = parameters_.rho / parameters_.dt, half_mu = 0.5 * parameters_.mu;
  // Spectra in FFTW's transposed layout: [ky local][kz][kx].
  const ptrdiff_t nz = grid_.cells(2);
  for (ptrdiff_t ky = 0; ky < local_n1_; ++ky) {
    const auto y = static_cast<std::size_t>(ky + local_1_start_);
    for (ptrdiff_t kz = 0; kz < nz; ++kz) {
      const auto z = static_cast<std::size_t>(kz);
      for (ptrdiff_t kx = 0; kx < half_; ++kx) {
        const auto x = static_cast<std::size_t>(kx);
        const std::size_t m = static_cast<std::size_t>((ky * nz + kz) * half_ + kx);
        const double lambda = laplacian_[0][x] + laplacian_[1][y] + laplacian_[2][z];
        const double helmholtz = rho_dt - half_mu * lambda;
        const C fd[3] = {forward_difference_[0][x], forward_difference_[1][y], forward_difference_[2][z]};
        C u[3];
        C divergence = 0.0;
        for (int d = 0; d < 3; ++d) {
          u[d] = s[d][m] / helmholtz;
          divergence += fd[d] * u[d];
        }
        const C phi = lambda < 0.0 ? divergence / lambda : C(0.0);
        // G phi on faces has the symbol (1 - e^{-i theta})/h = -conj(forward difference).
        for (int d = 0; d < 3; ++d) s[d][m] = u[d] + std::conj(fd[d]) * phi;
        s[3][m] = rho_dt * phi - half_mu * divergence;
      }
    }
  }
  const double t2 = MPI_Wtime();
  for (int d = 0; d < 4; ++d) {
    fftw_mpi_execute_dft_c2r(backward_.get(), spectra_[static_cast<std::size_t>(d)].get(), real_.get());
    store(real_.get(), solution, d < 3 ? grid_.face_slot(d) : grid_.pressure_slot());
  }
  const double t3 = MPI_Wtime();
  // Helmholtz: the three velocity transforms each way; Poisson: the pressure transform and the
  // projection (the per-mode work is counted with the pressure part).
  stats.helmholtz_seconds = (t1 - t0) + 0.75 * (t3 - t2);
  stats.poisson_seconds = (t2 - t1) + 0.25 * (t3 - t2);
  return stats;
}

} // namespace ibvalve::fluid
