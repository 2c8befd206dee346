// `model = "fluid"`: the Navier–Stokes solver alone (fluid/, docs/fluid.md) on a box whose six sides
// are periodic, walls, prescribed velocity (uniform or parabolic) or prescribed pressure (over the
// whole side or a disk of it, zero elsewhere). Writes timeseries.csv (t, norms, fluxes through the
// sides, the centre pressure; errors against the exact solution for the Taylor–Green and ABC
// initial conditions) and fields/*.h5 + fields_fluid.xdmf (velocity, vorticity, pressure).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <optional>

#include <mpi.h>

#include <fmt/format.h>

#include "app/fftw_plans.hpp"
#include "app/fluid_box.hpp"
#include "app/model.hpp"
#include "app/output_keys.hpp"
#include "app/resource_estimate.hpp"
#include "app/step_diagnostics.hpp"
#include "app/step_schedule.hpp"
#include "app/time_loop.hpp"
#include "base/errors.hpp"
#include "base/logger.hpp"
#include "fluid/exact_vortex.hpp"
#include "fluid/navier_stokes.hpp"
#include "fluid/output.hpp"
#include "fluid/queries.hpp"
#include "io/checkpoint.hpp"
#include "io/collective.hpp"
#include "io/files.hpp"

namespace ibvalve::app {

namespace {

using fluid::Real3;

/// One side's boundary.<side>.* keys.
struct SideKeys {
  enum class Type { periodic, wall, velocity, pressure } type = Type::periodic;
  std::vector<double> velocity;
  bool parabolic = false;
  double pressure = 0, disk_radius = 0, ramp = 0;
  std::vector<double> disk_center; // empty: the side's centre
};

enum class SolverChoice { automatic, fft, krylov };

/// The model's own keys and where they go (io/key_binder.hpp); checkpoints are io/'s section, the output
/// keys the time loop's (app/output_keys.hpp).
struct FluidKeys {
  fluid::FluidSettings fluid;
  std::vector<std::int64_t> cells;
  std::vector<double> lower, upper;
  SolverChoice solver = SolverChoice::automatic;
  std::array<SideKeys, 6> sides;
  std::string initial = "rest";
  double amplitude = 1.0;
  std::vector<double> mean_velocity;
  double end = 0, step = 0;
  std::optional<double> fields_interval;
  std::int64_t every = 1;
  io::CheckpointSettings checkpoints;
};

void bind_side(io::KeyBinder& keys, int side, SideKeys& b)
{
  const std::string p = "boundary." + fluid::side_name(side) + ".";
  using Type = SideKeys::Type;
  keys.choice(p + "type",
              "periodic, wall (no slip), velocity (prescribed), pressure (normal traction -p, no tangential "
              "flow)",
              b.type,
              {{"periodic", Type::periodic},
               {"wall", Type::wall},
               {"velocity", Type::velocity},
               {"pressure", Type::pressure}})
      .defaults(std::string("periodic"));
  keys.reals(p + "velocity", "velocity type: the velocity vector (the mean for a parabolic profile)",
             b.velocity)
      .unit("cm/s")
      .defaults(std::vector<double>{0, 0, 0})
      .size(3);
  keys.choice(p + "profile", "velocity type: uniform, or parabolic across the side (zero at its walls)",
              b.parabolic, {{"uniform", false}, {"parabolic", true}})
      .defaults(std::string("uniform"));
  keys.real(p + "pressure", "pressure type: boundary pressure p_b (n.sigma.n = -p_b)", b.pressure)
      .unit("mmHg")
      .defaults(0.0);
  keys.real(p + "disk_radius", "pressure type: apply the pressure inside this disk only (0: the whole side)",
            b.disk_radius)
      .unit("cm")
      .defaults(0.0)
      .non_negative();
  keys.reals(p + "disk_center", "pressure type: centre of the disk (default: the side's centre)",
             b.disk_center)
      .unit("cm")
      .size(3);
  keys.real(p + "ramp", "boundary data grow linearly from 0 over this time (0: at once)", b.ramp)
      .unit("s")
      .defaults(0.0)
      .non_negative();
}

void bind(io::KeyBinder& keys, FluidKeys& k)
{
  bind_fluid_density(keys, k.fluid.rho, "fluid density");
  bind_fluid_viscosity(keys, k.fluid.mu, 1.0);
  keys.integers("fluid.cells", "grid cells in x, y, z", k.cells)
      .required()
      .size(3)
      .at_most(max_grid_cells)
      .example(std::vector<std::int64_t>{16, 16, 16});
  keys.reals("fluid.lower", "lower corner of the box", k.lower)
      .unit("cm")
      .defaults(std::vector<double>{0, 0, 0})
      .size(3);
  keys.reals("fluid.upper", "upper corner of the box", k.upper)
      .unit("cm")
      .required()
      .size(3)
      .example(std::vector<double>{1.0, 1.0, 1.0});
  keys.choice(
          "fluid.solver", "Stokes solver: fft (periodic boxes), krylov (any sides), auto (fft when periodic)",
          k.solver,
          {{"auto", SolverChoice::automatic}, {"fft", SolverChoice::fft}, {"krylov", SolverChoice::krylov}})
      .defaults(std::string("auto"));
  keys.choice("fluid.subsolver",
              "krylov solver's preconditioner sub-solves: amg (hypre BoomerAMG V-cycles) or fft (FFTW "
              "sine/cosine transforms: exact pressure Poisson, Helmholtz preconditioner)",
              k.fluid.subsolver, {{"amg", fluid::SubsolverKind::amg}, {"fft", fluid::SubsolverKind::fft}})
      .defaults(std::string("fft"));
  keys.choice("fluid.convection", "convective scheme", k.fluid.convection,
              {{"limited_upwind", fluid::ConvectionScheme::limited_upwind},
               {"centered", fluid::ConvectionScheme::centered}})
      .defaults(std::string("limited_upwind"));
  keys.real("fluid.rtol", "relative tolerance of the Krylov (FGMRES) Stokes solve", k.fluid.rtol)
      .defaults(1e-10)
      .positive();
  keys.integer("fluid.max_iterations", "most FGMRES iterations per step", k.fluid.max_iterations)
      .defaults(std::int64_t{200})
      .at_least(1)
      .at_most(max_solver_iterations);
  for (int side = 0; side < 6; ++side) bind_side(keys, side, k.sides[side]);
  keys.string("initial.condition", "rest, taylor_green (x-y vortex, periodic x and y) or abc (periodic box)",
              k.initial)
      .defaults(std::string("rest"))
      .choices({"rest", "taylor_green", "abc"});
  keys.real("initial.amplitude", "velocity amplitude of the vortex", k.amplitude).unit("cm/s").defaults(1.0);
  keys.reals("initial.mean_velocity", "uniform velocity carrying the vortex", k.mean_velocity)
      .unit("cm/s")
      .defaults(std::vector<double>{0, 0, 0})
      .size(3);
  keys.real("time.end", "simulated time", k.end).unit("s").required().positive().example(0.01);
  keys.real("time.step", "time step", k.step).unit("s").required().positive().example(0.001);
  bind_fields_interval(keys, k.fields_interval, std::nullopt, "fields_fluid.xdmf");
  bind_row_every(keys, k.every, 1);
  io::bind(keys, k.checkpoints);
}

class FluidRun : public PreparedRun {
 public:
  explicit FluidRun(const io::Config& config) : config_(config), keys_(config_)
  {
    bind(keys_, k_);
    const FluidKeys& k = k_;
    box_ = fluid_box(keys_, k.cells, k.lower, k.upper);
    settings_ = k.fluid;
    using Type = SideKeys::Type;
    for (int d = 0; d < 3; ++d) {
      const SideKeys &lo = k.sides[fluid::side_index(d, 0)], &hi = k.sides[fluid::side_index(d, 1)];
      const bool lower_periodic = lo.type == Type::periodic, upper_periodic = hi.type == Type::periodic;
      if (lower_periodic != upper_periodic)
        keys_.fail(hi.type, "opposite sides must both be periodic or neither");
      box_.periodic[d] = lower_periodic;
    }
    for (int side = 0; side < 6; ++side) read_side(side);
    const bool all_periodic = box_.periodic[0] && box_.periodic[1] && box_.periodic[2];
    if (k.solver == SolverChoice::fft && !all_periodic) keys_.fail(k.solver, "fft needs every side periodic");
    settings_.solver =
        (k.solver == SolverChoice::fft || (k.solver == SolverChoice::automatic && all_periodic))
            ? fluid::SolverKind::fft
            : fluid::SolverKind::krylov;
    if (k.initial != "rest") {
      exact_.emplace();
      exact_->kind = k.initial == "taylor_green" ? fluid::ExactVortex::Kind::taylor_green
                                                 : fluid::ExactVortex::Kind::abc;
      exact_->amplitude = k.amplitude;
      exact_->nu = settings_.mu / settings_.rho;
      exact_->rho = settings_.rho;
      for (int d = 0; d < 3; ++d) {
        exact_->lower[d] = box_.lower[d];
        exact_->length[d] = box_.upper[d] - box_.lower[d];
        exact_->mean[d] = k.mean_velocity[d];
      }
      const bool tg = k.initial == "taylor_green";
      if (!box_.periodic[0] || !box_.periodic[1] || (!tg && !box_.periodic[2]))
        keys_.fail(k.initial, tg ? "taylor_green needs periodic x and y sides" : "abc needs a periodic box");
      if (std::abs(exact_->length[1] - exact_->length[0]) > 1e-12 * exact_->length[0] ||
          (!tg && std::abs(exact_->length[2] - exact_->length[0]) > 1e-12 * exact_->length[0]))
        keys_.fail(k.upper, k.initial + " needs equal box lengths in its periodic directions");
      if (tg && !box_.periodic[2] && exact_->mean[2] != 0.0)
        keys_.fail(k.mean_velocity, "must have no z part between z walls");
    }
    if (const std::string why = step_count_problem(k.end, k.step); !why.empty()) keys_.fail(k.step, why);
    k_.checkpoints.case_record = io::case_record(config);
    memory_line_ = check_memory(
        config, {{fluid_memory(grid_cells(box_), memory_kind(settings_), false, keys_.key_of(k.cells))}},
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
    if (!exact_)
      fluid->set_initial_condition([](const Real3&, double) { return Real3{0, 0, 0}; }, nullptr, 0.0);
    else
      fluid->set_initial_condition([this](const Real3& x, double t) { return exact_->velocity(x, t); },
                                   [this](const Real3& x, double t) { return exact_->pressure(x, t); }, 0.0);
    log.info(fmt::format("fluid: {} x {} x {} cells, solver {}, dt {:g} s", box_.cells[0], box_.cells[1],
                         box_.cells[2], fluid->solver().name(), k_.step));

    std::vector<int> flux_sides;
    const Real3 center{0.5 * (box_.lower[0] + box_.upper[0]), 0.5 * (box_.lower[1] + box_.upper[1]),
                       0.5 * (box_.lower[2] + box_.upper[2])};
    double last_divergence = 0.0;

    TimeLoop loop;
    loop.comm = context.comm;
    loop.steps = std::max(1L, std::lround(k_.end / k_.step));
    loop.end_time = static_cast<double>(loop.steps) * k_.step;
    loop.checkpoints = k_.checkpoints;
    set_columns(loop, flux_sides);
    loop.record_every = k_.every;
    loop.fields_every = fields_every_steps(k_.fields_interval, k_.step);
    loop.time = [&](std::int64_t) { return fluid->time(); };
    loop.advance = [&](std::int64_t) { advance(*fluid); };
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
      if (exact_) {
        const auto e = fluid::field_errors(
            *fluid, [this](const Real3& x, double t) { return exact_->velocity(x, t); },
            [this](const Real3& x, double t) { return exact_->pressure(x, t); }, bc_.any_traction() == false);
        row.push_back(e.velocity_max);
        row.push_back(e.pressure_max);
      }
      return row;
    };
    loop.write_fields = [&](FieldSeries& series, std::int64_t step) {
      const std::string name = fmt::format("fields/fluid_{:06}.h5", step);
      io::Hdf5File h5(context.comm, context.run_directory / name, io::Hdf5File::Mode::create);
      h5.write_attribute("time", fluid->time());
      h5.write_attribute("pressure_time", fluid->pressure_time());
      std::vector<io::XdmfGrid> grids = fluid->write_fields(h5, "fluid", name);
      h5.close(); // written, or a RunError on every rank (a full disk), before fields_fluid.xdmf names it
      series.at("fluid").add_step(fluid->time(), grids);
    };
    // The state of a continued run (docs/runs.md): the fluid's.
    loop.save = [&](io::Hdf5File& h5) { fluid->save(h5, "fluid"); };
    loop.restore = [&](const io::Hdf5File& h5) { fluid->restore(h5, "fluid"); };
    loop.before_save = [&] { save_fftw_plans(context); };
    loop.figures = [&] { return fluid_step_figures(*fluid, k_.step); };
    loop.finish = [&](RunSummary& summary, bool finished, std::size_t snapshots) {
      if (finished) summarize(summary, *fluid, last_divergence, snapshots);
    };
    return run_time_loop(context, loop);
  }

 private:
  /// A step of `fluid`; RunError when it fails, its velocity is not finite or its Courant number shows
  /// it diverging.
  void advance(fluid::NavierStokes& fluid) const
  {
    try {
      fluid.step(k_.step);
    } catch (const InputError&) {
      throw; // a warning --strict made an error (base/logger.hpp)
    } catch (const std::runtime_error& e) {
      throw RunError(e.what());
    }
    const double umax = fluid.max_velocity();
    if (!std::isfinite(umax))
      throw RunError(fmt::format("fluid: the velocity is not finite at t = {:g} s (time step too large?)",
                                 fluid.time()));
    // Explicit convection (AB2, upwind-biased) is stable for Courant numbers below about 1; far
    // above, the run is diverging: stop with the figure rather than run on to overflow.
    const double courant = umax * k_.step / fluid.finest_spacing();
    if (courant > 2.0) {
      const std::string text = fmt::format(
          "fluid: Courant number {:.2f} at t = {:.4g} s (max |u| {:.3g} cm/s): the run is unstable; "
          "use a {} below {:.3g} s",
          courant, fluid.time(), umax, keys_.key_of(k_.step), 0.5 * fluid.finest_spacing() / umax);
      throw RunError(text);
    }
  }

  /// The finished run's closing lines: its steps' timing and solver iterations, its last divergence.
  static void summarize(RunSummary& summary, const fluid::NavierStokes& fluid, double last_divergence,
                        std::size_t snapshots)
  {
    const fluid::StepStatistics& timing = fluid.statistics();
    const long taken = std::max<long>(1, static_cast<long>(timing.steps));
    const double n = static_cast<double>(taken);
    summary.lines.push_back(
        fmt::format("fluid: {} steps, {:.4f} s per step (convection {:.4f}, viscous {:.4f}, "
                    "pressure {:.4f}, halo {:.4f}), {:.1f} solver iterations per step",
                    taken, timing.total / n, timing.convection / n, timing.viscous / n, timing.pressure / n,
                    timing.halo / n, static_cast<double>(timing.solver_iterations) / n));
    summary.lines.push_back(fmt::format(
        "fluid: max |div u| {:.2e} at the end; {} field files, timeseries.csv", last_divergence, snapshots));
  }

  /// timeseries.csv's columns: the norms, the outflow through each side that is not periodic (those
  /// sides into `flux_sides`), the centre pressure and, for an exact vortex, the errors.
  void set_columns(TimeLoop& loop, std::vector<int>& flux_sides) const
  {
    loop.columns = {"t",         "step",           "max_velocity",     "kinetic_energy",
                    "enstrophy", "max_divergence", "solver_iterations"};
    // Kinetic energy 1/2 rho int |u|^2, enstrophy 1/2 int |omega|^2 (fluid/queries.hpp).
    loop.units = {"s", "1", "cm/s", "erg", "cm^3/s^2", "1/s", "1"};
    for (int side = 0; side < 6; ++side)
      if (!box_.periodic[side / 2]) {
        flux_sides.push_back(side);
        loop.columns.push_back("outflow_" + fluid::side_name(side));
        loop.units.push_back("mL/s");
      }
    loop.columns.push_back("p_center");
    loop.units.push_back("dyn/cm^2");
    if (exact_) {
      loop.columns.push_back("u_error_max");
      loop.columns.push_back("p_error_max");
      loop.units.insert(loop.units.end(), {"cm/s", "dyn/cm^2"});
    }
  }

  void read_side(int side)
  {
    const SideKeys& k = k_.sides[side];
    const int d = side / 2;
    fluid::BoundarySide& b = bc_.side(side);
    const double ramp = k.ramp;
    auto ramp_factor = [ramp](double t) { return ramp > 0.0 ? std::min(1.0, t / ramp) : 1.0; };
    using Type = SideKeys::Type;
    if (k.type == Type::periodic) {
      b.kind = fluid::SideKind::periodic;
    } else if (k.type == Type::wall) {
      b.kind = fluid::SideKind::velocity;
    } else if (k.type == Type::velocity) {
      b.kind = fluid::SideKind::velocity;
      const Real3 value{k.velocity[0], k.velocity[1], k.velocity[2]};
      const bool parabolic = k.parabolic;
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
      const double pressure = k.pressure;
      const double radius = k.disk_radius;
      Real3 c{0.5 * (box_.lower[0] + box_.upper[0]), 0.5 * (box_.lower[1] + box_.upper[1]),
              0.5 * (box_.lower[2] + box_.upper[2])};
      if (!k.disk_center.empty()) c = {k.disk_center[0], k.disk_center[1], k.disk_center[2]};
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
  io::KeyBinder keys_; // reads config_ into k_, and names a key in a message
  FluidKeys k_;
  fluid::BoxGeometry box_;
  fluid::BoundaryConditions bc_;
  fluid::FluidSettings settings_;
  std::optional<fluid::ExactVortex> exact_; // the initial condition's exact solution, if it has one
};

} // namespace

Model fluid_model()
{
  return {"fluid", "incompressible Navier-Stokes in a box (no structure): Taylor-Green, ABC, ducts, channels",
          add_bound_schema<FluidKeys>, [](const io::Config& config) -> std::unique_ptr<PreparedRun> {
            return std::make_unique<FluidRun>(config);
          }};
}

} // namespace ibvalve::app
