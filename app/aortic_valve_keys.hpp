#pragma once
// The aortic-valve model's keys (app/aortic_valve_model.cpp) and where they go (io/key_binder.hpp), bound
// section by section; the sections of other folders (the boundary drivers, the LV pressure table, the
// Windkessel, the materials, the report, checkpoints, nested levels) are theirs.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "app/adaptive_step.hpp"
#include "app/valve_mesh.hpp"
#include "drivers/keys.hpp"
#include "fe/volumetric_integration.hpp"
#include "fibers/rules.hpp"
#include "fluid/hierarchy.hpp"
#include "fluid/settings.hpp"
#include "hemodynamics/report.hpp"
#include "ib/ibfe.hpp"
#include "io/checkpoint.hpp"
#include "io/key_binder.hpp"
#include "materials/settings.hpp"

namespace ibvalve::app {

/// The model's own keys, in CGS; each value is its key's (the default written in bind, once).
struct AorticValveKeys {
  std::int64_t cycles = 0, every = 0;
  std::optional<double> end;
  double step = 0, coaptation_step = 0, pressure_ramp = 0;
  std::optional<double> fields_interval; // its default set: always read
  std::vector<double> coaptation_window;
  bool adaptive = false;
  AdaptiveStepSettings adaptive_step;
  std::vector<std::int64_t> cells;
  std::vector<double> lower, upper;
  fluid::FluidSettings fluid;
  double backflow = 0;
  ValveMeshKeys mesh;
  materials::MaterialKeys leaflets_material, tube_material;
  bool tube_wall = false; // tube.model = "wall": blocked fluid cells outside the lumen, no tube elements
  fibers::FiberRule rule = fibers::FiberRule::FD1;
  std::vector<std::string> tube_surfaces;
  double tube_stiffness = 0, tube_damping = 0, attachment_stiffness = 0, attachment_damping = 0;
  drivers::DriverKeys drivers; // inlet.driver, outlet.driver, circulation.*
  double inlet_radius = 0, outlet_radius = 0;
  bool inlet_walled = false, outlet_walled = false;
  double probe_offset = 0, flow_plane_offset = 0;
  int orifice_resolution = 0;
  ib::IbfeSettings coupling; // ib.kernel, ib.point_spacing
  int quadrature_degree = 0;
  fe::VolumetricIntegration volumetric_integration = fe::VolumetricIntegration::full;
  hemodynamics::ReportSettings report;
  std::vector<std::filesystem::path> fit_data;
  io::CheckpointSettings checkpoints; // its case_record the model's to fill in
  fluid::NestedKeys nested;
};

/// Declares (a Schema binder) or reads (a Config binder) every key of the model.
void bind(io::KeyBinder& keys, AorticValveKeys& k);

} // namespace ibvalve::app
