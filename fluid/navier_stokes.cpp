#include "fluid/navier_stokes.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <fmt/format.h>
#include <stdexcept>
#include <vector>

#include "base/stopwatch.hpp"
#include "fluid/fft_stokes.hpp"
#include "fluid/krylov_stokes.hpp"
#include "fluid/output.hpp"
#include "fluid/queries.hpp"
#include "fluid/solver_clock.hpp"
#include "io/petsc_check.hpp"

namespace ibvalve::fluid {

namespace {
using base::Stopwatch;

/// This rank's block of a checkpoint array (NavierStokes::save): (z, y, x, 4) over the elements it
/// owns, including the extra face layer N of a non-periodic direction on the rank that owns it.
struct CheckpointBlock {
  std::array<hsize_t, 4> dims{}, offset{}, count{};
  Index3 end{}; // exclusive element index ends in x, y, z
};

CheckpointBlock checkpoint_block(const StaggeredGrid& grid)
{
  CheckpointBlock b;
  for (int d = 0; d < 3; ++d) {
    const bool extra_layer = !grid.periodic(d);
    b.end[d] = grid.begin(d) + grid.count(d) + (extra_layer && grid.owns_upper(d) ? 1 : 0);
    b.dims[2 - d] = static_cast<hsize_t>(grid.cells(d) + (extra_layer ? 1 : 0));
    b.offset[2 - d] = static_cast<hsize_t>(grid.begin(d));
    b.count[2 - d] = static_cast<hsize_t>(b.end[d] - grid.begin(d));
  }
  b.dims[3] = b.count[3] = 4;
  return b;
}

/// The DMStag slot of entry q (0..2: the x, y, z faces at the element's low sides, 3: the cell) of
/// element e, or -1 when e lies in the extra face layer where that unknown does not exist: there
/// only the face normal to the layer's direction does, and only off the other layers.
PetscInt checkpoint_slot(const StaggeredGrid& grid, int q, const Index3& e)
{
  for (int d = 0; d < 3; ++d)
    if (e[d] == grid.cells(d) && q != d) return -1;
  return q < 3 ? grid.face_slot(q) : grid.pressure_slot();
}

/// Calls visit(slot or -1, i, j, k) for every entry of this rank's block, in the file's C order.
template <class Visit>
void for_checkpoint_entries(const StaggeredGrid& grid, const CheckpointBlock& b, Visit&& visit)
{
  for (PetscInt k = grid.begin(2); k < b.end[2]; ++k)
    for (PetscInt j = grid.begin(1); j < b.end[1]; ++j)
      for (PetscInt i = grid.begin(0); i < b.end[0]; ++i)
        for (int q = 0; q < 4; ++q) visit(checkpoint_slot(grid, q, {i, j, k}), i, j, k);
}

void write_checkpoint_field(io::Hdf5File& file, const std::string& name, const StaggeredGrid& grid, Vec local)
{
  const CheckpointBlock b = checkpoint_block(grid);
  std::vector<double> data;
  data.reserve(b.count[0] * b.count[1] * b.count[2] * b.count[3]);
  {
    StagArray a(grid, local, true);
    for_checkpoint_entries(grid, b, [&](PetscInt slot, PetscInt i, PetscInt j, PetscInt k) {
      data.push_back(slot < 0 ? 0.0 : a(i, j, k, slot));
    });
  }
  file.write_block(name, data, b.dims, b.offset, b.count);
}

/// Fills the owned entries of `local` (not its ghosts) from a checkpoint array.
void read_checkpoint_field(const io::Hdf5File& file, const std::string& name, const StaggeredGrid& grid,
                           Vec local)
{
  const CheckpointBlock b = checkpoint_block(grid);
  if (file.dims(name) != std::vector<hsize_t>(b.dims.begin(), b.dims.end()))
    throw std::runtime_error(file.path().string() + ": " + name +
                             " was written for another grid (its shape differs from fluid.cells)");
  const std::vector<double> data = file.read_block(name, b.offset, b.count);
  StagArray a(grid, local);
  std::size_t n = 0;
  for_checkpoint_entries(grid, b, [&](PetscInt slot, PetscInt i, PetscInt j, PetscInt k) {
    if (slot >= 0) a(i, j, k, slot) = data[n];
    ++n;
  });
}
} // namespace

NavierStokes::NavierStokes(MPI_Comm comm, const BoxGeometry& box, BoundaryConditions bc,
                           const FluidSettings& settings)
    : comm_(comm), bc_(std::move(bc)), settings_(settings)
{
  bc_.check(box);
  if (!(settings.rho > 0.0) || !(settings.mu >= 0.0))
    throw std::invalid_argument("fluid: density must be positive and viscosity non-negative");
  const bool all_periodic = box.periodic[0] && box.periodic[1] && box.periodic[2];
  // The convection stencil reaches two faces beyond a boundary face: three ghost layers when a
  // side is not periodic (faces N+1, N+2), two otherwise.
  const PetscInt width = all_periodic ? 2 : 3;
  if (settings.solver == SolverKind::fft) {
    if (!all_periodic) throw std::invalid_argument("fluid: the fft solver needs a periodic box (use krylov)");
    if (bc_.solid()) throw std::invalid_argument("fluid: blocked cells need the krylov solver");
    grid_ = std::make_unique<StaggeredGrid>(comm, box, fft_decomposition(comm, box.cells), width);
    solver_ = std::make_unique<FftStokesSolver>(*grid_);
  } else {
    // With the transform sub-solves, FFTW's z slabs keep the scatters to the transforms' layout
    // (nearly) rank-local; slabs thinner than the ghost width fall back to PETSc's decomposition.
    Decomposition decomposition;
    if (settings.subsolver == SubsolverKind::fft) {
      try {
        Decomposition slabs = fft_decomposition(comm, box.cells);
        bool thick = true;
        for (PetscInt planes : slabs.z_ownership) thick = thick && planes >= width;
        if (thick) decomposition = slabs;
      } catch (const std::invalid_argument&) {
      }
    }
    grid_ = std::make_unique<StaggeredGrid>(comm, box, decomposition, width);
    auto krylov = std::make_unique<KrylovStokesSolver>(*grid_, bc_, settings);
    solid_ = &krylov->solid();
    solver_ = std::move(krylov);
  }
  state_ = grid_->create_local();
  force_ = grid_->create_local();
  rhs_ = grid_->create_local();
  convection_ = grid_->create_local();
  convection_old_ = grid_->create_local();
  convection_half_ = grid_->create_local();
  saved_ = grid_->create_local();
}

void NavierStokes::set_initial_condition(const VelocityFunction& velocity, const ScalarFunction& pressure,
                                         double t)
{
  {
    StagArray a(*grid_, state_);
    for (int d = 0; d < 3; ++d)
      for (PetscInt k = grid_->begin(2); k < grid_->face_end(d, 2); ++k)
        for (PetscInt j = grid_->begin(1); j < grid_->face_end(d, 1); ++j)
          for (PetscInt i = grid_->begin(0); i < grid_->face_end(d, 0); ++i)
            a(i, j, k, grid_->face_slot(d)) = velocity(grid_->face_position(d, i, j, k), t)[d];
    for (PetscInt k = grid_->begin(2); k < grid_->begin(2) + grid_->count(2); ++k)
      for (PetscInt j = grid_->begin(1); j < grid_->begin(1) + grid_->count(1); ++j)
        for (PetscInt i = grid_->begin(0); i < grid_->begin(0) + grid_->count(0); ++i)
          a(i, j, k, grid_->pressure_slot()) = pressure ? pressure(grid_->cell_center(i, j, k), t) : 0.0;
  }
  set_boundary_normal_velocity(*grid_, bc_, state_, t);
  if (solid_) solid_->zero_faces(state_);
  time_ = t;
  pressure_time_ = t;
  steps_ = 0;
  have_old_convection_ = false;
  exchange(t);
}

void NavierStokes::set_body_force(const VelocityFunction& force, double t)
{
  StagArray a(*grid_, force_);
  for (int d = 0; d < 3; ++d)
    for (PetscInt k = grid_->begin(2); k < grid_->face_end(d, 2); ++k)
      for (PetscInt j = grid_->begin(1); j < grid_->face_end(d, 1); ++j)
        for (PetscInt i = grid_->begin(0); i < grid_->face_end(d, 0); ++i)
          a(i, j, k, grid_->face_slot(d)) = force(grid_->face_position(d, i, j, k), t)[d];
}

void NavierStokes::exchange(double t)
{
  Stopwatch watch(statistics_.halo);
  Vec global;
  PETSC_CHECK(DMGetGlobalVector(grid_->dm(), &global));
  PETSC_CHECK(DMLocalToGlobal(grid_->dm(), state_, INSERT_VALUES, global));
  grid_->global_to_local(global, state_);
  PETSC_CHECK(DMRestoreGlobalVector(grid_->dm(), &global));
  update_backflow_drop();
  fill_ghosts(*grid_, bc_, state_, t);
}

void NavierStokes::update_backflow_drop()
{
  // From the state's boundary normal velocities (owned faces), summed over the ranks so that every
  // rank holds each side's whole plane; the next boundary terms and ghosts then use it. Computing it
  // here, from the state alone, keeps a restarted run identical to the uninterrupted one.
  for (int s = 0; s < 6; ++s) {
    const BoundarySide& side = bc_.side(s);
    if (side.kind != SideKind::traction || !(side.backflow > 0.0)) continue;
    const int a = s / 2, b = (a + 1) % 3, c = (a + 2) % 3;
    const bool upper = s % 2 == 1;
    std::vector<double> drop(static_cast<std::size_t>(grid_->cells(b) * grid_->cells(c)), 0.0);
    if (upper ? grid_->owns_upper(a) : grid_->owns_lower(a)) {
      StagArray u(*grid_, state_, true);
      const double coefficient = 0.5 * side.backflow * settings_.rho;
      for (PetscInt ic = grid_->begin(c); ic < grid_->begin(c) + grid_->count(c); ++ic)
        for (PetscInt ib = grid_->begin(b); ib < grid_->begin(b) + grid_->count(b); ++ib) {
          Index3 idx{};
          idx[a] = upper ? grid_->cells(a) : 0;
          idx[b] = ib;
          idx[c] = ic;
          const double u_n = u(idx[0], idx[1], idx[2], grid_->face_slot(a));
          const double outward = upper ? u_n : -u_n;
          if (outward < 0.0)
            drop[static_cast<std::size_t>(ic * grid_->cells(b) + ib)] = coefficient * outward * outward;
        }
    }
    PETSC_CHECK(
        MPI_Allreduce(MPI_IN_PLACE, drop.data(), static_cast<int>(drop.size()), MPI_DOUBLE, MPI_SUM, comm_));
    bc_.set_backflow_drop(s, grid_->box(), std::move(drop));
  }
}

void NavierStokes::explicit_rhs(Vec convection_half, double dt)
{
  // rhs = rho/dt u^n + mu/2 L u^n - rho N^{n+1/2} + f on faces, 0 on cells (continuity); one pass.
  Stopwatch watch(statistics_.viscous);
  const double rho_dt = settings_.rho / dt, half_mu = 0.5 * settings_.mu, rho = settings_.rho;
  StagArray r(*grid_, rhs_), u(*grid_, state_, true), n(*grid_, convection_half, true),
      f(*grid_, force_, true);
  double inv_h2[3];
  for (int e = 0; e < 3; ++e) inv_h2[e] = 1.0 / (grid_->h(e) * grid_->h(e));
  const PetscInt sx = u.stride(0), sy = u.stride(1), sz = u.stride(2);
  for (int d = 0; d < 3; ++d) {
    const PetscInt s = grid_->face_slot(d);
    for (PetscInt k = grid_->begin(2); k < grid_->face_end(d, 2); ++k)
      for (PetscInt j = grid_->begin(1); j < grid_->face_end(d, 1); ++j) {
        const PetscInt i0 = grid_->begin(0);
        const PetscScalar* up = &u(i0, j, k, s);
        const PetscScalar* np = &n(i0, j, k, s);
        const PetscScalar* fp = &f(i0, j, k, s);
        PetscScalar* rp = &r(i0, j, k, s);
        const PetscInt count = grid_->face_end(d, 0) - i0;
        for (PetscInt m = 0; m < count; ++m, up += sx, np += sx, fp += sx, rp += sx) {
          const double c = 2.0 * up[0];
          const double laplacian = (up[sx] - c + up[-sx]) * inv_h2[0] + (up[sy] - c + up[-sy]) * inv_h2[1] +
                                   (up[sz] - c + up[-sz]) * inv_h2[2];
          rp[0] = rho_dt * up[0] + half_mu * laplacian - rho * np[0] + fp[0];
        }
      }
  }
  // A wall half a cell beyond a tangential neighbour (blocked cells): that neighbour, 0, becomes the
  // ghost -u_0, as in the implicit half (fluid/krylov_stokes.cpp).
  if (solid_)
    for (const WallGhost& g : solid_->wall_ghosts()) {
      const PetscInt s = grid_->face_slot(g.d);
      r(g.face[0], g.face[1], g.face[2], s) -= half_mu * inv_h2[g.e] * u(g.face[0], g.face[1], g.face[2], s);
    }
  for (PetscInt k = grid_->begin(2); k < grid_->begin(2) + grid_->count(2); ++k)
    for (PetscInt j = grid_->begin(1); j < grid_->begin(1) + grid_->count(1); ++j)
      for (PetscInt i = grid_->begin(0); i < grid_->begin(0) + grid_->count(0); ++i)
        r(i, j, k, grid_->pressure_slot()) = 0.0;
}

void NavierStokes::step(double dt)
{
  if (!(dt > 0.0)) throw std::invalid_argument("fluid: the time step must be positive");
  const double start = MPI_Wtime();
  if (parameters_.dt != dt) {
    parameters_ = {settings_.rho, settings_.mu, dt};
    solver_->set_parameters(parameters_);
  }
  auto solve = [&] {
    solver_->add_boundary_terms(rhs_, time_ + dt, time_ + 0.5 * dt);
    last_solve_ = solver_->solve(rhs_, state_);
    statistics_.viscous += last_solve_.helmholtz_seconds;
    statistics_.pressure += last_solve_.poisson_seconds;
    statistics_.solver_iterations += last_solve_.iterations;
  };
  {
    Stopwatch watch(statistics_.convection);
    convective_term(*grid_, bc_, time_, state_, convection_, settings_.convection);
  }
  if (have_old_convection_) {
    // Adams–Bashforth 2 with variable steps: N^{n+1/2} = (1 + r/2) N^n - (r/2) N^{n-1}.
    const double r = dt / last_dt_;
    PETSC_CHECK(VecAXPBYPCZ(convection_half_, 1.0 + 0.5 * r, -0.5 * r, 0.0, convection_, convection_old_));
    explicit_rhs(convection_half_, dt);
    solve();
  } else {
    // First step: predictor with N^0, corrector with the average of N^0 and N(predicted u^1).
    PETSC_CHECK(VecCopy(state_, saved_));
    explicit_rhs(convection_, dt);
    solve();
    exchange(time_ + dt);
    {
      Stopwatch watch(statistics_.convection);
      convective_term(*grid_, bc_, time_ + dt, state_, convection_half_, settings_.convection);
    }
    PETSC_CHECK(VecAXPBY(convection_half_, 0.5, 0.5, convection_));
    PETSC_CHECK(VecSwap(state_, saved_)); // back to u^n; the prediction serves as the initial guess
    explicit_rhs(convection_half_, dt);
    PETSC_CHECK(VecSwap(state_, saved_));
    solve();
  }
  exchange(time_ + dt);
  std::swap(convection_, convection_old_);
  have_old_convection_ = true;
  last_dt_ = dt;
  time_ += dt;
  pressure_time_ = time_ - 0.5 * dt;
  ++steps_;
  ++statistics_.steps;
  statistics_.total += MPI_Wtime() - start;
}

void NavierStokes::stokes_response(Vec force, double dt, Vec velocity)
{
  if (!(dt > 0.0)) throw std::invalid_argument("fluid: the time step must be positive");
  if (parameters_.dt != dt) {
    parameters_ = {settings_.rho, settings_.mu, dt};
    solver_->set_parameters(parameters_);
  }
  if (!response_rhs_) response_rhs_ = grid_->create_local();
  PETSC_CHECK(VecCopy(force, response_rhs_));
  {
    StagArray r(*grid_, response_rhs_);
    for (PetscInt k = grid_->begin(2); k < grid_->begin(2) + grid_->count(2); ++k)
      for (PetscInt j = grid_->begin(1); j < grid_->begin(1) + grid_->count(1); ++j)
        for (PetscInt i = grid_->begin(0); i < grid_->begin(0) + grid_->count(0); ++i)
          r(i, j, k, grid_->pressure_slot()) = 0.0;
  }
  solver_->set_homogeneous_boundary_rows(response_rhs_);
  PETSC_CHECK(VecSet(velocity, 0.0));
  solver_->solve(response_rhs_, velocity);
  Vec global;
  PETSC_CHECK(DMGetGlobalVector(grid_->dm(), &global));
  PETSC_CHECK(DMLocalToGlobal(grid_->dm(), velocity, INSERT_VALUES, global));
  grid_->global_to_local(global, velocity);
  PETSC_CHECK(DMRestoreGlobalVector(grid_->dm(), &global));
}

void NavierStokes::add_to_state(Vec increment)
{
  PETSC_CHECK(VecAXPY(state_, 1.0, increment));
  exchange(time_);
}

void NavierStokes::save(io::Hdf5File& file, const std::string& group) const
{
  // After a step, convection_old_ holds N^n (the swap at its end); the next step extrapolates from it.
  write_checkpoint_field(file, group + "/state", *grid_, state_);
  write_checkpoint_field(file, group + "/convection", *grid_, convection_old_);
  write_checkpoint_field(file, group + "/body_force", *grid_, force_);
  write_solver_clock(file, group, {time_, pressure_time_, last_dt_, steps_, have_old_convection_});
}

void NavierStokes::restore(const io::Hdf5File& file, const std::string& group)
{
  const SolverClock clock = read_solver_clock(file, group, "fluid checkpoint");
  read_checkpoint_field(file, group + "/state", *grid_, state_);
  read_checkpoint_field(file, group + "/convection", *grid_, convection_old_);
  read_checkpoint_field(file, group + "/body_force", *grid_, force_);
  time_ = clock.time;
  pressure_time_ = clock.pressure_time;
  last_dt_ = clock.last_dt;
  steps_ = static_cast<PetscInt>(clock.steps);
  have_old_convection_ = clock.have_old_convection;
  // Ghosts (other ranks' values, boundary ghosts at time_) as the step's last exchange left them.
  exchange(time_);
}

std::string NavierStokes::describe() const
{
  const Index3& n = grid_->box().cells;
  return fmt::format("grid {} x {} x {}", n[0], n[1], n[2]);
}

double NavierStokes::finest_spacing() const
{
  return std::min({grid_->h(0), grid_->h(1), grid_->h(2)});
}

double NavierStokes::flux(const PlaneRegion& region) const
{
  return volume_flux(*this, region);
}

std::vector<double> NavierStokes::pressure_at(const std::vector<Real3>& points) const
{
  std::vector<double> p;
  p.reserve(points.size());
  for (const Real3& x : points) p.push_back(fluid::pressure_at(*this, x));
  return p;
}

std::vector<Real3> NavierStokes::velocity_at(const std::vector<Real3>& points) const
{
  std::vector<Real3> u;
  u.reserve(points.size());
  for (const Real3& x : points) u.push_back(fluid::velocity_at(*this, x));
  return u;
}

double NavierStokes::kinetic_energy() const
{
  return fluid::kinetic_energy(*this);
}

double NavierStokes::max_velocity() const
{
  return max_velocity_magnitude(*this);
}

double NavierStokes::max_speed_in(const PointSet& region) const
{
  return max_velocity_magnitude(*this, region);
}

std::vector<io::XdmfGrid> NavierStokes::write_fields(io::Hdf5File& file, const std::string& group,
                                                     const std::string& file_reference) const
{
  return {fluid::write_fields(file, *this, group, file_reference)};
}

std::vector<SolverFigure> NavierStokes::last_solves() const
{
  return {{"fluid_iterations", static_cast<double>(last_solve_.iterations), "fluid it"},
          {"fluid_residual", last_solve_.residual, ""}};
}

} // namespace ibvalve::fluid
