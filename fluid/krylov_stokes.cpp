#include "fluid/krylov_stokes.hpp"

#include <cmath>
#include <fmt/format.h>
#include <stdexcept>

#include "fluid/jacobi.hpp"
#include "io/petsc_check.hpp"

namespace ibvalve::fluid {

namespace {

DMStagStencilLocation face_location(int d)
{
  static const DMStagStencilLocation faces[3] = {DMSTAG_LEFT, DMSTAG_DOWN, DMSTAG_BACK};
  return faces[d];
}

DMStagStencil face_stencil(int d, const Index3& idx)
{
  return {face_location(d), idx[0], idx[1], idx[2], 0};
}
DMStagStencil cell_stencil(const Index3& idx)
{
  return {DMSTAG_ELEMENT, idx[0], idx[1], idx[2], 0};
}

/// Calls f(idx) for every owned face of component d.
template <class F>
void for_owned_faces(const StaggeredGrid& grid, int d, F&& f)
{
  for (PetscInt k = grid.begin(2); k < grid.face_end(d, 2); ++k)
    for (PetscInt j = grid.begin(1); j < grid.face_end(d, 1); ++j)
      for (PetscInt i = grid.begin(0); i < grid.face_end(d, 0); ++i) f(Index3{i, j, k});
}

template <class F>
void for_owned_cells(const StaggeredGrid& grid, F&& f)
{
  for (PetscInt k = grid.begin(2); k < grid.begin(2) + grid.count(2); ++k)
    for (PetscInt j = grid.begin(1); j < grid.begin(1) + grid.count(1); ++j)
      for (PetscInt i = grid.begin(0); i < grid.begin(0) + grid.count(0); ++i) f(Index3{i, j, k});
}

} // namespace

KrylovStokesSolver::KrylovStokesSolver(const StaggeredGrid& grid, const BoundaryConditions& bc,
                                       const FluidSettings& settings)
    : grid_(grid), bc_(bc), settings_(settings), pressure_has_constant_(!bc.any_traction()), solid_(grid, bc),
      transforms_used_(settings.subsolver == SubsolverKind::fft && solid_.empty())
{
}

void KrylovStokesSolver::destroy()
{
  axial_.reset();
  for (petsc::OwnedMat* m : {&A_, &H_, &G_, &Dn_, &K_}) m->reset();
  for (petsc::OwnedIS* is : {&is_u_, &is_p_}) is->reset();
  for (petsc::OwnedKSP* k : {&ksp_, &ksp_h_, &ksp_k_}) k->reset();
  for (petsc::OwnedVec* v : {&x_, &b_, &r_p_, &phi_, &gphi_, &x_u_, &y_u_, &x_p_, &y_p_, &fluid_cells_})
    v->reset();
}

bool KrylovStokesSolver::velocity_row(int d, const Index3& idx, double t_new, double t_half,
                                      std::vector<Entry>& entries, double& constant) const
{
  entries.clear();
  constant = 0.0;
  const PetscInt n_d = grid_.cells(d);
  if (solid_.face(d, idx)) { // a face of a blocked cell: u = 0
    entries.push_back({face_stencil(d, idx), 1.0});
    return true;
  }
  if (grid_.is_boundary_face(d, idx[d])) {
    const int s = side_index(d, idx[d] == 0 ? 0 : 1);
    const Real3 x = grid_.face_position(d, idx[0], idx[1], idx[2]);
    if (!bc_.traction_at(s, x)) {
      entries.push_back({face_stencil(d, idx), 1.0});
      constant = bc_.velocity(s, x, t_new)[d];
      return true;
    }
  }
  const double half_mu = 0.5 * parameters_.mu;
  double diagonal = parameters_.rho / parameters_.dt;
  for (int e = 0; e < 3; ++e) {
    const double c = 1.0 / (grid_.h(e) * grid_.h(e));
    diagonal += half_mu * 2.0 * c;
    for (int sign : {-1, 1}) {
      Index3 nb = idx;
      nb[e] += sign;
      const PetscInt n_e = grid_.cells(e);
      if (!grid_.periodic(e)) {
        const int s = side_index(e, sign > 0 ? 1 : 0);
        if (e == d && (nb[e] < 0 || nb[e] > n_e)) {
          // Traction side, normal component: even ghost u_{N+1} = u_{N-1} (du_n/dn = 0).
          nb[e] = idx[e] - sign;
          entries.push_back({face_stencil(d, nb), -half_mu * c});
          continue;
        }
        if (e != d && (nb[e] < 0 || nb[e] >= n_e)) {
          // Tangential component: ghost 8/3 g - 2 u_0 + 1/3 u_1 (g = 0 on a traction side).
          diagonal += half_mu * c * 2.0;
          Index3 in1 = idx;
          in1[e] -= sign;
          entries.push_back({face_stencil(d, in1), -half_mu * c / 3.0});
          if (bc_.side(s).kind == SideKind::velocity) {
            Real3 x = grid_.face_position(d, idx[0], idx[1], idx[2]);
            x[e] = sign > 0 ? grid_.box().upper[e] : grid_.box().lower[e];
            constant += half_mu * c * 8.0 / 3.0 * bc_.velocity(s, x, t_new)[d];
          }
          continue;
        }
      }
      if (e != d && solid_.wall_beyond(d, idx, e, sign)) {
        // A wall half a cell beyond: the odd ghost -u_0 (the neighbour face is blocked, u = 0 there).
        diagonal += half_mu * c;
        continue;
      }
      entries.push_back({face_stencil(d, nb), -half_mu * c});
    }
  }
  entries.push_back({face_stencil(d, idx), diagonal});
  // Pressure gradient (p(idx) - p(idx - e_d)) / h_d; one-sided over h/2 with p_b at a traction side.
  const double h = grid_.h(d);
  Index3 below = idx;
  below[d] -= 1;
  if (!grid_.periodic(d) && idx[d] == 0) {
    const double pb = bc_.pressure(side_index(d, 0), grid_.face_position(d, idx[0], idx[1], idx[2]), t_half);
    entries.push_back({cell_stencil(idx), 2.0 / h});
    constant += 2.0 * pb / h;
  } else if (!grid_.periodic(d) && idx[d] == n_d) {
    const double pb = bc_.pressure(side_index(d, 1), grid_.face_position(d, idx[0], idx[1], idx[2]), t_half);
    entries.push_back({cell_stencil(below), -2.0 / h});
    constant -= 2.0 * pb / h;
  } else {
    entries.push_back({cell_stencil(idx), 1.0 / h});
    entries.push_back({cell_stencil(below), -1.0 / h});
  }
  return false;
}

void KrylovStokesSolver::pressure_row(const Index3& idx, std::vector<Entry>& entries) const
{
  // -D u: -(u(idx + e_d) - u(idx)) / h_d; a blocked cell's pressure is decoupled, p = 0.
  entries.clear();
  if (solid_.cell(idx)) {
    entries.push_back({cell_stencil(idx), 1.0});
    return;
  }
  for (int d = 0; d < 3; ++d) {
    Index3 up = idx;
    up[d] += 1;
    entries.push_back({face_stencil(d, up), -1.0 / grid_.h(d)});
    entries.push_back({face_stencil(d, idx), 1.0 / grid_.h(d)});
  }
}

void KrylovStokesSolver::assemble(Mat matrix) const
{
  std::vector<Entry> entries;
  std::vector<DMStagStencil> columns;
  std::vector<PetscScalar> values;
  auto insert = [&](const DMStagStencil& row) {
    columns.clear();
    values.clear();
    for (const Entry& e : entries) {
      columns.push_back(e.column);
      values.push_back(e.value);
    }
    PETSC_CHECK(DMStagMatSetValuesStencil(grid_.dm(), matrix, 1, &row, static_cast<PetscInt>(columns.size()),
                                          columns.data(), values.data(), ADD_VALUES));
  };
  double constant = 0.0;
  for (int d = 0; d < 3; ++d)
    for_owned_faces(grid_, d, [&](const Index3& idx) {
      velocity_row(d, idx, 0.0, 0.0, entries, constant);
      insert(face_stencil(d, idx));
    });
  for_owned_cells(grid_, [&](const Index3& idx) {
    pressure_row(idx, entries);
    insert(cell_stencil(idx));
  });
  PETSC_CHECK(MatAssemblyBegin(matrix, MAT_FINAL_ASSEMBLY));
  PETSC_CHECK(MatAssemblyEnd(matrix, MAT_FINAL_ASSEMBLY));
}

namespace {

/// Constant pressure is in the kernel of the coupled operator `A` (a vector shaped as `x`, the pressure
/// unknowns `is_p`) and of the pressure Poisson operator `K`: their null spaces say so. With blocked cells
/// the constant lives on the fluid cells only (`fluid_cells`, the pressure block's indicator; null: all).
void set_constant_pressure_null_space(MPI_Comm comm, Vec x, IS is_p, Mat A, Mat K, Vec fluid_cells)
{
  petsc::OwnedVec constant;
  PETSC_CHECK(VecDuplicate(x, constant.out()));
  PETSC_CHECK(VecZeroEntries(constant));
  Vec constant_p;
  PETSC_CHECK(VecGetSubVector(constant, is_p, &constant_p));
  if (fluid_cells)
    PETSC_CHECK(VecCopy(fluid_cells, constant_p));
  else
    PETSC_CHECK(VecSet(constant_p, 1.0));
  PETSC_CHECK(VecRestoreSubVector(constant, is_p, &constant_p));
  PETSC_CHECK(VecNormalize(constant, nullptr));
  const Vec basis = constant.get();
  petsc::OwnedMatNullSpace space;
  PETSC_CHECK(MatNullSpaceCreate(comm, PETSC_FALSE, 1, &basis, space.out()));
  PETSC_CHECK(MatSetNullSpace(A, space));
  petsc::OwnedMatNullSpace k_space;
  if (fluid_cells) {
    petsc::OwnedVec k_basis;
    PETSC_CHECK(VecDuplicate(fluid_cells, k_basis.out()));
    PETSC_CHECK(VecCopy(fluid_cells, k_basis));
    PETSC_CHECK(VecNormalize(k_basis, nullptr));
    const Vec k_vector = k_basis.get();
    PETSC_CHECK(MatNullSpaceCreate(comm, PETSC_FALSE, 1, &k_vector, k_space.out()));
  } else {
    PETSC_CHECK(MatNullSpaceCreate(comm, PETSC_TRUE, 0, nullptr, k_space.out()));
  }
  PETSC_CHECK(MatSetNullSpace(K, k_space));
}

} // namespace

bool KrylovStokesSolver::helmholtz_wants_jacobi() const
{
  // Why and when: set_parameters; with blocked cells the sweeps stand in for BoomerAMG.
  PetscReal limit = jacobi_ratio_limit;
  PETSC_CHECK(PetscOptionsGetReal(nullptr, "fluid_helmholtz_", "-jacobi_limit", &limit, nullptr));
  return (transforms_used_ || !solid_.empty()) && jacobi_ratio(H_) <= limit;
}

bool KrylovStokesSolver::change_step(const StokesParameters& parameters)
{
  // Only rho/dt moves, and it sits on the diagonal of the velocity rows: A and H take their new diagonal
  // in place, and K = -D G (independent of dt) keeps its sub-solver's setup (BoomerAMG's is the dear
  // part). The diagonal is the one a fresh assembly computes, bit for bit, so a run that changes its
  // step and a run restarted at the new step solve the same system.
  if (!A_ || parameters.rho != parameters_.rho || parameters.mu != parameters_.mu) return false;
  parameters_ = parameters;
  std::vector<Entry> entries;
  double constant = 0.0;
  for (int d = 0; d < 3; ++d)
    for_owned_faces(grid_, d, [&](const Index3& idx) {
      if (velocity_row(d, idx, 0.0, 0.0, entries, constant)) return; // identity rows keep their 1
      const DMStagStencil self = face_stencil(d, idx);
      for (const Entry& e : entries)
        if (e.column.loc == self.loc && e.column.i == self.i && e.column.j == self.j && e.column.k == self.k)
          PETSC_CHECK(DMStagMatSetValuesStencil(grid_.dm(), A_, 1, &self, 1, &self, &e.value, INSERT_VALUES));
    });
  PETSC_CHECK(MatAssemblyBegin(A_, MAT_FINAL_ASSEMBLY));
  PETSC_CHECK(MatAssemblyEnd(A_, MAT_FINAL_ASSEMBLY));
  Mat h = H_.get();
  PETSC_CHECK(MatCreateSubMatrix(A_, is_u_, is_u_, MAT_REUSE_MATRIX, &h));
  if (helmholtz_wants_jacobi() != helmholtz_by_jacobi_) return false; // the sub-solver changes kind
  PETSC_CHECK(KSPSetOperators(ksp_h_, H_, H_));
  PETSC_CHECK(KSPSetOperators(ksp_, A_, A_));
  return true;
}

void KrylovStokesSolver::regularise_blocked_cells()
{
  const MPI_Comm comm = grid_.comm();
  // Blocked cells: K = -D G has empty rows there (their faces are identity rows); an identity makes it
  // regular, and the preconditioner returns p = x_p on them (apply_projection).
  PETSC_CHECK(VecDuplicate(x_p_, fluid_cells_.out()));
  Vec whole;
  PETSC_CHECK(DMGetGlobalVector(grid_.dm(), &whole));
  PETSC_CHECK(VecSet(whole, 0.0));
  {
    petsc::OwnedVec local = grid_.create_local();
    {
      StagArray a(grid_, local);
      for_owned_cells(grid_, [&](const Index3& idx) {
        a(idx[0], idx[1], idx[2], grid_.pressure_slot()) = solid_.cell(idx) ? 0.0 : 1.0;
      });
    }
    PETSC_CHECK(DMLocalToGlobal(grid_.dm(), local, INSERT_VALUES, whole));
  }
  PETSC_CHECK(VecISCopy(whole, is_p_, SCATTER_REVERSE, fluid_cells_));
  PETSC_CHECK(DMRestoreGlobalVector(grid_.dm(), &whole));
  petsc::OwnedVec blocked;
  PETSC_CHECK(VecDuplicate(fluid_cells_, blocked.out()));
  PETSC_CHECK(VecSet(blocked, 1.0));
  PETSC_CHECK(VecAXPY(blocked, -1.0, fluid_cells_));
  // The product has no entry in the blocked rows: add a diagonal matrix (MatAXPY merges the patterns
  // with a preallocation; inserting into K_ entry by entry would move its storage each time).
  PetscInt rows, global_rows;
  PETSC_CHECK(VecGetLocalSize(blocked, &rows));
  PETSC_CHECK(VecGetSize(blocked, &global_rows));
  petsc::OwnedMat diagonal;
  PETSC_CHECK(
      MatCreateAIJ(comm, rows, rows, global_rows, global_rows, 1, nullptr, 0, nullptr, diagonal.out()));
  PETSC_CHECK(MatDiagonalSet(diagonal, blocked, INSERT_VALUES));
  PETSC_CHECK(MatAXPY(K_, 1.0, diagonal, DIFFERENT_NONZERO_PATTERN));
}

void KrylovStokesSolver::make_outer_solver()
{
  const MPI_Comm comm = grid_.comm();
  PETSC_CHECK(KSPCreate(comm, ksp_.out()));
  PETSC_CHECK(KSPSetOperators(ksp_, A_, A_));
  PETSC_CHECK(KSPSetType(ksp_, KSPFGMRES));
  PETSC_CHECK(KSPGMRESSetRestart(ksp_, 50));
  PETSC_CHECK(
      KSPSetTolerances(ksp_, settings_.rtol, settings_.atol, PETSC_DEFAULT, settings_.max_iterations));
  PETSC_CHECK(KSPSetInitialGuessNonzero(ksp_, PETSC_TRUE));
  PC pc;
  PETSC_CHECK(KSPGetPC(ksp_, &pc));
  PETSC_CHECK(PCSetType(pc, PCSHELL));
  PETSC_CHECK(PCShellSetContext(pc, this));
  PETSC_CHECK(PCShellSetApply(pc, &KrylovStokesSolver::apply_projection));
  PETSC_CHECK(PCShellSetName(pc, "projection (Griffith 2009)"));
  PETSC_CHECK(KSPSetOptionsPrefix(ksp_, "fluid_stokes_"));
  PETSC_CHECK(KSPSetFromOptions(ksp_));
}

void KrylovStokesSolver::set_parameters(const StokesParameters& parameters)
{
  if (change_step(parameters)) return;
  destroy();
  parameters_ = parameters;
  const MPI_Comm comm = grid_.comm();
  PETSC_CHECK(DMCreateGlobalVector(grid_.dm(), x_.out()));
  PETSC_CHECK(VecDuplicate(x_, b_.out()));
  PetscInt local_size, global_size;
  PETSC_CHECK(VecGetLocalSize(x_, &local_size));
  PETSC_CHECK(VecGetSize(x_, &global_size));
  ISLocalToGlobalMapping l2g;
  PETSC_CHECK(DMGetLocalToGlobalMapping(grid_.dm(), &l2g));
  // Exact preallocation: a first pass counts the nonzeros.
  petsc::OwnedMat counter;
  PETSC_CHECK(MatCreate(comm, counter.out()));
  PETSC_CHECK(MatSetSizes(counter, local_size, local_size, global_size, global_size));
  PETSC_CHECK(MatSetType(counter, MATPREALLOCATOR));
  PETSC_CHECK(MatSetLocalToGlobalMapping(counter, l2g, l2g));
  PETSC_CHECK(MatSetUp(counter));
  assemble(counter);
  PETSC_CHECK(MatCreate(comm, A_.out()));
  PETSC_CHECK(MatSetSizes(A_, local_size, local_size, global_size, global_size));
  PETSC_CHECK(MatSetType(A_, MATAIJ));
  PETSC_CHECK(MatSetLocalToGlobalMapping(A_, l2g, l2g));
  PETSC_CHECK(MatPreallocatorPreallocate(counter, PETSC_TRUE, A_));
  counter.reset();
  assemble(A_);

  // Velocity and pressure index sets, and the blocks the projection preconditioner needs.
  DMStagStencil faces[3] = {{DMSTAG_LEFT, 0, 0, 0, 0}, {DMSTAG_DOWN, 0, 0, 0, 0}, {DMSTAG_BACK, 0, 0, 0, 0}};
  DMStagStencil cells[1] = {{DMSTAG_ELEMENT, 0, 0, 0, 0}};
  PETSC_CHECK(DMStagCreateISFromStencils(grid_.dm(), 3, faces, is_u_.out()));
  PETSC_CHECK(DMStagCreateISFromStencils(grid_.dm(), 1, cells, is_p_.out()));
  PETSC_CHECK(MatCreateSubMatrix(A_, is_u_, is_u_, MAT_INITIAL_MATRIX, H_.out()));
  PETSC_CHECK(MatCreateSubMatrix(A_, is_u_, is_p_, MAT_INITIAL_MATRIX, G_.out()));
  PETSC_CHECK(MatCreateSubMatrix(A_, is_p_, is_u_, MAT_INITIAL_MATRIX, Dn_.out()));
  PETSC_CHECK(MatMatMult(Dn_, G_, MAT_INITIAL_MATRIX, PETSC_DEFAULT, K_.out()));
  PETSC_CHECK(MatCreateVecs(K_, phi_.out(), r_p_.out()));
  PETSC_CHECK(MatCreateVecs(G_, nullptr, gphi_.out()));
  PETSC_CHECK(MatCreateVecs(H_, x_u_.out(), y_u_.out()));
  PETSC_CHECK(MatCreateVecs(K_, x_p_.out(), y_p_.out()));
  if (!solid_.empty()) regularise_blocked_cells();

  if (pressure_has_constant_)
    set_constant_pressure_null_space(comm, x_, is_p_, A_, K_, fluid_cells_ ? fluid_cells_.get() : nullptr);

  const bool transforms = transforms_used_;
  if (transforms && !transforms_)
    transforms_ = std::make_unique<TransformSubsolvers>(grid_, bc_, is_u_, is_p_);
  // Blocked cells the same in every z-plane: the exact axial solve, unless the options database names
  // another preconditioner (-fluid_poisson_pc_type hypre: BoomerAMG, as for any other region).
  if (!solid_.empty() && !axial_) {
    PetscBool other = PETSC_FALSE;
    PETSC_CHECK(PetscOptionsHasName(nullptr, "fluid_poisson_", "-pc_type", &other));
    if (!other) axial_ = AxialPoisson::make(grid_, K_, is_p_);
  }
  // With the transform sub-solves, a Helmholtz operator whose diagonal dominates (fluid/jacobi.hpp) is
  // inverted by two Jacobi sweeps, exact to q^2, for one matrix product, where the three transforms cost
  // several (docs/fluid.md). -fluid_helmholtz_jacobi_limit sets the limit on q (0: always the
  // transforms); the other -fluid_helmholtz_ options override the choice.
  helmholtz_by_jacobi_ = helmholtz_wants_jacobi();
  using ShellApply = PetscErrorCode (*)(PC, Vec, Vec);
  auto make_sub_ksp = [&](petsc::OwnedKSP& ksp, Mat op, const char* prefix, ShellApply transform) {
    PETSC_CHECK(KSPCreate(comm, ksp.out()));
    PETSC_CHECK(KSPSetOperators(ksp, op, op));
    PETSC_CHECK(KSPSetType(ksp, KSPPREONLY));
    PC pc;
    PETSC_CHECK(KSPGetPC(ksp, &pc));
    if (helmholtz_by_jacobi_ && op == H_.get()) {
      PETSC_CHECK(KSPSetType(ksp, KSPRICHARDSON));
      PETSC_CHECK(KSPSetNormType(ksp, KSP_NORM_NONE));
      PETSC_CHECK(KSPSetTolerances(ksp, PETSC_DEFAULT, PETSC_DEFAULT, PETSC_DEFAULT, jacobi_sweeps));
      PETSC_CHECK(PCSetType(pc, PCJACOBI));
    } else if (axial_ && op == K_.get()) {
      PETSC_CHECK(PCSetType(pc, PCSHELL));
      PETSC_CHECK(PCShellSetContext(pc, this));
      PETSC_CHECK(PCShellSetApply(pc, &KrylovStokesSolver::apply_axial_poisson));
      PETSC_CHECK(PCShellSetName(pc, "axial Poisson solve (z modes, a Cholesky factor a plane)"));
    } else if (transforms) {
      PETSC_CHECK(PCSetType(pc, PCSHELL));
      PETSC_CHECK(PCShellSetContext(pc, this));
      PETSC_CHECK(PCShellSetApply(pc, transform));
      PETSC_CHECK(PCShellSetName(pc, "FFTW real-to-real transform solve"));
    } else {
      PETSC_CHECK(PCSetType(pc, PCHYPRE));
      PETSC_CHECK(PCHYPRESetType(pc, "boomeramg"));
    }
    PETSC_CHECK(KSPSetOptionsPrefix(ksp, prefix));
    PETSC_CHECK(KSPSetFromOptions(ksp));
    PETSC_CHECK(KSPSetUp(ksp));
  };
  make_sub_ksp(ksp_h_, H_, "fluid_helmholtz_", &KrylovStokesSolver::apply_helmholtz_transform);
  make_sub_ksp(ksp_k_, K_, "fluid_poisson_", &KrylovStokesSolver::apply_poisson_transform);

  make_outer_solver();
}

PetscErrorCode KrylovStokesSolver::apply_projection(PC pc, Vec x, Vec y)
{
  PetscFunctionBeginUser;
  void* context = nullptr;
  PetscCall(PCShellGetContext(pc, &context));
  auto* self = static_cast<KrylovStokesSolver*>(context);
  // The blocks are copied through the index sets into vectors made once (VecISCopy: a local gather,
  // no scatter is built; VecGetSubVector would build and destroy one per call).
  Vec x_u = self->x_u_, y_u = self->y_u_, y_p = self->y_p_;
  PetscCall(VecISCopy(x, self->is_u_, SCATTER_REVERSE, x_u));
  PetscCall(VecISCopy(x, self->is_p_, SCATTER_REVERSE, self->x_p_));
  const double t0 = MPI_Wtime();
  PetscCall(KSPSolve(self->ksp_h_, x_u, y_u)); // u* = H^-1 w
  const double t1 = MPI_Wtime();
  PetscCall(MatMult(self->Dn_, y_u, self->r_p_)); // r = -D u* - g
  PetscCall(VecAXPY(self->r_p_, -1.0, self->x_p_));
  if (self->pressure_has_constant_) {
    // Keep the Poisson right side in the range of K (zero mean over the fluid cells).
    if (self->fluid_cells_) {
      PetscScalar sum, n;
      PetscCall(VecDot(self->r_p_, self->fluid_cells_, &sum));
      PetscCall(VecSum(self->fluid_cells_, &n));
      PetscCall(VecAXPY(self->r_p_, -sum / n, self->fluid_cells_));
    } else {
      PetscScalar sum;
      PetscInt n;
      PetscCall(VecSum(self->r_p_, &sum));
      PetscCall(VecGetSize(self->r_p_, &n));
      PetscCall(VecShift(self->r_p_, -sum / static_cast<double>(n)));
    }
  }
  PetscCall(KSPSolve(self->ksp_k_, self->r_p_, self->phi_)); // phi = K^-1 r
  PetscCall(MatMult(self->G_, self->phi_, self->gphi_));     // u = u* - G phi
  PetscCall(VecAXPY(y_u, -1.0, self->gphi_));
  // p = rho/dt phi + mu/2 r
  PetscCall(VecAXPBYPCZ(y_p, self->parameters_.rho / self->parameters_.dt, 0.5 * self->parameters_.mu, 0.0,
                        self->phi_, self->r_p_));
  if (self->fluid_cells_) {
    // Blocked cells' identity rows: p = x_p there, y_p = f y_p + (1 - f) x_p with the fluid indicator f.
    PetscCall(VecAXPY(y_p, -1.0, self->x_p_));
    PetscCall(VecPointwiseMult(y_p, y_p, self->fluid_cells_));
    PetscCall(VecAXPY(y_p, 1.0, self->x_p_));
  }
  const double t2 = MPI_Wtime();
  self->helmholtz_seconds_ += t1 - t0;
  self->poisson_seconds_ += t2 - t1;
  PetscCall(VecISCopy(y, self->is_u_, SCATTER_FORWARD, y_u));
  PetscCall(VecISCopy(y, self->is_p_, SCATTER_FORWARD, y_p));
  PetscFunctionReturn(0);
}

PetscErrorCode KrylovStokesSolver::apply_helmholtz_transform(PC pc, Vec x, Vec y)
{
  PetscFunctionBeginUser;
  void* context = nullptr;
  PetscCall(PCShellGetContext(pc, &context));
  auto* self = static_cast<KrylovStokesSolver*>(context);
  const StokesParameters& q = self->parameters_;
  try {
    self->transforms_->solve_helmholtz(self->H_, q.rho / q.dt, 0.5 * q.mu, x, y);
  } catch (const std::exception& e) {
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_LIB, "%s", e.what());
  }
  PetscFunctionReturn(0);
}

PetscErrorCode KrylovStokesSolver::apply_poisson_transform(PC pc, Vec x, Vec y)
{
  PetscFunctionBeginUser;
  void* context = nullptr;
  PetscCall(PCShellGetContext(pc, &context));
  auto* self = static_cast<KrylovStokesSolver*>(context);
  try {
    self->transforms_->solve_poisson(x, y);
  } catch (const std::exception& e) {
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_LIB, "%s", e.what());
  }
  PetscFunctionReturn(0);
}

PetscErrorCode KrylovStokesSolver::apply_axial_poisson(PC pc, Vec x, Vec y)
{
  PetscFunctionBeginUser;
  void* context = nullptr;
  PetscCall(PCShellGetContext(pc, &context));
  try {
    static_cast<KrylovStokesSolver*>(context)->axial_->solve(x, y);
  } catch (const std::exception& e) {
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_LIB, "%s", e.what());
  }
  PetscFunctionReturn(0);
}

void KrylovStokesSolver::add_boundary_terms(Vec rhs, double t_new, double t_half)
{
  StagArray r(grid_, rhs);
  std::vector<Entry> entries;
  double constant = 0.0;
  // Boundary data reach only the rows of boundary faces and of faces a cell from a non-periodic side
  // (their tangential wall ghost); every other row has no constant.
  auto touches_boundary = [&](int d, const Index3& idx) {
    for (int e = 0; e < 3; ++e) {
      if (grid_.periodic(e)) continue;
      const PetscInt last = e == d ? grid_.cells(e) : grid_.cells(e) - 1;
      if (idx[e] == 0 || idx[e] == last) return true;
    }
    return false;
  };
  for (int d = 0; d < 3; ++d)
    for_owned_faces(grid_, d, [&](const Index3& idx) {
      if (!touches_boundary(d, idx)) return;
      const bool dirichlet = velocity_row(d, idx, t_new, t_half, entries, constant);
      double& value = r(idx[0], idx[1], idx[2], grid_.face_slot(d));
      value = dirichlet ? constant : value + constant;
    });
  solid_.zero_rows(rhs);
  if (!pressure_has_constant_) return;
  // Without a traction side the boundary velocity must carry zero net flux for the system to have a
  // solution. Remove the discrete net outflow of the data (an O(h^2) change for smooth data that is
  // compatible in the continuum) in proportion to |u_n|, so impermeable walls stay impermeable.
  double sums[2] = {0.0, 0.0}; // net outflow, sum of |u_n| dA
  auto for_boundary_faces = [&](auto&& f) {
    for (int d = 0; d < 3; ++d) {
      if (grid_.periodic(d)) continue;
      const double area = grid_.cell_volume() / grid_.h(d);
      for_owned_faces(grid_, d, [&](const Index3& idx) {
        if (grid_.is_boundary_face(d, idx[d]))
          f(r(idx[0], idx[1], idx[2], grid_.face_slot(d)), idx[d] == 0 ? -1.0 : 1.0, area);
      });
    }
  };
  for_boundary_faces([&](double& un, double outward, double area) {
    sums[0] += outward * un * area;
    sums[1] += std::abs(un) * area;
  });
  MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPI_DOUBLE, MPI_SUM, grid_.comm());
  if (sums[1] == 0.0) return;
  const double c = sums[0] / sums[1];
  for_boundary_faces([&](double& un, double outward, double) { un -= outward * c * std::abs(un); });
}

void KrylovStokesSolver::set_homogeneous_boundary_rows(Vec rhs)
{
  solid_.zero_rows(rhs);
  StagArray r(grid_, rhs);
  std::vector<Entry> entries;
  double constant = 0.0;
  for (int d = 0; d < 3; ++d) {
    if (grid_.periodic(d)) continue;
    for_owned_faces(grid_, d, [&](const Index3& idx) {
      if (grid_.is_boundary_face(d, idx[d]) && velocity_row(d, idx, 0.0, 0.0, entries, constant))
        r(idx[0], idx[1], idx[2], grid_.face_slot(d)) = 0.0;
    });
  }
}

SolveStatistics KrylovStokesSolver::solve(Vec rhs, Vec solution)
{
  helmholtz_seconds_ = poisson_seconds_ = 0.0;
  const double start = MPI_Wtime();
  PETSC_CHECK(DMLocalToGlobal(grid_.dm(), rhs, INSERT_VALUES, b_));
  PETSC_CHECK(DMLocalToGlobal(grid_.dm(), solution, INSERT_VALUES, x_));
  PETSC_CHECK(KSPSolve(ksp_, b_, x_));
  KSPConvergedReason reason;
  PETSC_CHECK(KSPGetConvergedReason(ksp_, &reason));
  SolveStatistics stats;
  PETSC_CHECK(KSPGetIterationNumber(ksp_, &stats.iterations));
  PETSC_CHECK(KSPGetResidualNorm(ksp_, &stats.residual));
  if (reason < 0)
    throw std::runtime_error(
        fmt::format("fluid: the Stokes solver did not converge ({}, {} iterations, residual {:g})",
                    KSPConvergedReasons[reason], stats.iterations, stats.residual));
  PETSC_CHECK(DMGlobalToLocal(grid_.dm(), x_, INSERT_VALUES, solution));
  stats.helmholtz_seconds = helmholtz_seconds_;
  stats.poisson_seconds = MPI_Wtime() - start - helmholtz_seconds_;
  return stats;
}

} // namespace ibvalve::fluid
