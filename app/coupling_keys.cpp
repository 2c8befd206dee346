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
}

} // namespace ibvalve::app
