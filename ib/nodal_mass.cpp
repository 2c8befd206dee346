#include "ib/nodal_mass.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <stdexcept>

#include "base/errors.hpp"
#include "io/petsc_check.hpp"

namespace ibvalve::ib {

NodalMass::NodalMass(const fe::Mesh& mesh, fe::MassKind kind, MPI_Comm comm, const std::string& prefix)
    // `comm` sums the lumped masses; the consistent system lives on each rank whole.
    : mesh_(mesh), kind_(kind), comm_(comm), quadrature_(mesh, 2), system_(mesh, 1, PETSC_COMM_SELF)
{
  // Degree 2 integrates N_a N_b exactly on affine tetrahedra and on parallelepiped hexahedra.
  lumped_ = fe::lumped_mass(mesh, quadrature_, comm);
  if (kind_ == fe::MassKind::lumped) return;
  mass_ = fe::consistent_mass_matrix(mesh, quadrature_, system_);
  // The mesh is replicated and the right-hand sides are summed over the ranks, so every rank holds
  // the same small system: a sparse Cholesky factorization (nested-dissection ordering) computed
  // once, then two triangular solves per component, on the rank solve() gives that component.
  PETSC_CHECK(KSPCreate(PETSC_COMM_SELF, ksp_.out()));
  PETSC_CHECK(KSPSetOptionsPrefix(ksp_, prefix.c_str()));
  PETSC_CHECK(KSPSetOperators(ksp_, mass_, mass_));
  PETSC_CHECK(KSPSetType(ksp_, KSPPREONLY));
  PC pc;
  PETSC_CHECK(KSPGetPC(ksp_, &pc));
  PETSC_CHECK(PCSetType(pc, PCCHOLESKY));
  PETSC_CHECK(PCFactorSetMatOrderingType(pc, MATORDERINGND));
  // Iterative alternatives (-<prefix>ksp_type cg -<prefix>pc_type jacobi) start from the last
  // solution of the same field.
  PETSC_CHECK(KSPSetTolerances(ksp_, 1e-12, 1e-300, PETSC_DEFAULT, 1000));
  PETSC_CHECK(KSPSetFromOptions(ksp_));
  KSPType type;
  PETSC_CHECK(KSPGetType(ksp_, &type));
  PetscBool direct = PETSC_FALSE;
  PETSC_CHECK(PetscStrcmp(type, KSPPREONLY, &direct));
  if (!direct) PETSC_CHECK(KSPSetInitialGuessNonzero(ksp_, PETSC_TRUE));
  b_ = system_.create_vector();
}

std::vector<double> NodalMass::solve(std::span<const double> b, int guess_slot) const
{
  const std::size_t nodes = mesh_.num_nodes();
  if (kind_ == fe::MassKind::lumped) {
    std::vector<double> v(3 * nodes);
    for (std::size_t n = 0; n < nodes; ++n)
      for (int c = 0; c < 3; ++c) v[3 * n + c] = b[3 * n + c] / lumped_[n];
    return v;
  }
  // One scalar solve per component (the matrix is the same for all three), each warm-started. The
  // components are shared out over the ranks (component c on rank c mod size) and broadcast: every
  // rank would have solved the same system with the same right side, so the result is the same,
  // and two ranks take two solves' time instead of three. Every rank keeps every component's
  // solution as its next starting guess, so the guesses stay replicated (checkpoints, other rank
  // counts). The broadcast carries the owner's convergence reason and iterations, so a failed solve
  // stops every rank.
  while (static_cast<int>(guesses_.size()) < 3 * (guess_slot + 1)) {
    guesses_.push_back(system_.create_vector());
    PETSC_CHECK(VecZeroEntries(guesses_.back()));
  }
  int rank = 0, size = 1;
  MPI_Comm_rank(comm_, &rank);
  MPI_Comm_size(comm_, &size);
  // Per component: the solution, then the owner's convergence reason and iterations.
  std::array<std::vector<double>, 3> messages;
  std::array<int, 3> owners{};
  std::vector<double> component(nodes);
  for (int c = 0; c < 3; ++c) {
    owners[c] = c % size;
    messages[c].assign(nodes + 2, 0.0);
    if (rank != owners[c]) continue;
    // Each rank solves all its components first, so that the ranks solve at the same time.
    Vec x = guesses_[static_cast<std::size_t>(3 * guess_slot + c)];
    for (std::size_t n = 0; n < nodes; ++n) component[n] = b[3 * n + c];
    system_.scatter(component, b_);
    PETSC_CHECK(KSPSolve(ksp_, b_, x));
    KSPConvergedReason reason;
    PETSC_CHECK(KSPGetConvergedReason(ksp_, &reason));
    PetscInt its = 0;
    PETSC_CHECK(KSPGetIterationNumber(ksp_, &its));
    const std::vector<double> solution = system_.gather(x);
    std::copy(solution.begin(), solution.end(), messages[c].begin());
    messages[c][nodes] = static_cast<double>(reason);
    messages[c][nodes + 1] = static_cast<double>(its);
  }
  std::vector<double> v(3 * nodes);
  iterations_ = 0;
  bool converged = true;
  for (int c = 0; c < 3; ++c) {
    std::vector<double>& message = messages[c];
    if (size > 1) {
      MPI_Bcast(message.data(), static_cast<int>(message.size()), MPI_DOUBLE, owners[c], comm_);
      if (rank != owners[c])
        system_.scatter(std::span(message).first(nodes),
                        guesses_[static_cast<std::size_t>(3 * guess_slot + c)]);
    }
    converged = converged && message[nodes] >= 0.0;
    iterations_ += static_cast<PetscInt>(message[nodes + 1]);
    for (std::size_t n = 0; n < nodes; ++n) v[3 * n + c] = message[n];
  }
  if (!converged) throw RunError("ib: the mass-matrix solve (L2 projection) did not converge");
  return v;
}

void NodalMass::save(io::Hdf5File& file, const std::string& group) const
{
  // Every rank holds the same guesses (same system, same summed right-hand sides): rank 0 writes them.
  const std::array<std::int64_t, 1> count{static_cast<std::int64_t>(guesses_.size())};
  file.write_root(group + "/guess_count", count, std::array<hsize_t, 1>{1});
  if (guesses_.empty()) return; // lumped, or no solve yet
  const std::size_t nodes = mesh_.num_nodes();
  std::vector<double> all;
  all.reserve(guesses_.size() * nodes);
  for (Vec v : guesses_) {
    const std::vector<double> values = system_.gather(v);
    all.insert(all.end(), values.begin(), values.end());
  }
  const std::array<hsize_t, 2> dims{guesses_.size(), nodes};
  file.write_root(group + "/guesses", all, dims);
}

void NodalMass::restore(const io::Hdf5File& file, const std::string& group)
{
  const std::string name = group + "/guesses";
  guesses_.clear();
  if (file.read_integers(group + "/guess_count").at(0) == 0) return;
  const std::vector<hsize_t> dims = file.dims(name);
  const std::size_t nodes = mesh_.num_nodes();
  if (dims.size() != 2 || dims[1] != nodes)
    throw std::runtime_error(file.path().string() + ": " + name + " does not match the structure's mesh");
  const std::vector<double> all = file.read(name);
  for (std::size_t g = 0; g < dims[0]; ++g) {
    guesses_.push_back(system_.create_vector());
    system_.scatter(std::span(all).subspan(g * nodes, nodes), guesses_.back());
  }
}

} // namespace ibvalve::ib
