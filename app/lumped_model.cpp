// `model = "lumped"`: a pressure-driven valve between the LV pressure waveform and the three-element
// Windkessel, in 0-D, then the hemodynamic report. It explores outlet and valve parameters in about
// a second and exercises the metrics/report pipeline end to end before a 3-D run exists.
//
// Valve (Mynard, Davidson, Penny & Smolich 2012, Int J Numer Meth Biomed Eng 28:626): a state
// zeta in [0, 1] sets the effective orifice area A = (A_max - A_min) zeta + A_min, with
// A_max = M_st A_ann, A_min = M_rg A_ann; the flow obeys Bernoulli with inertance,
//   dp = B Q|Q| + L dQ/dt,  B = rho / (2 A^2),  L = rho l_eff / A,  dp = P_LV - P_Ao,
// and zeta opens or closes at rates proportional to the pressure difference,
//   dzeta/dt = (1 - zeta) K_vo (dp - dp_open)   when dp > dp_open,
//   dzeta/dt = zeta K_vc (dp - dp_close)         when dp < dp_close.
// Outlet: C dP_Wk/dt = Q - (P_Wk - P_d)/R_p, P_Ao = P_Wk + R_c Q (windkessel/windkessel.hpp). The
// three states (Q, zeta, P_Wk) advance together by classical Runge–Kutta 4 with a fixed step.
#include <array>
#include <cmath>
#include <functional>
#include <numbers>
#include <sstream>

#include <mpi.h>

#include "app/commands.hpp"
#include "app/model.hpp"
#include "app/restart.hpp"
#include "app/stop_signal.hpp"
#include "app/version.hpp"
#include "hemodynamics/report.hpp"
#include "hemodynamics/timeseries.hpp"
#include "io/checkpoint.hpp"
#include "io/collective.hpp"
#include "io/errors.hpp"
#include "io/files.hpp"
#include "io/logger.hpp"
#include "io/units.hpp"
#include "windkessel/waveform.hpp"
#include "windkessel/windkessel.hpp"

namespace ibvalve::app {

namespace {

struct ValveParameters {
  double annulus_area = 0.0;    // cm^2
  double max_area_fraction = 0; // M_st
  double min_area_fraction = 0; // M_rg
  double effective_length = 0;  // cm
  double opening_rate = 0;      // K_vo, 1/(dyn/cm^2 s)
  double closing_rate = 0;      // K_vc
  double opening_pressure = 0;  // dyn/cm^2
  double closing_pressure = 0;
  double density = 0; // g/cm^3

  double area(double zeta) const
  {
    return annulus_area * ((max_area_fraction - min_area_fraction) * zeta + min_area_fraction);
  }
};

/// The lumped system's state and right-hand side.
struct LumpedSystem {
  using State = std::array<double, 3>; // Q (cm^3/s), zeta, P_Wk (dyn/cm^2)
  const windkessel::PeriodicWaveform& lv_pressure;
  const windkessel::ThreeElementWindkessel& outlet; // for its parameters and right-hand side
  ValveParameters valve;

  double aortic_pressure(const State& y) const
  {
    return y[2] + outlet.parameters().proximal_resistance * y[0];
  }

  State rate(double t, const State& y) const
  {
    const double q = y[0], zeta = std::clamp(y[1], 0.0, 1.0);
    const double dp = lv_pressure(t) - aortic_pressure(y);
    const double area = valve.area(zeta);
    const double bernoulli = valve.density / (2.0 * area * area);
    const double inertance = valve.density * valve.effective_length / area;
    double dzeta = 0.0;
    if (dp > valve.opening_pressure)
      dzeta = (1.0 - zeta) * valve.opening_rate * (dp - valve.opening_pressure);
    else if (dp < valve.closing_pressure)
      dzeta = zeta * valve.closing_rate * (dp - valve.closing_pressure);
    return {(dp - bernoulli * q * std::abs(q)) / inertance, dzeta, outlet.reservoir_rate(y[2], q)};
  }

  State step(double t, const State& y, double dt) const
  {
    auto axpy = [](const State& a, double s, const State& b) {
      return State{a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]};
    };
    const State k1 = rate(t, y);
    const State k2 = rate(t + 0.5 * dt, axpy(y, 0.5 * dt, k1));
    const State k3 = rate(t + 0.5 * dt, axpy(y, 0.5 * dt, k2));
    const State k4 = rate(t + dt, axpy(y, dt, k3));
    State next;
    for (std::size_t i = 0; i < 3; ++i)
      next[i] = y[i] + dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
    next[1] = std::clamp(next[1], 0.0, 1.0);
    return next;
  }
};

void add_lumped_schema(io::Schema& s)
{
  s.add_integer("time.cycles", "cardiac cycles to run (the report analyses the last)")
      .defaults(std::int64_t{4})
      .at_least(1)
      .at_most(1000);
  s.add_real("time.step", "time step (rounded so a cycle holds a whole number of steps)")
      .unit("s")
      .defaults(1.0e-4)
      .positive()
      .at_most(0.01);
  s.add_integer("output.every", "write a time-series row every this many steps")
      .defaults(std::int64_t{1})
      .at_least(1);
  windkessel::add_waveform_schema(s, "lv_pressure", "LV pressure driving the valve, in mmHg");
  windkessel::add_schema(s, "windkessel");
  s.add_real("valve.annulus_radius", "radius of the annulus (A_ann = pi r^2)")
      .unit("cm")
      .defaults(1.3)
      .positive()
      .typical(0.5, 3.0, "an aortic annulus is about 1.2 cm; 10 times more is a value in mm");
  s.add_real("valve.max_area_fraction", "M_st: largest effective area / A_ann")
      .defaults(0.6)
      .above(0.0)
      .at_most(1.0);
  s.add_real("valve.min_area_fraction", "M_rg: effective area when closed / A_ann (leakage)")
      .defaults(0.002)
      .above(0.0)
      .below(1.0);
  s.add_real("valve.effective_length", "l_eff: length of the inertance L = rho l_eff / A")
      .unit("cm")
      .defaults(1.0)
      .positive();
  s.add_real("valve.opening_rate", "K_vo in 1/(mmHg s): dzeta/dt = (1 - zeta) K_vo (dp - dp_open)")
      .defaults(16.0)
      .positive();
  s.add_real("valve.closing_rate", "K_vc in 1/(mmHg s): dzeta/dt = zeta K_vc (dp - dp_close)")
      .defaults(16.0)
      .positive();
  s.add_real("valve.opening_pressure", "dp_open: pressure difference above which the valve opens")
      .unit("mmHg")
      .defaults(0.0);
  s.add_real("valve.closing_pressure", "dp_close: pressure difference below which the valve closes")
      .unit("mmHg")
      .defaults(0.0);
  add_fluid_density_key(s, "blood density");
  hemodynamics::add_report_schema(s, "report");
  io::add_checkpoint_schema(s);
}

class LumpedRun : public PreparedRun {
 public:
  explicit LumpedRun(const io::Config& config)
      : lv_pressure_(windkessel::waveform_from_config(config, "lv_pressure", units::mmHg)),
        outlet_(windkessel::parameters_from_config(config, "windkessel")),
        settings_(hemodynamics::metric_settings_from_config(config, "report")),
        templates_(hemodynamics::report_templates_from_config(config, "report"))
  {
    const double radius = config.real("valve.annulus_radius");
    valve_.annulus_area = std::numbers::pi * radius * radius;
    valve_.max_area_fraction = config.real("valve.max_area_fraction");
    valve_.min_area_fraction = config.real("valve.min_area_fraction");
    if (valve_.min_area_fraction >= valve_.max_area_fraction)
      config.fail("valve.min_area_fraction", "must be below valve.max_area_fraction");
    valve_.effective_length = config.real("valve.effective_length");
    valve_.opening_rate = config.real("valve.opening_rate") / units::mmHg;
    valve_.closing_rate = config.real("valve.closing_rate") / units::mmHg;
    valve_.opening_pressure = config.real("valve.opening_pressure");
    valve_.closing_pressure = config.real("valve.closing_pressure");
    if (valve_.closing_pressure > valve_.opening_pressure)
      config.fail("valve.closing_pressure", "must not exceed valve.opening_pressure");
    valve_.density = config.real("fluid.density");
    period_ = lv_pressure_.period();
    if (std::abs(settings_.period - period_) > 1e-9 * period_)
      config.fail("report.period", "is " + std::to_string(settings_.period) +
                                       " s but the LV pressure table's period is " + std::to_string(period_) +
                                       " s");
    cycles_ = config.integer("time.cycles");
    steps_per_cycle_ = std::max<long>(1, std::lround(period_ / config.real("time.step")));
    every_ = config.integer("output.every");
    plots_ = config.boolean("report.plots");
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
    auto& log = io::Logger::global();
    const double dt = period_ / static_cast<double>(steps_per_cycle_);
    const long steps = cycles_ * steps_per_cycle_;
    const double end_time = static_cast<double>(cycles_) * period_;
    std::vector<std::string> columns = hemodynamics::standard_columns();
    columns.push_back("valve_state");
    std::vector<std::string> column_units = hemodynamics::standard_units();
    column_units.push_back("1");
    LumpedSystem system{lv_pressure_, outlet_, valve_};
    LumpedSystem::State y{0.0, 0.0, outlet_.parameters().initial_pressure};
    // Rank 0 alone holds the state, so the checkpoints are its own (MPI_COMM_SELF).
    const io::Checkpoints checkpoints(MPI_COMM_SELF, directory, checkpoint_settings_);
    long first_step = 0;
    std::int64_t rows = 0;
    if (context.restart) {
      RunContext own = context; // rank 0 alone: its checkpoints, config.toml and series
      own.comm = MPI_COMM_SELF;
      const io::CheckpointHeader header =
          restart_from_latest(checkpoints, own, steps, [&](const io::Hdf5File& h5) {
            const std::vector<double> saved = h5.read("lumped/state");
            if (saved.size() != y.size())
              throw InputError(h5.path().string() + ": lumped/state has the wrong size");
            std::copy(saved.begin(), saved.end(), y.begin());
          });
      first_step = static_cast<long>(header.step);
      rows = header.timeseries_rows;
    }
    io::CsvWriter csv(directory / "timeseries.csv", columns, context.restart, column_units);
    auto save = [&](long step) {
      const std::array<hsize_t, 1> dims{y.size()};
      return checkpoints.write({step, static_cast<double>(step) * dt, rows},
                               [&](io::Hdf5File& h5) { h5.write_root("lumped/state", y, dims); });
    };
    auto write = [&](double t) {
      ++rows;
      const double p_lv = lv_pressure_(t), p_ao = system.aortic_pressure(y);
      const double q = y[0];
      csv.write_row({t, q / units::mL, q / units::mL, p_lv / units::mmHg, p_ao / units::mmHg,
                     y[2] / units::mmHg, p_lv / units::mmHg, p_ao / units::mmHg, valve_.area(y[1]), y[1]});
    };
    log.info("lumped valve + Windkessel: " + std::to_string(cycles_) + " cycle(s) of " +
             std::to_string(period_) + " s, dt = " + std::to_string(dt) + " s");
    if (!context.restart) write(0.0);
    long last_step = static_cast<long>(last_step_of_invocation(context, first_step, steps));
    int stop_signal = 0;
    std::filesystem::path saved; // the checkpoint of the step just taken, if it wrote one
    log.begin_steps(first_step, last_step);
    for (long n = first_step; n < last_step; ++n) {
      const double t = static_cast<double>(n) * dt;
      y = system.step(t, y, dt);
      if (!std::isfinite(y[0]) || !std::isfinite(y[2]))
        throw RunError("lumped model: the state is not finite at t = " + std::to_string(t + dt) +
                       " s (try a smaller time.step)");
      if ((n + 1) % every_ == 0 || n + 1 == steps) write(static_cast<double>(n + 1) * dt);
      if ((n + 1) % 1000 == 0) log.progress({n + 1, steps, static_cast<double>(n + 1) * dt, end_time, ""});
      saved.clear();
      if (checkpoints.due(n + 1, steps)) saved = save(n + 1);
      // SIGINT/SIGTERM (app/stop_signal.hpp), agreed with the other ranks every 1000 steps (a
      // millisecond of this model): the run stops after this step.
      if ((n + 1) % 1000 == 0 && n + 1 < steps &&
          (stop_signal = agree_on_stop(context.comm, false).signal) != 0) {
        last_step = n + 1;
        break;
      }
    }
    log.finish_progress();

    RunSummary summary;
    if (last_step < steps) {
      add_stop(summary, last_step, steps, saved.empty() ? save(last_step) : saved, directory, stop_signal);
      return summary;
    }
    hemodynamics::ReportOptions options;
    options.settings = settings_;
    options.python = python_executable;
    options.plots = plots_;
    options.templates = templates_;
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
    return summary;
  }

  windkessel::PeriodicWaveform lv_pressure_;
  windkessel::ThreeElementWindkessel outlet_;
  hemodynamics::MetricSettings settings_;
  std::filesystem::path templates_;
  ValveParameters valve_;
  double period_ = 0.8;
  long cycles_ = 1, steps_per_cycle_ = 1, every_ = 1;
  bool plots_ = true;
  io::CheckpointSettings checkpoint_settings_;
};

} // namespace

Model lumped_model()
{
  return Model{"lumped",
               "0-D valve (Mynard et al. 2012) between the LV pressure table and a three-element Windkessel; "
               "writes timeseries.csv and the report in about a second",
               add_lumped_schema, [](const io::Config& config) -> std::unique_ptr<PreparedRun> {
                 return std::make_unique<LumpedRun>(config);
               }};
}

} // namespace ibvalve::app
