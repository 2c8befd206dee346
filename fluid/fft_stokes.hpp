#pragma once
// The exact Stokes solver for periodic boxes (see fluid/stokes_solver.hpp) by FFTW-MPI.
#include <array>
#include <complex>
#include <string>
#include <vector>

#include <fftw3-mpi.h>

#include "fluid/fftw_handles.hpp"
#include "fluid/stokes_solver.hpp"

namespace ibvalve::fluid {

/// fftw_mpi_init() once per process (every FFTW-MPI user in fluid/ calls this first).
void initialise_fftw_mpi();
/// FFTW's planner rigor for the fluid solvers' transforms: the PETSc option -fluid_fftw_planner
/// estimate|measure|patient (default measure). `measure` and `patient` time candidate algorithms when
/// a solver is built, so two processes may choose different plans and then differ in round-off;
/// `estimate` chooses by rule, so every run of a case, restarted or not, computes the same bits (the
/// restart tests use it).
unsigned fftw_planner_flags();
/// The plans FFTW has chosen so far in this process, as FFTW's wisdom text. Each rank times its own
/// serial pieces and may choose differently, so a run keeps every rank's text for its restart.
std::string export_fftw_wisdom();
/// Makes the plans of `wisdom` (this rank's export_fftw_wisdom text of an earlier process) known:
/// solvers built afterwards take them instead of timing candidates, so a restarted run on the same
/// ranks computes the interrupted run's bits. False when FFTW does not accept the text.
bool import_fftw_wisdom(const std::string& wisdom);

/// The z-slab decomposition FFTW-MPI uses for a box of `cells`, to build the grid with.
Decomposition fft_decomposition(MPI_Comm comm, const Index3& cells);

class FftStokesSolver : public StokesSolver {
 public:
  /// `grid` must be periodic in every direction and decomposed by fft_decomposition().
  explicit FftStokesSolver(const StaggeredGrid& grid);
  FftStokesSolver(const FftStokesSolver&) = delete;
  FftStokesSolver& operator=(const FftStokesSolver&) = delete;

  void set_parameters(const StokesParameters& parameters) override { parameters_ = parameters; }
  SolveStatistics solve(Vec rhs, Vec solution) override;
  std::string name() const override { return "fft"; }

 private:
  void load(Vec local, PetscInt slot, double* real) const;
  void store(const double* real, Vec local, PetscInt slot) const;

  const StaggeredGrid& grid_;
  StokesParameters parameters_;
  ptrdiff_t local_n0_ = 0, local_0_start_ = 0, local_n1_ = 0, local_1_start_ = 0, alloc_ = 0, padded_ = 0,
            half_ = 0;
  // Owned, so a constructor that fails after allocating (FFTW returning no plan) frees them. The plans
  // are declared after the buffers they were made for and so destroyed before them.
  FftwBuffer real_;
  std::array<FftwComplexBuffer, 4> spectra_; // the three velocity components and the pressure
  FftwPlan forward_, backward_;
  // Per direction and wavenumber: the Laplacian eigenvalue (2 cos(theta) - 2)/h^2 and the symbol of
  // the forward difference (e^{i theta} - 1)/h (divergence: face i+1 minus face i of cell i).
  std::vector<double> laplacian_[3];
  std::vector<std::complex<double>> forward_difference_[3];
};

} // namespace ibvalve::fluid
