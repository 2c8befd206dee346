// IbfeIntegrator::coupled_stability_estimate (ib/ibfe.hpp): power iterations on the linearised
// explicit coupling A = P_h J (R / dt) S M^{-1} K at the current state, R the fluid's response to a
// force over one step.
#include <algorithm>
#include <cmath>
#include <numeric>

#include <mpi.h>

#include "base/stopwatch.hpp"
#include "ib/ibfe.hpp"

namespace ibvalve::ib {

namespace {

double norm(const std::vector<double>& v)
{
  return std::sqrt(std::inner_product(v.begin(), v.end(), v.begin(), 0.0));
}

} // namespace

std::vector<double> IbfeIntegrator::coupled_operator(const std::vector<double>& mode)
{
  const std::size_t dofs = solid_.num_dofs();
  // K mode: the full rule's forces differentiated along the mode (central differences, a step of 1e-6
  // of the stability length for a mode of unit largest entry: far below any strain scale, far above
  // round-off), plus the tethers' springs.
  double largest = 0.0;
  for (double m : mode) largest = std::max(largest, std::abs(m));
  const double epsilon = 1e-6 * stability_length_ / largest;
  std::vector<double> plus(displacement_), minus(displacement_), f_plus(dofs), f_minus(dofs);
  for (std::size_t i = 0; i < dofs; ++i) {
    plus[i] += epsilon * mode[i];
    minus[i] -= epsilon * mode[i];
  }
  solid_.forces(plus, f_plus, false);
  solid_.forces(minus, f_minus, false);
  // The tethers' springs are linear: their part of K mode is -F_tether(mode).
  std::vector<double> springs(dofs, 0.0);
  add_tether_forces(springs, mode, {});
  std::vector<double> stiffness(dofs);
  for (std::size_t i = 0; i < dofs; ++i)
    stiffness[i] = (f_minus[i] - f_plus[i]) / (2.0 * epsilon) - springs[i];
  // S M^{-1}: the force density's L2 projection, spread from the points as the step spreads it.
  const NodalMass& mass = force_mass_ ? *force_mass_ : velocity_mass_;
  const std::vector<double> density = mass.solve(stiffness, 4);
  interaction_.spread(prepared_, point_forces(density), probe_force_);
  // R / dt: the faces' velocity change per unit time that one step of the fluid gives the force. Its
  // pressure projection removes the part of the force that the incompressible flow does not let move
  // the fluid (a third of a point force's, on average over directions), and its viscous solve damps
  // the rest a little, so the explicit step's true limit is set by R, not by the bare acceleration
  // f / rho. R is taken with the last step's dt, for which the fluid's solvers are already set up (the
  // grid-scale viscous damping, nu dt / h^2, is below 1e-2 at the valve's steps, so the dt hardly
  // matters). The default (ib.stability_estimate), a fluid without the response (nested levels) and
  // the estimate before the first step use f / rho, whose norm bounds R f / dt's from above: a lower,
  // safe estimate, whose dominant mode also stands further above the rest, so that a few power
  // iterations catch a stiff mode that emerges within an interval (the response's lagged on the
  // 1/16 cm grid's first loading: docs/ib.md).
  const double dt = fluid_.last_step();
  const bool with_response = settings_.stability_estimate == StabilityEstimateKind::fluid_response &&
                             fluid_.has_stokes_response() && dt > 0.0;
  if (with_response) {
    if (!probe_velocity_) probe_velocity_ = fluid_.grid().create_local();
    fluid_.stokes_response(probe_force_, dt, probe_velocity_);
  }
  // P_h J: interpolated at the same points and projected to the nodes.
  std::vector<double> response = project_velocity(with_response ? probe_velocity_ : probe_force_, 5);
  const double divisor = with_response ? dt : fluid_.density();
  for (double& r : response) r /= divisor;
  return response;
}

CoupledStabilityEstimate IbfeIntegrator::coupled_stability_estimate(int iterations)
{
  // The estimate's placing, interpolation and mass solves are its own time, not the steps' parts.
  const IbfeTimings steps_timings = timings_;
  base::Stopwatch watch(timings_.stability);
  const std::size_t dofs = solid_.num_dofs();
  if (!probe_force_) probe_force_ = fluid_.grid().create_local();
  if (stability_mode_.size() != dofs) {
    // The first start: a smooth field with a part along every direction everywhere.
    stability_mode_.assign(dofs, 0.0);
    const auto& X = solid_.mesh().nodes();
    for (std::size_t n = 0; n < X.size(); ++n)
      for (int c = 0; c < 3; ++c)
        stability_mode_[3 * n + c] = 1.0 + 0.5 * std::sin(3.0 * X[n][c] + static_cast<double>(c));
  }
  place_points(displacement_);
  const PetscInt counted = projection_iterations_;
  CoupledStabilityEstimate estimate;
  double previous = 0.0;
  for (int k = 0; k < iterations; ++k) {
    std::vector<double> image = coupled_operator(stability_mode_);
    const double ratio = norm(image) / norm(stability_mode_);
    if (!(ratio > 0.0) || !std::isfinite(ratio)) break; // nothing stiff (no tether, no stress)
    estimate.omega2 = ratio;
    estimate.change = previous > 0.0 ? std::abs(ratio - previous) / ratio : 1.0;
    estimate.iterations = k + 1;
    previous = ratio;
    const double scale = 1.0 / *std::max_element(image.begin(), image.end(), [](double a, double b) {
                           return std::abs(a) < std::abs(b);
                         });
    for (double& v : image) v *= scale;
    stability_mode_ = std::move(image);
  }
  projection_iterations_ = counted; // the step's count, not the estimate's
  timings_ = steps_timings;         // the stopwatch then adds the whole call to `stability`
  estimate.dt = estimate.omega2 > 0.0 ? 2.0 / std::sqrt(estimate.omega2) : 1e300;
  coupled_estimate_ = estimate;
  return estimate;
}

} // namespace ibvalve::ib
