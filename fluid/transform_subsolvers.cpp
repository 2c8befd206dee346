#include "fluid/transform_subsolvers.hpp"

#include <cmath>
#include <stdexcept>
#include <vector>

#include "io/petsc_check.hpp"

namespace ibvalve::fluid {

namespace {

// Every unknown of the grid's global vector is labelled by a code that names its kind (face of
// component 0..2, or cell = 3) and its indices, so the sub-vector layouts need no assumption about
// the order DMStag uses.
constexpr PetscInt cell_kind = 3;

struct Label {
  PetscInt kind;
  Index3 idx;
};

double encode(const StaggeredGrid& grid, PetscInt kind, PetscInt i, PetscInt j, PetscInt k)
{
  const PetscInt nx = grid.cells(0) + 1, ny = grid.cells(1) + 1;
  return static_cast<double>(4 * ((k * ny + j) * nx + i) + kind);
}

Label decode(const StaggeredGrid& grid, double code)
{
  const PetscInt nx = grid.cells(0) + 1, ny = grid.cells(1) + 1;
  const auto c = static_cast<PetscInt>(std::llround(code));
  const PetscInt kind = c % 4, linear = c / 4;
  return {kind, {linear % nx, (linear / nx) % ny, linear / (nx * ny)}};
}

EndCondition end_condition(const BoundaryConditions& bc, int d, int upper, bool velocity_is_dirichlet)
{
  switch (bc.side(d, upper).kind) {
  case SideKind::periodic:
    return EndCondition::periodic;
  case SideKind::velocity:
    return velocity_is_dirichlet ? EndCondition::dirichlet : EndCondition::neumann;
  case SideKind::traction:
    return velocity_is_dirichlet ? EndCondition::neumann : EndCondition::dirichlet;
  }
  return EndCondition::periodic;
}

} // namespace

TransformSubsolvers::TransformSubsolvers(const StaggeredGrid& grid, const BoundaryConditions& bc, IS velocity,
                                         IS pressure)
    : grid_(grid)
{
  // Codes on every owned unknown.
  petsc::OwnedVec local = grid.create_local(), global = grid.create_global();
  {
    StagArray a(grid, local);
    for (PetscInt k = grid.begin(2); k < grid.begin(2) + grid.count(2) + 1; ++k)
      for (PetscInt j = grid.begin(1); j < grid.begin(1) + grid.count(1) + 1; ++j)
        for (PetscInt i = grid.begin(0); i < grid.begin(0) + grid.count(0) + 1; ++i) {
          const Index3 idx{i, j, k};
          for (int d = 0; d < 3; ++d) {
            bool owned = true;
            for (int e = 0; e < 3; ++e) owned = owned && idx[e] < grid.face_end(d, e);
            if (owned) a(i, j, k, grid.face_slot(d)) = encode(grid, d, i, j, k);
          }
          bool cell = true;
          for (int e = 0; e < 3; ++e) cell = cell && idx[e] < grid.begin(e) + grid.count(e);
          if (cell) a(i, j, k, grid.pressure_slot()) = encode(grid, cell_kind, i, j, k);
        }
  }
  PETSC_CHECK(DMLocalToGlobal(grid.dm(), local, INSERT_VALUES, global));
  local.reset();

  std::array<TransformAxis, 3> axes;
  // Pressure: velocity side -> Neumann, traction side -> Dirichlet, at cell centres.
  for (int e = 0; e < 3; ++e)
    axes[e] = TransformAxis::make(Placement::cell, end_condition(bc, e, 0, false),
                                  end_condition(bc, e, 1, false), grid.cells(e), grid.h(e));
  Vec codes_p;
  PETSC_CHECK(VecGetSubVector(global, pressure, &codes_p));
  build(pressure_, axes, codes_p, codes_p, cell_kind, nullptr);
  PETSC_CHECK(VecRestoreSubVector(global, pressure, &codes_p));
  // -fluid_poisson_capacitance false: the uncorrected transform solve (a preconditioner only, for
  // comparison).
  PetscBool capacitance = PETSC_TRUE;
  PETSC_CHECK(PetscOptionsGetBool(nullptr, "fluid_poisson_", "-capacitance", &capacitance, nullptr));
  if (capacitance) capacitance_ = WalledSideCapacitance::make(grid, bc, *pressure_.solver);
  // x and y sides walled in part are not corrected; z sides only with the correction on.
  for (int s = 0; s < 6; ++s)
    if (bc.side(s).kind == SideKind::traction && bc.side(s).wall && (s < 4 || !capacitance))
      poisson_exact_ = false;

  Vec codes_u;
  PETSC_CHECK(VecGetSubVector(global, velocity, &codes_u));
  PETSC_CHECK(VecDuplicate(codes_u, dirichlet_.out()));
  PETSC_CHECK(VecDuplicate(codes_u, fixed_.out()));
  PETSC_CHECK(VecDuplicate(codes_u, work_.out()));
  PETSC_CHECK(VecZeroEntries(dirichlet_));
  for (int c = 0; c < 3; ++c) {
    for (int e = 0; e < 3; ++e) {
      if (e == c)
        // Along the component: nodes; a velocity side fixes the boundary node, a traction side is even.
        axes[e] = TransformAxis::make(Placement::node, end_condition(bc, e, 0, true),
                                      end_condition(bc, e, 1, true), grid.cells(e), grid.h(e));
      else if (grid.periodic(e))
        axes[e] = TransformAxis::make(Placement::cell, EndCondition::periodic, EndCondition::periodic,
                                      grid.cells(e), grid.h(e));
      else {
        // Tangential to a side: the linear ghost (odd about the side) in place of the quadratic one.
        axes[e] = TransformAxis::make(Placement::cell, EndCondition::dirichlet, EndCondition::dirichlet,
                                      grid.cells(e), grid.h(e));
        helmholtz_exact_ = false;
      }
    }
    build(velocity_[static_cast<std::size_t>(c)], axes, codes_u, codes_u, c, dirichlet_);
  }
  PETSC_CHECK(VecRestoreSubVector(global, velocity, &codes_u));
}

void TransformSubsolvers::build(Problem& problem, const std::array<TransformAxis, 3>& axes, Vec sub,
                                const Vec codes, PetscInt kind, Vec dirichlet_mask)
{
  const MPI_Comm comm = grid_.comm();
  problem.solver = std::make_unique<SeparableTransformSolver>(comm, axes);
  PETSC_CHECK(VecCreateMPIWithArray(comm, 1, problem.solver->local_size(), PETSC_DECIDE,
                                    problem.solver->data(), problem.transformed.out()));
  PetscInt start = 0, n = 0;
  PETSC_CHECK(VecGetOwnershipRange(codes, &start, nullptr));
  PETSC_CHECK(VecGetLocalSize(codes, &n));
  std::vector<PetscInt> from, to;
  const PetscScalar* c = nullptr;
  PETSC_CHECK(VecGetArrayRead(codes, &c));
  PetscScalar* mask = nullptr;
  if (dirichlet_mask) PETSC_CHECK(VecGetArray(dirichlet_mask, &mask));
  const PetscInt nx = axes[0].unknowns, ny = axes[1].unknowns;
  for (PetscInt m = 0; m < n; ++m) {
    const Label label = decode(grid_, c[m]);
    if (label.kind != kind) continue;
    Index3 j{};
    bool unknown = true;
    for (int e = 0; e < 3; ++e) {
      j[e] = label.idx[e] - axes[e].first;
      unknown = unknown && j[e] >= 0 && j[e] < axes[e].unknowns;
    }
    if (unknown) {
      from.push_back(start + m);
      to.push_back((j[2] * ny + j[1]) * nx + j[0]);
    } else if (mask) {
      mask[m] = 1.0; // a fixed boundary normal velocity (identity row)
    } else {
      throw std::logic_error("transform sub-solver: a cell outside the transform's unknowns");
    }
  }
  PETSC_CHECK(VecRestoreArrayRead(codes, &c));
  if (mask) PETSC_CHECK(VecRestoreArray(dirichlet_mask, &mask));
  PetscInt counted = static_cast<PetscInt>(from.size()), size = 0;
  MPI_Allreduce(MPI_IN_PLACE, &counted, 1, MPIU_INT, MPI_SUM, comm);
  PETSC_CHECK(VecGetSize(problem.transformed, &size));
  if (counted != size) throw std::logic_error("transform sub-solver: unknowns and transform sizes differ");
  petsc::OwnedIS is_from, is_to;
  PETSC_CHECK(ISCreateGeneral(comm, static_cast<PetscInt>(from.size()), from.data(), PETSC_COPY_VALUES,
                              is_from.out()));
  PETSC_CHECK(
      ISCreateGeneral(comm, static_cast<PetscInt>(to.size()), to.data(), PETSC_COPY_VALUES, is_to.out()));
  PETSC_CHECK(VecScatterCreate(sub, is_from, problem.transformed, is_to, problem.scatter.out()));
}

void TransformSubsolvers::solve_poisson(Vec r, Vec phi)
{
  PETSC_CHECK(VecScatterBegin(pressure_.scatter, r, pressure_.transformed, INSERT_VALUES, SCATTER_FORWARD));
  PETSC_CHECK(VecScatterEnd(pressure_.scatter, r, pressure_.transformed, INSERT_VALUES, SCATTER_FORWARD));
  if (capacitance_)
    capacitance_->solve(*pressure_.solver);
  else
    pressure_.solver->solve(0.0, 1.0); // K = -L
  PETSC_CHECK(VecScatterBegin(pressure_.scatter, pressure_.transformed, phi, INSERT_VALUES, SCATTER_REVERSE));
  PETSC_CHECK(VecScatterEnd(pressure_.scatter, pressure_.transformed, phi, INSERT_VALUES, SCATTER_REVERSE));
}

void TransformSubsolvers::solve_helmholtz(Mat H, double a, double b, Vec w, Vec u)
{
  // The fixed boundary normal velocities are w's identity rows; their couplings to the first interior
  // nodes move to the right side: work = w - H fixed (zero on the fixed rows).
  PETSC_CHECK(VecPointwiseMult(fixed_, dirichlet_, w));
  PETSC_CHECK(MatMult(H, fixed_, work_));
  PETSC_CHECK(VecAYPX(work_, -1.0, w));
  for (Problem& p : velocity_) {
    PETSC_CHECK(VecScatterBegin(p.scatter, work_, p.transformed, INSERT_VALUES, SCATTER_FORWARD));
    PETSC_CHECK(VecScatterEnd(p.scatter, work_, p.transformed, INSERT_VALUES, SCATTER_FORWARD));
    p.solver->solve(a, b);
  }
  PETSC_CHECK(VecCopy(fixed_, u));
  for (Problem& p : velocity_) {
    PETSC_CHECK(VecScatterBegin(p.scatter, p.transformed, u, INSERT_VALUES, SCATTER_REVERSE));
    PETSC_CHECK(VecScatterEnd(p.scatter, p.transformed, u, INSERT_VALUES, SCATTER_REVERSE));
  }
}

} // namespace ibvalve::fluid
