// IbfeIntegrator's semi-implicit coupling (ib/ibfe.hpp, docs/ib.md "The semi-implicit coupling"): the
// fluid's step without the structure's force, the half-step position by Newton iterations on
//   W = W_free + 1/2 R F(chi^n + dt/2 W),   R: the nodes' velocity change over a step per nodal force,
// each a matrix-free GMRES solve of (I + dt/4 R K) dW = r, and the fluid's response to the force there
// added to its free step.
#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <memory>

#include <mpi.h>

#include "base/errors.hpp"
#include "base/stopwatch.hpp"
#include "ib/ibfe.hpp"
#include "io/petsc_check.hpp"

namespace ibvalve::ib {

namespace {

using base::Stopwatch;

void copy_to(std::span<const double> values, Vec v)
{
  PetscScalar* a = nullptr;
  PETSC_CHECK(VecGetArray(v, &a));
  std::copy(values.begin(), values.end(), a);
  PETSC_CHECK(VecRestoreArray(v, &a));
}

std::vector<double> copy_from(Vec v)
{
  PetscInt n = 0;
  PETSC_CHECK(VecGetLocalSize(v, &n));
  const PetscScalar* a = nullptr;
  PETSC_CHECK(VecGetArrayRead(v, &a));
  std::vector<double> values(a, a + n);
  PETSC_CHECK(VecRestoreArrayRead(v, &a));
  return values;
}

/// KSPConvergedDefault on the largest residual norm over the fluid's ranks. Every rank solves the same
/// replicated system, but each applies A through collective spreading and interpolation: the ranks
/// must take the same number of iterations, which a round-off difference in a local norm could break.
struct CollectiveTest {
  MPI_Comm comm;
  void* defaults = nullptr;

  static PetscErrorCode converged(KSP ksp, PetscInt it, PetscReal rnorm, KSPConvergedReason* reason,
                                  void* ctx)
  {
    auto* test = static_cast<CollectiveTest*>(ctx);
    PetscReal largest = rnorm;
    // NaN compares false: carried as +inf so that every rank sees it.
    if (!(largest == largest)) largest = PETSC_INFINITY;
    if (MPI_Allreduce(MPI_IN_PLACE, &largest, 1, MPIU_REAL, MPI_MAX, test->comm) != MPI_SUCCESS)
      return PETSC_ERR_MPI;
    return KSPConvergedDefault(ksp, it, largest, reason, test->defaults);
  }
  static PetscErrorCode destroy(void* ctx)
  {
    auto* test = static_cast<CollectiveTest*>(ctx);
    const PetscErrorCode code = KSPConvergedDefaultDestroy(test->defaults);
    delete test;
    return code;
  }
};

} // namespace

void IbfeIntegrator::create_implicit_solver()
{
  const auto n = static_cast<PetscInt>(solid_.num_dofs());
  PETSC_CHECK(MatCreateShell(PETSC_COMM_SELF, n, n, n, n, this, implicit_.matrix.out()));
  PETSC_CHECK(
      MatShellSetOperation(implicit_.matrix, MATOP_MULT,
                           reinterpret_cast<void (*)(void)>(&IbfeIntegrator::apply_implicit_operator)));
  PETSC_CHECK(VecCreateSeq(PETSC_COMM_SELF, n, implicit_.rhs.out()));
  PETSC_CHECK(VecDuplicate(implicit_.rhs, implicit_.solution.out()));
  PETSC_CHECK(KSPCreate(PETSC_COMM_SELF, implicit_.ksp.out()));
  PETSC_CHECK(KSPSetOptionsPrefix(implicit_.ksp, "ib_implicit_"));
  PETSC_CHECK(KSPSetOperators(implicit_.ksp, implicit_.matrix, implicit_.matrix));
  // R K is not symmetric (self-adjoint in the K inner product only where K is positive): GMRES.
  PETSC_CHECK(KSPSetType(implicit_.ksp, KSPGMRES));
  PC pc;
  PETSC_CHECK(KSPGetPC(implicit_.ksp, &pc));
  PETSC_CHECK(PCSetType(pc, PCNONE));
  const SemiImplicitSettings& s = settings_.semi_implicit;
  PETSC_CHECK(KSPSetTolerances(implicit_.ksp, s.tolerance, 0.0, PETSC_DEFAULT, s.max_iterations));
  auto test = std::make_unique<CollectiveTest>();
  test->comm = fluid_.grid().comm();
  PETSC_CHECK(KSPConvergedDefaultCreate(&test->defaults));
  PETSC_CHECK(
      KSPSetConvergenceTest(implicit_.ksp, &CollectiveTest::converged, test.get(), &CollectiveTest::destroy));
  test.release(); // the KSP owns it now
  PETSC_CHECK(KSPSetFromOptions(implicit_.ksp));
}

PetscErrorCode IbfeIntegrator::apply_implicit_operator(Mat matrix, Vec x, Vec y)
{
  void* context = nullptr;
  PetscCall(MatShellGetContext(matrix, &context));
  auto& self = *static_cast<IbfeIntegrator*>(context);
  ImplicitSolve& solve = self.implicit_;
  // Exceptions must not cross PETSc's C frames: kept, and rethrown once KSPSolve has returned.
  try {
    const std::vector<double> v = copy_from(x);
    const std::size_t dofs = v.size();
    // K v = -dF/du v by a one-sided difference about chi_k (a step of 1e-6 of the stability length for
    // the largest entry, as the coupled estimate's), plus the tethers' linear springs.
    double largest = 0.0;
    for (double value : v) largest = std::max(largest, std::abs(value));
    std::vector<double> image(v);
    if (largest > 0.0) {
      const double epsilon = 1e-6 * self.stability_length_ / largest;
      std::vector<double> moved(solve.displacement), forces(dofs, 0.0), springs(dofs, 0.0);
      for (std::size_t i = 0; i < dofs; ++i) moved[i] += epsilon * v[i];
      self.solid_.forces(moved, forces);
      self.add_tether_forces(springs, v, {});
      std::vector<double> stiffness(dofs);
      for (std::size_t i = 0; i < dofs; ++i)
        stiffness[i] = (solve.forces[i] - forces[i]) / epsilon - springs[i];
      const std::vector<double> response = self.stokes_model_response(stiffness, solve.dt);
      for (std::size_t i = 0; i < dofs; ++i) image[i] += solve.scale * response[i];
    }
    copy_to(image, y);
  } catch (...) {
    solve.error = std::current_exception();
    return PETSC_ERR_LIB;
  }
  return 0;
}

std::vector<double> IbfeIntegrator::stokes_model_response(std::span<const double> nodal_forces, double dt)
{
  if (!probe_force_) probe_force_ = fluid_.grid().create_local();
  if (!probe_velocity_) probe_velocity_ = fluid_.grid().create_local();
  const NodalMass& mass = force_mass_ ? *force_mass_ : velocity_mass_;
  const std::vector<double> density = mass.solve(nodal_forces, 4);
  interaction_.spread(prepared_, point_forces(density), probe_force_);
  fluid_.stokes_response(probe_force_, dt, probe_velocity_);
  return project_velocity(probe_velocity_, 5);
}

void IbfeIntegrator::step_semi_implicit(double dt)
{
  const std::size_t dofs = solid_.num_dofs();
  // 1. U^n at chi^n and the first Newton iterate chi_0 = chi^n + dt/2 U^n.
  place_points(displacement_);
  const std::vector<double> U_n = project_velocity(fluid_.velocity(), 0);
  std::vector<double> predicted(dofs);
  for (std::size_t i = 0; i < dofs; ++i) predicted[i] = displacement_[i] + 0.5 * dt * U_n[i];
  require_inside(predicted);
  // 2. The fluid's step without the structure's force (the step is linear in its body force: the
  // force's part is added after the structure's solve), and W_free at chi_0.
  PETSC_CHECK(VecCopy(fluid_.velocity(), velocity_old_));
  PETSC_CHECK(VecSet(fluid_.force(), 0.0));
  fluid_.apply_force();
  {
    Stopwatch watch(timings_.fluid);
    fluid_.step(dt);
  }
  place_points(predicted);
  PETSC_CHECK(VecAXPBYPCZ(velocity_mid_, 0.5, 0.5, 0.0, velocity_old_, fluid_.velocity()));
  const std::vector<double> W_free = project_velocity(velocity_mid_, 1);
  // 3. The half-step position by Newton iterations, each linearised where the last one ended; the
  // force there spread from the points at chi_0 (placed once: the operators R, S and J stay those of
  // the step, so the force's power is what the structure receives back), and the fluid's response to
  // it added.
  std::vector<double> position = implicit_position(dt, predicted, U_n, W_free);
  long iterations = implicit_iterations_;
  std::vector<double> W(dofs); // chi_k = chi^n + dt/2 W_k
  for (int k = 1; k < settings_.semi_implicit.newton_iterations; ++k) {
    for (std::size_t i = 0; i < dofs; ++i) W[i] = (position[i] - displacement_[i]) / (0.5 * dt);
    position = implicit_position(dt, position, W, W_free);
    iterations += implicit_iterations_;
  }
  implicit_iterations_ = iterations;
  require_inside(position);
  for (std::size_t i = 0; i < dofs; ++i) W[i] = (position[i] - displacement_[i]) / (0.5 * dt);
  forces_ = structure_forces(position, W);
  spread_force_density(forces_);
  {
    Stopwatch watch(timings_.fluid);
    if (!probe_velocity_) probe_velocity_ = fluid_.grid().create_local();
    fluid_.stokes_response(fluid_.force(), dt, probe_velocity_);
    fluid_.add_to_state(probe_velocity_);
  }
  finish_step(dt);
}

std::vector<double> IbfeIntegrator::implicit_position(double dt, std::span<const double> position_k,
                                                      std::span<const double> W,
                                                      std::span<const double> W_free)
{
  // Its forces, mass solves, spreading and interpolation are the solve's own time, not the step's parts.
  const IbfeTimings parts = timings_;
  const PetscInt counted = projection_iterations_;
  std::vector<double> position(position_k.begin(), position_k.end());
  {
    Stopwatch watch(timings_.implicit);
    if (!implicit_.ksp) create_implicit_solver();
    const std::size_t dofs = solid_.num_dofs();
    implicit_.displacement = position;
    implicit_.forces.assign(dofs, 0.0);
    solid_.forces(position, implicit_.forces);
    implicit_.scale = 0.25 * dt;
    implicit_.dt = dt;
    implicit_.error = nullptr;
    // The residual of W = W_free + 1/2 R F(chi^n + dt/2 W) at W_k (the tethers' dashpots at W_k).
    std::vector<double> forces = implicit_.forces;
    add_tether_forces(forces, position, W);
    std::vector<double> b = stokes_model_response(forces, dt);
    for (std::size_t i = 0; i < dofs; ++i) b[i] = 0.5 * b[i] + W_free[i] - W[i];
    copy_to(b, implicit_.rhs);
    PETSC_CHECK(VecSet(implicit_.solution, 0.0));
    const PetscErrorCode code = KSPSolve(implicit_.ksp, implicit_.rhs, implicit_.solution);
    if (implicit_.error) std::rethrow_exception(implicit_.error);
    PETSC_CHECK(code);
    KSPConvergedReason reason;
    PETSC_CHECK(KSPGetConvergedReason(implicit_.ksp, &reason));
    PETSC_CHECK(KSPGetIterationNumber(implicit_.ksp, &implicit_iterations_));
    // Running out of iterations leaves a usable, less accurate dU; a breakdown or a non-finite
    // residual does not.
    if (reason < 0 && reason != KSP_DIVERGED_ITS)
      throw RunError(fmt::format("ib: the semi-implicit coupling's solve failed at t = {:g} s ({}) after {} "
                                 "iterations",
                                 fluid_.time(), KSPConvergedReasons[reason], implicit_iterations_));
    const std::vector<double> dU = copy_from(implicit_.solution);
    for (std::size_t i = 0; i < dofs; ++i) position[i] += 0.5 * dt * dU[i];
    projection_iterations_ = counted;
    timings_ = parts; // the stopwatch then adds the whole solve to `implicit`
  }
  return position;
}

} // namespace ibvalve::ib
