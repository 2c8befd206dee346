#include "app/coupling_keys.hpp"

#include <string>
#include <utility>
#include <vector>

#include "ib/kernels.hpp"

namespace ibvalve::app {

void bind_coupling_keys(io::KeyBinder& keys, ib::IbfeSettings& ib, double default_point_spacing)
{
  std::vector<std::pair<std::string, ib::KernelKind>> kernels;
  for (const ib::KernelKind kind : ib::every_kernel()) kernels.emplace_back(ib::kernel_name(kind), kind);
  keys.choice("ib.kernel", "regularized delta function", ib.kernel, kernels)
      .defaults(ib::kernel_name(ib::default_kernel));
  keys.real("ib.point_spacing", "largest spacing of the coupling points, in grid cells", ib.points.spacing)
      .defaults(default_point_spacing)
      .positive();
  keys.choice("ib.coupling",
              "how the structure's force at the half step is found: explicit (the explicit midpoint step, "
              "stable below the coupled stability estimate) or semi-implicit (the half-step position by "
              "Newton iterations through the fluid's own linear response: measured stable to 2-3 times the "
              "explicit step, at several Stokes solves a step; docs/ib.md, \"The semi-implicit coupling\")",
              ib.coupling,
              {{"explicit", ib::CouplingKind::explicit_midpoint},
               {"semi-implicit", ib::CouplingKind::semi_implicit}})
      .defaults(std::string("explicit"));
  keys.real("ib.implicit_tolerance",
            "with the semi-implicit coupling: the relative residual each Newton iteration's GMRES solve on "
            "the structure stops at",
            ib.semi_implicit.tolerance)
      .defaults(1e-3)
      .above(0.0)
      .below(1.0);
}

} // namespace ibvalve::app
