#include "ib/ibfe.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <fmt/format.h>
#include <sstream>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <mpi.h>

#include "base/errors.hpp"
#include "base/logger.hpp"
#include "base/stopwatch.hpp"
#include "fe/loads.hpp"
#include "io/petsc_check.hpp"

namespace ibvalve::ib {

namespace {

using base::Stopwatch;

std::string format(double value)
{
  std::ostringstream s;
  s.precision(3);
  s << value;
  return s.str();
}

// w_a of a tether: int_group N_a (area or volume) or 1 per node of a point group.
std::vector<double> tether_weights(const fe::Mesh& mesh, const std::string& name, MPI_Comm comm)
{
  const fe::PhysicalGroup& group = mesh.group(name);
  std::vector<double> w(mesh.num_nodes(), 0.0);
  if (group.dimension == 2) {
    const std::vector<double> load = fe::surface_traction_load(
        mesh, name, [](const fe::Vec3&) { return fe::Vec3(1.0, 0.0, 0.0); }, 2, comm);
    for (std::size_t n = 0; n < w.size(); ++n) w[n] = load[3 * n];
  } else if (group.dimension == 3) {
    const fe::QuadratureData quadrature(mesh, 2);
    for (int e : group.elements) {
      const auto element = mesh.element(e);
      for (int q = 0; q < quadrature.points_per_element(); ++q)
        for (std::size_t a = 0; a < element.size(); ++a)
          w[element[a]] += quadrature.value(q, static_cast<int>(a)) * quadrature.JxW(e, q);
    }
  } else {
    for (int n : group.nodes) w[n] = 1.0;
  }
  return w;
}

} // namespace

IbfeIntegrator::IbfeIntegrator(fluid::FlowSolver& fluid, const fe::SolidModel& solid, IbfeSettings settings)
    : IbfeIntegrator(make_eulerian_fluid(fluid), nullptr, solid, std::move(settings))
{
}

IbfeIntegrator::IbfeIntegrator(EulerianFluid& fluid, const fe::SolidModel& solid, IbfeSettings settings)
    : IbfeIntegrator(nullptr, &fluid, solid, std::move(settings))
{
}

IbfeIntegrator::IbfeIntegrator(std::unique_ptr<EulerianFluid> owned, EulerianFluid* fluid,
                               const fe::SolidModel& solid, IbfeSettings settings)
    : owned_fluid_(std::move(owned)), fluid_(fluid ? *fluid : *owned_fluid_), solid_(solid),
      settings_(std::move(settings)), interaction_(fluid_.grid(), settings_.kernel),
      points_(solid.mesh(), settings_.points),
      velocity_mass_(solid.mesh(), settings_.velocity_projection, fluid_.grid().comm(), "ib_velocity_mass_"),
      displacement_(solid.num_dofs(), 0.0), velocity_(solid.num_dofs(), 0.0), forces_(solid.num_dofs(), 0.0)
{
  if (settings_.force_projection != settings_.velocity_projection)
    force_mass_ = std::make_unique<NodalMass>(solid.mesh(), settings_.force_projection, fluid_.grid().comm(),
                                              "ib_force_mass_");
  const SemiImplicitSettings& implicit = settings_.semi_implicit;
  if (!(implicit.tolerance > 0.0 && implicit.tolerance < 1.0) || implicit.max_iterations < 1 ||
      implicit.newton_iterations < 1)
    throw InputError(
        "ib: the semi-implicit solve's tolerance must lie in (0, 1) and its iterations be positive");
  if (settings_.coupling == CouplingKind::semi_implicit && !fluid_.has_stokes_response())
    throw InputError("ib: the semi-implicit coupling needs the fluid on one grid (not nested levels)");
  for (const Tether& t : settings_.tethers) {
    if (t.stiffness < 0.0 || t.damping < 0.0)
      throw InputError("ib: tether '" + t.group + "': stiffness and damping must be non-negative");
    tethers_.emplace_back(tether_weights(solid.mesh(), t.group, fluid_.grid().comm()), t);
  }
  h_min_ = std::min({fluid_.grid().h(0), fluid_.grid().h(1), fluid_.grid().h(2)});
  stability_length_ = std::max(h_min_, solid_.mesh().edge_length_range().first);
  velocity_old_ = fluid_.grid().create_local();
  velocity_mid_ = fluid_.grid().create_local();
  place_points(displacement_);

  const StabilityEstimate s = stability_estimate();
  base::Logger::global().info(fmt::format(
      "ib: IB/FE coupling with the {} kernel, {} coupling points at the start; stable time step estimate {} "
      "s (structure modulus {} dyn/cm^2, length {} cm; {})",
      interaction_.kernel().name(), points_.size(), format(s.dt), format(s.modulus), format(s.length),
      describe_stability_terms(s)));
}

std::string describe_time_step(double dt, const StabilityEstimate& s)
{
  // The estimate is the larger of the two limits: the viscous one only holds where viscosity dominates
  // the stiffest mode (gamma > omega), and then it is the larger. Naming the smaller one bare read like
  // a violated bound.
  const bool viscous = s.viscous_dt > s.inertial_dt;
  const std::string binding =
      viscous
          ? "the structure's viscous-regime limit 2 mu/E binds, viscosity dominating its stiffest mode "
            "(the inertial limit 2/omega, " +
                format(s.inertial_dt) + " s, holds only where inertia dominates)"
          : "the structure's inertial limit 2/omega binds (the viscous-regime limit 2 mu/E, " +
                format(s.viscous_dt) + " s, holds only where viscosity dominates, which it does not here)";
  return "dt = " + format(dt) + " s " + (dt > s.dt ? "is above" : "is within") +
         " the stable time step estimate " + format(s.dt) + " s of the explicit IB/FE coupling: " + binding;
}

void IbfeIntegrator::set_displacement(std::vector<double> displacement)
{
  if (displacement.size() != solid_.num_dofs())
    throw std::invalid_argument("ib: displacement has the wrong size");
  displacement_ = std::move(displacement);
  require_inside(displacement_);
  place_points(displacement_);
}

void IbfeIntegrator::require_inside(std::span<const double> displacement) const
{
  const auto& X = solid_.mesh().nodes();
  std::vector<Vec3> x(X.size());
  for (std::size_t n = 0; n < X.size(); ++n)
    x[n] = X[n] + Vec3(displacement[3 * n], displacement[3 * n + 1], displacement[3 * n + 2]);
  fluid_.require_inside(x, (interaction_.kernel().support() + 1) / 2);
}

std::vector<Vec3> IbfeIntegrator::positions() const
{
  const auto& X = solid_.mesh().nodes();
  std::vector<Vec3> x(X.size());
  for (std::size_t n = 0; n < X.size(); ++n)
    x[n] = X[n] + Vec3(displacement_[3 * n], displacement_[3 * n + 1], displacement_[3 * n + 2]);
  return x;
}

void IbfeIntegrator::place_points(std::span<const double> displacement)
{
  Stopwatch watch(timings_.points);
  const auto& X = solid_.mesh().nodes();
  std::vector<Vec3> x(X.size());
  for (std::size_t n = 0; n < X.size(); ++n)
    x[n] = X[n] + Vec3(displacement[3 * n], displacement[3 * n + 1], displacement[3 * n + 2]);
  // Each rank places and prepares only the points of elements whose nodes' bounding box meets its
  // cells (a point is a convex combination of its element's nodes): the others are other ranks'.
  const fe::Mesh& mesh = solid_.mesh();
  placed_.assign(mesh.num_elements(), 0);
  for (std::size_t e = 0; e < mesh.num_elements(); ++e) {
    const auto element = mesh.element(e);
    Vec3 lower = x[element[0]], upper = x[element[0]];
    bool finite = true;
    for (const auto n : element) {
      lower = lower.cwiseMin(x[n]);
      upper = upper.cwiseMax(x[n]);
      finite = finite && x[n].allFinite();
    }
    // A non-finite element is placed everywhere, so that every rank raises the same error.
    placed_[e] = !finite || interaction_.may_hold(lower, upper) ? 1 : 0;
  }
  const std::size_t capped = points_.update(x, h_min_, placed_);
  if (capped > 0 && !warned_capped_) {
    warned_capped_ = true;
    base::Logger::global().warn(
        fmt::format("ib: {} elements are stretched so far that {} coupling points per direction leave gaps "
                    "wider than ib.point_spacing grid cells; the fluid may leak through them (shown once)",
                    capped, settings_.points.max_points));
  }
  candidates_.clear();
  for (std::size_t e = 0; e < mesh.num_elements(); ++e)
    if (placed_[e] != 0)
      for (std::size_t q = points_.first_point(e); q < points_.first_point(e + 1); ++q)
        candidates_.push_back(q);
  interaction_.prepare(points_.positions(), candidates_, prepared_);
}

std::vector<double> IbfeIntegrator::project_velocity(Vec velocity, int guess_slot)
{
  std::vector<Vec3> values(prepared_.size());
  {
    Stopwatch watch(timings_.interpolation);
    interaction_.interpolate(velocity, prepared_, values);
  }
  Stopwatch watch(timings_.projection);
  std::vector<double> rhs(solid_.num_dofs(), 0.0);
  points_.add_projection_rhs(prepared_.index, values, rhs);
  MPI_Allreduce(MPI_IN_PLACE, rhs.data(), static_cast<int>(rhs.size()), MPI_DOUBLE, MPI_SUM,
                fluid_.grid().comm());
  std::vector<double> projected = velocity_mass_.solve(rhs, guess_slot);
  projection_iterations_ += velocity_mass_.last_iterations();
  return projected;
}

std::vector<double> IbfeIntegrator::nodal_velocity(Vec velocity, std::span<const double> displacement)
{
  place_points(displacement);
  return project_velocity(velocity, 3);
}

std::vector<double> IbfeIntegrator::structure_forces(std::span<const double> displacement,
                                                     std::span<const double> velocity)
{
  Stopwatch watch(timings_.force);
  std::vector<double> F(solid_.num_dofs(), 0.0);
  solid_.forces(displacement, F);
  add_tether_forces(F, displacement, velocity);
  return F;
}

void IbfeIntegrator::add_tether_forces(std::span<double> F, std::span<const double> displacement,
                                       std::span<const double> velocity) const
{
  for (const auto& [w, t] : tethers_)
    for (std::size_t n = 0; n < w.size(); ++n)
      if (w[n] != 0.0)
        for (int c = 0; c < 3; ++c)
          F[3 * n + c] -= w[n] * (t.stiffness * displacement[3 * n + c] +
                                  (velocity.empty() ? 0.0 : t.damping * velocity[3 * n + c]));
}

void IbfeIntegrator::spread_force_density(std::span<const double> nodal_forces)
{
  std::vector<double> density;
  {
    Stopwatch watch(timings_.projection);
    const NodalMass& mass = force_mass_ ? *force_mass_ : velocity_mass_;
    density = mass.solve(nodal_forces, 2);
    projection_iterations_ += mass.last_iterations();
  }
  Stopwatch watch(timings_.spreading);
  interaction_.spread(prepared_, point_forces(density), fluid_.force());
  fluid_.apply_force();
}

std::vector<Vec3> IbfeIntegrator::point_forces(std::span<const double> density) const
{
  std::vector<Vec3> forces(prepared_.size());
  for (std::size_t i = 0; i < prepared_.size(); ++i) {
    const std::size_t q = prepared_.index[i];
    const auto element = solid_.mesh().element(points_.element(q));
    const auto N = points_.shape_values(q);
    Vec3 f = Vec3::Zero();
    for (std::size_t a = 0; a < element.size(); ++a)
      f += N[a] * Vec3(density[3 * element[a]], density[3 * element[a] + 1], density[3 * element[a] + 2]);
    forces[i] = f * points_.weight(q);
  }
  return forces;
}

void IbfeIntegrator::step(double dt)
{
  Stopwatch total(timings_.total);
  projection_iterations_ = 0;
  if (timings_.steps == 0 && settings_.coupling == CouplingKind::semi_implicit) {
    base::Logger::global().info(fmt::format(
        "ib: semi-implicit coupling ({} Newton iterations a step through the fluid's linear response, GMRES "
        "to a relative residual of {}); dt = {} s",
        settings_.semi_implicit.newton_iterations, format(settings_.semi_implicit.tolerance), format(dt)));
  } else if (timings_.steps == 0 && coupled_estimate_.dt > 0.0) {
    // An adaptive run measured the coupled estimate before its first step: that is the limit to name.
    const std::string line =
        fmt::format("dt = {} s is {} the coupled stability estimate {} s (docs/ib.md)", format(dt),
                    dt > coupled_estimate_.dt ? "above" : "within", format(coupled_estimate_.dt));
    if (dt > coupled_estimate_.dt)
      base::Logger::global().warn("ib: " + line + "; the run may blow up");
    else
      base::Logger::global().info("ib: " + line);
  } else if (timings_.steps == 0) {
    const StabilityEstimate s = stability_estimate();
    if (dt > s.dt)
      base::Logger::global().warn("ib: " + describe_time_step(dt, s) + "; the run may blow up");
    else
      base::Logger::global().info("ib: " + describe_time_step(dt, s));
  }
  if (settings_.coupling == CouplingKind::semi_implicit) return step_semi_implicit(dt);
  const std::size_t dofs = solid_.num_dofs();
  // 1. U^n at chi^n, and the half-step position.
  place_points(displacement_);
  const std::vector<double> U_n = project_velocity(fluid_.velocity(), 0);
  std::vector<double> u_half(dofs);
  for (std::size_t i = 0; i < dofs; ++i) u_half[i] = displacement_[i] + 0.5 * dt * U_n[i];
  require_inside(u_half);
  // 2. Forces at chi^{n+1/2}, spread from the points placed there.
  place_points(u_half);
  forces_ = structure_forces(u_half, U_n);
  spread_force_density(forces_);
  // 3. The fluid step, keeping u^n.
  PETSC_CHECK(VecCopy(fluid_.velocity(), velocity_old_));
  {
    Stopwatch watch(timings_.fluid);
    fluid_.step(dt);
  }
  // 4. U^{n+1/2} from (u^n + u^{n+1})/2 at the same points, and the full position update.
  finish_step(dt);
}

void IbfeIntegrator::finish_step(double dt)
{
  PETSC_CHECK(VecAXPBYPCZ(velocity_mid_, 0.5, 0.5, 0.0, velocity_old_, fluid_.velocity()));
  velocity_ = project_velocity(velocity_mid_, 1);
  for (std::size_t i = 0; i < displacement_.size(); ++i) {
    displacement_[i] += dt * velocity_[i];
    if (!std::isfinite(displacement_[i]))
      throw RunError("ib: the structure's position became non-finite at t = " + format(fluid_.time()) +
                     " s (the time step is probably above the stable limit)");
  }
  require_inside(displacement_);
  ++timings_.steps;
}

void IbfeIntegrator::save(io::Hdf5File& file, const std::string& group) const
{
  // Replicated on every rank: rank 0 writes.
  const std::array<hsize_t, 2> dims{solid_.mesh().num_nodes(), 3};
  file.write_root(group + "/displacement", displacement_, dims);
  file.write_root(group + "/velocity", velocity_, dims);
  file.write_root(group + "/nodal_forces", forces_, dims);
  velocity_mass_.save(file, group + "/velocity_mass");
  if (force_mass_) force_mass_->save(file, group + "/force_mass");
  if (!stability_mode_.empty()) file.write_root(group + "/stability_mode", stability_mode_, dims);
}

void IbfeIntegrator::restore(const io::Hdf5File& file, const std::string& group)
{
  fluid_.refresh(); // the fluid was restored first: its u^n is the checkpoint's
  auto read = [&](const std::string& name) {
    std::vector<double> values = file.read(group + "/" + name);
    if (values.size() != solid_.num_dofs())
      throw std::runtime_error(file.path().string() + ": " + group + "/" + name +
                               " does not match the structure's mesh");
    return values;
  };
  displacement_ = read("displacement");
  velocity_ = read("velocity");
  forces_ = read("nodal_forces");
  velocity_mass_.restore(file, group + "/velocity_mass");
  if (force_mass_) force_mass_->restore(file, group + "/force_mass");
  if (file.has(group + "/stability_mode")) stability_mode_ = read("stability_mode");
  require_inside(displacement_);
  place_points(displacement_);
}

double IbfeIntegrator::volume() const
{
  double total = 0.0;
  const fe::QuadratureData& quadrature = solid_.quadrature();
  for (std::size_t e = 0; e < solid_.mesh().num_elements(); ++e)
    for (int q = 0; q < quadrature.points_per_element(); ++q)
      total += solid_.deformation_gradient(displacement_, e, q).determinant() * quadrature.JxW(e, q);
  return total;
}

namespace {

/// The stiffness an isochoric perturbation dF meets at F: the largest |eigenvalue| of sym(dP/dF)
/// projected orthogonally to n = F^-T / |F^-T| (flattened column-major, as the tangent).
double isochoric_modulus(const materials::Mat3& F, const materials::Tangent& T)
{
  const materials::Mat3 inverse_transpose = F.inverse().transpose();
  Eigen::Matrix<double, 9, 1> n = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(inverse_transpose.data());
  n.normalize();
  const materials::Tangent projector = materials::Tangent::Identity() - n * n.transpose();
  const materials::Tangent symmetric = projector * (0.5 * (T + T.transpose())) * projector;
  const Eigen::SelfAdjointEigenSolver<materials::Tangent> eigen(symmetric, Eigen::EigenvaluesOnly);
  return eigen.eigenvalues().cwiseAbs().maxCoeff();
}

} // namespace

std::vector<double> IbfeIntegrator::element_moduli(std::span<const double> displacement) const
{
  if (!displacement.empty() && displacement.size() != solid_.num_dofs())
    throw std::invalid_argument("ib: element_moduli: displacement has the wrong size");
  const fe::QuadratureData& rule = solid_.quadrature();
  std::vector<double> moduli(solid_.mesh().num_elements(), 0.0);
  for (const fe::BodyPart& part : solid_.parts())
    for (const int element : part.elements) {
      const auto e = static_cast<std::size_t>(element);
      const bool reference = displacement.empty();
      const materials::Mat3 centre_F = reference || !solid_.centre_quadrature()
                                           ? materials::Mat3::Identity()
                                           : solid_.centre_deformation_gradient(displacement, e);
      materials::Tangent centre = materials::Tangent::Zero();
      for (const auto& law : part.centre_laws) centre += law->tangent(centre_F, solid_.centre_fibers(e));
      for (int q = 0; q < rule.points_per_element(); ++q) {
        const materials::Mat3 F =
            reference ? materials::Mat3::Identity() : solid_.deformation_gradient(displacement, e, q);
        materials::Tangent T = centre;
        for (const auto& law : part.laws) T += law->tangent(F, solid_.fibers(e, q));
        moduli[e] = std::max(moduli[e], isochoric_modulus(F, T));
      }
    }
  return moduli;
}

double IbfeIntegrator::stable_step(double omega2) const
{
  const double h = stability_length_;
  const double gamma = 12.0 * fluid_.viscosity() / (fluid_.density() * h * h);
  return omega2 > 0.0 ? std::max(2.0 / std::sqrt(omega2), 2.0 * gamma / omega2) : 1e300;
}

std::vector<double> IbfeIntegrator::element_stable_steps(std::span<const double> displacement) const
{
  const double h = stability_length_;
  std::vector<double> steps = element_moduli(displacement);
  for (double& step : steps) step = stable_step(12.0 * step / (fluid_.density() * h * h));
  return steps;
}

StabilityEstimate IbfeIntegrator::stability_estimate(std::span<const double> displacement) const
{
  StabilityEstimate s;
  s.length = stability_length_;
  const double rho = fluid_.density(), mu = fluid_.viscosity(), h = s.length;
  const std::vector<double> moduli = element_moduli(displacement);
  double largest_part = 0.0, largest_tether = 0.0;
  for (const fe::BodyPart& part : solid_.parts()) {
    if (part.elements.empty()) continue;
    double modulus = 0.0;
    for (const int e : part.elements) modulus = std::max(modulus, moduli[static_cast<std::size_t>(e)]);
    s.modulus = std::max(s.modulus, modulus);
    const double omega2 = 12.0 * modulus / (rho * h * h);
    largest_part = std::max(largest_part, omega2);
    s.terms.push_back({"part " + part.name, omega2, stable_step(omega2)});
  }
  for (const auto& [w, t] : tethers_) {
    double stiffest = 0.0;
    for (double wa : w) stiffest = std::max(stiffest, t.stiffness * wa);
    s.tether_stiffness = std::max(s.tether_stiffness, stiffest);
    const double omega2 = stiffest / (rho * h * h * h);
    largest_tether = std::max(largest_tether, omega2);
    s.terms.push_back({"tether " + t.group, omega2, stable_step(omega2)});
  }
  const double omega2 = largest_part + largest_tether;
  const double gamma = 12.0 * mu / (rho * h * h);
  s.inertial_dt = omega2 > 0.0 ? 2.0 / std::sqrt(omega2) : 1e300;
  s.viscous_dt = omega2 > 0.0 ? 2.0 * gamma / omega2 : 1e300;
  s.dt = std::max(s.inertial_dt, s.viscous_dt);
  std::stable_sort(s.terms.begin(), s.terms.end(),
                   [](const auto& a, const auto& b) { return a.omega2 > b.omega2; });
  return s;
}

std::string describe_stability_terms(const StabilityEstimate& s)
{
  // omega^2 of the estimate: the largest part's plus the largest tether's.
  const double omega2 = s.inertial_dt < 1e300 ? 4.0 / (s.inertial_dt * s.inertial_dt) : 0.0;
  std::string out;
  for (const auto& t : s.terms)
    out += fmt::format("{}{} {:.0f} % of omega^2 (alone {} s)", out.empty() ? "" : ", ", t.source,
                       omega2 > 0.0 ? 100.0 * t.omega2 / omega2 : 0.0, format(t.dt));
  return out;
}

} // namespace ibvalve::ib
