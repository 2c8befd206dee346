#pragma once
// Quasi-static hyperelastic equilibrium with PETSc SNES: find u with
//   R(u) = - forces(u) - lambda f_ext = 0   at free unknowns,   u = lambda g(X)   at Dirichlet unknowns,
// for load factors lambda = 1/n, 2/n, ..., 1 (load stepping), by Newton's method with the consistent
// tangent K = dR/du (SolidModel::add_stiffness) in a PETSc Mat. Dirichlet rows of K are replaced by
// identity rows (columns kept): each step starts from the previous solution and its first Newton
// update moves the prescribed values and, through the kept columns, the interior consistently
// (a linearised predictor), so large prescribed increments do not invert boundary elements.
//
// Everything is tunable through the options prefix (default "fe_"): -fe_snes_rtol, -fe_snes_monitor,
// -fe_ksp_type, -fe_pc_type ... The defaults are Newton with a backtracking line search and a direct
// solve (LU; MUMPS on several ranks).
#include <array>
#include <functional>
#include <string>
#include <vector>

#include <petscsnes.h>

#include "fe/solid.hpp"

namespace ibvalve::fe {

struct DirichletCondition {
  std::vector<int> nodes;
  std::array<bool, 3> components{true, true, true};
  /// Displacement at full load (lambda = 1) at reference position X.
  std::function<Vec3(const Vec3& X)> displacement = [](const Vec3&) { return Vec3::Zero(); };
};

/// The nodes of group `group` with components fixed to `displacement` (default zero).
DirichletCondition dirichlet_on_group(const Mesh& mesh, const std::string& group,
                                      std::array<bool, 3> components = {true, true, true},
                                      std::function<Vec3(const Vec3&)> displacement = nullptr);

struct QuasiStaticOptions {
  int load_steps = 1;
  std::string prefix = "fe_";
  double relative_tolerance = 1e-10;
  double absolute_tolerance = 1e-10;
  int max_iterations = 30;
};

struct QuasiStaticResult {
  std::vector<double> displacement;   ///< replicated, interlaced x y z
  std::vector<int> newton_iterations; ///< per load step
  double final_residual_norm = 0.0;
};

class QuasiStaticSolver {
 public:
  /// `external_load`: nodal load at full load (size 3 x nodes, replicated) or empty for none.
  QuasiStaticSolver(const SolidModel& solid, std::vector<DirichletCondition> conditions,
                    std::vector<double> external_load, QuasiStaticOptions options = {});
  QuasiStaticSolver(const QuasiStaticSolver&) = delete;
  QuasiStaticSolver& operator=(const QuasiStaticSolver&) = delete;

  /// Runs every load step from `initial` (zero when empty). RunError when Newton fails at a step.
  QuasiStaticResult solve(std::vector<double> initial = {});

  // Called by PETSc (public only so the C callbacks can reach them).
  void residual(Vec u, Vec r);
  void jacobian(Vec u, Mat J);

 private:
  const SolidModel& solid_;
  NodalSystem system_;
  std::vector<double> external_;
  QuasiStaticOptions options_;
  std::vector<PetscInt> constrained_;      // global dof indices
  std::vector<double> constrained_values_; // at full load
  double load_factor_ = 1.0;
  petsc::OwnedMat K_;
  petsc::OwnedVec r_;
  petsc::OwnedSNES snes_; // after K_ and r_: destroyed first
};

} // namespace ibvalve::fe
