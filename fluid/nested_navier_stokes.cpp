#include "fluid/nested_navier_stokes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <fmt/format.h>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "base/errors.hpp"
#include "base/stopwatch.hpp"
#include "fluid/composite_multigrid.hpp"
#include "fluid/composite_output.hpp"
#include "fluid/composite_queries.hpp"
#include "fluid/jacobi.hpp"
#include "fluid/solver_clock.hpp"
#include "io/petsc_check.hpp"
#include "io/petsc_handle.hpp"
#include "io/petsc_options.hpp"

namespace ibvalve::fluid {

namespace {

// BoomerAMG's settings for the viscous solve (3D, wide stencils from the quadratic coarse-fine ghosts),
// unless the user chose others: HMIS coarsening, extended+i interpolation, strength threshold 0.5, at most 4
// interpolation weights per row (Falgout coarsening and classical interpolation, PETSc's defaults, cost
// several times more per solve here), and one forward hybrid Gauss-Seidel sweep down the V-cycle and one
// backward sweep up it: the cycle stays symmetric at half the smoothing work of PETSc's default (a
// symmetric sweep each way), with the same iterations on the study's valve grid (docs/nested.md). The
// projection takes them too when the box has pressure sides (its operator is then non-singular): 1.7x faster
// on the study's valve grid. In a closed box it keeps PETSc's defaults: with these settings GMRES breaks down
// on the singular operator of the ratio-4 Taylor-Green test on 2 ranks (docs/nested.md). `prefix` is the
// solver's options prefix with its leading dash; returns the options it set (those the user had not).
std::vector<std::string> set_default_amg_options(const std::string& prefix)
{
  const std::vector<std::pair<std::string, std::string>> defaults{
      {"coarsen_type", "HMIS"}, {"interp_type", "ext+i"},          {"strong_threshold", "0.5"},
      {"P_max", "4"},           {"relax_type_down", "SOR/Jacobi"}, {"relax_type_up", "backward-SOR/Jacobi"}};
  std::vector<std::string> added;
  for (const auto& [name, value] : defaults) {
    const std::string option = prefix + "pc_hypre_boomeramg_" + name;
    if (petsc::set_option_unless_given(option, value)) added.push_back(option);
  }
  return added;
}

PetscInt floor_div(PetscInt a, PetscInt b)
{
  return a >= 0 ? a / b : -((-a + b - 1) / b);
}

/// Derivative at 0 of the Lagrange basis of the three nodes s.
std::array<double, 3> derivative_weights(const std::array<double, 3>& s)
{
  std::array<double, 3> w{};
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    w[a] = -(s[b] + s[c]) / ((s[a] - s[b]) * (s[a] - s[c]));
  }
  return w;
}

std::vector<double> lagrange(const std::vector<PetscInt>& nodes, double x)
{
  std::vector<double> w(nodes.size(), 1.0);
  for (std::size_t i = 0; i < nodes.size(); ++i)
    for (std::size_t j = 0; j < nodes.size(); ++j)
      if (j != i) w[i] *= (x - static_cast<double>(nodes[j])) / static_cast<double>(nodes[i] - nodes[j]);
  return w;
}

void check_reason(KSP ksp, const char* what)
{
  KSPConvergedReason reason;
  PETSC_CHECK(KSPGetConvergedReason(ksp, &reason));
  if (reason < 0) {
    PetscInt iterations = 0;
    PETSC_CHECK(KSPGetIterationNumber(ksp, &iterations));
    throw RunError(fmt::format("nested Navier-Stokes: the {} solve diverged ({}) after {} iterations", what,
                               KSPConvergedReasons[reason], iterations));
  }
}

} // namespace

namespace {

/// U* at the coarse-fine face `k`: the tensor quadratic interpolation of the coarse layer along the
/// interface (the coarse cells of level l-1 beside `coarse` and their weights), on the first of the
/// sample windows whose cells are all composite cells.
std::vector<std::pair<PetscInt, double>> coarse_layer_stencil(const CompositeVelocity& velocity,
                                                              const FaceKey& k, const Index3& coarse)
{
  const GridHierarchy& h = velocity.hierarchy();
  const CompositeCells& cells = velocity.operators().cells();
  const int l = k.level, d = k.normal;
  const Real3 x = velocity.position(k);
  std::array<std::vector<std::vector<PetscInt>>, 3> windows;
  std::array<double, 3> target{};
  for (int e = 0; e < 3; ++e) {
    if (e == d) {
      windows[e] = {{coarse[e]}};
      continue;
    }
    target[e] = (x[e] - h.domain().lower[e]) / h.h(l - 1, e) - 0.5;
    windows[e] = sample_windows(target[e], h.domain_cells(l - 1)[e] - 1);
  }
  std::vector<std::pair<PetscInt, double>> interpolated;
  for (const auto& wx : windows[0]) {
    for (const auto& wy : windows[1]) {
      for (const auto& wz : windows[2]) {
        bool ok = true;
        for (const PetscInt a : wx)
          for (const PetscInt b : wy)
            for (const PetscInt c : wz) ok = ok && cells.index(l - 1, {a, b, c}) >= 0;
        if (!ok) continue;
        const auto ax = d == 0 ? std::vector<double>{1.0} : lagrange(wx, target[0]);
        const auto ay = d == 1 ? std::vector<double>{1.0} : lagrange(wy, target[1]);
        const auto az = d == 2 ? std::vector<double>{1.0} : lagrange(wz, target[2]);
        for (std::size_t c = 0; c < wz.size(); ++c)
          for (std::size_t b = 0; b < wy.size(); ++b)
            for (std::size_t a = 0; a < wx.size(); ++a)
              interpolated.emplace_back(cells.index(l - 1, {wx[a], wy[b], wz[c]}), ax[a] * ay[b] * az[c]);
        return interpolated;
      }
    }
  }
  throw std::logic_error("consistent composite gradient: no coarse stencil along the interface");
}

/// The row of G at the coarse-fine face `k` (its cells `lower` below and `above`, one of them covered or
/// outside the level): the normal derivative from the fine cells and U*, xi running along the normal
/// from the fine cell towards the coarse one.
void coarse_fine_row(const CompositeVelocity& velocity, const FaceKey& k, const Index3& lower, PetscInt above,
                     std::vector<PetscInt>& columns, std::vector<PetscScalar>& values)
{
  const GridHierarchy& h = velocity.hierarchy();
  const CompositeCells& cells = velocity.operators().cells();
  const int l = k.level, d = k.normal;
  const double hd = h.h(l, d);
  const int side = above < 0 ? 1 : -1;
  const Index3 fine = side > 0 ? lower : k.index, outside = side > 0 ? k.index : lower;
  const PetscInt r = h.ratio(l);
  Index3 coarse;
  for (int e = 0; e < 3; ++e) coarse[e] = floor_div(outside[e], r);
  const std::vector<std::pair<PetscInt, double>> interpolated = coarse_layer_stencil(velocity, k, coarse);
  const double H = h.h(l - 1, d);
  Index3 second = fine;
  second[d] -= side;
  const PetscInt f1 = cells.index(l, fine), f2 = cells.index(l, second);
  double coarse_weight = 0.0;
  if (f2 >= 0) {
    const auto w = derivative_weights({-1.5 * hd, -0.5 * hd, 0.5 * H});
    columns = {f2, f1};
    values = {side * w[0], side * w[1]};
    coarse_weight = side * w[2];
  } else {
    const double distance = 0.5 * (hd + H);
    columns = {f1};
    values = {-side / distance};
    coarse_weight = side / distance;
  }
  for (const auto& [c, w] : interpolated) {
    columns.push_back(c);
    values.push_back(coarse_weight * w);
  }
}

} // namespace

petsc::OwnedMat consistent_composite_gradient(const CompositeVelocity& velocity)
{
  const CompositeOperators& ops = velocity.operators();
  const GridHierarchy& h = velocity.hierarchy();
  const CompositeCells& cells = ops.cells();
  const auto& keys = velocity.owned_keys();
  PetscInt local_cells = 0;
  {
    const petsc::OwnedVec v = ops.create_cell_vector();
    PETSC_CHECK(VecGetLocalSize(v, &local_cells));
  }
  petsc::OwnedMat g;
  PETSC_CHECK(MatCreateAIJ(ops.comm(), static_cast<PetscInt>(keys.size()), local_cells, PETSC_DETERMINE,
                           cells.size(), 12, nullptr, 12, nullptr, g.out()));
  PETSC_CHECK(MatSetOption(g, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_FALSE));
  PetscInt row = 0;
  {
    PetscInt end = 0;
    PETSC_CHECK(MatGetOwnershipRange(g, &row, &end));
  }
  for (const FaceKey& k : keys) {
    const int l = k.level, d = k.normal;
    Index3 lower = k.index;
    --lower[d];
    const PetscInt below = cells.index(l, lower), above = cells.index(l, k.index);
    std::vector<PetscInt> columns;
    std::vector<PetscScalar> values;
    const double hd = h.h(l, d);
    if (k.index[d] == 0 || k.index[d] == h.domain_cells(l)[d]) {
      // A traction face: (p_b - p)/(h/2) on the upper side, (p - p_b)/(h/2) on the lower one (p_b in the
      // boundary part, NestedNavierStokes::pressure_boundary_part), as in the two-point operators.
      const bool upper = k.index[d] != 0;
      columns = {upper ? below : above};
      values = {(upper ? -2.0 : 2.0) / hd};
    } else if (below >= 0 && above >= 0) {
      columns = {above, below};
      values = {1.0 / hd, -1.0 / hd};
    } else {
      coarse_fine_row(velocity, k, lower, above, columns, values);
    }
    PETSC_CHECK(MatSetValues(g, 1, &row, static_cast<PetscInt>(columns.size()), columns.data(), values.data(),
                             ADD_VALUES));
    ++row;
  }
  PETSC_CHECK(MatAssemblyBegin(g, MAT_FINAL_ASSEMBLY));
  PETSC_CHECK(MatAssemblyEnd(g, MAT_FINAL_ASSEMBLY));
  return g;
}

namespace {

BoundaryConditions closed_box(const VelocityFunction& wall_velocity)
{
  BoundaryConditions bc;
  for (int side = 0; side < 6; ++side) {
    bc.side(side).kind = SideKind::velocity;
    bc.side(side).velocity = wall_velocity;
  }
  return bc;
}

} // namespace

NestedNavierStokes::NestedNavierStokes(MPI_Comm comm, const GridHierarchy& hierarchy,
                                       VelocityFunction wall_velocity, const FluidSettings& settings)
    : NestedNavierStokes(comm, hierarchy, closed_box(wall_velocity), settings)
{
}

NestedNavierStokes::NestedNavierStokes(MPI_Comm comm, const GridHierarchy& hierarchy, BoundaryConditions bc,
                                       const FluidSettings& settings)
    : comm_(comm), hierarchy_(&hierarchy), bc_(std::move(bc)), settings_(settings)
{
  if (!(settings.rho > 0.0) || !(settings.mu >= 0.0))
    throw std::invalid_argument("nested Navier-Stokes: rho must be positive and mu non-negative");
  if (bc_.solid()) throw std::invalid_argument("nested Navier-Stokes: blocked cells need one grid");
  for (int side = 0; side < 6; ++side)
    if (bc_.side(side).kind == SideKind::periodic)
      throw std::invalid_argument("nested Navier-Stokes: side " + side_name(side) +
                                  " is periodic; nested levels take velocity and traction sides only");
  // The wall data at a boundary point: the velocity side's function there (a point on an edge takes the
  // first velocity side it lies on), zero on traction sides (zero tangential velocity, and walled parts).
  wall_velocity_ = [this](const Real3& x, double t) {
    const BoxGeometry& box = hierarchy_->domain();
    for (int side = 0; side < 6; ++side) {
      const int d = side / 2;
      const double plane = side % 2 == 1 ? box.upper[d] : box.lower[d];
      const BoundarySide& b = bc_.side(side);
      if (b.kind == SideKind::velocity && b.velocity && std::abs(x[d] - plane) <= 1e-9 * box.length(d))
        return b.velocity(x, t);
    }
    return Real3{0.0, 0.0, 0.0};
  };
  // The operators first (the projection's preconditioner is one of them), then the two solvers, then the
  // state; PETSc's options are read by the solvers in this order, as they always were.
  const Mat preconditioner = build_operators();
  set_up_pressure_solver(preconditioner);
  set_up_velocity_solver();

  u_ = operators_->create_face_vector();
  force_ = operators_->create_face_vector();
  convection_ = operators_->create_face_vector();
  convection_old_ = operators_->create_face_vector();
  p_ = operators_->create_cell_vector();
  PETSC_CHECK(VecScatterCreateToAll(p_, pressure_gather_.out(), pressure_gathered_.out()));
  if (hierarchy.boxes(hierarchy.finest()).size() == 1) build_finest_level();
}

Mat NestedNavierStokes::build_operators()
{
  const bool open = bc_.any_traction();
  const DirichletFaces traction = [this](int side, const Real3& x) { return bc_.traction_at(side, x); };
  const CompositeBoundary boundary = open ? CompositeBoundary::mixed : CompositeBoundary::neumann;
  operators_ = std::make_unique<CompositeOperators>(comm_, *hierarchy_, CoarseFineStencil::two_point,
                                                    boundary, nullptr, open ? traction : DirichletFaces{});
  velocity_ops_ = std::make_unique<CompositeVelocity>(*operators_);
  Mat preconditioner = nullptr;
  if (settings_.coupling == PressureCoupling::consistent) {
    gradient_ = consistent_composite_gradient(*velocity_ops_);
    divergence_ = petsc::OwnedMat::shared(operators_->gradient());
    preconditioner = operators_->laplacian();
  } else {
    tangential_ =
        std::make_unique<CompositeOperators>(comm_, *hierarchy_, CoarseFineStencil::tangential_linear,
                                             boundary, nullptr, open ? traction : DirichletFaces{});
    gradient_ = petsc::OwnedMat::shared(tangential_->gradient());
    divergence_ = petsc::OwnedMat::shared(tangential_->gradient());
  }
  {
    petsc::OwnedMat weighted;
    PETSC_CHECK(MatDuplicate(gradient_, MAT_COPY_VALUES, weighted.out()));
    PETSC_CHECK(MatDiagonalScale(weighted, operators_->weights(), nullptr));
    PETSC_CHECK(
        MatTransposeMatMult(divergence_, weighted, MAT_INITIAL_MATRIX, PETSC_DEFAULT, projection_.out()));
  }
  if (!preconditioner) preconditioner = projection_;
  if (!operators_->any_dirichlet()) {
    // A closed box: the pressure is defined up to a constant.
    PETSC_CHECK(MatNullSpaceCreate(comm_, PETSC_TRUE, 0, nullptr, constants_.out()));
    PETSC_CHECK(MatSetNullSpace(projection_, constants_));
    PETSC_CHECK(MatSetTransposeNullSpace(projection_, constants_));
  }
  return preconditioner;
}

void NestedNavierStokes::set_up_pressure_solver(Mat preconditioner)
{
  const std::string pressure_prefix = settings_.nested_prefix + "pressure_";
  PetscBool multigrid = PETSC_FALSE;
  PETSC_CHECK(
      PetscOptionsGetBool(nullptr, pressure_prefix.c_str(), "-composite_multigrid", &multigrid, nullptr));
  if (multigrid && !operators_->any_dirichlet())
    throw std::invalid_argument("-" + pressure_prefix +
                                "composite_multigrid needs a traction side: in a closed box the "
                                "projection's operator is singular");
  PC pc = nullptr;
  PETSC_CHECK(KSPCreate(comm_, pressure_ksp_.out()));
  // The composite multigrid smooths the projection's own operator on the composite cells and builds only
  // its coarse spaces from `preconditioner`: smoothing A_tp's error instead of M's cost 4 of the 14 GMRES
  // iterations on the study's valve grid (docs/nested.md, "The projection's multigrid").
  PETSC_CHECK(KSPSetOperators(pressure_ksp_, projection_, multigrid ? projection_.get() : preconditioner));
  if (settings_.coupling == PressureCoupling::consistent) {
    PETSC_CHECK(KSPSetType(pressure_ksp_, KSPGMRES));
    PETSC_CHECK(KSPSetPCSide(pressure_ksp_, PC_RIGHT));
  } else {
    PETSC_CHECK(KSPSetType(pressure_ksp_, KSPCG));
    PETSC_CHECK(KSPSetNormType(pressure_ksp_, KSP_NORM_UNPRECONDITIONED));
  }
  PETSC_CHECK(KSPSetTolerances(pressure_ksp_, settings_.rtol, 1e-50, PETSC_DEFAULT, 1000));
  PETSC_CHECK(KSPSetOptionsPrefix(pressure_ksp_, pressure_prefix.c_str()));
  // The prefix first: the multigrid's level solvers take theirs from it when they are made.
  PETSC_CHECK(KSPGetPC(pressure_ksp_, &pc));
  if (multigrid) {
    set_composite_multigrid(pc, preconditioner, operators_->cells());
  } else {
    PETSC_CHECK(PCSetType(pc, PCHYPRE));
    PETSC_CHECK(PCHYPRESetType(pc, "boomeramg"));
  }
  {
    // Set for this solver only: a closed-box solver made later in the process keeps PETSc's defaults.
    const std::vector<std::string> added = !multigrid && operators_->any_dirichlet()
                                               ? set_default_amg_options("-" + pressure_prefix)
                                               : std::vector<std::string>{};
    PETSC_CHECK(KSPSetFromOptions(pressure_ksp_));
    for (const std::string& option : added) PETSC_CHECK(PetscOptionsClearValue(nullptr, option.c_str()));
  }
}

void NestedNavierStokes::set_up_velocity_solver()
{
  PC pc = nullptr;
  PETSC_CHECK(KSPCreate(comm_, velocity_ksp_.out()));
  PETSC_CHECK(KSPSetType(velocity_ksp_, KSPGMRES));
  PETSC_CHECK(KSPSetPCSide(velocity_ksp_, PC_RIGHT));
  PETSC_CHECK(KSPGetPC(velocity_ksp_, &pc));
  PETSC_CHECK(PCSetType(pc, PCHYPRE));
  PETSC_CHECK(PCHYPRESetType(pc, "boomeramg"));
  PETSC_CHECK(KSPSetInitialGuessNonzero(velocity_ksp_, PETSC_TRUE));
  PETSC_CHECK(KSPSetTolerances(velocity_ksp_, settings_.rtol, 1e-50, PETSC_DEFAULT, 1000));
  PETSC_CHECK(KSPSetOptionsPrefix(velocity_ksp_, (settings_.nested_prefix + "velocity_").c_str()));
}

void NestedNavierStokes::set_initial_condition(const VelocityFunction& velocity,
                                               const ScalarFunction& pressure, double t)
{
  operators_->sample_normal([&](const Real3& x) { return velocity(x, t); }, u_);
  if (pressure)
    operators_->sample([&](const Real3& x) { return pressure(x, t); }, p_);
  else
    PETSC_CHECK(VecSet(p_, 0.0));
  time_ = pressure_time_ = t;
  have_old_convection_ = false;
}

void NestedNavierStokes::set_body_force(const VelocityFunction& force, double t)
{
  operators_->sample_normal([&](const Real3& x) { return force(x, t); }, force_);
}

void NestedNavierStokes::build_helmholtz(double dt)
{
  if (helmholtz_ && dt == helmholtz_dt_) return;
  PETSC_CHECK(MatDuplicate(velocity_ops_->laplacian(), MAT_COPY_VALUES, helmholtz_.out()));
  PETSC_CHECK(MatScale(helmholtz_, -0.5 * settings_.mu));
  PETSC_CHECK(MatShift(helmholtz_, settings_.rho / dt));
  PETSC_CHECK(KSPSetOperators(velocity_ksp_, helmholtz_, helmholtz_));
  // When the diagonal dominates (a small viscous number: the study's valve grid has q = 6e-5), Jacobi
  // makes each GMRES iteration reduce the residual by about q, so the solve needs two or three
  // iterations of one matrix product each, where BoomerAMG's set-up and V-cycles cost far more
  // (docs/nested.md). Options under <prefix>velocity_ still choose otherwise.
  PC pc;
  PETSC_CHECK(KSPGetPC(velocity_ksp_, &pc));
  velocity_by_jacobi_ = jacobi_ratio(helmholtz_) <= jacobi_ratio_limit;
  if (velocity_by_jacobi_) {
    PETSC_CHECK(PCSetType(pc, PCJACOBI));
  } else {
    PETSC_CHECK(PCSetType(pc, PCHYPRE));
    PETSC_CHECK(PCHYPRESetType(pc, "boomeramg"));
  }
  // The AMG settings only when AMG is used (set for this solve and taken back, so that a Jacobi-
  // preconditioned run is not warned of options it never read).
  const std::vector<std::string> added =
      velocity_by_jacobi_ ? std::vector<std::string>{}
                          : set_default_amg_options("-" + settings_.nested_prefix + "velocity_");
  PETSC_CHECK(KSPSetFromOptions(velocity_ksp_));
  for (const std::string& option : added) PETSC_CHECK(PetscOptionsClearValue(nullptr, option.c_str()));
  helmholtz_dt_ = dt;
}

void NestedNavierStokes::advance(double dt, Vec convection_half)
{
  const double rho = settings_.rho, mu = settings_.mu, t0 = time_, t1 = time_ + dt;
  build_helmholtz(dt);
  const petsc::OwnedVec rhs = operators_->create_face_vector(), work = operators_->create_face_vector();
  {
    base::Stopwatch watch(stats_.viscous);
    // rho/dt u^n + mu/2 (L u^n + b(g^n) + b(g^{n+1})) - rho N - G p + f
    PETSC_CHECK(MatMult(velocity_ops_->laplacian(), u_, rhs));
    velocity_ops_->laplacian_data(velocity_ops_->data_values(wall_velocity_, t0), work);
    PETSC_CHECK(VecAXPY(rhs, 1.0, work));
    velocity_ops_->laplacian_data(velocity_ops_->data_values(wall_velocity_, t1), work);
    PETSC_CHECK(VecAXPY(rhs, 1.0, work));
    PETSC_CHECK(VecScale(rhs, 0.5 * mu));
    PETSC_CHECK(VecAXPY(rhs, rho / dt, u_));
    PETSC_CHECK(VecAXPY(rhs, -rho, convection_half));
    PETSC_CHECK(MatMult(gradient_, p_, work));
    PETSC_CHECK(VecAXPY(rhs, -1.0, work));
    if (operators_->any_dirichlet()) {
      pressure_boundary_part(t0 + 0.5 * dt, work);
      PETSC_CHECK(VecAXPY(rhs, -1.0, work));
    }
    PETSC_CHECK(VecAXPY(rhs, 1.0, force_));
    PETSC_CHECK(KSPSolve(velocity_ksp_, rhs, u_)); // u_ := u*
    check_reason(velocity_ksp_, "viscous");
    PETSC_CHECK(KSPGetIterationNumber(velocity_ksp_, &velocity_iterations_));
  }
  {
    base::Stopwatch watch(stats_.pressure);
    const petsc::OwnedVec b = operators_->create_cell_vector(), phi = operators_->create_cell_vector(),
                          m_phi = operators_->create_cell_vector();
    PETSC_CHECK(VecPointwiseMult(work, operators_->weights(), u_));
    PETSC_CHECK(MatMultTranspose(divergence_, work, b));
    PETSC_CHECK(KSPSolve(pressure_ksp_, b, phi));
    check_reason(pressure_ksp_, "projection");
    PETSC_CHECK(KSPGetIterationNumber(pressure_ksp_, &pressure_iterations_));
    PETSC_CHECK(MatMult(gradient_, phi, work));
    PETSC_CHECK(VecAXPY(u_, -1.0, work));
    // p^{n+1/2} = p^{n-1/2} + rho/dt phi - mu/2 D G phi, with D G phi = -V^{-1} M phi.
    PETSC_CHECK(MatMult(projection_, phi, m_phi));
    PETSC_CHECK(VecPointwiseDivide(m_phi, m_phi, operators_->volumes()));
    PETSC_CHECK(VecAXPY(p_, rho / dt, phi));
    PETSC_CHECK(VecAXPY(p_, 0.5 * mu, m_phi));
  }
}

void NestedNavierStokes::pressure_boundary_part(double t, Vec out) const
{
  const auto& faces = operators_->owned_faces();
  const double rho = settings_.rho;
  const PetscScalar* u = nullptr;
  PetscScalar* c = nullptr;
  PETSC_CHECK(VecGetArrayRead(u_, &u));
  PETSC_CHECK(VecGetArray(out, &c));
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const CompositeFace& face = faces[f];
    c[f] = 0.0;
    if (!face.on_boundary) continue;
    const BoundarySide& side = bc_.side(face.side);
    double p_b = side.pressure ? side.pressure(face.center, t) : 0.0;
    // Backflow stabilization (fluid/boundary.hpp): inflow through the side pays beta rho/2 (u.n)^2.
    const double u_n = face.outward * u[f];
    if (side.backflow > 0.0 && u_n < 0.0) p_b -= 0.5 * side.backflow * rho * u_n * u_n;
    c[f] = face.outward * 2.0 / hierarchy_->h(face.level, face.normal) * p_b;
  }
  PETSC_CHECK(VecRestoreArray(out, &c));
  PETSC_CHECK(VecRestoreArrayRead(u_, &u));
}

void NestedNavierStokes::step(double dt)
{
  if (!(dt > 0.0)) throw std::invalid_argument("nested Navier-Stokes: dt must be positive");
  base::Stopwatch total(stats_.total);
  {
    base::Stopwatch watch(stats_.convection);
    velocity_ops_->convection(u_, velocity_ops_->data_values(wall_velocity_, time_), convection_,
                              settings_.convection);
  }
  const petsc::OwnedVec half = operators_->create_face_vector();
  if (have_old_convection_) {
    const double r = dt / last_dt_;
    PETSC_CHECK(VecAXPBYPCZ(half, 1.0 + 0.5 * r, -0.5 * r, 0.0, convection_, convection_old_));
    advance(dt, half);
  } else {
    // Heun: a predictor step with N(u^n), then the step again with (N(u^n) + N(u~^{n+1}))/2.
    petsc::OwnedVec u0, p0;
    PETSC_CHECK(VecDuplicate(u_, u0.out()));
    PETSC_CHECK(VecCopy(u_, u0));
    PETSC_CHECK(VecDuplicate(p_, p0.out()));
    PETSC_CHECK(VecCopy(p_, p0));
    advance(dt, convection_);
    {
      base::Stopwatch watch(stats_.convection);
      velocity_ops_->convection(u_, velocity_ops_->data_values(wall_velocity_, time_ + dt), half,
                                settings_.convection);
    }
    PETSC_CHECK(VecAXPBY(half, 0.5, 0.5, convection_));
    PETSC_CHECK(VecCopy(u0, u_));
    PETSC_CHECK(VecCopy(p0, p_));
    u0.reset();
    p0.reset();
    advance(dt, half);
  }
  PETSC_CHECK(VecCopy(convection_, convection_old_));
  have_old_convection_ = true;
  last_dt_ = dt;
  time_ += dt;
  pressure_time_ = time_ - 0.5 * dt;
  ++stats_.steps;
  stats_.solver_iterations += velocity_iterations_ + pressure_iterations_;
  double u_max = 0.0;
  PETSC_CHECK(VecNorm(u_, NORM_INFINITY, &u_max));
  if (!std::isfinite(u_max))
    throw RunError(fmt::format("nested Navier-Stokes: the velocity is not finite at t = {:g} s", time_));
}

namespace {

// A distributed vector as one dataset in global order: each rank writes its ownership range.
void write_vector(io::Hdf5File& file, const std::string& name, Vec v)
{
  PetscInt begin = 0, end = 0, size = 0;
  PETSC_CHECK(VecGetOwnershipRange(v, &begin, &end));
  PETSC_CHECK(VecGetSize(v, &size));
  const PetscScalar* a = nullptr;
  PETSC_CHECK(VecGetArrayRead(v, &a));
  const std::array<hsize_t, 1> dims{static_cast<hsize_t>(size)}, offset{static_cast<hsize_t>(begin)},
      count{static_cast<hsize_t>(end - begin)};
  file.write_block(name, std::span<const double>(a, static_cast<std::size_t>(end - begin)), dims, offset,
                   count);
  PETSC_CHECK(VecRestoreArrayRead(v, &a));
}

void read_vector(const io::Hdf5File& file, const std::string& name, Vec v)
{
  PetscInt begin = 0, end = 0, size = 0;
  PETSC_CHECK(VecGetOwnershipRange(v, &begin, &end));
  PETSC_CHECK(VecGetSize(v, &size));
  const std::vector<hsize_t> dims = file.has(name) ? file.dims(name) : std::vector<hsize_t>{};
  if (dims.size() != 1 || dims[0] != static_cast<hsize_t>(size))
    throw std::runtime_error(fmt::format("{}: {} is missing or does not fit this grid hierarchy ({} values)",
                                         file.path().string(), name, size));
  const std::array<hsize_t, 1> offset{static_cast<hsize_t>(begin)}, count{static_cast<hsize_t>(end - begin)};
  const std::vector<double> values = file.read_block(name, offset, count);
  PetscScalar* a = nullptr;
  PETSC_CHECK(VecGetArray(v, &a));
  std::copy(values.begin(), values.end(), a);
  PETSC_CHECK(VecRestoreArray(v, &a));
}

/// The finest level whose boxes hold the point x (0 when none does).
int finest_level_holding(const GridHierarchy& h, const Real3& x)
{
  for (int l = h.finest(); l > 0; --l) {
    Index3 cell;
    for (int e = 0; e < 3; ++e)
      cell[e] = static_cast<PetscInt>(std::floor((x[e] - h.domain().lower[e]) / h.h(l, e)));
    if (h.box_containing(l, cell) >= 0) return l;
  }
  return 0;
}

} // namespace

void NestedNavierStokes::save(io::Hdf5File& file, const std::string& group) const
{
  // After a step, convection_old_ holds N^n; the next step extrapolates from it.
  write_vector(file, group + "/velocity", u_);
  write_vector(file, group + "/pressure", p_);
  write_vector(file, group + "/convection", convection_old_);
  write_vector(file, group + "/body_force", force_);
  write_solver_clock(file, group, {time_, pressure_time_, last_dt_, stats_.steps, have_old_convection_});
}

void NestedNavierStokes::restore(const io::Hdf5File& file, const std::string& group)
{
  const SolverClock clock = read_solver_clock(file, group, "nested fluid checkpoint");
  read_vector(file, group + "/velocity", u_);
  read_vector(file, group + "/pressure", p_);
  read_vector(file, group + "/convection", convection_old_);
  read_vector(file, group + "/body_force", force_);
  time_ = clock.time;
  pressure_time_ = clock.pressure_time;
  last_dt_ = clock.last_dt;
  stats_.steps = static_cast<PetscInt>(clock.steps);
  have_old_convection_ = clock.have_old_convection;
}

std::vector<double> NestedNavierStokes::max_divergence_by_level() const
{
  const petsc::OwnedVec w = operators_->create_face_vector(), div = operators_->create_cell_vector();
  PETSC_CHECK(VecPointwiseMult(w, operators_->weights(), u_));
  PETSC_CHECK(MatMultTranspose(divergence_, w, div));
  PETSC_CHECK(VecPointwiseDivide(div, div, operators_->volumes()));
  PetscInt begin = 0, end = 0;
  PETSC_CHECK(VecGetOwnershipRange(div, &begin, &end));
  std::vector<double> local(hierarchy_->levels(), 0.0), global(hierarchy_->levels(), 0.0);
  const PetscScalar* a = nullptr;
  PETSC_CHECK(VecGetArrayRead(div, &a));
  operators_->cells().for_each(begin, end, [&](PetscInt n, const CompositeCells::Cell& c) {
    local[c.level] = std::max(local[c.level], std::abs(a[n - begin]));
  });
  PETSC_CHECK(VecRestoreArrayRead(div, &a));
  MPI_Allreduce(local.data(), global.data(), hierarchy_->levels(), MPI_DOUBLE, MPI_MAX, comm_);
  return global;
}

double NestedNavierStokes::flux(const PlaneRegion& region) const
{
  // On a face plane of level 0 the composite faces there; between two, linear along the normal as on
  // one grid (fluid/queries.hpp, volume_flux).
  const int a = region.normal;
  const double h0 = hierarchy_->h(0, a), lower = hierarchy_->domain().lower[a];
  const double s = (region.position - lower) / h0;
  if (std::abs(s - std::round(s)) <= 1e-9 * std::max(1.0, std::abs(s)))
    return composite_flux(*operators_, u_, region);
  const double below = std::floor(s), weight = s - below;
  PlaneRegion lower_plane = region, upper_plane = region;
  lower_plane.position = lower + below * h0;
  upper_plane.position = lower + (below + 1.0) * h0;
  return (1.0 - weight) * composite_flux(*operators_, u_, lower_plane) +
         weight * composite_flux(*operators_, u_, upper_plane);
}

std::vector<double> NestedNavierStokes::pressure_at(const std::vector<Real3>& points) const
{
  const GridHierarchy& h = *hierarchy_;
  const CompositeCells& cells = operators_->cells();
  const std::vector<double> p = gathered_pressure();
  // The pressure of a cell of any level: its composite value, the mean of its finer cells when covered,
  // its coarser cell's value when outside its level.
  std::function<double(int, const Index3&)> cell_value = [&](int l, const Index3& c) -> double {
    if (h.box_containing(l, c) < 0) {
      Index3 coarse;
      for (int e = 0; e < 3; ++e) coarse[e] = floor_div(c[e], h.ratio(l));
      return cell_value(l - 1, coarse);
    }
    if (const PetscInt n = cells.index(l, c); n >= 0) return p[static_cast<std::size_t>(n)];
    const PetscInt r = h.ratio(l + 1);
    double sum = 0.0;
    for (PetscInt k = 0; k < r; ++k)
      for (PetscInt j = 0; j < r; ++j)
        for (PetscInt i = 0; i < r; ++i) sum += cell_value(l + 1, {c[0] * r + i, c[1] * r + j, c[2] * r + k});
    return sum / static_cast<double>(r * r * r);
  };
  std::vector<double> values(points.size(), 0.0);
  for (std::size_t q = 0; q < points.size(); ++q) {
    const Real3& x = points[q];
    const int level = finest_level_holding(h, x);
    const Index3& n = h.domain_cells(level);
    Index3 base;
    std::array<double, 3> t{};
    for (int e = 0; e < 3; ++e) {
      const double s =
          std::clamp((x[e] - h.domain().lower[e]) / h.h(level, e) - 0.5, 0.0, static_cast<double>(n[e] - 1));
      base[e] = std::min<PetscInt>(static_cast<PetscInt>(std::floor(s)), std::max<PetscInt>(n[e] - 2, 0));
      t[e] = s - static_cast<double>(base[e]);
    }
    for (int c = 0; c < 8; ++c) {
      Index3 index = base;
      double w = 1.0;
      for (int e = 0; e < 3; ++e) {
        const int bit = (c >> e) & 1;
        index[e] = std::min(index[e] + bit, n[e] - 1);
        w *= bit ? t[e] : 1.0 - t[e];
      }
      if (w != 0.0) values[q] += w * cell_value(level, index);
    }
  }
  return values;
}

std::vector<Real3> NestedNavierStokes::velocity_at(const std::vector<Real3>& points) const
{
  const GridHierarchy& h = *hierarchy_;
  // Per point and component the eight face values and their trilinear weights (built before the wall data
  // are evaluated: building them may name new wall points).
  std::vector<std::array<std::array<std::pair<const FaceValue*, double>, 8>, 3>> stencils(points.size());
  for (std::size_t p = 0; p < points.size(); ++p) {
    const Real3& x = points[p];
    const int level = finest_level_holding(h, x);
    const Index3& n = h.domain_cells(level);
    for (int d = 0; d < 3; ++d) {
      Index3 base;
      std::array<double, 3> t{};
      for (int e = 0; e < 3; ++e) {
        const double s = (x[e] - h.domain().lower[e]) / h.h(level, e) - (e == d ? 0.0 : 0.5);
        // base + 1 is at most n: the last face, or a ghost mirrored at the wall.
        base[e] = std::clamp<PetscInt>(static_cast<PetscInt>(std::floor(s)), e == d ? 0 : -1, n[e] - 1);
        t[e] = s - static_cast<double>(base[e]);
      }
      for (int c = 0; c < 8; ++c) {
        Index3 index = base;
        double w = 1.0;
        for (int e = 0; e < 3; ++e) {
          const int bit = (c >> e) & 1;
          index[e] += bit;
          w *= bit ? t[e] : 1.0 - t[e];
        }
        stencils[p][d][c] = {&velocity_ops_->value({level, d, index}), w};
      }
    }
  }
  const std::vector<double> all = velocity_ops_->gather(u_);
  const std::vector<double> data = velocity_ops_->data_values(wall_velocity_, time_);
  std::vector<Real3> values(points.size(), Real3{0.0, 0.0, 0.0});
  for (std::size_t p = 0; p < points.size(); ++p)
    for (int d = 0; d < 3; ++d)
      for (const auto& [value, w] : stencils[p][d])
        values[p][d] += w * CompositeVelocity::evaluate(*value, all, data);
  return values;
}

void NestedNavierStokes::build_finest_level()
{
  const GridHierarchy& h = *hierarchy_;
  const int f = h.finest();
  const IndexBox& box = h.boxes(f)[0];
  BoxGeometry geometry;
  geometry.periodic = {false, false, false};
  for (int d = 0; d < 3; ++d) {
    geometry.cells[d] = box.cells(d);
    geometry.lower[d] = h.domain().lower[d] + static_cast<double>(box.lower[d]) * h.h(f, d);
    geometry.upper[d] = h.domain().lower[d] + static_cast<double>(box.upper[d]) * h.h(f, d);
  }
  finest_ = std::make_unique<StaggeredGrid>(comm_, geometry, Decomposition{}, 2);
  const StaggeredGrid& g = *finest_;
  const Index3& n = h.domain_cells(f);
  std::vector<const FaceValue*> values;
  for (PetscInt k = g.ghost_begin(2); k < g.ghost_end(2); ++k)
    for (PetscInt j = g.ghost_begin(1); j < g.ghost_end(1); ++j)
      for (PetscInt i = g.ghost_begin(0); i < g.ghost_end(0); ++i) {
        const Index3 cell{box.lower[0] + i, box.lower[1] + j, box.lower[2] + k};
        for (int d = 0; d < 3; ++d) {
          const FaceKey key{f, d, cell};
          bool inside = true;
          for (int e = 0; e < 3; ++e) {
            const PetscInt low = e == d ? 0 : -1, high = e == d ? n[e] : n[e];
            inside = inside && key.index[e] >= low && key.index[e] <= high;
          }
          values.push_back(inside ? &velocity_ops_->value(key) : nullptr);
          const bool owned = i >= g.begin(0) && i < g.face_end(d, 0) && j >= g.begin(1) &&
                             j < g.face_end(d, 1) && k >= g.begin(2) && k < g.face_end(d, 2);
          finest_owned_index_.push_back(owned ? velocity_ops_->index(key) : -1);
        }
        finest_cells_.push_back(operators_->cells().index(f, cell));
      }
  finest_values_ = FaceValueTable(values);
  finest_buffer_.resize(finest_values_.size());
}

const StaggeredGrid& NestedNavierStokes::finest_level_grid() const
{
  if (!finest_)
    throw std::invalid_argument("nested Navier-Stokes: the finest level has several boxes (IB needs one)");
  return *finest_;
}

void NestedNavierStokes::velocity_to_finest(Vec local) const
{
  const StaggeredGrid& g = finest_level_grid();
  velocity_ops_->evaluate(finest_values_, u_, velocity_ops_->data_values(wall_velocity_, time_),
                          finest_buffer_);
  // The pressure of the owned finest cells (all composite cells of the finest level are uncovered).
  const std::vector<double> p = gathered_pressure();
  {
    StagArray a(g, local);
    std::size_t slot = 0, cell = 0;
    for (PetscInt k = g.ghost_begin(2); k < g.ghost_end(2); ++k)
      for (PetscInt j = g.ghost_begin(1); j < g.ghost_end(1); ++j)
        for (PetscInt i = g.ghost_begin(0); i < g.ghost_end(0); ++i, ++cell) {
          for (int d = 0; d < 3; ++d, ++slot) a(i, j, k, g.face_slot(d)) = finest_buffer_[slot];
          const PetscInt c = finest_cells_[cell];
          a(i, j, k, g.pressure_slot()) = c >= 0 ? p[static_cast<std::size_t>(c)] : 0.0;
        }
  }
}

std::vector<double> NestedNavierStokes::gathered_pressure() const
{
  std::vector<double> values;
  petsc::with_scattered(pressure_gather_, p_, pressure_gathered_,
                        [&](std::span<const double> a) { values.assign(a.begin(), a.end()); });
  return values;
}

void NestedNavierStokes::add_force_from_finest(Vec local)
{
  const StaggeredGrid& g = finest_level_grid();
  std::vector<PetscInt> rows;
  std::vector<PetscScalar> values;
  {
    StagArray a(g, local, true);
    std::size_t slot = 0;
    for (PetscInt k = g.ghost_begin(2); k < g.ghost_end(2); ++k)
      for (PetscInt j = g.ghost_begin(1); j < g.ghost_end(1); ++j)
        for (PetscInt i = g.ghost_begin(0); i < g.ghost_end(0); ++i)
          for (int d = 0; d < 3; ++d, ++slot)
            if (const PetscInt n = finest_owned_index_[slot]; n >= 0) {
              rows.push_back(n);
              values.push_back(a(i, j, k, g.face_slot(d)));
            }
  }
  PETSC_CHECK(
      VecSetValues(force_, static_cast<PetscInt>(rows.size()), rows.data(), values.data(), ADD_VALUES));
  PETSC_CHECK(VecAssemblyBegin(force_));
  PETSC_CHECK(VecAssemblyEnd(force_));
}

std::vector<SolverFigure> NestedNavierStokes::last_solves() const
{
  return {{"velocity_iterations", static_cast<double>(velocity_iterations_), "viscous it"},
          {"pressure_iterations", static_cast<double>(pressure_iterations_), "pressure it"}};
}

double NestedNavierStokes::kinetic_energy() const
{
  petsc::OwnedVec squared;
  PETSC_CHECK(VecDuplicate(u_, squared.out()));
  PETSC_CHECK(VecPointwiseMult(squared, u_, u_));
  double sum = 0.0;
  PETSC_CHECK(VecDot(squared, operators_->weights(), &sum));
  return 0.5 * settings_.rho * sum;
}

double NestedNavierStokes::max_velocity() const
{
  PetscReal umax = 0.0;
  PETSC_CHECK(VecNorm(u_, NORM_INFINITY, &umax));
  return static_cast<double>(umax);
}

double NestedNavierStokes::max_speed_in(const PointSet& region) const
{
  // The vectors are owned, so they are freed also when a call throws.
  std::array<petsc::OwnedVec, 3> owned;
  std::array<Vec, 3> components{};
  for (std::size_t d = 0; d < 3; ++d) {
    owned[d] = operators_->create_cell_vector();
    components[d] = owned[d];
  }
  cell_velocity(components);
  PetscInt begin = 0, end = 0;
  PETSC_CHECK(VecGetOwnershipRange(components[0], &begin, &end));
  std::array<const PetscScalar*, 3> u{};
  for (std::size_t d = 0; d < 3; ++d) PETSC_CHECK(VecGetArrayRead(components[d], &u[d]));
  const GridHierarchy& h = *hierarchy_;
  double largest = 0.0;
  operators_->cells().for_each(begin, end, [&](PetscInt n, const CompositeCells::Cell& c) {
    Real3 centre{};
    for (int d = 0; d < 3; ++d)
      centre[d] = h.domain().lower[d] + (static_cast<double>(c.index[d]) + 0.5) * h.h(c.level, d);
    if (!region(centre)) return;
    double m2 = 0.0;
    for (std::size_t d = 0; d < 3; ++d) m2 += u[d][n - begin] * u[d][n - begin];
    largest = std::max(largest, m2);
  });
  for (std::size_t d = 0; d < 3; ++d) PETSC_CHECK(VecRestoreArrayRead(components[d], &u[d]));
  double global = 0.0;
  MPI_Allreduce(&largest, &global, 1, MPI_DOUBLE, MPI_MAX, comm_);
  return std::sqrt(global);
}

std::string NestedNavierStokes::describe() const
{
  const GridHierarchy& h = *hierarchy_;
  std::ostringstream s;
  s.precision(4);
  PetscInt cells = 0;
  for (int l = 0; l < h.levels(); ++l) cells += h.uncovered_cells(l);
  s << h.levels() << " nested levels (" << cells << " composite cells; level 0 " << h.domain_cells(0)[0]
    << " x " << h.domain_cells(0)[1] << " x " << h.domain_cells(0)[2] << ", finest spacing "
    << h.h(h.finest(), 0) << " cm)";
  return s.str();
}

double NestedNavierStokes::finest_spacing() const
{
  const int finest = hierarchy_->finest();
  return std::min({hierarchy_->h(finest, 0), hierarchy_->h(finest, 1), hierarchy_->h(finest, 2)});
}

std::vector<io::XdmfGrid> NestedNavierStokes::write_fields(io::Hdf5File& file, const std::string& group,
                                                           const std::string& file_reference) const
{
  // The cell velocity's vectors are owned, so they are freed also when a write throws (a full disk must
  // not leak them); `components` borrows their handles for the calls that take an array.
  std::array<petsc::OwnedVec, 3> owned;
  std::array<Vec, 3> components{};
  for (std::size_t d = 0; d < 3; ++d) {
    owned[d] = operators_->create_cell_vector();
    components[d] = owned[d];
  }
  cell_velocity(components);
  return write_composite_fields(file, operators_->cells(), {{"pressure", p_.get()}}, group, file_reference,
                                group + "_", {{"velocity", components}},
                                {{"pressure", "dyn/cm^2"}, {"velocity", "cm/s"}});
}

} // namespace ibvalve::fluid
