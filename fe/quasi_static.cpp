#include "fe/quasi_static.hpp"

#include <cmath>
#include <fmt/format.h>
#include <map>

#include <petscsnes.h>

#include "base/errors.hpp"
#include "base/logger.hpp"
#include "io/petsc_check.hpp"

namespace ibvalve::fe {

DirichletCondition dirichlet_on_group(const Mesh& mesh, const std::string& group,
                                      std::array<bool, 3> components,
                                      std::function<Vec3(const Vec3&)> displacement)
{
  DirichletCondition condition;
  condition.nodes = mesh.group(group).nodes;
  condition.components = components;
  if (displacement) condition.displacement = std::move(displacement);
  return condition;
}

namespace {

PetscErrorCode residual_callback(SNES, Vec u, Vec r, void* context)
{
  try {
    static_cast<QuasiStaticSolver*>(context)->residual(u, r);
  } catch (const std::exception& error) {
    base::Logger::global().error(std::string("quasi-static residual: ") + error.what());
    return PETSC_ERR_LIB;
  }
  return 0;
}

PetscErrorCode jacobian_callback(SNES, Vec u, Mat J, Mat, void* context)
{
  try {
    static_cast<QuasiStaticSolver*>(context)->jacobian(u, J);
  } catch (const std::exception& error) {
    base::Logger::global().error(std::string("quasi-static tangent: ") + error.what());
    return PETSC_ERR_LIB;
  }
  return 0;
}

} // namespace

QuasiStaticSolver::QuasiStaticSolver(const SolidModel& solid, std::vector<DirichletCondition> conditions,
                                     std::vector<double> external_load, QuasiStaticOptions options)
    : solid_(solid), system_(solid.mesh(), 3, solid.comm()), external_(std::move(external_load)),
      options_(std::move(options))
{
  if (external_.empty()) external_.assign(solid.num_dofs(), 0.0);
  if (external_.size() != solid.num_dofs())
    throw std::invalid_argument("quasi-static: load vector has the wrong size");
  // Later conditions win where two fix the same unknown.
  std::map<PetscInt, double> fixed;
  for (const auto& condition : conditions)
    for (int n : condition.nodes) {
      const Vec3 g = condition.displacement(solid.mesh().nodes()[n]);
      for (int i = 0; i < 3; ++i)
        if (condition.components[i]) fixed[3 * static_cast<PetscInt>(n) + i] = g[i];
    }
  for (const auto& [dof, value] : fixed) {
    constrained_.push_back(dof);
    constrained_values_.push_back(value);
  }

  K_ = system_.create_matrix();
  r_ = system_.create_vector();
  PETSC_CHECK(SNESCreate(solid.comm(), snes_.out()));
  PETSC_CHECK(SNESSetOptionsPrefix(snes_, options_.prefix.c_str()));
  PETSC_CHECK(SNESSetType(snes_, SNESNEWTONLS));
  PETSC_CHECK(SNESSetFunction(snes_, r_, residual_callback, this));
  PETSC_CHECK(SNESSetJacobian(snes_, K_, K_, jacobian_callback, this));
  PETSC_CHECK(SNESSetTolerances(snes_, options_.absolute_tolerance, options_.relative_tolerance, 0.0,
                                options_.max_iterations, 100000));
  KSP ksp;
  PC pc;
  PETSC_CHECK(SNESGetKSP(snes_, &ksp));
  PETSC_CHECK(KSPSetType(ksp, KSPPREONLY));
  PETSC_CHECK(KSPGetPC(ksp, &pc));
  PETSC_CHECK(PCSetType(pc, PCLU));
  int size = 1;
  MPI_Comm_size(solid.comm(), &size);
  if (size > 1) PETSC_CHECK(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS));
  PETSC_CHECK(SNESSetFromOptions(snes_));
}

void QuasiStaticSolver::residual(Vec u_vec, Vec r_vec)
{
  const std::vector<double> u = system_.gather(u_vec);
  std::vector<double> r(u.size());
  solid_.forces(u, r);
  bool finite = true;
  for (std::size_t i = 0; i < r.size(); ++i) {
    r[i] = -r[i] - load_factor_ * external_[i];
    finite = finite && std::isfinite(r[i]);
  }
  for (std::size_t k = 0; k < constrained_.size(); ++k)
    r[constrained_[k]] = u[constrained_[k]] - load_factor_ * constrained_values_[k];
  // An inverted element (NaN stress) tells the line search to step back.
  if (!finite) PETSC_CHECK(SNESSetFunctionDomainError(snes_));
  system_.scatter(r, r_vec);
}

void QuasiStaticSolver::jacobian(Vec u_vec, Mat J)
{
  const std::vector<double> u = system_.gather(u_vec);
  PETSC_CHECK(MatZeroEntries(J));
  solid_.add_stiffness(u, system_, J);
  PETSC_CHECK(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
  PETSC_CHECK(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
  zero_rows(J, constrained_, 1.0);
}

QuasiStaticResult QuasiStaticSolver::solve(std::vector<double> initial)
{
  if (initial.empty()) initial.assign(solid_.num_dofs(), 0.0);
  QuasiStaticResult result;
  const petsc::OwnedVec u = system_.create_vector();
  std::vector<double> current = std::move(initial);
  for (int step = 1; step <= options_.load_steps; ++step) {
    load_factor_ = static_cast<double>(step) / options_.load_steps;
    system_.scatter(current, u);
    PETSC_CHECK(SNESSolve(snes_, nullptr, u));
    SNESConvergedReason reason;
    PetscInt iterations = 0;
    PETSC_CHECK(SNESGetConvergedReason(snes_, &reason));
    PETSC_CHECK(SNESGetIterationNumber(snes_, &iterations));
    if (reason <= 0) {
      throw RunError(fmt::format(
          "quasi-static solve: Newton did not converge at load step {} of {} ({}); try more load steps", step,
          options_.load_steps, SNESConvergedReasons[reason]));
    }
    result.newton_iterations.push_back(static_cast<int>(iterations));
    current = system_.gather(u);
  }
  PetscReal norm = 0;
  PETSC_CHECK(SNESGetFunctionNorm(snes_, &norm));
  result.final_residual_norm = norm;
  result.displacement = std::move(current);
  return result;
}

} // namespace ibvalve::fe
