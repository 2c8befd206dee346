// `model = "fluid"`: the Navier–Stokes solver alone (fluid/, docs/fluid.md) on a box whose six sides
// are periodic, walls, prescribed velocity (uniform or parabolic) or prescribed pressure (over the
// whole side or a disk of it, zero elsewhere). Writes timeseries.csv (t, norms, fluxes through the
// sides, the centre pressure; errors against the exact solution for the Taylor–Green and ABC
// initial conditions) and fields/*.h5 + fields.xdmf (velocity, vorticity, pressure).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>

#include <mpi.h>

#include "app/fftw_plans.hpp"
#include "app/fluid_box.hpp"
#include "app/model.hpp"
#include "app/resource_estimate.hpp"
#include "app/step_diagnostics.hpp"
#include "app/time_loop.hpp"
#include "fluid/navier_stokes.hpp"
#include "fluid/output.hpp"
#include "fluid/queries.hpp"
#include "io/checkpoint.hpp"
#include "io/collective.hpp"
#include "base/errors.hpp"
#include "io/files.hpp"
#include "base/logger.hpp"

namespace ibvalve::app {

namespace {

using fluid::Real3;
constexpr double two_pi = 2.0 * std::numbers::pi;

void add_fluid_schema(io::Schema& s)
{
  add_fluid_density_key(s, "fluid density");
  add_fluid_viscosity_key(s, 1.0);
  s.add_integer_list("fluid.cells", "grid cells in x, y, z")
      .required()
      .size(3)
      .at_most(max_grid_cells)
      .example(std::vector<std::int64_t>{16, 16, 16});
  s.add_real_list("fluid.lower", "lower corner of the box")
      .unit("cm")
      .defaults(std::vector<double>{0, 0, 0})
      .size(3);
  s.add_real_list("fluid.upper", "upper corner of the box")
      .unit("cm")
      .required()
      .size(3)
      .example(std::vector<double>{1.0, 1.0, 1.0});
  s.add_string("fluid.solver",
               "Stokes solver: fft (periodic boxes), krylov (any sides), auto (fft when periodic)")
      .defaults(std::string("auto"))
      .choices({"auto", "fft", "krylov"});
  s.add_string("fluid.subsolver",
               "krylov solver's preconditioner sub-solves: amg (hypre BoomerAMG V-cycles) or fft (FFTW "
               "sine/cosine transforms: exact pressure Poisson, Helmholtz preconditioner)")
      .defaults(std::string("fft"))
      .choices({"amg", "fft"});
  s.add_string("fluid.convection", "convective scheme")
      .defaults(std::string("limited_upwind"))
      .choices({"limited_upwind", "centered"});
  s.add_real("fluid.rtol", "relative tolerance of the Krylov (FGMRES) Stokes solve")
      .defaults(1e-10)
      .positive();
  s.add_integer("fluid.max_iterations", "most FGMRES iterations per step")
      .defaults(std::int64_t{200})
      .at_least(1)
      .at_most(max_solver_iterations);
  for (int side = 0; side < 6; ++side) {
    const std::string p = "boundary." + fluid::side_name(side) + ".";
    s.add_string(
         p + "type",
         "periodic, wall (no slip), velocity (prescribed), pressure (normal traction -p, no tangential flow)")
        .defaults(std::string("periodic"))
        .choices({"periodic", "wall", "velocity", "pressure"});
    s.add_real_list(p + "velocity", "velocity type: the velocity vector (the mean for a parabolic profile)")
        .unit("cm/s")
        .defaults(std::vector<double>{0, 0, 0})
        .size(3);
    s.add_string(p + "profile", "velocity type: uniform, or parabolic across the side (zero at its walls)")
        .defaults(std::string("uniform"))
        .choices({"uniform", "parabolic"});
    s.add_real(p + "pressure", "pressure type: boundary pressure p_b (n.sigma.n = -p_b)")
        .unit("mmHg")
        .defaults(0.0);
    s.add_real(p + "disk_radius",
               "pressure type: apply the pressure inside this disk only (0: the whole side)")
        .unit("cm")
        .defaults(0.0)
        .non_negative();
    s.add_real_list(p + "disk_center", "pressure type: centre of the disk (default: the side's centre)")
        .unit("cm")
        .size(3);
    s.add_real(p + "ramp", "boundary data grow linearly from 0 over this time (0: at once)")
        .unit("s")
        .defaults(0.0)
        .non_negative();
  }
  s.add_string("initial.condition", "rest, taylor_green (x-y vortex, periodic x and y) or abc (periodic box)")
      .defaults(std::string("rest"))
      .choices({"rest", "taylor_green", "abc"});
  s.add_real("initial.amplitude", "velocity amplitude of the vortex").unit("cm/s").defaults(1.0);
  s.add_real_list("initial.mean_velocity", "uniform velocity carrying the vortex")
      .unit("cm/s")
      .defaults(std::vector<double>{0, 0, 0})
      .size(3);
  s.add_real("time.end", "simulated time").unit("s").required().positive().example(0.01);
  s.add_real("time.step", "time step").unit("s").required().positive().example(0.001);
  s.add_integer("output.fields_every",
                "write fields every this many steps (and the first and last; 0: those only)")
      .defaults(std::int64_t{0})
      .at_least(0);
  s.add_integer("output.timeseries_every", "write a timeseries.csv row every this many steps")
      .defaults(std::int64_t{1})
      .at_least(1);
  io::add_checkpoint_schema(s);
}

/// The exact decaying vortices (Taylor–Green in x-y; ABC) carried by a uniform velocity.
struct ExactVortex {
  std::string kind; // "taylor_green" or "abc"
  Real3 lower{}, length{}, mean{};
  double amplitude = 1.0, nu = 0.0, rho = 1.0;

  double phase(const Real3& x, double t, int d) const
  {
    return two_pi * (x[d] - lower[d] - mean[d] * t) / length[d];
  }
  Real3 velocity(const Real3& x, double t) const
  {
    const double X = phase(x, t, 0), Y = phase(x, t, 1), Z = phase(x, t, 2);
    if (kind == "taylor_green") {
      const double k = two_pi / length[0], e = amplitude * std::exp(-2.0 * k * k * nu * t);
      return {mean[0] - std::cos(X) * std::sin(Y) * e, mean[1] + std::sin(X) * std::cos(Y) * e, mean[2]};
    }
    const double k = two_pi / length[0], e = amplitude * std::exp(-k * k * nu * t);
    return {mean[0] + e * (std::cos(Y) + std::sin(Z)), mean[1] + e * (std::sin(X) + std::cos(Z)),
            mean[2] + e * (std::cos(X) + std::sin(Y))};
  }
  double pressure(const Real3& x, double t) const
  {
    const double X = phase(x, t, 0), Y = phase(x, t, 1), Z = phase(x, t, 2);
    const double k = two_pi / length[0];
    if (kind == "taylor_green") {
      const double e = amplitude * amplitude * std::exp(-4.0 * k * k * nu * t);
      return -0.25 * rho * (std::cos(2.0 * X) + std::cos(2.0 * Y)) * e;
    }
    const double e = amplitude * amplitude * std::exp(-2.0 * k * k * nu * t);
    return -rho * e * (std::cos(Y) * std::sin(Z) + std::sin(X) * std::cos(Z) + std::cos(X) * std::sin(Y));
  }
};

class FluidRun : public PreparedRun {
 public:
  explicit FluidRun(const io::Config& config) : config_(config)
  {
    box_ = read_fluid_box(config);
    settings_.rho = config.real("fluid.density");
    settings_.mu = config.real("fluid.viscosity");
    settings_.rtol = config.real("fluid.rtol");
    settings_.max_iterations = static_cast<PetscInt>(config.integer("fluid.max_iterations"));
    settings_.convection = config.string("fluid.convection") == "centered"
                               ? fluid::ConvectionScheme::centered
                               : fluid::ConvectionScheme::limited_upwind;
    for (int d = 0; d < 3; ++d) {
      const std::string lo = "boundary." + fluid::side_name(fluid::side_index(d, 0)) + ".type";
      const std::string hi = "boundary." + fluid::side_name(fluid::side_index(d, 1)) + ".type";
      const bool lower_periodic = config.string(lo) == "periodic",
                 upper_periodic = config.string(hi) == "periodic";
      if (lower_periodic != upper_periodic)
        config.fail(hi, "opposite sides must both be periodic or neither");
      box_.periodic[d] = lower_periodic;
    }
    for (int side = 0; side < 6; ++side) read_side(side);
    const bool all_periodic = box_.periodic[0] && box_.periodic[1] && box_.periodic[2];
    const std::string solver = config.string("fluid.solver");
    if (solver == "fft" && !all_periodic) config.fail("fluid.solver", "fft needs every side periodic");
    settings_.solver = (solver == "fft" || (solver == "auto" && all_periodic)) ? fluid::SolverKind::fft
                                                                               : fluid::SolverKind::krylov;
    settings_.subsolver =
        config.string("fluid.subsolver") == "fft" ? fluid::SubsolverKind::fft : fluid::SubsolverKind::amg;
    const std::string initial = config.string("initial.condition");
    if (initial != "rest") {
      exact_.kind = initial;
      exact_.amplitude = config.real("initial.amplitude");
      exact_.nu = settings_.mu / settings_.rho;
      exact_.rho = settings_.rho;
      for (int d = 0; d < 3; ++d) {
        exact_.lower[d] = box_.lower[d];
        exact_.length[d] = box_.upper[d] - box_.lower[d];
        exact_.mean[d] = config.reals("initial.mean_velocity")[d];
      }
      const bool tg = initial == "taylor_green";
      if (!box_.periodic[0] || !box_.periodic[1] || (!tg && !box_.periodic[2]))
        config.fail("initial.condition",
                    tg ? "taylor_green needs periodic x and y sides" : "abc needs a periodic box");
      if (std::abs(exact_.length[1] - exact_.length[0]) > 1e-12 * exact_.length[0] ||
          (!tg && std::abs(exact_.length[2] - exact_.length[0]) > 1e-12 * exact_.length[0]))
        config.fail("fluid.upper", initial + " needs equal box lengths in its periodic directions");
      if (tg && !box_.periodic[2] && exact_.mean[2] != 0.0)
        config.fail("initial.mean_velocity", "must have no z part between z walls");
    }
    end_ = config.real("time.end");
    dt_ = config.real("time.step");
    fields_every_ = config.integer("output.fields_every");
    series_every_ = config.integer("output.timeseries_every");
    checkpoint_settings_ = io::checkpoint_settings_from_config(config);
    memory_line_ =
        check_memory(config, {{fluid_memory(grid_cells(box_), memory_kind(settings_), false, "fluid.cells")}},
                     PETSC_COMM_WORLD);
  }

  RunSummary run(const RunContext& context) override
  {
    auto& log = base::Logger::global();
    std::unique_ptr<fluid::NavierStokes> fluid;
    if (context.restart) load_fftw_plans(context);
    try {
      fluid = std::make_unique<fluid::NavierStokes>(context.comm, box_, bc_, settings_);
    } catch (const std::invalid_argument& e) {
      throw InputError(config_.file().string() + ": fluid: " + e.what());
    }
    if (exact_.kind.empty())
      fluid->set_initial_condition([](const Real3&, double) { return Real3{0, 0, 0}; }, nullptr, 0.0);
    else
      fluid->set_initial_condition([this](const Real3& x, double t) { return exact_.velocity(x, t); },
                                   [this](const Real3& x, double t) { return exact_.pressure(x, t); }, 0.0);
    log.info("fluid: " + std::to_string(box_.cells[0]) + " x " + std::to_string(box_.cells[1]) + " x " +
             std::to_string(box_.cells[2]) + " cells, solver " + fluid->solver().name() + ", dt " +
             std::to_string(dt_) + " s");

    std::vector<std::string> columns{"t",         "step",           "max_velocity",     "kinetic_energy",
                                     "enstrophy", "max_divergence", "solver_iterations"};
    // Kinetic energy 1/2 rho int |u|^2, enstrophy 1/2 int |omega|^2 (fluid/queries.hpp).
    std::vector<std::string> column_units{"s", "1", "cm/s", "erg", "cm^3/s^2", "1/s", "1"};
    std::vector<int> flux_sides;
    for (int side = 0; side < 6; ++side)
      if (!box_.periodic[side / 2]) {
        flux_sides.push_back(side);
        columns.push_back("outflow_" + fluid::side_name(side));
        column_units.push_back("mL/s");
      }
    columns.push_back("p_center");
    column_units.push_back("dyn/cm^2");
    if (!exact_.kind.empty()) {
      columns.push_back("u_error_max");
      columns.push_back("p_error_max");
      column_units.insert(column_units.end(), {"cm/s", "dyn/cm^2"});
    }
    const Real3 center{0.5 * (box_.lower[0] + box_.upper[0]), 0.5 * (box_.lower[1] + box_.upper[1]),
                       0.5 * (box_.lower[2] + box_.upper[2])};
    double last_divergence = 0.0;

    TimeLoop loop;
    loop.comm = context.comm;
    loop.steps = std::max(1L, std::lround(end_ / dt_));
    loop.dt = dt_;
    loop.checkpoints = checkpoint_settings_;
    loop.columns = columns;
    loop.units = column_units;
    loop.record_every = series_every_;
    loop.fields_every = fields_every_;
    loop.time = [&](std::int64_t) { return fluid->time(); };
    loop.advance = [&](std::int64_t) {
      try {
        fluid->step(dt_);
      } catch (const std::runtime_error& e) {
        throw RunError(e.what());
      }
      const double umax = fluid->max_velocity();
      if (!std::isfinite(umax))
        throw RunError("fluid: the velocity is not finite at t = " + std::to_string(fluid->time()) +
                       " s (time step too large?)");
      // Explicit convection (AB2, upwind-biased) is stable for Courant numbers below about 1; far
      // above, the run is diverging: stop with the figure rather than run on to overflow.
      const double courant = umax * dt_ / fluid->finest_spacing();
      if (courant > 2.0) {
        char text[200];
        std::snprintf(text, sizeof text,
                      "fluid: Courant number %.2f at t = %.4g s (max |u| %.3g cm/s): the run is unstable; "
                      "use a time.step below %.3g s",
                      courant, fluid->time(), umax, 0.5 * fluid->finest_spacing() / umax);
        throw RunError(text);
      }
    };
    loop.row = [&](std::int64_t step) {
      last_divergence = fluid::max_divergence(*fluid);
      std::vector<double> row{fluid->time(),
                              static_cast<double>(step),
                              fluid->max_velocity(),
                              fluid->kinetic_energy(),
                              fluid::enstrophy(*fluid),
                              last_divergence,
                              static_cast<double>(fluid->last_solve().iterations)};
      for (int side : flux_sides) {
        const int d = side / 2, upper = side % 2;
        const double position = upper ? box_.upper[d] : box_.lower[d];
        const double flux = fluid->flux(fluid::PlaneRegion::rectangle(d, position, box_.lower, box_.upper));
        row.push_back(upper ? flux : -flux);
      }
      row.push_back(fluid::pressure_at(*fluid, center));
      if (!exact_.kind.empty()) {
        const auto e = fluid::field_errors(
            *fluid, [this](const Real3& x, double t) { return exact_.velocity(x, t); },
            [this](const Real3& x, double t) { return exact_.pressure(x, t); }, bc_.any_traction() == false);
        row.push_back(e.velocity_max);
        row.push_back(e.pressure_max);
      }
      return row;
    };
    loop.write_fields = [&](io::XdmfTimeSeries& series, std::int64_t step) {
      char name[64];
      std::snprintf(name, sizeof name, "fields/fluid_%06lld.h5", static_cast<long long>(step));
      io::Hdf5File h5(context.comm, context.run_directory / name, io::Hdf5File::Mode::create);
      h5.write_attribute("time", fluid->time());
      h5.write_attribute("pressure_time", fluid->pressure_time());
      std::vector<io::XdmfGrid> grids = fluid->write_fields(h5, "fluid", name);
      h5.close(); // written, or a RunError on every rank (a full disk), before fields.xdmf names it
      series.add_step(fluid->time(), grids);
    };
    // The state of a continued run (docs/runs.md): the fluid's.
    loop.save = [&](io::Hdf5File& h5) { fluid->save(h5, "fluid"); };
    loop.restore = [&](const io::Hdf5File& h5) { fluid->restore(h5, "fluid"); };
    loop.before_save = [&] { save_fftw_plans(context); };
    loop.figures = [&] { return fluid_step_figures(*fluid, dt_); };
    loop.finish = [&](RunSummary& summary, bool finished, std::size_t snapshots) {
      if (!finished) return;
      const fluid::StepStatistics& timing = fluid->statistics();
      const long taken = std::max<long>(1, static_cast<long>(timing.steps));
      char line[256];
      std::snprintf(line, sizeof line,
                    "fluid: %ld steps, %.4f s per step (convection %.4f, viscous %.4f, pressure %.4f, halo "
                    "%.4f), %.1f solver iterations per step",
                    taken, timing.total / taken, timing.convection / taken, timing.viscous / taken,
                    timing.pressure / taken, timing.halo / taken,
                    static_cast<double>(timing.solver_iterations) / taken);
      summary.lines.push_back(line);
      std::snprintf(line, sizeof line, "fluid: max |div u| %.2e at the end; %zu field files, timeseries.csv",
                    last_divergence, snapshots);
      summary.lines.push_back(line);
    };
    return run_time_loop(context, loop);
  }

 private:
  void read_side(int side)
  {
    const std::string p = "boundary." + fluid::side_name(side) + ".";
    const std::string type = config_.string(p + "type");
    const int d = side / 2;
    fluid::BoundarySide& b = bc_.side(side);
    const double ramp = config_.real(p + "ramp");
    auto ramp_factor = [ramp](double t) { return ramp > 0.0 ? std::min(1.0, t / ramp) : 1.0; };
    if (type == "periodic") {
      b.kind = fluid::SideKind::periodic;
    } else if (type == "wall") {
      b.kind = fluid::SideKind::velocity;
    } else if (type == "velocity") {
      b.kind = fluid::SideKind::velocity;
      const auto v = config_.reals(p + "velocity");
      const Real3 value{v[0], v[1], v[2]};
      const bool parabolic = config_.string(p + "profile") == "parabolic";
      const fluid::BoxGeometry box = box_;
      b.velocity = [=](const Real3& x, double t) {
        double shape = 1.0;
        if (parabolic)
          for (int e = 0; e < 3; ++e) {
            if (e == d || box.periodic[e]) continue;
            const double s = (x[e] - box.lower[e]) / box.length(e);
            shape *= 6.0 * s * (1.0 - s); // mean 1 over the side
          }
        const double f = shape * ramp_factor(t);
        return Real3{f * value[0], f * value[1], f * value[2]};
      };
    } else {
      b.kind = fluid::SideKind::traction;
      const double pressure = config_.real(p + "pressure");
      const double radius = config_.real(p + "disk_radius");
      Real3 c{0.5 * (box_.lower[0] + box_.upper[0]), 0.5 * (box_.lower[1] + box_.upper[1]),
              0.5 * (box_.lower[2] + box_.upper[2])};
      if (config_.has(p + "disk_center")) {
        const auto given = config_.reals(p + "disk_center");
        c = {given[0], given[1], given[2]};
      }
      b.pressure = [=](const Real3& x, double t) {
        if (radius > 0.0) {
          double r2 = 0.0;
          for (int e = 0; e < 3; ++e)
            if (e != d) r2 += (x[e] - c[e]) * (x[e] - c[e]);
          if (r2 > radius * radius) return 0.0;
        }
        return pressure * ramp_factor(t);
      };
    }
  }

  io::Config config_;
  fluid::BoxGeometry box_;
  fluid::BoundaryConditions bc_;
  fluid::FluidSettings settings_;
  ExactVortex exact_;
  double end_ = 0.0, dt_ = 0.0;
  long fields_every_ = 0, series_every_ = 1;
  io::CheckpointSettings checkpoint_settings_;
};

} // namespace

Model fluid_model()
{
  return {"fluid", "incompressible Navier-Stokes in a box (no structure): Taylor-Green, ABC, ducts, channels",
          add_fluid_schema, [](const io::Config& config) -> std::unique_ptr<PreparedRun> {
            return std::make_unique<FluidRun>(config);
          }};
}

} // namespace ibvalve::app
