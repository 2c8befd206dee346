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
