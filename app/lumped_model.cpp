// `model = "lumped"`: a pressure-driven valve between the LV pressure waveform and the three-element
// Windkessel, in 0-D, then the hemodynamic report. It explores outlet and valve parameters in about
// a second and exercises the metrics/report pipeline end to end before a 3-D run exists.
//
// The valve's equations and their Runge–Kutta 4 step (Mynard et al. 2012) are
// windkessel/lumped_valve.hpp; this file holds the case-file keys, the run's time loop and its output.
#include <array>
#include <cmath>
#include <fmt/format.h>
#include <functional>
#include <numbers>
#include <sstream>

#include <mpi.h>

#include "app/commands.hpp"
#include "app/model.hpp"
#include "app/step_schedule.hpp"
#include "app/stop_signal.hpp"
#include "app/time_loop.hpp"
#include "base/errors.hpp"
#include "base/logger.hpp"
#include "base/units.hpp"
#include "hemodynamics/report.hpp"
#include "hemodynamics/timeseries.hpp"
#include "io/checkpoint.hpp"
#include "io/collective.hpp"
#include "io/files.hpp"
#include "windkessel/lumped_valve.hpp"
#include "windkessel/waveform.hpp"
#include "windkessel/windkessel.hpp"

namespace ibvalve::app {

namespace {

using windkessel::LumpedSystem;
using windkessel::ValveParameters;

/// The model's own keys and where they go (io/key_binder.hpp); the LV pressure table, the Windkessel and
/// checkpoints are their folders' sections, [report] is bound by hemodynamics/.
struct LumpedKeys {
  std::int64_t cycles = 4, every = 1;
  double step = 0, annulus_radius = 0;
  double opening_rate = 0, closing_rate = 0; // 1/(mmHg s) as written
  ValveParameters valve;                     // the rest of the valve, and the blood's density
  hemodynamics::ReportSettings report;
};

void bind(io::KeyBinder& keys, LumpedKeys& k)
{
  keys.integer("time.cycles", "cardiac cycles to run (the report analyses the last)", k.cycles)
      .defaults(std::int64_t{4})
      .at_least(1)
      .at_most(1000);
  keys.real("time.step", "time step (rounded so a cycle holds a whole number of steps)", k.step)
      .unit("s")
      .defaults(1.0e-4)
      .positive()
      .at_most(0.01);
  keys.integer("output.every", "write a time-series row every this many steps", k.every)
      .defaults(std::int64_t{1})
      .at_least(1);
  keys.section([](io::Schema& s) {
    windkessel::add_waveform_schema(s, "lv_pressure", "LV pressure driving the valve, in mmHg");
    windkessel::add_schema(s, "windkessel");
  });
  ValveParameters& v = k.valve;
  keys.real("valve.annulus_radius", "radius of the annulus (A_ann = pi r^2)", k.annulus_radius)
      .unit("cm")
      .defaults(1.3)
      .positive()
      .typical(0.5, 3.0, "an aortic annulus is about 1.2 cm; 10 times more is a value in mm");
  keys.real("valve.max_area_fraction", "M_st: largest effective area / A_ann", v.max_area_fraction)
      .defaults(0.6)
      .above(0.0)
      .at_most(1.0);
  keys.real("valve.min_area_fraction", "M_rg: effective area when closed / A_ann (leakage)",
            v.min_area_fraction)
      .defaults(0.002)
      .above(0.0)
      .below(1.0);
  keys.real("valve.effective_length", "l_eff: length of the inertance L = rho l_eff / A", v.effective_length)
      .unit("cm")
      .defaults(1.0)
      .positive();
  keys.real("valve.opening_rate", "K_vo in 1/(mmHg s): dzeta/dt = (1 - zeta) K_vo (dp - dp_open)",
            k.opening_rate)
      .defaults(16.0)
      .positive();
  keys.real("valve.closing_rate", "K_vc in 1/(mmHg s): dzeta/dt = zeta K_vc (dp - dp_close)", k.closing_rate)
      .defaults(16.0)
      .positive();
  keys.real("valve.opening_pressure", "dp_open: pressure difference above which the valve opens",
            v.opening_pressure)
      .unit("mmHg")
      .defaults(0.0);
  keys.real("valve.closing_pressure", "dp_close: pressure difference below which the valve closes",
            v.closing_pressure)
      .unit("mmHg")
      .defaults(0.0);
  bind_fluid_density(keys, v.density, "blood density");
  hemodynamics::bind_report(keys, k.report);
  keys.section([](io::Schema& s) { io::add_checkpoint_schema(s); });
}

class LumpedRun : public PreparedRun {
 public:
  explicit LumpedRun(const io::Config& config)
      : config_(config), keys_(config_),
        lv_pressure_(windkessel::waveform_from_config(config, "lv_pressure", units::mmHg)),
        outlet_(windkessel::parameters_from_config(config, "windkessel"))
  {
    bind(keys_, k_);
    const LumpedKeys& k = k_;
    hemodynamics::check_report_templates(keys_, k.report);
    valve_ = k.valve;
    valve_.annulus_area = std::numbers::pi * k.annulus_radius * k.annulus_radius;
    if (valve_.min_area_fraction >= valve_.max_area_fraction)
      keys_.fail(k.valve.min_area_fraction, "must be below " + keys_.key_of(k.valve.max_area_fraction));
    valve_.opening_rate = k.opening_rate / units::mmHg;
    valve_.closing_rate = k.closing_rate / units::mmHg;
    if (valve_.closing_pressure > valve_.opening_pressure)
      keys_.fail(k.valve.closing_pressure, "must not exceed " + keys_.key_of(k.valve.opening_pressure));
    period_ = lv_pressure_.period();
    const double report_period = k.report.metrics.period;
    if (std::abs(report_period - period_) > 1e-9 * period_)
      keys_.fail(k.report.metrics.period,
                 fmt::format("is {} s but the LV pressure table's period is {} s", report_period, period_));
    if (const std::string why = step_count_problem(static_cast<double>(k.cycles) * period_, k.step);
        !why.empty())
      keys_.fail(k.step, why);
    steps_per_cycle_ = std::max<long>(1, std::lround(period_ / k.step));
    checkpoint_settings_ = io::checkpoint_settings_from_config(config);
  }

  RunSummary run(const RunContext& context) override
  {
    int rank = 0;
    MPI_Comm_rank(context.comm, &rank);
    // A 0-D model: rank 0 computes and writes. The others take part in its agreements on a stop signal
    // (agree_on_stop; a signal may reach any rank) until it is done, then share its outcome: its
    // error, if any (every rank throws it), and its exit code.
    RunSummary summary;
    std::exception_ptr error;
    if (rank == 0) {
      try {
        summary = simulate(context);
      } catch (...) {
        error = std::current_exception();
      }
      agree_on_stop(context.comm, true);
    } else {
      while (!agree_on_stop(context.comm, false).done) {
      }
    }
    io::rethrow_on_every_rank(context.comm, error);
    MPI_Bcast(&summary.exit_code, 1, MPI_INT, 0, context.comm);
    return summary;
  }

 private:
  struct Agreement {
    bool done = false; // rank 0 has finished (or failed)
    int signal = 0;    // the stop signal any rank noted
  };
  /// Collective over `comm`: rank 0 says whether it is done, every rank which signal it noted.
  static Agreement agree_on_stop(MPI_Comm comm, bool done)
  {
    int mine[2] = {done ? 1 : 0, noted_stop_signal()}, all[2] = {0, 0};
    MPI_Allreduce(mine, all, 2, MPI_INT, MPI_MAX, comm);
    return {all[0] != 0, all[1]};
  }

  RunSummary simulate(const RunContext& context)
  {
    const std::filesystem::path& directory = context.run_directory;
    auto& log = base::Logger::global();
    const double dt = period_ / static_cast<double>(steps_per_cycle_);
    LumpedSystem system{lv_pressure_, outlet_, valve_};
    LumpedSystem::State y{0.0, 0.0, outlet_.parameters().initial_pressure};
    log.info(
        fmt::format("lumped valve + Windkessel: {} cycle(s) of {:g} s, dt = {:g} s", k_.cycles, period_, dt));
    TimeLoop loop;
    loop.comm = MPI_COMM_SELF; // rank 0 alone holds the state: its checkpoints, config.toml and series
    loop.steps = k_.cycles * steps_per_cycle_;
    loop.end_time = static_cast<double>(loop.steps) * dt;
    loop.checkpoints = checkpoint_settings_;
    loop.columns = hemodynamics::standard_columns();
    loop.columns.push_back("valve_state");
    loop.units = hemodynamics::standard_units();
    loop.units.push_back("1");
    loop.record_every = k_.every;
    loop.record_also_every = steps_per_cycle_; // each cycle's report ends on its last step's row
    // A step is a microsecond: the progress line and the ranks' agreement on a stop signal (a
    // millisecond of this model) every 1000 steps.
    loop.progress_every = 1000;
    loop.stop_check_every = 1000;
    loop.time = [&](std::int64_t n) { return static_cast<double>(n) * dt; };
    loop.advance = [&](std::int64_t n) {
      const double t = static_cast<double>(n - 1) * dt;
      y = system.step(t, y, dt);
      if (!std::isfinite(y[0]) || !std::isfinite(y[2]))
        throw RunError(fmt::format("lumped model: the state is not finite at t = {:g} s (try a smaller {})",
                                   t + dt, keys_.key_of(k_.step)));
    };
    loop.row = [&](std::int64_t n) {
      const double t = static_cast<double>(n) * dt;
      const double p_lv = lv_pressure_(t), p_ao = system.aortic_pressure(y);
      const double q = y[0];
      return std::vector<double>{t,
                                 q / units::mL,
                                 q / units::mL,
                                 p_lv / units::mmHg,
                                 p_ao / units::mmHg,
                                 y[2] / units::mmHg,
                                 p_lv / units::mmHg,
                                 p_ao / units::mmHg,
                                 valve_.area(y[1]),
                                 y[1]};
    };
    loop.save = [&](io::Hdf5File& h5) { h5.write_root("lumped/state", y, std::array<hsize_t, 1>{y.size()}); };
    loop.restore = [&](const io::Hdf5File& h5) {
      const std::vector<double> saved = h5.read("lumped/state");
      if (saved.size() != y.size())
        throw InputError(h5.path().string() + ": lumped/state has the wrong size");
      std::copy(saved.begin(), saved.end(), y.begin());
    };
    loop.stop_signal = [&] { return agree_on_stop(context.comm, false).signal; };
    loop.finish = [&](RunSummary& summary, bool finished, std::size_t) {
      if (finished) write_report(directory, summary);
    };
    return run_time_loop(context, loop);
  }

  void write_report(const std::filesystem::path& directory, RunSummary& summary) const
  {
    hemodynamics::ReportOptions options;
    options.settings = k_.report.metrics;
    options.settings.density = k_.valve.density; // the EOA's density is the fluid's (g/cm^3 = g/mL)
    options.plots = k_.report.plots;
    options.templates = k_.report.templates;
    const hemodynamics::ReportFiles files = hemodynamics::write_report(directory, options);
    const auto doc = hemodynamics::Json::parse(io::read_text_file(files.json));
    const auto& m = doc.at("metrics");
    auto show = [&](const char* key) {
      if (!m.contains(key)) return std::string("missing ");
      const auto& entry = m.at(key);
      const auto& v = entry.at("value");
      return (v.is_number() ? hemodynamics::format_value(v.get<double>()) : std::string("missing")) + " " +
             entry.at("unit").get<std::string>();
    };
    summary.lines.push_back("V_F " + show("forward_volume") + ", RF " + show("regurgitant_fraction") +
                            ", TPG " + show("transvalvular_pressure_gradient") + ", EOA " +
                            show("effective_orifice_area") + ", E_L " + show("energy_loss"));
    summary.lines.push_back("report: " + files.html.string());
  }

  io::Config config_;
  io::KeyBinder keys_; // reads config_ into k_, and names a key in a message
  LumpedKeys k_;
  windkessel::PeriodicWaveform lv_pressure_;
  windkessel::ThreeElementWindkessel outlet_;
  ValveParameters valve_; // in CGS
  double period_ = 0.8;
  long steps_per_cycle_ = 1;
  io::CheckpointSettings checkpoint_settings_;
};

} // namespace

Model lumped_model()
{
  return Model{"lumped",
               "0-D valve (Mynard et al. 2012) between the LV pressure table and a three-element Windkessel; "
               "writes timeseries.csv and the report in about a second",
               add_bound_schema<LumpedKeys>, [](const io::Config& config) -> std::unique_ptr<PreparedRun> {
                 return std::make_unique<LumpedRun>(config);
               }};
}

} // namespace ibvalve::app
