#include "app/aortic_valve_keys.hpp"

#include <string>
#include <vector>

#include "app/model.hpp"
#include "app/output_keys.hpp"
#include "app/resource_estimate.hpp"
#include "fe/volumetric_integration.hpp"
#include "fluid/hierarchy.hpp"
#include "ib/keys.hpp"
#include "io/checkpoint.hpp"
#include "materials/settings.hpp"
#include "windkessel/keys.hpp"

namespace ibvalve::app {

namespace {

/// The run's length and its steps: time.*.
void bind_time(io::KeyBinder& keys, AorticValveKeys& k)
{
  keys.integer("time.cycles",
               "cardiac cycles to run (a report after each; the study reports the second of two)", k.cycles)
      .defaults(std::int64_t{2})
      .at_least(1);
  keys.real("time.end",
            "simulated end time; unset = " + keys.key_of(k.cycles) +
                " x the LV pressure's period; a run shorter than a cycle is reported over its whole length",
            k.end)
      .unit("s")
      .positive();
  keys.real("time.step",
            "time step (rounded so a cycle holds a whole number of steps); with the adaptive step the "
            "longest sub-step",
            k.step)
      .unit("s")
      .defaults(1e-4)
      .positive();
  keys.real("time.coaptation_step",
            "a finer step over the coaptation window of each cycle, where the leaflets meet and the "
            "explicit coupling needs it (the FD2 fiber field: docs/runs.md, \"A finer step over the "
            "coaptation\"); 0 = one step throughout",
            k.coaptation_step)
      .unit("s")
      .defaults(0.0)
      .non_negative();
  keys.reals("time.coaptation_window", "start and end, within each cycle, of the coaptation step",
             k.coaptation_window)
      .unit("s")
      .size(2)
      .defaults(std::vector<double>{0.37, 0.47});
  keys.boolean("time.adaptive",
               "choose the step from the state: fixed intervals, each taken in equal sub-steps within the "
               "structure's current stability estimate and the fluid's advective limit (docs/runs.md, "
               "\"The adaptive step\"); false = one step as set throughout",
               k.adaptive)
      .defaults(true);
  const std::string adaptive = keys.key_of(k.adaptive);
  keys.real("time.interval",
            "with " + adaptive +
                ": the run's rows, snapshots, checkpoints and cycle ends fall on these (rounded so a cycle "
                "holds a whole number), and the counts of its steps count them",
            k.adaptive_step.interval)
      .unit("s")
      .defaults(8e-4)
      .positive();
  keys.real("time.safety",
            "with " + adaptive +
                ": the fraction of the structure's stability estimate a sub-step may take (0.8 with "
                "ib.stability_estimate = response, which lies 5-10 % above the true limit: docs/ib.md)",
            k.adaptive_step.safety)
      .defaults(0.9)
      .positive()
      .at_most(2.0);
  keys.integer("time.estimate_iterations",
               "with " + adaptive +
                   ": power iterations of the structure's stability estimate at each interval's start, each "
                   "from the last one's mode (docs/ib.md, \"The coupled estimate\")",
               k.adaptive_step.estimate_iterations)
      .defaults(std::int64_t{6})
      .at_least(1)
      .at_most(100);
  keys.integer("time.retries",
               "with " + adaptive +
                   ": times an interval whose sub-steps went unstable (a point left the grid, a solver "
                   "diverged) is taken again from its start with twice the sub-steps before the run stops "
                   "(docs/runs.md, \"The adaptive step\"); 0 = stop at once",
               k.adaptive_step.retries)
      .defaults(std::int64_t{3})
      .at_least(0)
      .at_most(10);
  keys.real("time.cfl", "with " + adaptive + ": the largest advective CFL number max|u| dt / h of a sub-step",
            k.adaptive_step.cfl)
      .defaults(0.5)
      .positive()
      .at_most(2.0);
  keys.real("time.pressure_ramp",
            "the inlet and outlet pressures rise from zero to their values over this time, as "
            "(1 - cos(pi t / T)) / 2, so that the valve closes under the Windkessel pressure without the "
            "water hammer of a sudden load (docs/reference.md, \"Choices the study left open\"); 0 = applied "
            "at once",
            k.pressure_ramp)
      .unit("s")
      .defaults(0.05)
      .non_negative();
}

/// The outputs' cadence and the blood in its box: output.*, fluid.*.
void bind_fluid(io::KeyBinder& keys, AorticValveKeys& k)
{
  bind_fields_interval(keys, k.fields_interval, 0.02, "fields_fluid.xdmf and fields_structure.xdmf");
  bind_row_every(keys, k.every, 1); // with the adaptive step a row an interval
  bind_fluid_density(keys, k.fluid.rho, "blood density");
  keys.real("fluid.viscosity", "blood viscosity", k.fluid.mu)
      .unit("cP")
      .defaults(4.0)
      .positive()
      .typical(1.0, 20.0, "blood is 3.5 to 4 cP; 1000 times less is a value in Pa s, 100 times less in P");
  keys.integers("fluid.cells", "grid cells in x, y, z", k.cells)
      .size(3)
      .at_most(max_grid_cells)
      .defaults(std::vector<std::int64_t>{26, 26, 43});
  // 0.125 cm cells around the default tube (mesh.tube_length), its ends half a cell inside the box; across,
  // the narrowest whole number of cells that holds the kernel's reach (2 cells) beyond the leaflets'
  // attachment at r = 1.3 cm: the cells beyond the lumen are blocked (tube.model = "wall"), so a wider
  // box solves the same problem (docs/convergence.md, "One lumen, each grid's narrowest box").
  keys.reals("fluid.lower", "lower corner of the box (the tube's axis is x = y = 0, inlet at z = 0)", k.lower)
      .unit("cm")
      .size(3)
      .defaults(std::vector<double>{-1.625, -1.625, -0.0625});
  keys.reals("fluid.upper", "upper corner of the box", k.upper)
      .unit("cm")
      .size(3)
      .defaults(std::vector<double>{1.625, 1.625, 5.3125});
  keys.choice("fluid.subsolver",
              "sub-solves of the Krylov Stokes solver's preconditioner: fft (FFTW sine/cosine transforms) "
              "or amg (hypre BoomerAMG V-cycles)",
              k.fluid.subsolver, {{"amg", fluid::SubsolverKind::amg}, {"fft", fluid::SubsolverKind::fft}})
      .defaults(std::string("fft"));
  keys.real("fluid.rtol", "relative tolerance of the Krylov (FGMRES) Stokes solve each step", k.fluid.rtol)
      .defaults(1e-8)
      .positive();
  keys.integer("fluid.max_iterations", "most FGMRES iterations per step", k.fluid.max_iterations)
      .defaults(std::int64_t{100})
      .at_least(1)
      .at_most(max_solver_iterations);
  keys.real("fluid.backflow_stabilization",
            "beta: where fluid enters through the box's pressure sides, their pressure is lowered by "
            "beta rho/2 (u.n)^2 (the LV pressure becomes a total pressure); 0 = plain static pressure, "
            "which lets backflow grow",
            k.backflow)
      .defaults(1.0)
      .non_negative();
}

/// The valve and its tube: mesh.*, the materials, fibers.rule, tether.*.
void bind_structure(io::KeyBinder& keys, AorticValveKeys& k)
{
  bind(keys, k.mesh);

  // The leaflets' isochoric invariant holds the commissures' element corners (docs/reference.md, "Choices
  // the study left open"); the tube is a stiff neo-Hookean wall.
  materials::MaterialRecommendation leaflets, tube;
  leaflets.isotropic_invariant = "isochoric";
  tube.preset.clear();
  tube.law = "neo-hookean";
  tube.parameters = {{"mu", 100.0}}; // kPa
  materials::bind(keys, k.leaflets_material, "leaflets.material", leaflets);
  keys.choice(
          "tube.model",
          "the tube: immersed (an elastic hexahedral wall coupled to the fluid like the leaflets: "
          "tube.material, tether.tube_*) or wall (rigid: the fluid's cells beyond the tube's inner radius "
          "are blocked, docs/fluid.md; no tube elements, so no explicit step limit "
          "from the tube's stiffness and no coupling points in it; one grid only)",
          k.tube_wall, {{"immersed", false}, {"wall", true}})
      .defaults(std::string("wall"));
  materials::bind(keys, k.tube_material, "tube.material", tube);
  keys.paths("leaflets.fit_data",
             "planar biaxial samples (CSV files with the columns of `ibvalve fit`) that the leaflet law with "
             "its parameters is measured against: the report's fit_error, the first criterion of the study's "
             "ranking; unset = no fit error",
             k.fit_data);
  keys.choice("fibers.rule", "leaflet fiber rule (docs/fibers.md)", k.rule,
              {{"FD1", fibers::FiberRule::FD1}, {"FD2", fibers::FiberRule::FD2}})
      .defaults(std::string("FD1"));
  keys.strings("tether.tube_surfaces",
               "the tube's surface groups held in place: tube_outer (the study), and its end faces "
               "tube_inlet, tube_outlet",
               k.tube_surfaces)
      .choices({"tube_outer", "tube_inlet", "tube_outlet"})
      .defaults(std::vector<std::string>{"tube_outer", "tube_inlet", "tube_outlet"});
  keys.real("tether.tube_stiffness", "spring per area holding the tube's surfaces in place, dyn/cm^3",
            k.tube_stiffness)
      .defaults(1e8)
      .non_negative();
  keys.real("tether.tube_damping", "dashpot per area on the tube's surfaces", k.tube_damping)
      .defaults(0.0)
      .non_negative();
  keys.real("tether.attachment_stiffness", "spring per area holding each leaflet's attachment, dyn/cm^3",
            k.attachment_stiffness)
      .defaults(1e8)
      .non_negative();
  keys.real("tether.attachment_damping", "dashpot per area on the attachments", k.attachment_damping)
      .defaults(0.0)
      .non_negative();
}

/// The drive and what is measured: lv_pressure.*, inlet.*, windkessel.*, outlet.*, circulation.*, probes.*.
void bind_boundary(io::KeyBinder& keys, AorticValveKeys& k)
{
  windkessel::bind(keys, k.drivers.lv_pressure, "lv_pressure", "LV pressure on the inlet disk, in mmHg",
                   false);
  drivers::bind(keys, k.drivers); // which drivers: the table and the Windkessel, or the closed loop
  keys.real("inlet.radius", "radius of the inlet pressure disk (0 = the middle of the tube wall)",
            k.inlet_radius)
      .unit("cm")
      .defaults(0.0)
      .non_negative();
  keys.choice("inlet.outside",
              "the inlet side outside its disk: zero-pressure (the study) or wall (no slip, closes the "
              "space around the tube's end)",
              k.inlet_walled, {{"zero-pressure", false}, {"wall", true}})
      .defaults(std::string("wall"));
  windkessel::bind(keys, k.drivers.windkessel, "windkessel");
  keys.real("outlet.radius", "radius of the Windkessel disk (0 = the middle of the tube wall)",
            k.outlet_radius)
      .unit("cm")
      .defaults(0.0)
      .non_negative();
  keys.choice("outlet.outside", "the outlet side outside its disk: zero-pressure (the study) or wall",
              k.outlet_walled, {{"zero-pressure", false}, {"wall", true}})
      .defaults(std::string("wall"));
  keys.real("probes.offset", "P_nlv / P_nao: on the axis this far below the nadir / above the commissures",
            k.probe_offset)
      .unit("cm")
      .defaults(1.0)
      .positive();
  keys.real("probes.flow_plane_offset", "Q_valve through the tube section this far below the nadir",
            k.flow_plane_offset)
      .unit("cm")
      .defaults(0.5)
      .non_negative();
  keys.integer("probes.orifice_resolution", "pixels per side of the orifice-area raster",
               k.orifice_resolution)
      .defaults(std::int64_t{256})
      .at_least(16)
      .at_most(8192);
}

} // namespace

void bind(io::KeyBinder& keys, AorticValveKeys& k)
{
  bind_time(keys, k);
  bind_fluid(keys, k);
  bind_structure(keys, k);
  bind_boundary(keys, k);
  // The default mesh's cells, a little longer than a grid cell, get 2 x 2 x 2 points (docs/reference.md).
  ib::bind(keys, k.coupling, 1.0);
  keys.integer("structure.quadrature_degree", "Gauss rule degree of the force integrals", k.quadrature_degree)
      .defaults(std::int64_t{2})
      .at_least(1)
      .at_most(max_quadrature_degree);
  // One hex through the leaflet thickness locks in bending when the penalty (kappa/mu ~ 800) is
  // integrated on the full rule: selective reduced integration by default (docs/fe.md).
  fe::bind(keys, k.volumetric_integration, fe::VolumetricIntegration::reduced);
  hemodynamics::bind_report(keys, k.report);
  io::bind(keys, k.checkpoints);
  // Nested grid levels around the valve and tube (docs/nested.md): the structure on the finest level.
  fluid::bind(keys, k.nested);
}

} // namespace ibvalve::app
