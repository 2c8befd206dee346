// `model = "aortic-valve"`: the study's set-up (docs/reference.md) on top of the IB/FE coupling
// (ib/ibfe.hpp): the tri-leaflet valve in its tube (fe/valve_mesh.hpp, generated at start-up or read
// from a Gmsh file), fibers from the mesh groups (fibers/rules.hpp, FD1 or FD2), one material per body
// (leaflets, tube), the tube's outer surface and the leaflets' attachments tethered; the box's inlet
// side (z lower) carries the upstream driver's pressure in a disk of the tube's radius, the outlet side
// (z upper) the downstream driver's, zero pressure elsewhere. The drivers (drivers/, docs/drivers.md)
// are the LV pressure table and the three-element Windkessel, or the closed-loop circulation's left
// ventricle and systemic arteries; each is given the flux through its disk after every step.
// Probes come from the geometry; the orifice area from the deformed leaflets; the report is written at
// the end of every cycle. With `nested.ratios` the fluid is fluid::NestedNavierStokes on nested levels
// placed around the valve and tube, with the same sides, and the structure lives on the finest level
// (docs/nested.md, "The aortic-valve case on nested levels").
//
// The drivers' coupling: explicit, lagged by one step. Step n uses the sides' pressures P^n; after it the
// fluxes Q^{n+1} through the inlet and outlet disks advance the drivers (linear flow over the step) to
// give P^{n+1}. For the Windkessel the lag is O(dt) in P_Ao; with dt = 1e-4 s and R_c = 0.033 mmHg s/mL
// it changes P_Ao by R_c dQ, well below 0.1 mmHg. docs/drivers.md gives the closed loop's margin.
#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <functional>
#include <numbers>
#include <sstream>
#include <vector>

#include <mpi.h>
#include <nlohmann/json.hpp>

#include "app/adaptive_step.hpp"
#include "app/aortic_valve_keys.hpp"
#include "app/fftw_plans.hpp"
#include "app/fluid_box.hpp"
#include "app/ibfe_fields.hpp"
#include "app/jet_region.hpp"
#include "app/leaflet_fit_error.hpp"
#include "app/leaflet_state.hpp"
#include "app/model.hpp"
#include "app/resource_estimate.hpp"
#include "app/step_diagnostics.hpp"
#include "app/step_schedule.hpp"
#include "app/structure_levels.hpp"
#include "app/structure_parts.hpp"
#include "app/time_loop.hpp"
#include "app/valve_mesh.hpp"
#include "base/errors.hpp"
#include "base/logger.hpp"
#include "base/stopwatch.hpp"
#include "base/units.hpp"
#include "drivers/boundary_drivers.hpp"
#include "fe/gmsh_io.hpp"
#include "fe/mesh.hpp"
#include "fe/solid.hpp"
#include "fe/valve_mesh.hpp"
#include "fe/volumetric_integration.hpp"
#include "fibers/rules.hpp"
#include "fluid/flow_solver.hpp"
#include "fluid/hierarchy.hpp"
#include "hemodynamics/geometry.hpp"
#include "hemodynamics/report.hpp"
#include "hemodynamics/timeseries.hpp"
#include "ib/eulerian_fluid.hpp"
#include "ib/ibfe.hpp"
#include "io/checkpoint.hpp"
#include "io/collective.hpp"
#include "io/files.hpp"
#include "io/key_binder.hpp"
#include "materials/fitting.hpp"
#include "materials/settings.hpp"

namespace ibvalve::app {

namespace {

constexpr int leaflet_count = 3;

class AorticValveRun : public PreparedRun {
 public:
  explicit AorticValveRun(const io::Config& config) : config_(config), keys_(config_)
  {
    bind(keys_, k_);
    const AorticValveKeys& k = k_;
    drivers_ = std::make_unique<drivers::BoundaryDrivers>(drivers::make_drivers(keys_, k.drivers));
    hemodynamics::check_report_templates(keys_, k.report);
    box_ = fluid_box(keys_, k.cells, k.lower, k.upper);
    box_.periodic = {false, false, false};
    fluid_ = k.fluid;
    fluid_.solver = fluid::SolverKind::krylov;

    const fe::ValveMeshParameters& g = k.mesh.geometry;
    read_mesh();
    for (const fe::Vec3& X : mesh_.nodes())
      for (int d = 0; d < 3; ++d)
        if (!(X[d] > box_.lower[d] && X[d] < box_.upper[d]))
          keys_.fail(k.lower, "the valve and tube must lie inside the box");

    // The leaflets carry one fiber family (fibers.rule), the tube none.
    leaflet_material_ = part_material(keys_, k.leaflets_material, 1);
    if (!k.fit_data.empty()) fit_error_ = leaflet_fit_error(leaflet_material_, k.fit_data);
    if (!k.tube_wall) tube_material_ = part_material(keys_, k.tube_material, 0); // a wall has no elements
    ib_ = k.coupling;
    if (!k.tube_wall)
      for (const std::string& surface : k.tube_surfaces)
        ib_.tethers.push_back({surface, k.tube_stiffness, k.tube_damping});
    for (int n = 1; n <= leaflet_count; ++n)
      ib_.tethers.push_back({leaflet(n) + "_attachment", k.attachment_stiffness, k.attachment_damping});

    // The disks end in the middle of the tube wall by default: the jump of the boundary pressure then
    // sits inside the structure, which holds it, and not in the fluid at the tube's end (docs/reference.md,
    // "Choices the study left open").
    const double mid_wall = g.tube_radius + 0.5 * g.tube_wall;
    inlet_radius_ = k.inlet_radius > 0 ? k.inlet_radius : mid_wall;
    outlet_radius_ = k.outlet_radius > 0 ? k.outlet_radius : mid_wall;
    period_ = drivers_->period().value(); // the table's and the loop's drivers have one
    if (std::abs(k.report.metrics.period - period_) > 1e-9 * period_)
      keys_.fail(
          k.report.metrics.period,
          fmt::format("differs from the drivers' beat, {} s (the LV pressure table's period, or 60 s / "
                      "{})",
                      hemodynamics::format_value(period_),
                      keys_.key_of(k.drivers.circulation.parameters.heart_rate)));
    const double length = k.end ? *k.end : static_cast<double>(k.cycles) * period_;
    if (const std::string why = step_count_problem(length, k.step); !why.empty()) keys_.fail(k.step, why);
    if (k.adaptive) {
      if (k.coaptation_step > 0.0)
        keys_.fail(k.coaptation_step, "a fixed coaptation step and " + keys_.key_of(k.adaptive) +
                                          " exclude each other: the adaptive step finds the coaptation's");
      if (k.adaptive_step.interval < k.step)
        keys_.fail(k.adaptive_step.interval,
                   "must be at least " + keys_.key_of(k.step) + ", the longest sub-step it is cut into");
      adaptive_step_.emplace(AdaptiveStepSettings{k.adaptive_step.interval, k.step, k.adaptive_step.safety,
                                                  k.adaptive_step.cfl, k.adaptive_step.grow});
      schedule_ = StepSchedule(period_, k.adaptive_step.interval);
    } else if (k.coaptation_step > 0.0) {
      const double a = k.coaptation_window[0], b = k.coaptation_window[1];
      if (!(a >= 0.0 && a < b && b <= period_))
        keys_.fail(k.coaptation_window,
                   fmt::format("must be a start and a later end within the cycle [0, {}] s",
                               hemodynamics::format_value(period_)));
      const double windows = std::ceil(length / period_) * (b - a);
      if (const std::string why = step_count_problem(windows, k.coaptation_step); !why.empty())
        keys_.fail(k.coaptation_step, why);
      schedule_ = StepSchedule(period_, k.step, k.coaptation_step, {a, b});
    } else {
      schedule_ = StepSchedule(period_, k.step);
    }
    steps_per_cycle_ = static_cast<long>(schedule_.steps_per_cycle());
    read_end();
    const double fields_interval = k.fields_interval.value_or(0.0);
    fields_every_ = fields_interval > 0
                        ? std::max<long>(1, std::lround(fields_interval *
                                                        static_cast<double>(steps_per_cycle_) / period_))
                        : 0;
    const double nadir = g.valve_base, top = nadir + g.commissure_height;
    flow_plane_z_ = nadir - k.flow_plane_offset;
    near_lv_z_ = nadir - k.probe_offset;
    near_ao_z_ = top + k.probe_offset;
    k_.checkpoints.case_record = io::case_record(config);
    if (!k.nested.ratios.empty()) {
      if (k.tube_wall)
        keys_.fail(k.tube_wall, "\"wall\" needs one grid: nested levels (" + keys_.key_of(k.nested.ratios) +
                                    ") do not take blocked cells");
      read_levels(config);
    }
    compute_leaflet_fibers(); // the last check: it solves a Laplace problem per leaflet
  }

  std::string summary() const override
  {
    return fmt::format("{}; fibers {}; {} steps to t = {} s (dt {})",
                       describe_valve_mesh(k_.mesh, mesh_, leaflet_count),
                       k_.rule == fibers::FiberRule::FD1 ? "FD1" : "FD2", steps_,
                       hemodynamics::format_value(schedule_.time_of(steps_)), describe_steps());
  }

  RunSummary run(const RunContext& context) override
  {
    auto& log = base::Logger::global();
    // The mean step: whole cycles end at steps x dt; with a coaptation step the steps differ.
    const double dt = schedule_.mean_step();
    std::vector<int> leaflet_elements;
    fe::SolidModel solid(mesh_, body_parts(leaflet_elements), k_.quadrature_degree, context.comm);
    solid.set_fibers(frames_);
    // The fluid: one grid (fluid::NavierStokes) or nested levels around the valve and tube
    // (fluid::NestedNavierStokes, the structure on the finest level); both take the same sides and
    // answer the same probes.
    if (context.restart) load_fftw_plans(context); // the interrupted run's FFTW plans: the same bits
    const std::unique_ptr<fluid::FlowSolver> fluid =
        fluid::make_flow_solver(context.comm, box_, hierarchy_.get(), boundary_conditions(), fluid_);
    fluid->set_initial_condition(
        [](const fluid::Real3&, double) {
          return fluid::Real3{0.0, 0.0, 0.0};
        },
        nullptr, 0.0);
    ib::IbfeIntegrator ibfe(*fluid, solid, ib_);
    log_start(*fluid, ibfe, leaflet_elements.size());
    const Probes probes = make_probes(leaflet_elements);
    const LeafletState leaflet_state(solid, leaflet_count, k_.mesh.geometry.leaflet_thickness);
    log.info(leaflet_state.describe());
    const JetRegion jet = jet_region(near_lv_z_, near_ao_z_, k_.mesh.geometry.tube_radius, box_);
    log.info(jet.describe());
    write_extra_metrics(context);

    Record record;
    TimeLoop loop = time_loop_settings(context);
    set_ibfe_hooks(loop, context, mesh_, *fluid, ibfe, dt);
    set_steps(loop, *fluid, ibfe, solid, probes, record);
    loop.row = [&](std::int64_t) { return row(*fluid, ibfe, probes, leaflet_state, jet, record); };
    set_checkpoint(loop, record);
    loop.after_step = [&](std::int64_t n, RunSummary& summary) { report_after_step(context, n, summary); };
    loop.finish = [&](RunSummary& summary, bool, std::size_t) {
      summary.lines.push_back(timing_line(ibfe, *fluid, record));
    };
    return run_time_loop(context, loop);
  }

 private:
  /// What a run carries from step to step besides the fluid, the structure and the drivers: the sides'
  /// last fluxes, the orifice-area range of the summary, the adaptive step's last choice.
  struct Record {
    double inlet_flow = 0.0, outlet_flow = 0.0, largest_area = 0.0, smallest_area = 1e300;
    std::int64_t substeps = 0;
    std::int64_t retries = 0; // times the interval under way was taken again (time.retries)
    double step_cap = 0.0;    // s: no sub-step longer, after an interval taken again (0: none)
    double snapshot_seconds = 0.0, lost_seconds = 0.0; // the intervals' snapshots; the attempts that failed
    std::int64_t intervals_taken_again = 0;
    double structure_dt = 0.0; // the structure's estimate for the interval under way
    double speed_over_h = 0.0; // the fluid's max|u| / h at that interval's start
  };

  /// Where the run measures: the valve's section, the inlet and outlet disks (half a level-0 cell inside
  /// their sides), the pressure probes, the leaflets' faces for the orifice area.
  struct Probes {
    fluid::PlaneRegion valve_plane, inlet_plane, outlet_plane;
    std::vector<fluid::Real3> points; // P_LV, P_Ao, P_nlv, P_nao
    std::vector<hemodynamics::Quad> leaflet_faces;
    hemodynamics::CrossSection section;
  };

  /// The structure's parts: the three leaflets (their elements gathered in `leaflet_elements`), the tube.
  std::vector<fe::BodyPart> body_parts(std::vector<int>& leaflet_elements) const
  {
    std::vector<fe::BodyPart> parts;
    const fe::VolumetricIntegration volumetric_integration = k_.volumetric_integration;
    for (int k = 1; k <= leaflet_count; ++k) {
      const auto& elements = mesh_.group(leaflet(k)).elements;
      leaflet_elements.insert(leaflet_elements.end(), elements.begin(), elements.end());
      parts.push_back(
          fe::material_part(leaflet(k), elements, leaflet_material_.build(), volumetric_integration));
    }
    if (!k_.tube_wall)
      parts.push_back(fe::material_part("tube", mesh_.group("tube").elements, tube_material_.build(),
                                        volumetric_integration));
    return parts;
  }

  /// Every side a traction side; zero pressure except the inlet disk (the upstream driver's pressure)
  /// and the outlet disk (the downstream driver's), both under the start-up ramp; the inlet/outlet sides
  /// outside their disks walled when asked (fluid/boundary.hpp).
  fluid::BoundaryConditions boundary_conditions() const
  {
    fluid::BoundaryConditions bc;
    for (int side = 0; side < 6; ++side) {
      bc.side(side).kind = fluid::SideKind::traction;
      bc.side(side).backflow = k_.backflow;
    }
    const double rin = inlet_radius_, rout = outlet_radius_;
    const drivers::BoundaryDriver* upstream = &drivers_->upstream();
    const drivers::BoundaryDriver* downstream = &drivers_->downstream();
    bc.side(2, 0).pressure = [this, upstream, rin](const fluid::Real3& x, double t) {
      return std::hypot(x[0], x[1]) < rin ? pressure_ramp(t) * upstream->pressure(t) : 0.0;
    };
    bc.side(2, 1).pressure = [this, downstream, rout](const fluid::Real3& x, double t) {
      return std::hypot(x[0], x[1]) < rout ? pressure_ramp(t) * downstream->pressure(t) : 0.0;
    };
    if (k_.inlet_walled)
      bc.side(2, 0).wall = [rin](const fluid::Real3& x) { return std::hypot(x[0], x[1]) >= rin; };
    if (k_.outlet_walled)
      bc.side(2, 1).wall = [rout](const fluid::Real3& x) { return std::hypot(x[0], x[1]) >= rout; };
    if (k_.tube_wall) {
      // The tube as a rigid wall the fluid holds: every cell whose centre lies outside the lumen.
      const double lumen = k_.mesh.geometry.tube_radius;
      bc.set_solid([lumen](const fluid::Real3& x) { return std::hypot(x[0], x[1]) > lumen; });
    }
    return bc;
  }

  void log_start(const fluid::FlowSolver& fluid, ib::IbfeIntegrator& ibfe, std::size_t leaflet_elements) const
  {
    auto& log = base::Logger::global();
    const ib::StabilityEstimate stability = ibfe.stability_estimate();
    log.info(describe_valve_mesh(k_.mesh, mesh_, leaflet_count));
    log.info(fmt::format("aortic valve: {} elements ({} in the leaflets), {} nodes; {}; dt {} (the "
                         "stability estimate {} s), {} steps to t = {} s; leaflets {}; fibers {}",
                         mesh_.num_elements(), leaflet_elements, mesh_.num_nodes(), fluid.describe(),
                         describe_steps(), hemodynamics::format_value(stability.dt), steps_,
                         hemodynamics::format_value(schedule_.time_of(steps_)), leaflet_material_.describe(),
                         std::string(k_.rule == fibers::FiberRule::FD1 ? "FD1" : "FD2")));
    for (const std::string& line : drivers_->describe()) log.info("boundary driver: " + line);
  }

  Probes make_probes(const std::vector<int>& leaflet_elements) const
  {
    const fluid::Real3 axis{0.0, 0.0, 0.0};
    const double h_z = box_.spacing(2);
    Probes p{fluid::PlaneRegion::disk(2, flow_plane_z_, axis, k_.mesh.geometry.tube_radius),
             fluid::PlaneRegion::disk(2, box_.lower[2] + 0.5 * h_z, axis, inlet_radius_),
             fluid::PlaneRegion::disk(2, box_.upper[2] - 0.5 * h_z, axis, outlet_radius_),
             {{0.0, 0.0, box_.lower[2] + 0.5 * h_z},
              {0.0, 0.0, box_.upper[2] - 0.5 * h_z},
              {0.0, 0.0, near_lv_z_},
              {0.0, 0.0, near_ao_z_}},
             {},
             {}};
    for (int e : leaflet_elements) {
      const auto n = mesh_.element(static_cast<std::size_t>(e));
      p.leaflet_faces.push_back({static_cast<std::size_t>(n[0]), static_cast<std::size_t>(n[1]),
                                 static_cast<std::size_t>(n[2]), static_cast<std::size_t>(n[3])});
      p.leaflet_faces.push_back({static_cast<std::size_t>(n[4]), static_cast<std::size_t>(n[5]),
                                 static_cast<std::size_t>(n[6]), static_cast<std::size_t>(n[7])});
    }
    p.section.radius = k_.mesh.geometry.tube_radius;
    p.section.centre = {0.0, 0.0, k_.mesh.geometry.valve_base};
    return p;
  }

  double orifice_area(const ib::IbfeIntegrator& ibfe, const Probes& probes) const
  {
    const auto positions = ibfe.positions();
    std::vector<hemodynamics::Point> points(positions.size());
    for (std::size_t i = 0; i < points.size(); ++i)
      points[i] = {positions[i][0], positions[i][1], positions[i][2]};
    return hemodynamics::geometric_orifice_area(points, {}, probes.leaflet_faces, probes.section,
                                                hemodynamics::OrificeOptions{k_.orifice_resolution});
  }

  /// The loop's settings: its length, checkpoints and outputs; the report's columns, the leaflet
  /// state's, then the drivers' own.
  TimeLoop time_loop_settings(const RunContext& context) const
  {
    TimeLoop loop;
    loop.comm = context.comm;
    loop.steps = steps_;
    loop.end_time = schedule_.time_of(steps_);
    loop.checkpoints = k_.checkpoints;
    loop.columns = hemodynamics::standard_columns();
    loop.units = hemodynamics::standard_units();
    for (const std::string& c : hemodynamics::leaflet_state_columns()) loop.columns.push_back(c);
    for (const std::string& u : hemodynamics::leaflet_state_units()) loop.units.push_back(u);
    for (const drivers::Column& c : drivers_->columns()) {
      loop.columns.push_back(c.name);
      loop.units.push_back(c.unit);
    }
    loop.record_every = k_.every;
    loop.record_also_every = steps_per_cycle_; // each cycle's report ends on its last step's row
    loop.fields_every = fields_every_ > 0 ? fields_every_ : -1;
    return loop;
  }

  /// Each step: the coupled step, then the fluxes through the inlet and outlet disks advance the
  /// drivers (lagged by one (sub-)step). With the adaptive step, each interval's sub-steps and its
  /// diagnostics.
  void set_steps(TimeLoop& loop, fluid::FlowSolver& fluid, ib::IbfeIntegrator& ibfe, fe::SolidModel& solid,
                 const Probes& probes, Record& record)
  {
    auto coupled_step = [&, this](std::int64_t n, double step) {
      const double t = ibfe.time();
      try {
        ibfe.step(step);
      } catch (const InputError&) {
        throw; // a warning --strict made an error (base/logger.hpp)
      } catch (const std::runtime_error& e) {
        // A solver that diverges here is the run going unstable, not bad input: keep the output.
        throw RunError(fmt::format(
            "aortic-valve: step {} (t = {:g} s): {} (try a smaller {} or a finer grid)", n, ibfe.time(),
            e.what(), keys_.key_of(adaptive_step_ ? k_.adaptive_step.safety : k_.step)));
      }
      record.inlet_flow = fluid.flux(probes.inlet_plane);
      record.outlet_flow = fluid.flux(probes.outlet_plane);
      drivers_->advance(t, step, record.inlet_flow, record.outlet_flow);
    };
    loop.advance = [&, this, coupled_step](std::int64_t n) {
      const double interval = schedule_.step(n);
      if (!adaptive_step_) return coupled_step(n, interval);
      const StepLimits before{record.structure_dt, record.speed_over_h};
      record.structure_dt =
          ibfe.coupled_stability_estimate(static_cast<int>(k_.adaptive_step.estimate_iterations)).dt;
      const double h = std::min({box_.spacing(0), box_.spacing(1), box_.spacing(2)});
      record.speed_over_h = fluid.max_velocity() / h;
      const StepLimits limits = extrapolated_limits({record.structure_dt, record.speed_over_h}, before);
      // The semi-implicit coupling is not bound by the explicit estimate (kept in diagnostics.csv).
      const bool bound = ibfe.settings().coupling == ib::CouplingKind::explicit_midpoint;
      record.step_cap = adaptive_step_->relaxed_cap(record.step_cap);
      record.substeps = adaptive_step_->substeps(interval, bound ? limits.structure_dt : HUGE_VAL,
                                                 limits.speed_over_h, record.substeps, record.step_cap);
      take_interval(loop, n, interval, record, [&](double step) { coupled_step(n, step); });
    };
    if (!adaptive_step_) return;
    // diagnostics.csv: each interval's sub-steps, their length and the structure's estimate, beside the
    // last sub-step's solver figures and its CFL number.
    loop.figures = [&, this, watch = std::make_shared<InversionWatch>(solid)] {
      const double step = schedule_.step(1) / static_cast<double>(std::max<std::int64_t>(record.substeps, 1));
      StepFigures figures = ibfe_step_figures(fluid, ibfe, step, watch.get());
      figures.solver.push_back({"substeps", static_cast<double>(record.substeps), "sub"});
      figures.solver.push_back({"dt", step, "dt", "s"});
      figures.solver.push_back({"dt_structure", record.structure_dt, "", "s"});
      figures.solver.push_back({"retries", static_cast<double>(record.retries), ""});
      return figures;
    };
  }

  std::vector<double> row(fluid::FlowSolver& fluid, const ib::IbfeIntegrator& ibfe, const Probes& probes,
                          const LeafletState& leaflet_state, const JetRegion& jet, Record& record) const
  {
    const double t = ibfe.time();
    const double q_valve = fluid.flux(probes.valve_plane);
    const std::vector<double> p = fluid.pressure_at(probes.points); // P_LV, P_Ao, P_nlv, P_nao
    const double area = orifice_area(ibfe, probes);
    record.largest_area = std::max(record.largest_area, area);
    record.smallest_area = std::min(record.smallest_area, area);
    if (!std::isfinite(q_valve) || !std::isfinite(p[2]))
      throw RunError(fmt::format("aortic-valve: the flow is not finite at t = {:g} s (try a smaller {})", t,
                                 keys_.key_of(k_.step)));
    std::vector<double> r{t,
                          q_valve / units::mL,
                          record.outlet_flow / units::mL,
                          p[0] / units::mmHg,
                          p[1] / units::mmHg,
                          drivers_->downstream().reservoir_pressure(t) / units::mmHg,
                          p[2] / units::mmHg,
                          p[3] / units::mmHg,
                          area};
    for (double v : leaflet_state.row(ibfe.displacement(), fluid.max_speed_in(jet.points()))) r.push_back(v);
    for (double v : drivers_->row(t)) r.push_back(v);
    return r;
  }

  /// One interval of the adaptive step in record.substeps sub-steps; one whose sub-steps go unstable
  /// (a RunError) is taken again from its start, kept in memory, with twice the sub-steps, up to
  /// time.retries times (docs/runs.md, "The adaptive step"). Collective.
  void take_interval(TimeLoop& loop, std::int64_t n, double interval, Record& record,
                     const std::function<void(double)>& sub_step) const
  {
    record.retries = 0;
    std::vector<char> start;
    if (k_.adaptive_step.retries > 0) {
      base::Stopwatch watch(record.snapshot_seconds);
      io::Hdf5File snapshot(loop.comm, "the interval's start", io::Hdf5File::Mode::memory);
      loop.save(snapshot);
      snapshot.close();
      start = snapshot.take_image();
    }
    for (;;) {
      const double attempt_start = MPI_Wtime();
      try {
        for (std::int64_t m = 0; m < record.substeps; ++m)
          sub_step(interval / static_cast<double>(record.substeps));
        if (record.retries > 0) record.step_cap = interval / static_cast<double>(record.substeps);
        return;
      } catch (const RunError& e) {
        if (record.retries >= k_.adaptive_step.retries) throw;
        record.lost_seconds += MPI_Wtime() - attempt_start;
        if (record.retries == 0) ++record.intervals_taken_again;
        // The snapshot was taken after the interval's choice: it gives back the same sub-steps and limits.
        const std::int64_t failed = record.substeps, retries = record.retries + 1;
        loop.restore(io::Hdf5File(loop.comm, "the interval's start", start));
        record.substeps = 2 * failed;
        record.retries = retries;
        base::Logger::global().warn(
            fmt::format("step {} taken again from t = {:g} s in {} sub-steps ({} of {} {}): {}", n,
                        loop.time(n - 1), record.substeps, record.retries, k_.adaptive_step.retries,
                        keys_.key_of(k_.adaptive_step.retries), e.what()));
      }
    }
  }

  /// Checkpoints (docs/runs.md): the fluid and the structure (set_ibfe_hooks), the drivers' states by
  /// name (drivers/...), and the run's record by name (aortic_valve/...).
  void set_checkpoint(TimeLoop& loop, Record& record)
  {
    loop.save = [this, &record, save_coupled = loop.save](io::Hdf5File& h5) {
      save_coupled(h5);
      drivers_->save(h5);
      drivers::save_number(h5, "aortic_valve", "Q_inlet", record.inlet_flow);
      drivers::save_number(h5, "aortic_valve", "Q_outlet", record.outlet_flow);
      drivers::save_number(h5, "aortic_valve", "largest_area", record.largest_area);
      drivers::save_number(h5, "aortic_valve", "smallest_area", record.smallest_area);
      // The adaptive step's last choice: the next interval's depends on it.
      if (adaptive_step_) {
        drivers::save_number(h5, "aortic_valve", "substeps", static_cast<double>(record.substeps));
        // The limits at the last interval's start: the next interval's extrapolation starts from them.
        drivers::save_number(h5, "aortic_valve", "structure_dt", record.structure_dt);
        drivers::save_number(h5, "aortic_valve", "speed_over_h", record.speed_over_h);
        drivers::save_number(h5, "aortic_valve", "step_cap", record.step_cap);
      }
    };
    loop.restore = [this, &record, restore_coupled = loop.restore](const io::Hdf5File& h5) {
      drivers_->restore(h5); // before the fluid: its boundary ghosts are refilled with their pressures
      record.inlet_flow = drivers::read_number(h5, "aortic_valve", "Q_inlet");
      record.outlet_flow = drivers::read_number(h5, "aortic_valve", "Q_outlet");
      record.largest_area = drivers::read_number(h5, "aortic_valve", "largest_area");
      record.smallest_area = drivers::read_number(h5, "aortic_valve", "smallest_area");
      if (h5.has("aortic_valve/substeps"))
        record.substeps = static_cast<std::int64_t>(drivers::read_number(h5, "aortic_valve", "substeps"));
      if (h5.has("aortic_valve/structure_dt")) {
        record.structure_dt = drivers::read_number(h5, "aortic_valve", "structure_dt");
        record.speed_over_h = drivers::read_number(h5, "aortic_valve", "speed_over_h");
      }
      if (h5.has("aortic_valve/step_cap"))
        record.step_cap = drivers::read_number(h5, "aortic_valve", "step_cap");
      restore_coupled(h5);
    };
  }

  /// After step n: the report of each cycle as it ends (or of a run shorter than a cycle).
  void report_after_step(const RunContext& context, std::int64_t n, RunSummary& summary) const
  {
    auto& log = base::Logger::global();
    if (n % steps_per_cycle_ == 0) {
      log.finish_progress();
      write_report(context, summary, static_cast<long>(n / steps_per_cycle_));
    } else if (n == steps_ && steps_ < steps_per_cycle_) {
      log.finish_progress();
      write_report(context, summary, 0, schedule_.time_of(steps_));
    } else if (n == steps_) {
      summary.lines.push_back(fmt::format(
          "the last {} s after cycle {} are not a whole cycle: no report of them",
          hemodynamics::format_value(schedule_.time_of(n % steps_per_cycle_)), n / steps_per_cycle_));
    }
  }

  std::string timing_line(const ib::IbfeIntegrator& ibfe, const fluid::FlowSolver& fluid,
                          const Record& record) const
  {
    const ib::IbfeTimings& t = ibfe.timings();
    std::ostringstream timing;
    timing.precision(3);
    timing << "per step: " << t.total / static_cast<double>(t.steps) << " s (fluid " << t.fluid / t.steps
           << ", interpolation " << t.interpolation / t.steps << ", projection " << t.projection / t.steps
           << ", force " << t.force / t.steps << ", spreading " << t.spreading / t.steps << ", points "
           << t.points / t.steps
           << (t.implicit > 0.0 ? fmt::format(", semi-implicit solve {:.3g}", t.implicit / t.steps)
                                : std::string())
           << ") over " << t.steps << " steps"
           << (adaptive_step_
                   ? fmt::format(", adaptive step's stability estimates {:.3g} s in all", t.stability)
                   : std::string())
           << (adaptive_step_ && k_.adaptive_step.retries > 0
                   ? fmt::format(", interval snapshots {:.3g} s in all", record.snapshot_seconds)
                   : std::string())
           << (record.intervals_taken_again > 0
                   ? fmt::format(", {} intervals taken again ({:.3g} s in the attempts that failed)",
                                 record.intervals_taken_again, record.lost_seconds)
                   : std::string())
           << "; orifice area " << record.smallest_area << " to " << record.largest_area << " cm^2; "
           << fluid_summary(fluid);
    return timing.str();
  }

  static std::string leaflet(int k) { return fmt::format("leaflet{}", k); }

  /// "3e-05 s", or "3e-05 s, 2e-05 s over [0.37, 0.47] s of each cycle" with a coaptation step.
  std::string describe_steps() const
  {
    const std::string coarse = hemodynamics::format_value(schedule_.step(1)) + " s";
    if (adaptive_step_)
      return fmt::format("adaptive: intervals of {}, sub-steps up to {} s within {} x the structure's "
                         "estimate and CFL {}",
                         coarse, hemodynamics::format_value(k_.step),
                         hemodynamics::format_value(k_.adaptive_step.safety),
                         hemodynamics::format_value(k_.adaptive_step.cfl));
    if (schedule_.uniform()) return coarse;
    return fmt::format("{}, {} s over [{}, {}] s of each cycle", coarse,
                       hemodynamics::format_value(k_.coaptation_step),
                       hemodynamics::format_value(k_.coaptation_window[0]),
                       hemodynamics::format_value(k_.coaptation_window[1]));
  }

  // The structure: the mesh file, or the generated valve (its size checked before it is built), with
  // every group the model reads from it; all it lacks are named in one error.
  void read_mesh()
  {
    const ValveMeshKeys& m = k_.mesh;
    if (!m.file.empty()) {
      try {
        mesh_ = fe::read_msh(m.file);
      } catch (const InputError& e) {
        keys_.fail(m.file, e.what());
      }
      // The orifice area projects each leaflet element's two faces through the thickness (nodes 1-4
      // and 5-8 of a hexahedron).
      if (mesh_.shape() != fe::CellShape::hexahedron)
        keys_.fail(m.file, m.file.string() + ": tetrahedra; a valve run needs hexahedra (docs/own-valve.md)");
      check_size(static_cast<double>(mesh_.num_nodes()), static_cast<double>(mesh_.num_elements()),
                 keys_.key_of(m.file));
      if (k_.tube_wall && mesh_.has_group("tube"))
        keys_.fail(k_.tube_wall, m.file.string() +
                                     " has a tube: with \"wall\" the mesh holds the leaflets only "
                                     "(ibvalve mesh aortic-valve --no-tube)");
    } else {
      try {
        fe::check(m.geometry);
      } catch (const std::invalid_argument& e) {
        config_.fail("mesh", e.what());
      }
      fe::ValveMeshParameters geometry = m.geometry;
      geometry.include_tube = !k_.tube_wall;
      const GeneratedSize size = generated_size(geometry, leaflet_count);
      check_size(size.nodes, size.elements,
                 size.tube_dominates ? keys_.key_of(m.geometry.tube_around)
                                     : keys_.key_of(m.geometry.leaflet_across));
      mesh_ = fe::aortic_valve_mesh(geometry);
    }
    const std::string missing =
        missing_groups(mesh_, required_valve_groups(leaflet_count, k_.rule, !k_.tube_wall, k_.tube_surfaces,
                                                    keys_.key_of(k_.tube_surfaces)));
    if (!missing.empty())
      keys_.fail(m.file, (m.file.empty() ? "the generated mesh" : m.file.string()) + ": " + missing);
  }

  // Fibers (fibers.rule) computed before the run starts, so that a mesh they cannot be computed on is bad
  // input before the run folder exists (and `ibvalve check` finds it).
  void compute_leaflet_fibers()
  {
    try {
      frames_ = leaflet_fibers(mesh_, k_.rule, leaflet_count, PETSC_COMM_WORLD);
    } catch (const InputError& e) {
      keys_.fail(k_.rule,
                 fmt::format("{} ({})", e.what(), describe_valve_mesh(k_.mesh, mesh_, leaflet_count)));
    }
  }

  // The run's last step: time.end when given (it wins over time.cycles), else whole cycles. A run
  // shorter than a cycle gets its report over its whole length, which needs rows enough for one.
  void read_end()
  {
    const long every = static_cast<long>(k_.every);
    // The report reads the valve's opening, closing and ejection window from the rows: a closure takes
    // about 50 ms (RESULTS.md's T_close), so rows further apart than 5 ms blur them. With time.adaptive
    // output.every counts intervals, so a case written for fixed steps (every 40 steps of 4e-5 s) writes
    // a row every 64 ms.
    const double mean_step = period_ / static_cast<double>(steps_per_cycle_);
    const double row_spacing = static_cast<double>(every) * mean_step;
    if (row_spacing > 5e-3)
      base::Logger::global().warn(fmt::format(
          "{}: a time-series row every {:g} ms ({} {} of {:g} s): the report's ejection window, volumes "
          "and opening and closing times are read from the rows, and a valve closure (about 50 ms) spans "
          "fewer than 10 of them; a smaller {} (the fixed-step cases write a row every 1.6 ms)",
          keys_.key_of(k_.every), row_spacing * 1e3, every, adaptive_step_ ? "intervals" : "steps", mean_step,
          keys_.key_of(k_.every)));
    steps_ = static_cast<long>(k_.cycles) * steps_per_cycle_;
    if (!k_.end) return;
    steps_ = std::max<long>(1, static_cast<long>(schedule_.steps_to(*k_.end)));
    if (steps_ >= steps_per_cycle_) return;
    const long rows = steps_ / every + (steps_ % every != 0 ? 1 : 0) + 1;
    constexpr long report_rows = 11; // hemodynamics::write_report: a window of at least 10 intervals
    if (rows < report_rows)
      keys_.fail(
          k_.end,
          fmt::format("a run shorter than a cycle ({} s) is reported over its whole length, which holds {} "
                      "time-series rows ({} = {} steps); the report needs {}: a smaller {} or a longer {}",
                      hemodynamics::format_value(period_), rows, keys_.key_of(k_.every), every, report_rows,
                      keys_.key_of(k_.every), keys_.key_of(k_.end)));
  }

  // The structure's and the one grid's size, checked before the mesh is built: indices, then memory.
  // Nested levels add theirs in read_levels.
  void check_size(double nodes, double elements, const std::string& key)
  {
    check_index_count(config_, key, 3.0 * nodes, "structure unknowns");
    structure_memory_ = structure_memory(nodes, elements, key);
    memory_line_ =
        check_memory(config_,
                     {{fluid_memory(grid_cells(box_), memory_kind(fluid_), true, keys_.key_of(k_.cells)),
                       structure_memory_}},
                     PETSC_COMM_WORLD);
  }

  // Nested levels (docs/nested.md): placed around the valve and tube (or given as [[nested.box]]), the
  // finest level one box holding the whole structure with the kernel's reach.
  void read_levels(const io::Config& config)
  {
    if (k_.coupling.coupling == ib::CouplingKind::semi_implicit)
      keys_.fail(k_.coupling.coupling,
                 "\"semi-implicit\" needs the fluid on one grid, not on the levels of " +
                     keys_.key_of(k_.nested.ratios));
    hierarchy_ = std::make_unique<fluid::GridHierarchy>(read_structure_levels(
        keys_, k_.nested, box_, mesh_.nodes(), ib_.kernel, keys_.key_of(k_.nested.boxes)));
    memory_line_ = check_memory(
        config,
        {{nested_fluid_memory(*hierarchy_, box_, keys_.key_of(k_.cells), keys_.key_of(k_.nested.ratios)),
          structure_memory_}},
        PETSC_COMM_WORLD);
  }

  /// At the end of cycle `cycle` (1, 2, ...) its report in report/cycle_N/, and report/ when it is the
  /// reported cycle (report.cycle); for a run shorter than a cycle (cycle 0), the report of its whole
  /// `length` in report/.
  void write_report(const RunContext& context, RunSummary& summary, long cycle, double length = 0.0) const
  {
    hemodynamics::ReportOptions options;
    options.settings = k_.report.metrics;
    options.settings.density = k_.fluid.rho; // the EOA's density is the fluid's (g/cm^3 = g/mL)
    options.cycle_folders = hemodynamics::CycleFolders::last;
    options.run_cycles = static_cast<int>(total_cycles());
    if (cycle == 0) {
      options.settings.period = length;
      options.settings.cycle = -1;
      options.cycle_folders = hemodynamics::CycleFolders::none;
    }
    options.plots = k_.report.plots;
    options.cycle_plots = k_.report.cycle_plots;
    options.templates = k_.report.templates;
    // Rank 0 writes it; a failure there (a full disk) reaches every rank instead of leaving them waiting.
    io::on_root(context.comm, [&] {
      const auto files = hemodynamics::write_report(context.run_directory, options);
      if (cycle == 0) {
        summary.lines.push_back("report of the run's " + hemodynamics::format_value(length) +
                                " s (shorter than a " + hemodynamics::format_value(period_) +
                                " s cycle: its metrics are of that window): " + files.html.string());
        return;
      }
      std::string line =
          fmt::format("cycle {} of {} report: {}", cycle, total_cycles(), files.cycle_pages.back().string());
      if (files.directory != files.cycle_pages.back().parent_path())
        line += fmt::format(" (the reported cycle's: {})", files.html.string());
      summary.lines.push_back(line);
      summary.lines.push_back(fmt::format(
          "cycle {}: {}", cycle,
          hemodynamics::metrics_summary(files.cycle_pages.back().parent_path() / "metrics.json")));
    });
  }

  /// The run's whole cycles: time.cycles, or those time.end holds.
  long total_cycles() const { return steps_ / steps_per_cycle_; }

  /// <run>/extra_metrics.json: what the report adds from outside the time series (docs/hemodynamics.md,
  /// "Extra metrics"), here the leaflet law's fit error. Written whole or not at all, by rank 0.
  void write_extra_metrics(const RunContext& context) const
  {
    if (!fit_error_) return;
    io::on_root(context.comm, [&] {
      nlohmann::ordered_json extra;
      extra["fit_error"] = fit_error_metric(*fit_error_, keys_.key_of(k_.fit_data));
      io::write_file_atomically(context.run_directory / "extra_metrics.json", extra.dump(2) + "\n");
    });
  }

  io::Config config_;
  io::KeyBinder keys_; // reads config_ into k_, and names a key in a message
  AorticValveKeys k_;
  std::unique_ptr<drivers::BoundaryDrivers> drivers_; // what the inlet and outlet sides get
  fluid::BoxGeometry box_;
  fluid::FluidSettings fluid_;
  fe::Mesh mesh_;
  std::vector<materials::FiberFrame> frames_; // per element: the leaflets' fibers, zero in the tube
  materials::MaterialSettings leaflet_material_, tube_material_;
  ib::IbfeSettings ib_;
  double inlet_radius_ = 0, outlet_radius_ = 0, period_ = 0.8;
  std::optional<LeafletFitError> fit_error_; ///< from leaflets.fit_data

  /// The factor of both boundary pressures at time t: a smooth rise from 0 to 1 over the ramp.
  double pressure_ramp(double t) const
  {
    if (t >= k_.pressure_ramp) return 1.0;
    return 0.5 * (1.0 - std::cos(std::numbers::pi * std::max(t, 0.0) / k_.pressure_ramp));
  }
  StepSchedule schedule_{1.0, 1.0};
  std::optional<AdaptiveStep> adaptive_step_; // with time.adaptive: the sub-steps of each interval
  long steps_per_cycle_ = 1, steps_ = 1, fields_every_ = 0;
  double flow_plane_z_ = 0, near_lv_z_ = 0, near_ao_z_ = 0;
  MemoryPart structure_memory_;
  std::unique_ptr<fluid::GridHierarchy> hierarchy_; // nested levels; null on one grid
};

} // namespace

Model aortic_valve_model()
{
  return Model{
      "aortic-valve",
      "the tri-leaflet valve in its tube (IB/FE): the LV pressure table in and a Windkessel out, or the "
      "closed-loop circulation around it; fibers FD1/FD2, report each cycle",
      add_bound_schema<AorticValveKeys>, [](const io::Config& config) -> std::unique_ptr<PreparedRun> {
        return std::make_unique<AorticValveRun>(config);
      }};
}

} // namespace ibvalve::app
