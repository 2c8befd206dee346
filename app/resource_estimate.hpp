#pragma once
// What a case needs before it allocates anything: grid and mesh counts that PETSc's
// index type can hold, and the memory of the fluid grid and the structure, estimated from their sizes
// with the bytes per cell, node and element measured for each solver (docs/runs.md, "Memory"). A case
// that does not fit is bad input naming the key that drives its size, so it is refused in a second,
// where allocating it would end in an out-of-memory dump or std::bad_alloc minutes later.
#include <string>
#include <string_view>
#include <vector>

#include <mpi.h>

#include "io/config.hpp"
#include "io/key_binder.hpp"

namespace ibvalve::app {

/// Upper bounds of the case files' size keys: far above what a case needs, low enough that no count
/// computed from one of them wraps an int on the way (their products are checked by check_index_count).
inline constexpr double max_grid_cells = 65536;      ///< fluid.cells, each direction
inline constexpr double max_mesh_cells = 4096;       ///< a generated mesh's elements along one direction
inline constexpr double max_solver_iterations = 1e5; ///< fluid.max_iterations
inline constexpr double max_quadrature_degree = 16;  ///< structure.quadrature_degree (9^3 points a hex)

/// The fluid solvers, as far as their memory goes.
enum class FluidMemoryKind {
  fft,        ///< periodic box, FFT projection
  krylov_fft, ///< Krylov Stokes solve, FFTW sine/cosine sub-solves
  krylov_amg, ///< Krylov Stokes solve, BoomerAMG sub-solves
  nested,     ///< composite solver on nested levels (cells of every level)
};

/// One part of a case's memory and the case-file key that drives it.
struct MemoryPart {
  std::string name; ///< "fluid", "structure"
  double bytes = 0.0;
  std::string key;
};

struct MemoryEstimate {
  std::vector<MemoryPart> parts;
  /// The parts plus what every rank holds before any of them (PETSc, MPI, the program).
  double total(int ranks) const;
};

/// The fluid's bytes for `cells` grid cells (all levels), the IB's grid fields included when `immersed`.
MemoryPart fluid_memory(double cells, FluidMemoryKind kind, bool immersed, std::string key);
/// The structure's bytes for a mesh of `nodes` and `elements` hexahedra (solid model, coupling points,
/// projections).
MemoryPart structure_memory(double nodes, double elements, std::string key);

/// Refuses, naming `key`, a count (`what`: "grid unknowns", "mesh nodes") that PETSc's index type
/// (PetscInt) or an int cannot hold; `count` is computed in floating point so that it cannot wrap.
void check_index_count(const io::Config& config, std::string_view key, double count, std::string_view what);

/// The memory limit, a key every case has (app/model.hpp, CommonKeys).
struct MemoryKeys {
  double max_memory = 0.0; ///< GiB over all ranks; 0 = the machines' physical memory
};

/// Declares or reads run.max_memory (io/key_binder.hpp).
void bind(io::KeyBinder& keys, MemoryKeys& k);

/// Compares the estimate with run.max_memory (GiB) or, when that is 0, the physical memory of the
/// machines the ranks of `comm` run on (each machine counted once): InputError naming the key of the
/// largest part, the estimate and the limit when it does not fit. Collective over `comm`. Returns the
/// one-line summary a run logs at its start.
std::string check_memory(const io::Config& config, const MemoryEstimate& estimate, MPI_Comm comm);

} // namespace ibvalve::app
