#include "app/ibfe_fields.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <memory>
#include <span>
#include <sstream>
#include <vector>

#include <fmt/format.h>

#include "app/fftw_plans.hpp"
#include "base/logger.hpp"
#include "base/units.hpp"
#include "fe/element.hpp"
#include "io/collective.hpp"
#include "io/petsc_check.hpp"

namespace ibvalve::app {

namespace {

// The structure's geometry is where the body is now, so ParaView shows the motion as it opens the file.
const std::string geometry_description =
    "current positions x = X + displacement (cm): shown as is; Warp By Vector with displacement "
    "would move the body twice (the reference X = coordinates - displacement)";

// The stress a field file shows, in the report's unit (its S_ff columns and metrics are the same quantity
// averaged over spheres, hemodynamics/timeseries.hpp).
const std::string stress_name = "cauchy_stress_along_fiber";
const std::string stress_description =
    "f . (sigma f), f = F f0 / |F f0|: the total Cauchy stress (matrix, fibers and volumetric penalty, "
    "the penalty's element checkerboard filtered: docs/fe.md) normal to the plane across the current "
    "fiber, element average, kPa as the report's S_ff";

} // namespace

std::string fields_file_name(long step)
{
  return fmt::format("fields/step_{:06}.h5", step);
}

std::vector<std::int64_t> structure_part_ids(const fe::SolidModel& solid)
{
  std::vector<std::int64_t> ids(solid.mesh().num_elements(), 0);
  const auto& parts = solid.parts();
  for (std::size_t p = 0; p < parts.size(); ++p)
    for (int e : parts[p].elements) ids[static_cast<std::size_t>(e)] = static_cast<std::int64_t>(p + 1);
  return ids;
}

std::string structure_part_table(const fe::SolidModel& solid)
{
  std::string table;
  const auto& parts = solid.parts();
  for (std::size_t p = 0; p < parts.size(); ++p)
    table += fmt::format("{}{} = {}", (p ? ", " : ""), p + 1, parts[p].name);
  return table;
}

io::XdmfGrid write_structure_fields(io::Hdf5File& h5, const fe::Mesh& mesh, const ib::IbfeIntegrator& ibfe,
                                    const std::string& file)
{
  // The mesh is replicated on every rank: current coordinates, nodal and element fields.
  const std::size_t nodes = mesh.num_nodes(), elements = mesh.num_elements();
  const std::size_t per_element = static_cast<std::size_t>(mesh.nodes_per_element());
  const fe::SolidModel& solid = ibfe.solid();
  std::vector<std::int64_t> connectivity(mesh.connectivity().begin(), mesh.connectivity().end());
  std::vector<double> coordinates(3 * nodes);
  const auto x = ibfe.positions();
  for (std::size_t i = 0; i < nodes; ++i)
    for (int d = 0; d < 3; ++d) coordinates[3 * i + d] = x[i][d];
  const fe::ElementFields ef = solid.element_fields(ibfe.displacement());
  const std::vector<double> stable_steps = ibfe.element_stable_steps(ibfe.displacement());
  // Fibers per element: the reference f0 (the element's frame, zero where a part has none) and the
  // current f = F f0 / |F f0| that element_fields already averages; both unit vectors or zero.
  std::vector<double> fiber_reference(3 * elements), fiber_direction(3 * elements);
  for (std::size_t e = 0; e < elements; ++e) {
    const Eigen::Vector3d f0 = solid.centre_fibers(e).f0;
    const Eigen::Vector3d r = f0.norm() > 0 ? Eigen::Vector3d(f0.normalized()) : Eigen::Vector3d::Zero();
    for (int d = 0; d < 3; ++d) {
      fiber_reference[3 * e + d] = r[d];
      fiber_direction[3 * e + d] = ef.fiber_direction[e][d];
    }
  }
  const std::vector<hsize_t> node_vector{nodes, 3}, cell_scalar{elements}, cell_nodes{elements, per_element};
  h5.write_root("mesh/connectivity", connectivity, cell_nodes);
  h5.write_root("mesh/coordinates", coordinates, node_vector);
  h5.write_string_attribute("mesh/coordinates", "units", "cm");
  h5.write_string_attribute("mesh/coordinates", "description", geometry_description);
  h5.write_root("mesh/part", structure_part_ids(solid), cell_scalar);
  h5.write_string_attribute("mesh/part", "parts", structure_part_table(solid));
  auto structure = io::XdmfGrid::mesh("structure", fe::xdmf_topology(mesh.shape()), elements, per_element,
                                      file + ":/mesh/connectivity", nodes, file + ":/mesh/coordinates");
  structure.add_information("geometry", geometry_description)
      .add_information(stress_name, stress_description)
      .add_information("part", structure_part_table(solid))
      .add_field("part", io::Center::cell, {elements}, file + ":/mesh/part", "", true);
  std::vector<double> stress(ef.fiber_stress.size());
  for (std::size_t e = 0; e < stress.size(); ++e) stress[e] = ef.fiber_stress[e] / units::kPa;
  struct Field {
    std::string name;
    io::Center center;
    std::span<const double> values;
    bool vector;
    const char* units;
  };
  const Field fields[] = {{"displacement", io::Center::node, ibfe.displacement(), true, "cm"},
                          {"structure_velocity", io::Center::node, ibfe.velocity(), true, "cm/s"},
                          {"J", io::Center::cell, ef.J, false, "1"},
                          {"fiber_strain", io::Center::cell, ef.fiber_strain, false, "1"},
                          {stress_name, io::Center::cell, stress, false, "kPa"},
                          {"fiber_direction", io::Center::cell, fiber_direction, true, "1"},
                          {"fiber_reference", io::Center::cell, fiber_reference, true, "1"},
                          {"stable_step", io::Center::cell, stable_steps, false, "s"}};
  for (const Field& f : fields) {
    const std::size_t count = f.center == io::Center::node ? nodes : elements;
    std::vector<hsize_t> dims{count};
    if (f.vector) dims.push_back(3);
    const std::string dataset = "mesh/" + f.name;
    h5.write_root(dataset, f.values, dims);
    h5.write_string_attribute(dataset, "units", f.units);
    structure.add_field(f.name, f.center, {dims.begin(), dims.end()}, file + ":/" + dataset, f.units);
  }
  return structure;
}

void write_ibfe_fields(MPI_Comm comm, const std::filesystem::path& directory, FieldSeries& series,
                       const fe::Mesh& mesh, const fluid::FlowSolver& fluid, const ib::IbfeIntegrator& ibfe,
                       long step)
{
  const std::string file = fields_file_name(step);
  io::Hdf5File h5(comm, directory / file, io::Hdf5File::Mode::create);
  std::vector<io::XdmfGrid> fluid_grids = fluid.write_fields(h5, "fluid", file);
  io::XdmfGrid structure = write_structure_fields(h5, mesh, ibfe, file);
  h5.close(); // written, or a RunError on every rank (a full disk), before an XDMF file names it
  series.at("fluid").add_step(ibfe.time(), std::move(fluid_grids));
  series.at("structure").add_step(ibfe.time(), {std::move(structure)});
}

void InversionWatch::observe(double t, const fe::SmallestJacobian& smallest)
{
  const bool inverted = smallest.element >= 0 && smallest.J <= 0.0;
  if (inverted && !inverted_) {
    const fe::Mesh& mesh = solid_.mesh();
    fe::Vec3 centre = fe::Vec3::Zero();
    const auto element = mesh.element(static_cast<std::size_t>(smallest.element));
    for (int node : element) centre += mesh.nodes()[node];
    centre /= static_cast<double>(element.size());
    std::string part = "no part";
    for (const fe::BodyPart& p : solid_.parts())
      if (std::find(p.elements.begin(), p.elements.end(), smallest.element) != p.elements.end())
        part = p.name;
    base::Logger::global().warn(fmt::format(
        "t = {:.6g} s: element {} ({}, reference centre ({:.4g}, {:.4g}, {:.4g}) cm) is inverted at a "
        "quadrature point, J = {:.3g}; a run usually blows up within some steps of this (docs/fe.md, "
        "\"Inverted element corners\"; diagnostics.csv's smallest_J follows it)",
        t, smallest.element, part, centre.x(), centre.y(), centre.z(), smallest.J));
  }
  inverted_ = inverted;
}

StepFigures ibfe_step_figures(const fluid::FlowSolver& fluid, const ib::IbfeIntegrator& ibfe, double dt,
                              InversionWatch* watch)
{
  StepFigures f = fluid_step_figures(fluid, dt);
  f.solver.push_back(
      {"structure_iterations", static_cast<double>(ibfe.last_projection_iterations()), "structure it"});
  if (ibfe.settings().coupling == ib::CouplingKind::semi_implicit)
    f.solver.push_back(
        {"implicit_iterations", static_cast<double>(ibfe.last_implicit_iterations()), "implicit it"});
  const fe::SmallestJacobian smallest = ibfe.solid().smallest_point_jacobian(ibfe.displacement());
  f.solver.push_back({"smallest_J", smallest.J, "min J"});
  if (watch) watch->observe(ibfe.time(), smallest);
  return f;
}

void set_ibfe_hooks(TimeLoop& loop, const RunContext& context, const fe::Mesh& mesh, fluid::FlowSolver& fluid,
                    ib::IbfeIntegrator& ibfe, double dt)
{
  const RunContext* run = &context;
  const fe::Mesh* structure = &mesh;
  fluid::FlowSolver* flow = &fluid;
  ib::IbfeIntegrator* coupled = &ibfe;
  loop.time = [coupled](std::int64_t) { return coupled->time(); };
  loop.field_parts = ibfe_field_parts;
  loop.write_fields = [=](FieldSeries& series, std::int64_t step) {
    write_ibfe_fields(run->comm, run->run_directory, series, *structure, *flow, *coupled,
                      static_cast<long>(step));
  };
  loop.save = [=](io::Hdf5File& h5) {
    flow->save(h5, "fluid");
    coupled->save(h5, "ibfe");
  };
  loop.restore = [=](const io::Hdf5File& h5) {
    flow->restore(h5, "fluid");
    coupled->restore(h5, "ibfe");
  };
  loop.before_save = [run] { save_fftw_plans(*run); };
  auto watch = std::make_shared<InversionWatch>(ibfe.solid());
  loop.figures = [=] { return ibfe_step_figures(*flow, *coupled, dt, watch.get()); };
}

std::vector<std::string> ibfe_summary_lines(const ib::IbfeIntegrator& ibfe, double initial_volume,
                                            const std::filesystem::path& directory, std::size_t outputs,
                                            const std::string& after_parts)
{
  const ib::IbfeTimings& t = ibfe.timings();
  std::ostringstream timing;
  timing.precision(3);
  timing << "per coupled step: " << t.total / t.steps << " s (fluid " << t.fluid / t.steps
         << ", interpolation " << t.interpolation / t.steps << ", projection " << t.projection / t.steps
         << ", force " << t.force / t.steps << ", spreading " << t.spreading / t.steps << ")" << after_parts;
  return {timing.str(),
          fmt::format("structure volume change {:g} %", 100.0 * (ibfe.volume() / initial_volume - 1.0)),
          fmt::format("fields: {} and {} ({} outputs), time series: {}",
                      (directory / field_series_file("fluid")).string(),
                      (directory / field_series_file("structure")).string(), outputs,
                      (directory / "timeseries.csv").string())};
}

} // namespace ibvalve::app
