#pragma once
// The IB/FE method (Griffith & Luo 2017, Int. J. Numer. Meth. Biomed. Engng. 33:e2888): the fluid on
// the staggered grid (fluid::NavierStokes), the structure a finite-element mesh (fe::SolidModel)
// whose current position chi(X, t) = X + u(X, t) moves with the fluid,
//
//   d chi/dt = P_h J[chi] u          velocity interpolated at the coupling points, then L2-projected
//                                    to the nodes (lumped or consistent mass)
//   f        = S[chi] M^{-1} F[chi]  nodal forces F_a = -int P : grad_X N_a dX (+ tethers), L2-
//                                    projected to a force density, spread from the coupling points
//
// advanced by the explicit midpoint rule (the "IB explicit" scheme of Griffith & Luo, section 3.4),
// second order in time for smooth problems:
//   1. U^n = P_h J[chi^n] u^n,                 chi^{n+1/2} = chi^n + dt/2 U^n
//      (the semi-implicit coupling finds chi^{n+1/2} implicitly instead, below)
//   2. f^{n+1/2} = S[chi^{n+1/2}] M^{-1} F(chi^{n+1/2}, U^n)
//   3. (u^{n+1}, p^{n+1/2}) from the Navier–Stokes step with body force f^{n+1/2}
//   4. U^{n+1/2} = P_h J[chi^{n+1/2}] (u^n + u^{n+1})/2,   chi^{n+1} = chi^n + dt U^{n+1/2}
// The fluid is an ib::EulerianFluid (ib/eulerian_fluid.hpp): one uniform grid, or the finest level of
// nested grids.
// Spreading (2) and the interpolation of (4) use the same points, so the power the structure puts
// into the fluid equals the power it receives (the operators are adjoint).
//
// The semi-implicit coupling (IbfeSettings::coupling; docs/ib.md, "The semi-implicit coupling") takes
// the structure's force at a half-step position found implicitly with the fluid's own linear response.
// The fluid's step is linear in its body force (convection is extrapolated from u^n and u^{n-1}, the
// boundary data do not depend on the force), so
//   u^{n+1} = u_free + R_u f,   u_free: the step without the force,  R_u f: the Stokes solve of the
//   step for the force alone from rest, homogeneous boundary data (EulerianFluid::stokes_response).
// With R F = P_h J R_u S M^{-1} F (the nodes' velocity change forces F give in one step) and
// W_free = P_h J (u^n + u_free)/2, the half-step velocity W = U^{n+1/2} solves
//   W = W_free + 1/2 R F(chi^n + dt/2 W)
// (the implicit midpoint rule for the structure; with the fluid exact, the linear problem's modes
// keep their amplitude at every dt). Newton's method from W_0 = U^n, K = -dF/du at chi_k:
//   (I + dt/4 R K) dW = W_free + 1/2 R F(chi_k) - W_k,   chi_k = chi^n + dt/2 W_k,
// each solved by matrix-free GMRES (PETSc; each product one Stokes solve, a force difference, a
// spreading and an interpolation). The coupling points stay at chi_0 = chi^n + dt/2 U^n, where the
// explicit step places them, for the whole step: R, S and J are the step's, and the force's power is
// what the structure receives back. Then F(chi^{n+1/2}) is spread from them, its response added to
// u_free, and step 4 runs as in the explicit step. Newren, Fogelson, Guy & Kirby 2007 (J. Comput. Phys.
// 222:702-719) show such linearly implicit discretisations unconditionally stable for linear forces;
// Ceniceros, Fisher & Roma 2009 (J. Comput. Phys. 228:7137-7158) solve the same kind of structure
// system with the fluid solve inside. Measured here: the nonlinear forces limit it to a few times the
// explicit step, and each GMRES product costs a Stokes solve (docs/ib.md).
//
// Tethers pull chosen nodes back to their reference positions with a spring and a dashpot,
//   F_a += -w_a (kappa (chi_a - X_a) + eta U_a),
// w_a = int_group N_a (dA for a surface group, dX for a volume group) or 1 for a point group; kappa is
// then a stiffness per area, per volume or per node.
#include <exception>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "fe/mass.hpp"
#include "fe/solid.hpp"
#include "fluid/navier_stokes.hpp"
#include "ib/coupling_points.hpp"
#include "ib/eulerian_fluid.hpp"
#include "ib/interaction.hpp"
#include "ib/nodal_mass.hpp"

namespace ibvalve::ib {

struct Tether {
  std::string group;      ///< a physical group of the mesh (surface, volume or points)
  double stiffness = 0.0; ///< kappa: dyn/cm^3 (surface), dyn/cm^4 (volume), dyn/cm (points)
  double damping = 0.0;   ///< eta: the same per unit velocity (s/cm times kappa's unit)
};

/// How the structure's force at the half step is found (docs/ib.md, "The semi-implicit coupling").
enum class CouplingKind {
  explicit_midpoint, ///< chi^{n+1/2} = chi^n + dt/2 U^n: stable below the coupled estimate's dt
  semi_implicit,     ///< chi^{n+1/2} implicitly, through the fluid's linear response (below)
};

/// The semi-implicit coupling's solves (header comment): Newton iterations, each a GMRES solve on the
/// structure's degrees of freedom.
struct SemiImplicitSettings {
  double tolerance = 1e-3;   ///< GMRES: relative residual of (I + dt/4 R K) dW = r
  int max_iterations = 100;  ///< GMRES stops there (counted, not an error)
  int newton_iterations = 2; ///< the second takes the stable step from 2 to 3 estimates (docs/ib.md)
};

/// The fluid's part of the coupled stability estimate's operator (docs/ib.md, "The coupled estimate").
enum class StabilityEstimateKind {
  acceleration,   ///< the spread force's bare acceleration f / rho: below the true limit
  fluid_response, ///< the fluid's one-step response R / dt (its pressure projection): sharp, slower to track
};

struct IbfeSettings {
  KernelKind kernel = default_kernel;
  CouplingKind coupling = CouplingKind::explicit_midpoint;
  StabilityEstimateKind stability_estimate = StabilityEstimateKind::acceleration;
  SemiImplicitSettings semi_implicit{};
  fe::MassKind velocity_projection = fe::MassKind::consistent;
  fe::MassKind force_projection = fe::MassKind::consistent;
  CouplingPointSettings points{};
  std::vector<Tether> tethers;
};

/// Wall-clock seconds spent in the parts of the coupled steps so far.
struct IbfeTimings {
  double fluid = 0.0;         ///< Navier–Stokes steps
  double interpolation = 0.0; ///< J u at the points (both interpolations)
  double projection = 0.0;    ///< mass solves and the assembly of their right-hand sides
  double force = 0.0;         ///< nodal forces from the materials and tethers
  double spreading = 0.0;     ///< S F
  double points = 0.0;        ///< choosing the rules and placing the coupling points
  double stability = 0.0;     ///< the coupled stability estimates (not part of the steps' total)
  double implicit = 0.0;      ///< the semi-implicit coupling's half-step solve (its own parts included)
  double total = 0.0;
  long steps = 0;
};

/// The time-step estimate logged when a run starts (docs/ib.md, "Stability"): the largest stable dt
/// of the explicit coupling for the structure's stiffest grid-resolved mode,
///   omega^2 = 12 E / (rho h_s^2) + max_a kappa w_a / (rho h_s^3),  gamma = 12 mu / (rho h_s^2),
///   dt_max ~ max(2 / omega, 2 gamma / omega^2),
/// with E the largest eigenvalue of dP/dF on isochoric perturbations (dF orthogonal to F^-T, the
/// gradient of det F: the fluid keeps the motion isochoric, so the volumetric penalty does not count)
/// over the body parts' quadrature points, h_s = max(grid spacing, smallest element edge); 2/omega is the
/// inertial (leapfrog) limit and 2 gamma/omega^2 = 2 mu/E the limit when viscosity dominates. An
/// estimate, not a guarantee. In the reference state (F = I) dF is trace-free; in a deformed state the
/// same bound with the current tangent says how the stiffening of an exponential law moves the limit.
struct StabilityEstimate {
  /// One source of omega^2: a body part's elasticity, 12 E_part / (rho h_s^2), or a tether group's
  /// stiffest node, kappa w_a / (rho h_s^3). omega^2 is the largest part's plus the largest tether's.
  struct Term {
    std::string source; ///< "part leaflets", "tether tube_outer", ...
    double omega2 = 0.0;
    double dt = 0.0; ///< the limit this source alone would set
  };
  double modulus = 0.0;          ///< E, dyn/cm^2
  double tether_stiffness = 0.0; ///< max_a kappa w_a, dyn/cm
  double length = 0.0;           ///< h_s, cm
  double inertial_dt = 0.0;
  double viscous_dt = 0.0;
  double dt = 0.0; ///< the estimate
  std::vector<Term> terms;
};

/// The explicit coupling's stiffest mode measured on the coupling's own operators (docs/ib.md,
/// "Stability"): the largest eigenvalue omega^2 of the linearised step
///   d^2 chi / dt^2 = -A chi,   A = (1/rho) P_h J S M^{-1} K,
/// K the structure's stiffness at chi (its full rule's laws, i.e. without a centre-law volumetric
/// penalty, whose modes the incompressible flow does not excite, plus the tethers), S M^{-1} the force's
/// L2 projection and spreading, J and P_h the interpolation and the velocity's L2 projection: a force's
/// one-step effect on the faces, u += dt/rho f, before the viscous and pressure solves, which only
/// lower it. The explicit midpoint step is stable for dt < 2/omega. Unlike the per-element estimate it
/// sees how much fluid a node moves (the kernel's support) and how thin the structure is.
struct CoupledStabilityEstimate {
  double omega2 = 0.0; ///< the largest eigenvalue the power iterations found, 1/s^2
  double dt = 0.0;     ///< 2 / omega
  int iterations = 0;
  double change = 0.0; ///< |omega^2 change| / omega^2 over the last iteration
};

/// "part tube 63 % of omega^2 (alone 5.1e-05 s), tether tube_outer 37 % of omega^2 (alone 6.6e-05 s),
/// ...": each source's share of the estimate's omega^2 and the limit it alone would set, largest first.
std::string describe_stability_terms(const StabilityEstimate& estimate);

/// "dt = 2e-05 s is within the stable time step estimate 4.04e-05 s of the explicit IB/FE coupling: the
/// structure's inertial limit 2/omega binds (...)": the first step's log line, naming the limit that binds.
std::string describe_time_step(double dt, const StabilityEstimate& estimate);

class IbfeIntegrator {
 public:
  /// The structure in either flow solver (through make_eulerian_fluid: one grid used in place, or the
  /// finest of nested levels), which must outlive the integrator.
  IbfeIntegrator(fluid::FlowSolver& fluid, const fe::SolidModel& solid, IbfeSettings settings);
  /// The structure on any EulerianFluid, e.g. the finest level of nested grids (NestedFluid), which
  /// must outlive the integrator.
  IbfeIntegrator(EulerianFluid& fluid, const fe::SolidModel& solid, IbfeSettings settings);
  IbfeIntegrator(const IbfeIntegrator&) = delete;
  IbfeIntegrator& operator=(const IbfeIntegrator&) = delete;

  /// Sets the structure's current configuration chi = X + u (u replicated, 3 per node); zero at start.
  void set_displacement(std::vector<double> displacement);

  /// Advances fluid and structure from time() to time() + dt together.
  void step(double dt);

  double time() const { return fluid_.time(); }
  const EulerianFluid& fluid() const { return fluid_; }
  const fe::SolidModel& solid() const { return solid_; }
  const IbfeSettings& settings() const { return settings_; }
  /// u = chi - X at the nodes (replicated, interlaced).
  const std::vector<double>& displacement() const { return displacement_; }
  /// The nodal velocity of the last position update, U^{n+1/2} (zero before the first step).
  const std::vector<double>& velocity() const { return velocity_; }
  /// The nodal forces of the last step (materials and tethers), F^{n+1/2}.
  const std::vector<double>& nodal_forces() const { return forces_; }
  /// Current node positions.
  std::vector<Vec3> positions() const;
  /// The structure's current volume, sum over quadrature points of det F w det J.
  double volume() const;
  const CouplingPoints& coupling_points() const { return points_; }
  std::size_t coupling_point_count() const { return points_.size(); }
  const IbfeTimings& timings() const { return timings_; }
  /// Krylov iterations of the last step's L2 projections (velocity twice, force once; 0 for direct solves).
  PetscInt last_projection_iterations() const { return projection_iterations_; }
  /// GMRES iterations of the last step's semi-implicit solves, summed over its Newton iterations (0
  /// with the explicit coupling).
  PetscInt last_implicit_iterations() const { return implicit_iterations_; }
  /// The estimate in the reference state (no argument) or at the displacement u = chi - X given
  /// (replicated, 3 per node), e.g. displacement() for the current state. Collective only in the sense
  /// that every rank computes the same figure from the replicated state.
  StabilityEstimate stability_estimate(std::span<const double> displacement = {}) const;
  /// Per element, the limit its own stiffness alone would set on the step (the estimate's formula with
  /// the element's E and no tether), in the reference state or at `displacement`: where an
  /// exponential law's stiffening binds. Written with every field snapshot (`stable_step`).
  std::vector<double> element_stable_steps(std::span<const double> displacement = {}) const;

  /// The coupled estimate at the current state by `iterations` power iterations on A, started from the
  /// last call's dominant mode (a smooth field at the first), so that a few suffice as the state moves.
  /// Collective. Leaves the fluid and the structure as they were.
  CoupledStabilityEstimate coupled_stability_estimate(int iterations = 6);

  /// Writes the structure's state into `group` of a checkpoint (collective): the displacement chi - X
  /// (all that the next step reads besides the fluid), the last nodal velocity and forces (output),
  /// and the starting points of the iterative mass solves. The fluid saves itself
  /// (fluid::FlowSolver::save); a checkpoint of a coupled run holds both.
  void save(io::Hdf5File& file, const std::string& group) const;
  /// Reads what save() wrote (same mesh) and places the coupling points there. Restore the fluid
  /// first: this re-reads its velocity (EulerianFluid::refresh).
  void restore(const io::Hdf5File& file, const std::string& group);

  /// Places the coupling points for the nodes at X + `displacement`, interpolates the face velocity
  /// held in `velocity` (a local vector of the fluid grid) there and L2-projects it to the nodes.
  std::vector<double> nodal_velocity(Vec velocity, std::span<const double> displacement);

 private:
  IbfeIntegrator(std::unique_ptr<EulerianFluid> owned, EulerianFluid* fluid, const fe::SolidModel& solid,
                 IbfeSettings settings);
  void place_points(std::span<const double> displacement);
  /// The fluid's check that the nodes at X + `displacement` are where the IB can follow them
  /// (EulerianFluid::require_inside with the kernel's reach); RunError otherwise.
  void require_inside(std::span<const double> displacement) const;
  /// `guess_slot`: which earlier solution the consistent mass solve starts from (ib/nodal_mass.hpp).
  std::vector<double> project_velocity(Vec velocity, int guess_slot);
  std::vector<double> structure_forces(std::span<const double> displacement,
                                       std::span<const double> velocity);
  /// Adds the tethers' forces -w_a (k u_a + c v_a) to `F` (3 per node); an empty `velocity` adds the
  /// springs' alone (the stiffness the stability estimate differentiates).
  void add_tether_forces(std::span<double> F, std::span<const double> displacement,
                         std::span<const double> velocity) const;
  void spread_force_density(std::span<const double> nodal_forces);
  /// The prepared points' forces of a nodal force density (3 per node): its value there times the
  /// point's weight.
  std::vector<Vec3> point_forces(std::span<const double> density) const;

  std::unique_ptr<EulerianFluid> owned_fluid_; // the view made by the FlowSolver constructor
  EulerianFluid& fluid_;
  const fe::SolidModel& solid_;
  IbfeSettings settings_;
  GridInteraction interaction_;
  CouplingPoints points_;
  NodalMass velocity_mass_;
  std::unique_ptr<NodalMass> force_mass_; // null when it is the same kind as velocity_mass_
  /// Per element, E of the stability estimate: the largest isochoric modulus over its points.
  std::vector<double> element_moduli(std::span<const double> displacement) const;
  /// max(2 / omega, 2 gamma / omega^2) for omega^2 (the estimate's formula).
  double stable_step(double omega2) const;
  std::vector<std::pair<std::vector<double>, Tether>> tethers_; // node weights w_a, settings
  std::vector<double> displacement_, velocity_, forces_;
  GridInteraction::PreparedPoints prepared_; // the coupling points this rank handles, with their stencils
  std::vector<std::uint8_t> placed_;         // per element: may hold points this rank handles
  std::vector<std::size_t> candidates_;      // the points of those elements
  petsc::OwnedVec velocity_old_, velocity_mid_;
  IbfeTimings timings_;
  PetscInt projection_iterations_ = 0; // of the step being taken
  /// A = P_h J (R / dt) S M^{-1} K applied to `mode` (coupled_stability_estimate); R / dt = 1 / rho unless
  /// ib.stability_estimate is the response, the fluid has stokes_response() and a step has been taken.
  std::vector<double> coupled_operator(const std::vector<double>& mode);
  /// P_h J u with u the fluid's Stokes response over one step of dt (EulerianFluid::stokes_response)
  /// to the force density S M^{-1} F: the nodes' velocity change that the forces F give in one step.
  std::vector<double> stokes_model_response(std::span<const double> nodal_forces, double dt);
  petsc::OwnedVec probe_velocity_;

  /// Step 4 of both couplings: U^{n+1/2} from (u^n + u^{n+1})/2 at the points placed last (u^n in
  /// velocity_old_) and chi^{n+1} = chi^n + dt U^{n+1/2}.
  void finish_step(double dt);
  void step_semi_implicit(double dt);
  /// One Newton iteration of the semi-implicit coupling (header comment) from chi_k = `position` (its
  /// points placed), W_k and W_free: chi_{k+1}. Sets implicit_iterations_.
  std::vector<double> implicit_position(double dt, std::span<const double> position,
                                        std::span<const double> W, std::span<const double> W_free);
  /// The semi-implicit solve's operator and the state it is linearised at (ib/semi_implicit.cpp).
  struct ImplicitSolve {
    petsc::OwnedMat matrix; ///< shell: x -> x + dt/4 R K x
    petsc::OwnedKSP ksp;
    petsc::OwnedVec rhs, solution;
    std::vector<double> displacement; ///< chi_k, where K is taken
    std::vector<double> forces;       ///< the material forces at chi_k (no tethers)
    double scale = 0.0;               ///< dt / 4
    double dt = 0.0;
    std::exception_ptr error; ///< thrown inside the operator, rethrown after the solve
  };
  void create_implicit_solver();
  /// MATOP_MULT of ImplicitSolve::matrix (its context: the integrator).
  static PetscErrorCode apply_implicit_operator(Mat matrix, Vec x, Vec y);
  ImplicitSolve implicit_;
  PetscInt implicit_iterations_ = 0;
  std::vector<double> stability_mode_;        // the last dominant mode of A (checkpointed: the next start)
  CoupledStabilityEstimate coupled_estimate_; // the last one (none: dt 0)
  petsc::OwnedVec probe_force_;               // a grid vector for A's spreading, apart from the fluid's force
  double h_min_ = 0.0;
  /// h_s of the stability estimate: max(h_min_, the reference mesh's smallest edge), fixed for the run.
  double stability_length_ = 0.0;
  bool warned_capped_ = false;
};

} // namespace ibvalve::ib
