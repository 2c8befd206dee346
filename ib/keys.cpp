#include "ib/keys.hpp"

#include <utility>

#include "ib/kernels.hpp"

namespace ibvalve::ib {

void bind(io::KeyBinder& keys, IbfeSettings& settings, double default_point_spacing,
          const std::string& prefix)
{
  std::vector<std::pair<std::string, KernelKind>> kernels;
  for (const KernelKind kind : every_kernel()) kernels.emplace_back(kernel_name(kind), kind);
  keys.choice(prefix + ".kernel", "regularized delta function", settings.kernel, kernels)
      .defaults(kernel_name(default_kernel));
  keys.real(prefix + ".point_spacing", "largest spacing of the coupling points, in grid cells",
            settings.points.spacing)
      .defaults(default_point_spacing)
      .positive();
  keys.choice(prefix + ".coupling",
              "how the structure's force at the half step is found: explicit (the explicit midpoint step, "
              "stable below the coupled stability estimate) or semi-implicit (the half-step position by "
              "Newton iterations through the fluid's own linear response: measured stable to 2-3 times the "
              "explicit step, at several Stokes solves a step; docs/ib.md, \"The semi-implicit coupling\")",
              settings.coupling,
              {{"explicit", CouplingKind::explicit_midpoint}, {"semi-implicit", CouplingKind::semi_implicit}})
      .defaults(std::string("explicit"));
  keys.choice(prefix + ".stability_estimate",
              "the fluid's part of the coupled stability estimate that the adaptive step follows: "
              "acceleration (the spread force's f / rho, 1.3-1.6 times below the true limit on loaded "
              "leaflets) or response (the fluid's one-step response with its pressure projection, 5-10 % "
              "above it, and slower to catch a mode that emerges within an interval; docs/ib.md, \"The "
              "coupled estimate\")",
              settings.stability_estimate,
              {{"acceleration", StabilityEstimateKind::acceleration},
               {"response", StabilityEstimateKind::fluid_response}})
      .defaults(std::string("acceleration"));
  keys.real(prefix + ".implicit_tolerance",
            "with the semi-implicit coupling: the relative residual each Newton iteration's GMRES solve on "
            "the structure stops at",
            settings.semi_implicit.tolerance)
      .defaults(1e-3)
      .above(0.0)
      .below(1.0);
}

void bind_projections(io::KeyBinder& keys, IbfeSettings& settings, const std::string& prefix)
{
  const std::vector<std::pair<std::string, fe::MassKind>> projections{
      {"consistent", fe::MassKind::consistent}, {"lumped", fe::MassKind::lumped}};
  keys.choice(prefix + ".velocity_projection", "L2 projection of the interpolated velocity to the nodes",
              settings.velocity_projection, projections)
      .defaults(std::string("consistent"));
  keys.choice(prefix + ".force_projection", "L2 projection of the nodal forces to a force density",
              settings.force_projection, projections)
      .defaults(std::string("consistent"));
}

namespace {

/// One [[ib.tether]]: a group of nodes pulled back to its reference positions (ib/ibfe.hpp, Tether).
void bind_tether(io::KeyBinder& keys, Tether& tether)
{
  keys.string("group", "a physical group of the mesh (surface, volume or points)", tether.group).required();
  keys.real("stiffness", "spring stiffness per area (surface), volume (volume) or per node (points), CGS",
            tether.stiffness)
      .defaults(0.0)
      .non_negative();
  keys.real("damping", "dashpot coefficient, the same per unit velocity, CGS", tether.damping)
      .defaults(0.0)
      .non_negative();
}

} // namespace

void bind_tethers(io::KeyBinder& keys, std::vector<Tether>& tethers, const std::string& prefix)
{
  keys.tables(prefix + ".tether", "tethers pulling groups of nodes back to their reference positions",
              tethers, bind_tether);
}

} // namespace ibvalve::ib
