#pragma once
// The `ibfe` model on nested grid levels (nested.ratios non-empty, walled box): the fluid is
// fluid::NestedNavierStokes on the levels of the case's hierarchy and the structure lives on the finest
// level (ib::NestedFluid; docs/nested.md, "IB on the finest level"). Output: timeseries.csv with the
// columns of the uniform run, and fields/*.h5 + fields.xdmf with the composite pressure of every level
// box and the structure's current mesh. A structure node leaving the finest level stops the run (exit 3,
// the output written so far kept). Checkpoints (`checkpoint.every`, --stop-after-steps) hold the
// composite fluid state and the structure's; --restart continues bit for bit on the same rank count.
#include <span>
#include <string>
#include <vector>

#include "app/model.hpp"
#include "fe/mesh.hpp"
#include "fe/solid.hpp"
#include "fluid/hierarchy.hpp"
#include "fluid/nested_navier_stokes.hpp"
#include "ib/ibfe.hpp"
#include "io/checkpoint.hpp"
#include "io/config.hpp"

namespace ibvalve::app {

struct NestedIbfeCase {
  const fluid::GridHierarchy* hierarchy = nullptr;
  fluid::NestedFluidSettings fluid;
  const fe::Mesh* mesh = nullptr;
  const std::vector<fe::BodyPart>* parts = nullptr;
  const std::vector<materials::FiberFrame>* fibers = nullptr;
  int quadrature_degree = 2;
  ib::IbfeSettings ib;
  std::vector<double> initial_displacement;
  double end = 0.0, dt = 0.0;
  long output_every = 1;
  io::CheckpointSettings checkpoints;
};

/// The nested levels of a case whose structure starts at `positions` (node positions): read_hierarchy with
/// the structure's bounding box and the reach of `kernel`, automatic levels placed around it;
/// `structure_key` names the structure in the error when explicit boxes miss it. InputError (nested.box)
/// unless the finest level is one box (the structure lives on it). For the ibfe and aortic-valve models.
/// The cells of every level of `hierarchy`, in floating point.
double composite_cells(const fluid::GridHierarchy& hierarchy);

fluid::GridHierarchy read_structure_levels(const io::Config& config, const fluid::BoxGeometry& box,
                                           std::span<const fe::Vec3> positions, ib::KernelKind kernel,
                                           const std::string& structure_key);

RunSummary run_ibfe_on_nested_levels(const RunContext& context, const NestedIbfeCase& c);

} // namespace ibvalve::app
