#include "app/coupling_keys.hpp"

#include <string>
#include <utility>
#include <vector>

#include "ib/kernels.hpp"

namespace ibvalve::app {

void bind_coupling_keys(io::KeyBinder& keys, ib::IbfeSettings& ib)
{
  std::vector<std::pair<std::string, ib::KernelKind>> kernels;
  for (const ib::KernelKind kind : ib::every_kernel()) kernels.emplace_back(ib::kernel_name(kind), kind);
  keys.choice("ib.kernel", "regularized delta function", ib.kernel, kernels)
      .defaults(ib::kernel_name(ib::default_kernel));
  keys.real("ib.point_spacing", "largest spacing of the coupling points, in grid cells", ib.points.spacing)
      .defaults(0.5)
      .positive();
  // docs/ib.md, "Time stepping": the lagged predictor saves a point placement, an interpolation and a
  // projection a step, at a lower stable time step.
  keys.choice("ib.predictor",
              "structure velocity of the half-step position: interpolated U^n (explicit midpoint rule) or "
              "lagged U^{n-1/2}",
              ib.predictor,
              std::vector<std::pair<std::string, ib::HalfStepPredictor>>{
                  {"interpolated", ib::HalfStepPredictor::interpolated},
                  {"lagged", ib::HalfStepPredictor::lagged}})
      .defaults(std::string("interpolated"));
}

} // namespace ibvalve::app
