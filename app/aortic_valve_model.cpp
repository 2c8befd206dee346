// `model = "aortic-valve"`: the study's set-up (REFERENCE.md) on top of the IB/FE coupling
// (ib/ibfe.hpp): the tri-leaflet valve in its tube (fe/valve_mesh.hpp, generated at start-up or read
// from a Gmsh file), fibers from the mesh groups (fibers/rules.hpp, FD1 or FD2), one material per body
// (leaflets, tube), the tube's outer surface and the leaflets' attachments tethered; the box's inlet
// side (z lower) carries the LV pressure in a disk of the tube's radius, the outlet side (z upper) the
// pressure of a three-element Windkessel fed with the outlet flux each step, zero pressure elsewhere.
// Probes come from the geometry; the orifice area from the deformed leaflets; the report is written at
// the end of every cycle. With `nested.ratios` the fluid is fluid::NestedNavierStokes on nested levels
// placed around the valve and tube, with the same sides, and the structure lives on the finest level
// (docs/nested.md, "The aortic-valve case on nested levels").
//
// Windkessel coupling: explicit, lagged by one step. Step n uses P_Ao^n as the outlet pressure; after
// it the flux Q^{n+1} through the outlet disk advances the Windkessel (linear flow over the step,
// windkessel/windkessel.hpp) to give P_Ao^{n+1}. The lag is O(dt) in P_Ao; with dt = 1e-4 s and
// R_c = 0.033 mmHg s/mL it changes P_Ao by R_c dQ, well below 0.1 mmHg.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include <mpi.h>

#include "app/fftw_plans.hpp"
#include "app/fluid_box.hpp"
#include "app/ibfe_fields.hpp"
#include "app/ibfe_nested_run.hpp"
#include "app/model.hpp"
#include "app/resource_estimate.hpp"
#include "app/restart.hpp"
#include "app/step_diagnostics.hpp"
#include "app/stop_signal.hpp"
#include "app/structure_parts.hpp"
#include "app/version.hpp"
#include "fe/gmsh_io.hpp"
#include "fe/mesh.hpp"
#include "fe/solid.hpp"
#include "fe/valve_mesh.hpp"
#include "fibers/rules.hpp"
#include "fluid/hierarchy.hpp"
#include "fluid/navier_stokes.hpp"
#include "fluid/nested_navier_stokes.hpp"
#include "fluid/queries.hpp"
#include "hemodynamics/geometry.hpp"
#include "hemodynamics/report.hpp"
#include "hemodynamics/timeseries.hpp"
#include "ib/eulerian_fluid.hpp"
#include "ib/ibfe.hpp"
#include "io/checkpoint.hpp"
#include "io/collective.hpp"
#include "io/errors.hpp"
#include "io/files.hpp"
#include "io/logger.hpp"
#include "io/units.hpp"
#include "materials/settings.hpp"
#include "windkessel/waveform.hpp"
#include "windkessel/windkessel.hpp"

namespace ibvalve::app {

namespace {

constexpr int leaflet_count = 3;

void add_aortic_valve_schema(io::Schema& s)
{
  s.add_integer("time.cycles", "cardiac cycles to run (a report after each)")
      .defaults(std::int64_t{1})
      .at_least(1);
  s.add_real("time.end",
             "simulated end time; unset = time.cycles x the LV pressure's period; a run shorter than a cycle "
             "is reported over its whole length")
      .unit("s")
      .positive();
  s.add_real("time.step", "time step (rounded so a cycle holds a whole number of steps)")
      .unit("s")
      .defaults(5e-5)
      .positive();
  s.add_real("time.pressure_ramp",
             "the inlet and outlet pressures rise from zero to their values over this time, as "
             "(1 - cos(pi t / T)) / 2, so that the valve closes under the Windkessel pressure without the "
             "water hammer of a sudden load (docs/speed-2026-12-01.md, \"The time step\"); 0 = applied "
             "at once")
      .unit("s")
      .defaults(0.05)
      .non_negative();
  s.add_real("output.fields_interval",
             "simulated time between field snapshots (fields/*.h5 + fields.xdmf for ParaView); 0 = none")
      .unit("s")
      .defaults(0.02)
      .non_negative();
  s.add_integer("output.every", "write a time-series row every this many steps")
      .defaults(std::int64_t{10})
      .at_least(1);
  add_fluid_density_key(s, "blood density");
  s.add_real("fluid.viscosity", "blood viscosity")
      .unit("cP")
      .defaults(4.0)
      .positive()
      .typical(1.0, 20.0, "blood is 3.5 to 4 cP; 1000 times less is a value in Pa s, 100 times less in P");
  s.add_integer_list("fluid.cells", "grid cells in x, y, z")
      .size(3)
      .at_most(max_grid_cells)
      .defaults(std::vector<std::int64_t>{16, 16, 28});
  s.add_real_list("fluid.lower", "lower corner of the box (the tube's axis is x = y = 0, inlet at z = 0)")
      .unit("cm")
      .size(3)
      .defaults(std::vector<double>{-4.0, -4.0, -0.5});
  s.add_real_list("fluid.upper", "upper corner of the box")
      .unit("cm")
      .size(3)
      .defaults(std::vector<double>{4.0, 4.0, 13.5});
  s.add_string("fluid.subsolver",
               "sub-solves of the Krylov Stokes solver's preconditioner: fft (FFTW sine/cosine transforms) "
               "or amg (hypre BoomerAMG V-cycles)")
      .defaults(std::string("fft"))
      .choices({"amg", "fft"});
  s.add_real("fluid.rtol", "relative tolerance of the Krylov (FGMRES) Stokes solve each step")
      .defaults(1e-8)
      .positive();
  s.add_integer("fluid.max_iterations", "most FGMRES iterations per step")
      .defaults(std::int64_t{100})
      .at_least(1)
      .at_most(max_solver_iterations);
  s.add_real("fluid.backflow_stabilization",
             "beta: where fluid enters through the box's pressure sides, their pressure is lowered by "
             "beta rho/2 (u.n)^2 (the LV pressure becomes a total pressure); 0 = plain static pressure, "
             "which lets backflow grow")
      .defaults(1.0)
      .non_negative();

  s.add_string("mesh.file", "a Gmsh mesh with the groups of `ibvalve mesh aortic-valve`; unset = generate it")
      .file(true);
  const fe::ValveMeshParameters d;
  s.add_real("mesh.tube_radius", "tube inner radius")
      .unit("cm")
      .defaults(d.tube_radius)
      .positive()
      .typical(0.5, 3.0, "an aortic root is about 1.2 cm; 10 times more is a value in mm");
  s.add_real("mesh.tube_wall", "tube wall thickness").unit("cm").defaults(d.tube_wall).positive();
  s.add_real("mesh.tube_length", "tube length")
      .unit("cm")
      .defaults(d.tube_length)
      .positive()
      .typical(1.0, 30.0, "a few aortic root radii; 10 times more is a value in mm");
  s.add_real("mesh.leaflet_thickness", "leaflet thickness")
      .unit("cm")
      .defaults(d.leaflet_thickness)
      .positive();
  s.add_real("mesh.valve_base", "z of the attachment's nadir").unit("cm").defaults(d.valve_base).positive();
  s.add_real("mesh.commissure_height", "commissures above the nadir")
      .unit("cm")
      .defaults(d.commissure_height)
      .positive();
  s.add_real("mesh.sag", "belly depth toward the ventricle").unit("cm").defaults(d.sag).non_negative();
  s.add_real("mesh.free_edge_drop",
             "how far the free edge descends from the commissures to the valve centre (slack for opening)")
      .unit("cm")
      .defaults(d.free_edge_drop)
      .non_negative();
  s.add_real("mesh.free_edge_gap", "gap between closed free edges")
      .unit("cm")
      .defaults(d.free_edge_gap)
      .positive();
  s.add_integer("mesh.leaflet_across", "leaflet elements commissure to commissure (even)")
      .defaults(std::int64_t{16})
      .at_most(max_mesh_cells);
  s.add_integer("mesh.leaflet_radial", "leaflet elements attachment to free edge")
      .defaults(std::int64_t{6})
      .at_most(max_mesh_cells);
  s.add_integer("mesh.tube_around", "tube elements around")
      .defaults(std::int64_t{48})
      .at_most(max_mesh_cells);
  s.add_integer("mesh.tube_along", "tube elements along").defaults(std::int64_t{52}).at_most(max_mesh_cells);

  s.merge(materials::material_schema("leaflets.material"));
  s.merge(materials::material_schema("tube.material"));
  s.add_string("fibers.rule", "leaflet fiber rule (docs/fibers.md)")
      .choices({"FD1", "FD2"})
      .defaults(std::string("FD1"));
  s.add_string_list("tether.tube_surfaces",
                    "the tube's surface groups held in place: tube_outer (the study), and its end faces "
                    "tube_inlet, tube_outlet")
      .choices({"tube_outer", "tube_inlet", "tube_outlet"})
      .defaults(std::vector<std::string>{"tube_outer"});
  s.add_real("tether.tube_stiffness", "spring per area holding the tube's surfaces in place, dyn/cm^3")
      .defaults(1e8)
      .non_negative();
  s.add_real("tether.tube_damping", "dashpot per area on the tube's surfaces").defaults(0.0).non_negative();
  s.add_real("tether.attachment_stiffness", "spring per area holding each leaflet's attachment, dyn/cm^3")
      .defaults(1e8)
      .non_negative();
  s.add_real("tether.attachment_damping", "dashpot per area on the attachments").defaults(0.0).non_negative();

  windkessel::add_waveform_schema(s, "lv_pressure", "LV pressure on the inlet disk, in mmHg");
  s.add_real("inlet.radius", "radius of the inlet pressure disk (0 = the middle of the tube wall)")
      .unit("cm")
      .defaults(0.0)
      .non_negative();
  s.add_string("inlet.outside",
               "the inlet side outside its disk: zero-pressure (the study) or wall (no slip, closes the "
               "space around the tube's end)")
      .choices({"zero-pressure", "wall"})
      .defaults(std::string("zero-pressure"));
  windkessel::add_schema(s, "windkessel");
  s.add_real("outlet.radius", "radius of the Windkessel disk (0 = the middle of the tube wall)")
      .unit("cm")
      .defaults(0.0)
      .non_negative();
  s.add_string("outlet.outside", "the outlet side outside its disk: zero-pressure (the study) or wall")
      .choices({"zero-pressure", "wall"})
      .defaults(std::string("zero-pressure"));
  s.add_real("probes.offset", "P_nlv / P_nao: on the axis this far below the nadir / above the commissures")
      .unit("cm")
      .defaults(1.0)
      .positive();
  s.add_real("probes.flow_plane_offset", "Q_valve through the tube section this far below the nadir")
      .unit("cm")
      .defaults(0.5)
      .non_negative();
  s.add_integer("probes.orifice_resolution", "pixels per side of the orifice-area raster")
      .defaults(std::int64_t{256})
      .at_least(16)
      .at_most(8192);

  s.add_string("ib.kernel", "regularized delta function")
      .choices({"piecewise-linear", "ib-3", "ib-4", "ib-6", "bspline-3"})
      .defaults(ib::kernel_name(ib::default_kernel));
  s.add_real("ib.point_spacing", "largest spacing of the coupling points, in grid cells")
      .defaults(0.5)
      .positive();
  s.add_integer("structure.quadrature_degree", "Gauss rule degree of the force integrals")
      .defaults(std::int64_t{2})
      .at_least(1)
      .at_most(max_quadrature_degree);
  // One hex through the leaflet thickness locks in bending when the penalty (kappa/mu ~ 800) is
  // integrated on the full rule: selective reduced integration by default (docs/fe.md).
  add_volumetric_integration_key(s, VolumetricIntegration::reduced);
  hemodynamics::add_report_schema(s, "report");
  io::add_checkpoint_schema(s);
  // Nested grid levels around the valve and tube (docs/nested.md): the structure on the finest level.
  s.merge(fluid::nested_schema());
}

class AorticValveRun : public PreparedRun {
 public:
  explicit AorticValveRun(const io::Config& config)
      : config_(config), lv_(windkessel::waveform_from_config(config, "lv_pressure", units::mmHg)),
        outlet_parameters_(windkessel::parameters_from_config(config, "windkessel")),
        report_(hemodynamics::metric_settings_from_config(config, "report")),
        report_templates_(hemodynamics::report_templates_from_config(config, "report"))
  {
    box_ = read_fluid_box(config);
    box_.periodic = {false, false, false};
    fluid_.rho = config.real("fluid.density");
    fluid_.mu = config.real("fluid.viscosity");
    fluid_.solver = fluid::SolverKind::krylov;
    fluid_.subsolver =
        config.string("fluid.subsolver") == "fft" ? fluid::SubsolverKind::fft : fluid::SubsolverKind::amg;
    fluid_.rtol = config.real("fluid.rtol");
    fluid_.max_iterations = static_cast<PetscInt>(config.integer("fluid.max_iterations"));
    backflow_ = config.real("fluid.backflow_stabilization");

    geometry_.tube_radius = config.real("mesh.tube_radius");
    geometry_.tube_wall = config.real("mesh.tube_wall");
    geometry_.tube_length = config.real("mesh.tube_length");
    geometry_.leaflet_thickness = config.real("mesh.leaflet_thickness");
    geometry_.valve_base = config.real("mesh.valve_base");
    geometry_.commissure_height = config.real("mesh.commissure_height");
    geometry_.sag = config.real("mesh.sag");
    geometry_.free_edge_drop = config.real("mesh.free_edge_drop");
    geometry_.free_edge_gap = config.real("mesh.free_edge_gap");
    geometry_.leaflet_across = static_cast<int>(config.integer("mesh.leaflet_across"));
    geometry_.leaflet_radial = static_cast<int>(config.integer("mesh.leaflet_radial"));
    geometry_.tube_around = static_cast<int>(config.integer("mesh.tube_around"));
    geometry_.tube_along = static_cast<int>(config.integer("mesh.tube_along"));
    if (config.has("mesh.file")) {
      mesh_ = fe::read_msh(config.path("mesh.file"));
      check_size(config, static_cast<double>(mesh_.num_nodes()), static_cast<double>(mesh_.num_elements()),
                 "mesh.file");
    } else {
      try {
        fe::check(geometry_);
      } catch (const std::invalid_argument& e) {
        config.fail("mesh", e.what());
      }
      // Hexahedra of the three leaflets and the tube, one layer through each (two layers of nodes).
      const double leaflets = leaflet_count * static_cast<double>(geometry_.leaflet_across) *
                              static_cast<double>(geometry_.leaflet_radial),
                   tube =
                       static_cast<double>(geometry_.tube_around) * static_cast<double>(geometry_.tube_along);
      const double nodes =
          2.0 * (leaflet_count * (geometry_.leaflet_across + 1.0) * (geometry_.leaflet_radial + 1.0) +
                 geometry_.tube_around * (geometry_.tube_along + 1.0));
      check_size(config, nodes, leaflets + tube,
                 tube > leaflets ? "mesh.tube_around" : "mesh.leaflet_across");
      mesh_ = fe::aortic_valve_mesh(geometry_);
    }
    for (const std::string group : {"tube", "tube_outer"})
      if (!mesh_.has_group(group)) config.fail("mesh.file", "the mesh has no group '" + group + "'");
    for (int k = 1; k <= leaflet_count; ++k)
      for (const std::string suffix : {"", "_attachment", "_n1", "_n2", "_tau1", "_tau2"})
        if (!mesh_.has_group(leaflet(k) + suffix))
          config.fail("mesh.file", "the mesh has no group '" + leaflet(k) + suffix + "'");
    for (const fe::Vec3& X : mesh_.nodes())
      for (int d = 0; d < 3; ++d)
        if (!(X[d] > box_.lower[d] && X[d] < box_.upper[d]))
          config.fail("fluid.lower", "the valve and tube must lie inside the box");

    leaflet_material_ = materials::read_material(config, "leaflets.material");
    tube_material_ = materials::read_material(config, "tube.material");
    rule_ = fibers::parse_fiber_rule(config.string("fibers.rule"));
    ib_.kernel = *ib::find_kernel(config.string("ib.kernel"));
    ib_.points.spacing = config.real("ib.point_spacing");
    for (const std::string& surface : config.strings("tether.tube_surfaces")) {
      if (!mesh_.has_group(surface))
        config.fail("tether.tube_surfaces", "the mesh has no group '" + surface + "'");
      ib_.tethers.push_back(
          {surface, config.real("tether.tube_stiffness"), config.real("tether.tube_damping")});
    }
    for (int k = 1; k <= leaflet_count; ++k)
      ib_.tethers.push_back({leaflet(k) + "_attachment", config.real("tether.attachment_stiffness"),
                             config.real("tether.attachment_damping")});

    const double r = geometry_.tube_radius;
    // The disks end in the middle of the tube wall by default: the jump of the boundary pressure then
    // sits inside the structure, which holds it, and not in the fluid at the tube's end (docs: the
    // example's README, "Boundary").
    const double mid_wall = r + 0.5 * geometry_.tube_wall;
    inlet_radius_ = config.real("inlet.radius") > 0 ? config.real("inlet.radius") : mid_wall;
    outlet_radius_ = config.real("outlet.radius") > 0 ? config.real("outlet.radius") : mid_wall;
    inlet_walled_ = config.string("inlet.outside") == "wall";
    outlet_walled_ = config.string("outlet.outside") == "wall";
    pressure_ramp_ = config.real("time.pressure_ramp");
    period_ = lv_.period();
    if (std::abs(report_.period - period_) > 1e-9 * period_)
      config.fail("report.period", "differs from the LV pressure table's period");
    steps_per_cycle_ = std::max<long>(1, std::lround(period_ / config.real("time.step")));
    cycles_ = config.integer("time.cycles");
    every_ = config.integer("output.every");
    read_end(config);
    const double fields_interval = config.real("output.fields_interval");
    fields_every_ = fields_interval > 0
                        ? std::max<long>(1, std::lround(fields_interval *
                                                        static_cast<double>(steps_per_cycle_) / period_))
                        : 0;
    const double nadir = geometry_.valve_base, top = nadir + geometry_.commissure_height;
    flow_plane_z_ = nadir - config.real("probes.flow_plane_offset");
    near_lv_z_ = nadir - config.real("probes.offset");
    near_ao_z_ = top + config.real("probes.offset");
    orifice_resolution_ = static_cast<int>(config.integer("probes.orifice_resolution"));
    plots_ = config.boolean("report.plots");
    checkpoint_settings_ = io::checkpoint_settings_from_config(config);
    if (!config.integers("nested.ratios").empty()) read_levels(config);
  }

  RunSummary run(const RunContext& context) override
  {
    auto& log = io::Logger::global();
    const double dt = period_ / static_cast<double>(steps_per_cycle_);

    // Fibers (rule FD1/FD2) from each leaflet's groups, computed on the mesh at start-up.
    std::vector<fibers::LeafletSpec> specs;
    for (int k = 1; k <= leaflet_count; ++k) {
      fibers::LeafletSpec spec;
      spec.group = leaflet(k);
      specs.push_back(spec);
    }
    const fibers::FiberField field = fibers::compute_fibers(mesh_, rule_, specs, context.comm);
    std::vector<materials::FiberFrame> frames(mesh_.num_elements());
    for (std::size_t e = 0; e < frames.size(); ++e) frames[e].f0 = field.element_directions[e];

    std::vector<fe::BodyPart> parts;
    const VolumetricIntegration volumetric_integration = read_volumetric_integration(config_);
    std::vector<int> leaflet_elements;
    for (int k = 1; k <= leaflet_count; ++k) {
      const auto& elements = mesh_.group(leaflet(k)).elements;
      leaflet_elements.insert(leaflet_elements.end(), elements.begin(), elements.end());
      parts.push_back(material_part(leaflet(k), elements, leaflet_material_.build(), volumetric_integration));
    }
    parts.push_back(
        material_part("tube", mesh_.group("tube").elements, tube_material_.build(), volumetric_integration));
    fe::SolidModel solid(mesh_, parts, static_cast<int>(config_.integer("structure.quadrature_degree")),
                         context.comm);
    solid.set_fibers(frames);

    // Boundary: every side a traction side; zero pressure except the inlet and outlet disks, and the
    // inlet/outlet sides outside their disks walled when asked (fluid/boundary.hpp).
    double outlet_pressure = outlet_parameters_.initial_pressure;
    fluid::BoundaryConditions bc;
    for (int side = 0; side < 6; ++side) {
      bc.side(side).kind = fluid::SideKind::traction;
      bc.side(side).backflow = backflow_;
    }
    const double rin = inlet_radius_, rout = outlet_radius_;
    bc.side(2, 0).pressure = [this, rin](const fluid::Real3& x, double t) {
      return std::hypot(x[0], x[1]) < rin ? pressure_ramp(t) * lv_(t) : 0.0;
    };
    bc.side(2, 1).pressure = [this, &outlet_pressure, rout](const fluid::Real3& x, double t) {
      return std::hypot(x[0], x[1]) < rout ? pressure_ramp(t) * outlet_pressure : 0.0;
    };
    if (inlet_walled_)
      bc.side(2, 0).wall = [rin](const fluid::Real3& x) { return std::hypot(x[0], x[1]) >= rin; };
    if (outlet_walled_)
      bc.side(2, 1).wall = [rout](const fluid::Real3& x) { return std::hypot(x[0], x[1]) >= rout; };
    // The fluid: one grid (fluid::NavierStokes) or nested levels (fluid::NestedNavierStokes, the structure
    // on the finest level). Both take the same boundary conditions; the probes below ask either.
    const auto at_rest = [](const fluid::Real3&, double) { return fluid::Real3{0.0, 0.0, 0.0}; };
    std::unique_ptr<fluid::NavierStokes> uniform;
    std::unique_ptr<fluid::NestedNavierStokes> nested;
    std::unique_ptr<ib::NestedFluid> finest;
    std::unique_ptr<ib::IbfeIntegrator> coupling;
    std::string grid_description;
    if (hierarchy_) {
      nested = std::make_unique<fluid::NestedNavierStokes>(context.comm, *hierarchy_, bc, nested_settings_);
      nested->set_initial_condition(at_rest, nullptr, 0.0);
      finest = std::make_unique<ib::NestedFluid>(*nested);
      coupling = std::make_unique<ib::IbfeIntegrator>(*finest, solid, ib_);
      grid_description = describe_levels(*hierarchy_);
    } else {
      if (context.restart) load_fftw_plans(context); // the interrupted run's FFTW plans: the same bits
      uniform = std::make_unique<fluid::NavierStokes>(context.comm, box_, bc, fluid_);
      uniform->set_initial_condition(at_rest, nullptr, 0.0);
      coupling = std::make_unique<ib::IbfeIntegrator>(*uniform, solid, ib_);
      grid_description = "grid " + std::to_string(box_.cells[0]) + " x " + std::to_string(box_.cells[1]) +
                         " x " + std::to_string(box_.cells[2]);
    }
    ib::IbfeIntegrator& ibfe = *coupling;
    windkessel::ThreeElementWindkessel outlet(outlet_parameters_);
    const ib::StabilityEstimate stability = ibfe.stability_estimate();
    log.info("aortic valve: " + std::to_string(mesh_.num_elements()) + " elements (" +
             std::to_string(leaflet_elements.size()) + " in the leaflets), " +
             std::to_string(mesh_.num_nodes()) + " nodes; " + grid_description + "; dt " +
             hemodynamics::format_value(dt) + " s (the stability estimate " +
             hemodynamics::format_value(stability.dt) + " s), " + std::to_string(steps_) +
             " steps to t = " + hemodynamics::format_value(static_cast<double>(steps_) * dt) +
             " s; leaflets " + leaflet_material_.describe() + "; fibers " + config_.string("fibers.rule"));

    // Probes from the geometry.
    const fluid::Real3 axis{0.0, 0.0, 0.0};
    double valve_z = flow_plane_z_;
    double outlet_z = box_.upper[2] - 0.5 * box_.spacing(2);
    if (nested) {
      // Fluxes on nested levels are sums over composite faces of a level-0 face plane: the valve plane
      // moves to the nearest one (any section of the rigid tube carries the same flow), the outlet flux is
      // the one through the outlet side's disk itself.
      const double h0 = hierarchy_->h(0, 2);
      valve_z = box_.lower[2] + h0 * std::round((flow_plane_z_ - box_.lower[2]) / h0);
      outlet_z = box_.upper[2];
      log.info("nested levels: the flow plane Q_valve at z = " + std::to_string(valve_z) +
               " cm (the level-0 face plane nearest to " + std::to_string(flow_plane_z_) + " cm)");
    }
    const auto valve_plane = fluid::PlaneRegion::disk(2, valve_z, axis, geometry_.tube_radius);
    const auto outlet_plane = fluid::PlaneRegion::disk(2, outlet_z, axis, outlet_radius_);
    const double h_z = nested ? hierarchy_->h(0, 2) : box_.spacing(2);
    auto volume_flux = [&](const fluid::PlaneRegion& plane) {
      return nested ? nested->flux(plane) : fluid::volume_flux(*uniform, plane);
    };
    auto pressures_at = [&](const std::vector<fluid::Real3>& points) {
      if (nested) return nested->pressure_at(points); // one gather of the composite pressure for all
      std::vector<double> p;
      for (const fluid::Real3& x : points) p.push_back(fluid::pressure_at(*uniform, x));
      return p;
    };
    const fluid::Real3 p_lv_at{0.0, 0.0, box_.lower[2] + 0.5 * h_z},
        p_ao_at{0.0, 0.0, box_.upper[2] - 0.5 * h_z};
    const fluid::Real3 p_nlv_at{0.0, 0.0, near_lv_z_}, p_nao_at{0.0, 0.0, near_ao_z_};
    std::vector<hemodynamics::Quad> leaflet_faces;
    for (int e : leaflet_elements) {
      const auto n = mesh_.element(static_cast<std::size_t>(e));
      leaflet_faces.push_back({static_cast<std::size_t>(n[0]), static_cast<std::size_t>(n[1]),
                               static_cast<std::size_t>(n[2]), static_cast<std::size_t>(n[3])});
      leaflet_faces.push_back({static_cast<std::size_t>(n[4]), static_cast<std::size_t>(n[5]),
                               static_cast<std::size_t>(n[6]), static_cast<std::size_t>(n[7])});
    }
    hemodynamics::CrossSection section;
    section.radius = geometry_.tube_radius;
    section.centre = {0.0, 0.0, geometry_.valve_base};
    auto orifice_area = [&] {
      const auto positions = ibfe.positions();
      std::vector<hemodynamics::Point> points(positions.size());
      for (std::size_t i = 0; i < points.size(); ++i)
        points[i] = {positions[i][0], positions[i][1], positions[i][2]};
      return hemodynamics::geometric_orifice_area(points, {}, leaflet_faces, section,
                                                  hemodynamics::OrificeOptions{orifice_resolution_});
    };

    const std::filesystem::path& directory = context.run_directory;
    double outlet_flow = 0.0, largest_area = 0.0, smallest_area = 1e300;
    // Checkpoints (docs/runs.md): the fluid, the structure, the Windkessel and the lagged outlet
    // pressure and flow, and the orifice-area range of the summary.
    const io::Checkpoints checkpoints(context.comm, directory, checkpoint_settings_);
    long first_step = 0;
    std::int64_t rows = 0;
    if (fields_every_ > 0) create_fields_directory(context.comm, directory);
    io::XdmfTimeSeries series(context.comm, directory / "fields.xdmf");
    if (context.restart) {
      const io::CheckpointHeader header =
          restart_from_latest(checkpoints, context, steps_, [&](const io::Hdf5File& h5) {
            const std::vector<double> saved = h5.read("aortic_valve/outlet");
            if (saved.size() != 7)
              throw InputError(h5.path().string() + ": aortic_valve/outlet has the wrong size");
            outlet.restore({saved[0], saved[1], saved[2]});
            outlet_pressure = saved[3]; // before the fluid: its boundary ghosts are refilled with it
            outlet_flow = saved[4];
            largest_area = saved[5];
            smallest_area = saved[6];
            if (nested) {
              nested->restore(h5, "nested_fluid");
              finest->copy_velocity();
            } else {
              uniform->restore(h5, "fluid");
            }
            ibfe.restore(h5, "ibfe");
          });
      first_step = static_cast<long>(header.step);
      if (fields_every_ > 0) series.resume(ibfe.time());
      rows = header.timeseries_rows;
    }
    auto save = [&](long n) {
      if (uniform) save_fftw_plans(context);
      return checkpoints.write({n, ibfe.time(), rows}, [&](io::Hdf5File& h5) {
        if (nested)
          nested->save(h5, "nested_fluid");
        else
          uniform->save(h5, "fluid");
        ibfe.save(h5, "ibfe");
        const windkessel::WindkesselState& w = outlet.state();
        const std::vector<double> saved{w.time,      w.reservoir_pressure, w.flow,       outlet_pressure,
                                        outlet_flow, largest_area,         smallest_area};
        h5.write_root("aortic_valve/outlet", saved, std::vector<hsize_t>{saved.size()});
      });
    };
    io::CsvWriter csv; // rank 0's; a failure to open it reaches every rank
    io::on_root(context.comm, [&] {
      csv = io::CsvWriter(directory / "timeseries.csv", hemodynamics::standard_columns(), context.restart,
                          hemodynamics::standard_units());
    });
    auto record = [&] {
      const double t = ibfe.time();
      const double q_valve = volume_flux(valve_plane);
      const std::vector<double> p = pressures_at({p_lv_at, p_ao_at, p_nlv_at, p_nao_at});
      const double p_lv = p[0], p_ao = p[1], p_nlv = p[2], p_nao = p[3];
      const double area = orifice_area();
      largest_area = std::max(largest_area, area);
      smallest_area = std::min(smallest_area, area);
      if (!std::isfinite(q_valve) || !std::isfinite(p_nlv))
        throw RunError("aortic-valve: the flow is not finite at t = " + std::to_string(t) +
                       " s (try a smaller time.step)");
      // Rank 0's row; a failure to write it (a full disk) reaches every rank.
      io::on_root(context.comm, [&] {
        csv.write_row({t, q_valve / units::mL, outlet_flow / units::mL, p_lv / units::mmHg,
                       p_ao / units::mmHg, outlet.reservoir_pressure() / units::mmHg, p_nlv / units::mmHg,
                       p_nao / units::mmHg, area});
      });
      ++rows;
    };

    auto write_fields = [&](long n) {
      if (nested)
        write_ibfe_fields(context.comm, directory, series, mesh_, *nested, ibfe, n);
      else
        write_ibfe_fields(context.comm, directory, series, mesh_, *uniform, ibfe, n);
    };

    RunSummary summary;
    const long steps = steps_;
    auto figures = [&] {
      StepFigures f = nested ? fluid_step_figures(*nested, dt) : fluid_step_figures(*uniform, dt);
      f.solver.push_back(
          {"structure_iterations", static_cast<double>(ibfe.last_projection_iterations()), "structure it"});
      return f;
    };
    StepDiagnostics diagnostics(context.comm, directory, figures(), context.restart, first_step);
    if (!context.restart) {
      record();
      if (fields_every_ > 0) write_fields(0);
    }
    long last_step = static_cast<long>(last_step_of_invocation(context, first_step, steps));
    int stop_signal = 0;
    std::filesystem::path saved; // the checkpoint of the step just taken, if it wrote one
    log.begin_steps(first_step, last_step);
    for (long n = first_step + 1; n <= last_step; ++n) {
      try {
        ibfe.step(dt);
      } catch (const std::runtime_error& e) {
        // A solver that diverges here is the run going unstable, not bad input: keep the output.
        throw RunError("aortic-valve: step " + std::to_string(n) + " (t = " + std::to_string(ibfe.time()) +
                       " s): " + e.what() + " (try a smaller time.step or a finer grid)");
      }
      const StepFigures f = figures();
      outlet_flow = volume_flux(outlet_plane);
      outlet_pressure = outlet.advance(dt, outlet_flow);
      if (n % every_ == 0 || n == steps) record();
      if (fields_every_ > 0 && (n % fields_every_ == 0 || n == steps)) write_fields(n);
      log.progress(
          {n, steps, ibfe.time(), static_cast<double>(steps) * dt, diagnostics.write(n, ibfe.time(), f)});
      if (n % steps_per_cycle_ == 0) {
        log.finish_progress();
        write_report(context, summary, n / steps_per_cycle_);
      } else if (n == steps && steps < steps_per_cycle_) {
        log.finish_progress();
        write_report(context, summary, 0, static_cast<double>(steps) * dt);
      } else if (n == steps) {
        summary.lines.push_back("the last " +
                                hemodynamics::format_value(static_cast<double>(n % steps_per_cycle_) * dt) +
                                " s after cycle " + std::to_string(n / steps_per_cycle_) +
                                " are not a whole cycle: no report of them");
      }
      saved.clear();
      if (checkpoints.due(n, steps)) saved = save(n);
      // SIGINT/SIGTERM (app/stop_signal.hpp): every rank stops after this step.
      if (n < steps && (stop_signal = agreed_stop_signal(context.comm)) != 0) {
        last_step = n;
        break;
      }
    }
    log.finish_progress();
    if (last_step < steps)
      add_stop(summary, last_step, steps, saved.empty() ? save(last_step) : saved, directory, stop_signal);
    const ib::IbfeTimings& t = ibfe.timings();
    std::ostringstream timing;
    timing.precision(3);
    timing << "per step: " << t.total / static_cast<double>(t.steps) << " s (fluid " << t.fluid / t.steps
           << ", interpolation " << t.interpolation / t.steps << ", projection " << t.projection / t.steps
           << ", force " << t.force / t.steps << ", spreading " << t.spreading / t.steps << ", points "
           << t.points / t.steps << ") over " << t.steps << " steps; orifice area " << smallest_area << " to "
           << largest_area << " cm^2";
    if (nested) {
      const fluid::NestedStepStatistics& f = nested->statistics();
      const double n = static_cast<double>(std::max<PetscInt>(f.steps, 1));
      timing << "; nested fluid per step: convection " << f.seconds_convection / n << " s, viscous "
             << f.seconds_velocity / n << " s (" << f.velocity_iterations << " iterations), projection "
             << f.seconds_pressure / n << " s (" << f.pressure_iterations << " iterations)";
    }
    summary.lines.push_back(timing.str());
    return summary;
  }

 private:
  static std::string leaflet(int k) { return "leaflet" + std::to_string(k); }

  // The run's last step: time.end when given (it wins over time.cycles), else whole cycles. A run
  // shorter than a cycle gets its report over its whole length, which needs rows enough for one.
  void read_end(const io::Config& config)
  {
    steps_ = cycles_ * steps_per_cycle_;
    if (!config.has("time.end")) return;
    const double dt = period_ / static_cast<double>(steps_per_cycle_);
    steps_ = std::max<long>(1, std::lround(config.real("time.end") / dt));
    if (steps_ >= steps_per_cycle_) return;
    const long rows = steps_ / every_ + (steps_ % every_ != 0 ? 1 : 0) + 1;
    constexpr long report_rows = 11; // hemodynamics::write_report: a window of at least 10 intervals
    if (rows < report_rows)
      config.fail("time.end", "a run shorter than a cycle (" + hemodynamics::format_value(period_) +
                                  " s) is reported over its whole length, which holds " +
                                  std::to_string(rows) +
                                  " time-series rows (output.every = " + std::to_string(every_) +
                                  " steps); the report needs " + std::to_string(report_rows) +
                                  ": a smaller output.every or a longer time.end");
  }

  // Nested levels (docs/nested.md): placed around the valve and tube (or given as [[nested.box]]), the
  // finest level one box holding the whole structure with the kernel's reach.
  // The structure's and the one grid's size, checked before the mesh is built: indices, then memory.
  // Nested levels add theirs in read_levels.
  void check_size(const io::Config& config, double nodes, double elements, const std::string& key)
  {
    check_index_count(config, key, 3.0 * nodes, "structure unknowns");
    structure_memory_ = structure_memory(nodes, elements, key);
    memory_line_ = check_memory(
        config,
        {{fluid_memory(grid_cells(box_), memory_kind(fluid_), true, "fluid.cells"), structure_memory_}},
        PETSC_COMM_WORLD);
  }

  void read_levels(const io::Config& config)
  {
    hierarchy_ = std::make_unique<fluid::GridHierarchy>(
        read_structure_levels(config, box_, mesh_.nodes(), ib_.kernel, "nested.box"));
    const double cells = composite_cells(*hierarchy_);
    memory_line_ =
        check_memory(config,
                     {{fluid_memory(cells, FluidMemoryKind::nested, true,
                                    cells > 2.0 * grid_cells(box_) ? "nested.ratios" : "fluid.cells"),
                       structure_memory_}},
                     PETSC_COMM_WORLD);
    nested_settings_.rho = fluid_.rho;
    nested_settings_.mu = fluid_.mu;
    nested_settings_.convection = fluid_.convection;
    nested_settings_.velocity_rtol = fluid_.rtol;
    nested_settings_.pressure_rtol = fluid_.rtol;
  }

  static std::string describe_levels(const fluid::GridHierarchy& h)
  {
    std::ostringstream s;
    s.precision(4);
    PetscInt cells = 0;
    for (int l = 0; l < h.levels(); ++l) cells += h.uncovered_cells(l);
    s << h.levels() << " nested levels (" << cells << " composite cells; level 0 " << h.domain_cells(0)[0]
      << " x " << h.domain_cells(0)[1] << " x " << h.domain_cells(0)[2] << ", finest spacing "
      << h.h(h.finest(), 0) << " cm)";
    return s.str();
  }

  /// The report of cycle `cycle` (1, 2, ...), or, for a run shorter than a cycle (cycle 0), of its
  /// whole `length`.
  void write_report(const RunContext& context, RunSummary& summary, long cycle, double length = 0.0) const
  {
    hemodynamics::ReportOptions options;
    options.settings = report_;
    if (cycle == 0) options.settings.period = length;
    options.python = python_executable;
    options.plots = plots_;
    options.templates = report_templates_;
    // Rank 0 writes it; a failure there (a full disk) reaches every rank instead of leaving them waiting.
    io::on_root(context.comm, [&] {
      const auto files = hemodynamics::write_report(context.run_directory, options);
      summary.lines.push_back((cycle > 0 ? "cycle " + std::to_string(cycle) + " report: "
                                         : "report of the run's " + hemodynamics::format_value(length) +
                                               " s (shorter than a " + hemodynamics::format_value(period_) +
                                               " s cycle: its metrics are of that window): ") +
                              files.html.string());
    });
  }

  io::Config config_;
  windkessel::PeriodicWaveform lv_;
  windkessel::WindkesselParameters outlet_parameters_;
  hemodynamics::MetricSettings report_;
  std::filesystem::path report_templates_;
  fluid::BoxGeometry box_;
  fluid::FluidSettings fluid_;
  fe::ValveMeshParameters geometry_;
  fe::Mesh mesh_;
  materials::MaterialSettings leaflet_material_, tube_material_;
  fibers::FiberRule rule_ = fibers::FiberRule::FD1;
  ib::IbfeSettings ib_;
  bool inlet_walled_ = false, outlet_walled_ = false;
  double inlet_radius_ = 0, outlet_radius_ = 0, period_ = 0.8, backflow_ = 1.0;
  double pressure_ramp_ = 0; // s: time.pressure_ramp

  /// The factor of both boundary pressures at time t: a smooth rise from 0 to 1 over the ramp.
  double pressure_ramp(double t) const
  {
    if (t >= pressure_ramp_) return 1.0;
    return 0.5 * (1.0 - std::cos(std::numbers::pi * std::max(t, 0.0) / pressure_ramp_));
  }
  long steps_per_cycle_ = 1, cycles_ = 1, steps_ = 1, every_ = 1, fields_every_ = 0;
  double flow_plane_z_ = 0, near_lv_z_ = 0, near_ao_z_ = 0;
  int orifice_resolution_ = 256;
  MemoryPart structure_memory_;
  bool plots_ = true;
  io::CheckpointSettings checkpoint_settings_;
  std::unique_ptr<fluid::GridHierarchy> hierarchy_; // nested levels; null on one grid
  fluid::NestedFluidSettings nested_settings_;
};

} // namespace

Model aortic_valve_model()
{
  return Model{"aortic-valve",
               "the tri-leaflet valve in its tube (IB/FE): LV pressure in, Windkessel out, fibers FD1/FD2, "
               "report each cycle",
               add_aortic_valve_schema, [](const io::Config& config) -> std::unique_ptr<PreparedRun> {
                 return std::make_unique<AorticValveRun>(config);
               }};
}

} // namespace ibvalve::app
