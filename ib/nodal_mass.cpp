#include "ib/nodal_mass.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <stdexcept>

#include "base/errors.hpp"
#include "io/petsc_check.hpp"
#include "io/petsc_options.hpp"

namespace ibvalve::ib {

namespace {

/// A dense nodes x 3 matrix of zeros (one column per component).
petsc::OwnedMat dense_columns(std::size_t nodes)
{
  petsc::OwnedMat m;
  const auto n = static_cast<PetscInt>(nodes);
  PETSC_CHECK(MatCreateSeqDense(PETSC_COMM_SELF, n, 3, nullptr, m.out()));
  PETSC_CHECK(MatZeroEntries(m));
  return m;
}

/// Column-major values of a dense matrix made by dense_columns, read or written in place.
class DenseValues {
 public:
  explicit DenseValues(Mat m) : m_(m)
  {
    PETSC_CHECK(MatDenseGetArray(m_, &a_));
    PETSC_CHECK(MatDenseGetLDA(m_, &lda_));
  }
  ~DenseValues() { MatDenseRestoreArray(m_, &a_); }
  DenseValues(const DenseValues&) = delete;
  DenseValues& operator=(const DenseValues&) = delete;
  PetscScalar& operator()(std::size_t row, int column) const
  {
    return a_[row + static_cast<std::size_t>(column) * static_cast<std::size_t>(lda_)];
  }

 private:
  Mat m_;
  PetscScalar* a_ = nullptr;
  PetscInt lda_ = 0;
};

} // namespace

NodalMass::NodalMass(const fe::Mesh& mesh, fe::MassKind kind, MPI_Comm comm, const std::string& prefix)
    // `comm` sums the lumped masses; the consistent system lives on each rank whole.
    : mesh_(mesh), kind_(kind), quadrature_(mesh, 2), system_(mesh, 1, PETSC_COMM_SELF)
{
  // Degree 2 integrates N_a N_b exactly on affine tetrahedra and on parallelepiped hexahedra.
  lumped_ = fe::lumped_mass(mesh, quadrature_, comm);
  if (kind_ == fe::MassKind::lumped) return;
  mass_ = fe::consistent_mass_matrix(mesh, quadrature_, system_);
  // The mesh is replicated and the right-hand sides are summed over the ranks, so every rank holds
  // the same small system: a sparse Cholesky factorization computed once, then one substitution that
  // carries the three components. CHOLMOD's simplicial (column by column) factor solves three columns
  // in about twice the time of one, and in a third of the time of PETSc's own factor solving them one
  // after the other; its supernodal factor, CHOLMOD's automatic choice for the structure block of
  // bench/ib, is slower at three columns on both meshes measured (docs/ib.md, "Coupling at quadrature
  // points").
  PETSC_CHECK(KSPCreate(PETSC_COMM_SELF, ksp_.out()));
  PETSC_CHECK(KSPSetOptionsPrefix(ksp_, prefix.c_str()));
  PETSC_CHECK(KSPSetOperators(ksp_, mass_, mass_));
  PETSC_CHECK(KSPSetType(ksp_, KSPPREONLY));
  PC pc;
  PETSC_CHECK(KSPGetPC(ksp_, &pc));
  PETSC_CHECK(PCSetType(pc, PCCHOLESKY));
  PETSC_CHECK(PCFactorSetMatSolverType(pc, MATSOLVERCHOLMOD));
  PETSC_CHECK(PCFactorSetMatOrderingType(pc, MATORDERINGND)); // for -<prefix>pc_factor_mat_solver_type petsc
  // Iterative alternatives (-<prefix>ksp_type cg -<prefix>pc_type jacobi) start from the last
  // solution of the same field.
  PETSC_CHECK(KSPSetTolerances(ksp_, 1e-12, 1e-300, PETSC_DEFAULT, 1000));
  PETSC_CHECK(KSPSetFromOptions(ksp_));
  KSPType type;
  PETSC_CHECK(KSPGetType(ksp_, &type));
  PetscBool preonly = PETSC_FALSE;
  PETSC_CHECK(PetscStrcmp(type, KSPPREONLY, &preonly));
  direct_ = preonly == PETSC_TRUE;
  // CHOLMOD's simplicial factor unless the options say otherwise; read when the factor is made (at the
  // first solve), and set only when CHOLMOD factors, so no option is left unused.
  MatSolverType solver = nullptr;
  PETSC_CHECK(PCFactorGetMatSolverType(pc, &solver));
  PetscBool cholmod = PETSC_FALSE;
  if (solver) PETSC_CHECK(PetscStrcmp(solver, MATSOLVERCHOLMOD, &cholmod));
  if (direct_ && cholmod) petsc::set_option_unless_given("-" + prefix + "mat_cholmod_factor", "simplicial");
  if (!direct_) PETSC_CHECK(KSPSetInitialGuessNonzero(ksp_, PETSC_TRUE));
  rhs_ = dense_columns(mesh_.num_nodes());
}

std::vector<double> NodalMass::solve(std::span<const double> b, int guess_slot) const
{
  const std::size_t nodes = mesh_.num_nodes();
  std::vector<double> v(3 * nodes);
  if (kind_ == fe::MassKind::lumped) {
    for (std::size_t n = 0; n < nodes; ++n)
      for (int c = 0; c < 3; ++c) v[3 * n + c] = b[3 * n + c] / lumped_[n];
    return v;
  }
  // Every rank solves all three components: the system and the summed right-hand side are the same on
  // every rank, so the results, and a failure, are too, with nothing sent.
  while (guesses_.size() < static_cast<std::size_t>(guess_slot + 1)) guesses_.push_back(dense_columns(nodes));
  Mat x = guesses_[static_cast<std::size_t>(guess_slot)];
  {
    const DenseValues rhs(rhs_);
    for (std::size_t n = 0; n < nodes; ++n)
      for (int c = 0; c < 3; ++c) rhs(n, c) = b[3 * n + c];
  }
  iterations_ = 0;
  if (direct_) {
    PETSC_CHECK(KSPMatSolve(ksp_, rhs_, x));
    iterations_ = 3;
  } else {
    for (PetscInt c = 0; c < 3; ++c) {
      Vec bc = nullptr, xc = nullptr;
      PETSC_CHECK(MatDenseGetColumnVecRead(rhs_, c, &bc));
      PETSC_CHECK(MatDenseGetColumnVec(x, c, &xc));
      const PetscErrorCode solved = KSPSolve(ksp_, bc, xc);
      PETSC_CHECK(MatDenseRestoreColumnVec(x, c, &xc));
      PETSC_CHECK(MatDenseRestoreColumnVecRead(rhs_, c, &bc));
      PETSC_CHECK(solved);
      KSPConvergedReason reason;
      PETSC_CHECK(KSPGetConvergedReason(ksp_, &reason));
      if (reason < 0) throw RunError("ib: the mass-matrix solve (L2 projection) did not converge");
      PetscInt its = 0;
      PETSC_CHECK(KSPGetIterationNumber(ksp_, &its));
      iterations_ += its;
    }
  }
  const DenseValues solution(x);
  for (std::size_t n = 0; n < nodes; ++n)
    for (int c = 0; c < 3; ++c) v[3 * n + c] = solution(n, c);
  return v;
}

void NodalMass::save(io::Hdf5File& file, const std::string& group) const
{
  // Every rank holds the same guesses (same system, same summed right-hand sides): rank 0 writes them,
  // one row per slot and component.
  const std::array<std::int64_t, 1> count{static_cast<std::int64_t>(3 * guesses_.size())};
  file.write_root(group + "/guess_count", count, std::array<hsize_t, 1>{1});
  if (guesses_.empty()) return; // lumped, or no solve yet
  const std::size_t nodes = mesh_.num_nodes();
  std::vector<double> all;
  all.reserve(3 * guesses_.size() * nodes);
  for (const petsc::OwnedMat& guess : guesses_) {
    const DenseValues values(guess);
    for (int c = 0; c < 3; ++c)
      for (std::size_t n = 0; n < nodes; ++n) all.push_back(values(n, c));
  }
  const std::array<hsize_t, 2> dims{3 * guesses_.size(), nodes};
  file.write_root(group + "/guesses", all, dims);
}

void NodalMass::restore(const io::Hdf5File& file, const std::string& group)
{
  const std::string name = group + "/guesses";
  guesses_.clear();
  if (file.read_integers(group + "/guess_count").at(0) == 0) return;
  const std::vector<hsize_t> dims = file.dims(name);
  const std::size_t nodes = mesh_.num_nodes();
  if (dims.size() != 2 || dims[1] != nodes || dims[0] % 3 != 0)
    throw std::runtime_error(file.path().string() + ": " + name + " does not match the structure's mesh");
  const std::vector<double> all = file.read(name);
  for (std::size_t slot = 0; slot < dims[0] / 3; ++slot) {
    guesses_.push_back(dense_columns(nodes));
    const DenseValues values(guesses_.back());
    for (int c = 0; c < 3; ++c)
      for (std::size_t n = 0; n < nodes; ++n)
        values(n, c) = all[(3 * slot + static_cast<std::size_t>(c)) * nodes + n];
  }
}

} // namespace ibvalve::ib
