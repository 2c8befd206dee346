// `model = "lumped"`: the 0-D valve and the hemodynamic report, in about a second. The drivers are chosen
// as in the 3-D valve's case (drivers/keys.hpp): inlet.driver = "table" with outlet.driver = "windkessel",
// the LV pressure waveform pushing the Mynard-type valve into the three-element Windkessel (open loop);
// both "circulation", the closed-loop lumped circulation of circulation/ (elastance
// chambers, four valves, systemic and pulmonary compartments), its aortic valve the published diode or
// the same Mynard-type valve. Either explores parameters in seconds and exercises the metrics/report
// pipeline end to end before a 3-D run exists.
//
// The valve's equations and their Runge–Kutta 4 step (Mynard et al. 2012) are
// windkessel/lumped_valve.hpp, the closed loop's circulation/closed_loop.hpp; this file holds the
// case-file keys, the runs' time loops and their output.
#include <array>
#include <cmath>
#include <fmt/format.h>
#include <functional>
#include <numbers>
#include <optional>
#include <span>
#include <sstream>

#include <mpi.h>

#include "app/commands.hpp"
#include "app/model.hpp"
#include "app/output_keys.hpp"
#include "app/step_schedule.hpp"
#include "app/stop_signal.hpp"
#include "app/time_loop.hpp"
#include "base/errors.hpp"
#include "base/logger.hpp"
#include "base/units.hpp"
#include "circulation/cycle.hpp"
#include "circulation/keys.hpp"
#include "drivers/keys.hpp"
#include "hemodynamics/report.hpp"
#include "hemodynamics/timeseries.hpp"
#include "io/checkpoint.hpp"
#include "io/collective.hpp"
#include "io/files.hpp"
#include "windkessel/keys.hpp"
#include "windkessel/lumped_valve.hpp"

namespace ibvalve::app {

namespace {

using windkessel::LumpedSystem;
using windkessel::ValveParameters;

/// The LV pressure table's section (windkessel/keys.hpp), which inlet.driver = "table" needs.
constexpr const char* table_section = "lv_pressure";

/// The model's own keys and where they go (io/key_binder.hpp); the LV pressure table, the Windkessel and
/// checkpoints are their folders' sections, [circulation] is bound by circulation/, [report] by
/// hemodynamics/.
struct LumpedKeys {
  drivers::DriverSides sides; // the table and the Windkessel, or the closed loop on both sides
  circulation::CirculationKeys circulation;
  std::int64_t cycles = 4, every = 1;
  double step = 0, annulus_radius = 0;
  double opening_rate = 0, closing_rate = 0; // 1/(mmHg s) as written
  ValveParameters valve;                     // the rest of the valve, and the blood's density
  hemodynamics::ReportSettings report;
  windkessel::WaveformKeys lv_pressure;
  windkessel::WindkesselKeys windkessel;
  io::CheckpointSettings checkpoints;
};

void bind(io::KeyBinder& keys, LumpedKeys& k)
{
  drivers::bind(keys, k.sides);
  keys.retired("heart",
               "replaced by inlet.driver and outlet.driver, as in the 3-D valve's case: \"table\" and "
               "\"windkessel\" (the default), or both \"circulation\"");
  keys.integer("time.cycles", "cardiac cycles to run (the report analyses the last)", k.cycles)
      .defaults(std::int64_t{4})
      .at_least(1)
      .at_most(1000);
  keys.real("time.step", "time step (rounded so a cycle holds a whole number of steps)", k.step)
      .unit("s")
      .defaults(1.0e-4)
      .positive()
      .at_most(0.01);
  bind_row_every(keys, k.every, 1);
  windkessel::bind(keys, k.lv_pressure, table_section,
                   "LV pressure driving the valve, in mmHg (with the pressure table)", false);
  windkessel::bind(keys, k.windkessel, "windkessel");
  circulation::bind(keys, k.circulation);
  ValveParameters& v = k.valve;
  // The valve: the table's, and the closed loop's aortic valve when circulation.aortic_valve.model =
  // "orifice".
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
  io::bind(keys, k.checkpoints);
}

/// Whether the case's drivers are the closed loop, read as every key is (the runs read all the keys again).
bool closed_loop(const io::Config& config)
{
  LumpedKeys k;
  io::KeyBinder keys(config);
  bind(keys, k);
  return drivers::closed_loop(keys, k.sides);
}

/// What both runs share: the keys read (the valve in CGS), the cycle's steps, checkpoints, the report,
/// and the 0-D run itself on rank 0, the other ranks joining its agreements on a stop signal.
class LumpedRun : public PreparedRun {
 public:
  RunSummary run(const RunContext& context) final
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

 protected:
  explicit LumpedRun(const io::Config& config) : config_(config), keys_(config_)
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
    k_.checkpoints.case_record = io::case_record(config);
  }

  /// The cycle is `period` s (`source` says whose): report.period must match it, and a cycle holds a
  /// whole number of steps.
  void set_period(double period, const std::string& source)
  {
    period_ = period;
    const double report_period = k_.report.metrics.period;
    if (std::abs(report_period - period_) > 1e-9 * period_)
      keys_.fail(k_.report.metrics.period,
                 fmt::format("is {} s but {} is {} s", report_period, source, period_));
    if (const std::string why = step_count_problem(static_cast<double>(k_.cycles) * period_, k_.step);
        !why.empty())
      keys_.fail(k_.step, why);
    steps_per_cycle_ = std::max<long>(1, std::lround(period_ / k_.step));
  }
  double step() const { return period_ / static_cast<double>(steps_per_cycle_); }

  virtual RunSummary simulate(const RunContext& context) = 0;

  /// The loop's settings both runs share; the model fills in columns, advance, row, save and restore.
  TimeLoop loop_settings(const RunContext& context, std::function<void(RunSummary&)> extra_lines)
  {
    const double dt = step();
    TimeLoop loop;
    loop.comm = MPI_COMM_SELF; // rank 0 alone holds the state: its checkpoints, config.toml and series
    loop.steps = k_.cycles * steps_per_cycle_;
    loop.end_time = static_cast<double>(loop.steps) * dt;
    loop.checkpoints = k_.checkpoints;
    loop.record_every = k_.every;
    loop.record_also_every = steps_per_cycle_; // each cycle's report ends on its last step's row
    // A step is a microsecond: the progress line and the ranks' agreement on a stop signal (a
    // millisecond of this model) every 1000 steps.
    loop.progress_every = 1000;
    loop.stop_check_every = 1000;
    loop.time = [dt](std::int64_t n) { return static_cast<double>(n) * dt; };
    loop.stop_signal = [comm = context.comm] { return agree_on_stop(comm, false).signal; };
    loop.finish = [this, directory = context.run_directory, extra_lines](RunSummary& summary, bool finished,
                                                                         std::size_t) {
      if (!finished) return;
      write_report(directory, summary);
      extra_lines(summary);
    };
    return loop;
  }

  /// "lumped model: the state is not finite" when a step went wrong.
  void check_finite(std::span<const double> y, double t) const
  {
    for (const double v : y)
      if (!std::isfinite(v))
        throw RunError(fmt::format("lumped model: the state is not finite at t = {:g} s (try a smaller {})",
                                   t, keys_.key_of(k_.step)));
  }

  io::Config config_;
  io::KeyBinder keys_; // reads config_ into k_, and names a key in a message
  LumpedKeys k_;
  ValveParameters valve_; // in CGS
  double period_ = 0.8;
  long steps_per_cycle_ = 1;

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

  void write_report(const std::filesystem::path& directory, RunSummary& summary) const
  {
    hemodynamics::ReportOptions options;
    options.settings = k_.report.metrics;
    options.settings.density = k_.valve.density; // the EOA's density is the fluid's (g/cm^3 = g/mL)
    options.plots = k_.report.plots;
    options.cycle_plots = k_.report.cycle_plots;
    options.templates = k_.report.templates;
    const hemodynamics::ReportFiles files = hemodynamics::write_report(directory, options);
    summary.lines.push_back(hemodynamics::metrics_summary(files.json));
    summary.lines.push_back(fmt::format("report of cycle {} of {}: {} (each cycle's in {}/cycle_N/)",
                                        files.reported_cycle, files.cycles, files.html.string(),
                                        files.directory.string()));
  }
};

/// inlet.driver = "table", outlet.driver = "windkessel": the LV pressure table drives the valve into the
/// three-element Windkessel.
class TableRun : public LumpedRun {
 public:
  explicit TableRun(const io::Config& config) : LumpedRun(config), lv_pressure_(table()), outlet_(outlet())
  {
    set_period(lv_pressure_.period(), "the LV pressure table's period");
  }

 private:
  windkessel::PeriodicWaveform table() const
  {
    if (k_.lv_pressure.file.empty())
      keys_.fail(k_.lv_pressure.file, "missing: the pressure table drives the valve");
    return windkessel::load_waveform(k_.lv_pressure, units::mmHg);
  }

  windkessel::WindkesselParameters outlet() const
  {
    windkessel::check(keys_, k_.windkessel);
    return k_.windkessel.parameters;
  }

  RunSummary simulate(const RunContext& context) override
  {
    const double dt = step();
    LumpedSystem system{lv_pressure_, outlet_, valve_};
    LumpedSystem::State y{0.0, 0.0, outlet_.parameters().initial_pressure};
    base::Logger::global().info(
        fmt::format("lumped valve + Windkessel: {} cycle(s) of {:g} s, dt = {:g} s", k_.cycles, period_, dt));
    TimeLoop loop = loop_settings(context, [](RunSummary&) {});
    loop.columns = hemodynamics::standard_columns();
    loop.columns.push_back("valve_state");
    loop.units = hemodynamics::standard_units();
    loop.units.push_back("1");
    loop.advance = [&](std::int64_t n) {
      const double t = static_cast<double>(n - 1) * dt;
      y = system.step(t, y, dt);
      check_finite(y, t + dt);
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
    return run_time_loop(context, loop);
  }

  windkessel::PeriodicWaveform lv_pressure_;
  windkessel::ThreeElementWindkessel outlet_;
};

/// inlet.driver = outlet.driver = "circulation": the closed-loop circulation; the valve analysed is its
/// aortic valve, the "aortic" pressure its systemic arteries'.
class CirculationRun : public LumpedRun {
 public:
  explicit CirculationRun(const io::Config& config) : LumpedRun(config), loop_(parameters())
  {
    set_period(loop_.period(), "the circulation's heartbeat (60 s / " +
                                   keys_.key_of(k_.circulation.parameters.heart_rate) + ")");
  }

 private:
  circulation::CirculationParameters parameters() const
  {
    if (!k_.lv_pressure.file.empty())
      keys_.fail(k_.lv_pressure.file, "not used with " + keys_.key_of(k_.sides.inlet) +
                                          " = \"circulation\" (the loop computes the LV pressure)");
    circulation::check(keys_, k_.circulation);
    circulation::CirculationParameters p = k_.circulation.parameters;
    p.aortic_orifice = valve_;
    return p; // ClosedLoop checks it again (std::invalid_argument: a bug, not bad input)
  }

  bool orifice() const { return loop_.parameters().aortic_kind == circulation::AorticValveKind::orifice; }

  /// timeseries.csv: the report's columns (the orifice's area and state only for the orifice valve), then
  /// every chamber's volume and pressure, every compartment's pressure and flow, every valve's flow.
  void add_columns(TimeLoop& loop) const
  {
    loop.columns = hemodynamics::standard_columns();
    loop.units = hemodynamics::standard_units();
    if (orifice()) {
      loop.columns.push_back("valve_state");
      loop.units.push_back("1");
    } else { // no area (the standard columns end with orifice_area): the report reads closure from the flow
      loop.columns.pop_back();
      loop.units.pop_back();
    }
    for (const char* name : {"V_LA", "V_LV", "V_RA", "V_RV"}) {
      loop.columns.push_back(name);
      loop.units.push_back("mL");
    }
    for (const char* name : {"p_LA", "p_RA", "p_RV", "p_AR_SYS", "p_VEN_SYS", "p_AR_PUL", "p_VEN_PUL"}) {
      loop.columns.push_back(name);
      loop.units.push_back("mmHg");
    }
    for (const char* name :
         {"Q_MV", "Q_AV", "Q_TV", "Q_PV", "Q_AR_SYS", "Q_VEN_SYS", "Q_AR_PUL", "Q_VEN_PUL"}) {
      loop.columns.push_back(name);
      loop.units.push_back("mL/s");
    }
  }

  std::vector<double> row(double t) const
  {
    using namespace circulation;
    const circulation::Derived d = loop_.derived(t, y_);
    const double mmHg = units::mmHg, mL = units::mL;
    std::vector<double> r{t,
                          d.Q_AV / mL,
                          d.Q_AV / mL,
                          d.p_LV / mmHg,
                          y_[p_AR_SYS] / mmHg,
                          y_[p_AR_SYS] / mmHg,
                          d.p_LV / mmHg,
                          y_[p_AR_SYS] / mmHg};
    if (orifice()) {
      r.push_back(valve_.area(y_[zeta_AV]));
      r.push_back(y_[zeta_AV]);
    }
    for (const double v : {y_[V_LA], y_[V_LV], y_[V_RA], y_[V_RV]}) r.push_back(v / mL);
    for (const double p : {d.p_LA, d.p_RA, d.p_RV, y_[p_AR_SYS], y_[p_VEN_SYS], y_[p_AR_PUL], y_[p_VEN_PUL]})
      r.push_back(p / mmHg);
    for (const double q :
         {d.Q_MV, d.Q_AV, d.Q_TV, d.Q_PV, y_[Q_AR_SYS], y_[Q_VEN_SYS], y_[Q_AR_PUL], y_[Q_VEN_PUL]})
      r.push_back(q / mL);
    return r;
  }

  /// The last full beat's figures and the blood volume's drift, for the summary.
  void beat_lines(RunSummary& summary) const
  {
    if (!last_beat_) return;
    const circulation::CycleFigures& f = *last_beat_;
    summary.lines.push_back(fmt::format(
        "last beat: EDV {:.2f} mL, ESV {:.2f} mL, SV {:.2f} mL, EF {:.3f}, peak P_LV {:.1f} mmHg, "
        "P_AR_SYS {:.1f}/{:.1f} mmHg, periodicity {:.1e}",
        f.end_diastolic_volume / units::mL, f.end_systolic_volume / units::mL, f.stroke_volume / units::mL,
        f.ejection_fraction, f.lv_peak_pressure / units::mmHg, f.aortic_systolic / units::mmHg,
        f.aortic_diastolic / units::mmHg, f.periodicity_error));
    summary.lines.push_back(
        fmt::format("blood volume {:.3f} mL, changed by {:.1e} of it", loop_.total_volume(y_) / units::mL,
                    std::abs(loop_.total_volume(y_) - initial_volume_) / initial_volume_));
  }

  RunSummary simulate(const RunContext& context) override
  {
    const double dt = step();
    y_ = loop_.initial_state();
    initial_volume_ = loop_.total_volume(y_);
    base::Logger::global().info(
        fmt::format("closed-loop circulation ({} aortic valve): {} beat(s) of {:g} s, dt = {:g} s",
                    orifice() ? "orifice" : "diode", k_.cycles, period_, dt));
    TimeLoop loop = loop_settings(context, [this](RunSummary& summary) { beat_lines(summary); });
    add_columns(loop);
    std::optional<circulation::CycleRecorder> beat;
    loop.advance = [&](std::int64_t n) {
      const double t = static_cast<double>(n - 1) * dt;
      if ((n - 1) % steps_per_cycle_ == 0) beat.emplace(loop_, t, y_);
      loop_.step(t, y_, dt);
      check_finite(y_, t + dt);
      if (beat) beat->add(t + dt, y_);
      if (beat && n % steps_per_cycle_ == 0) last_beat_ = beat->figures();
    };
    loop.row = [&](std::int64_t n) { return row(static_cast<double>(n) * dt); };
    // The state by name: circulation/<entry> for each entry of ClosedLoop::state_names(), and the blood
    // volume it started with.
    loop.save = [&](io::Hdf5File& h5) {
      const std::array<hsize_t, 1> one{1};
      for (std::size_t i = 0; i < y_.size(); ++i)
        h5.write_root("circulation/" + loop_.state_names()[i], std::span<const double>(&y_[i], 1), one);
      h5.write_root("circulation/initial_volume", std::span<const double>(&initial_volume_, 1), one);
    };
    loop.restore = [&](const io::Hdf5File& h5) {
      auto read = [&](const std::string& name) {
        const std::string path = "circulation/" + name;
        if (!h5.has(path))
          throw InputError(h5.path().string() + ": " + path +
                           " is missing (a checkpoint of the pressure-table run?)");
        const std::vector<double> value = h5.read(path);
        if (value.size() != 1) throw InputError(h5.path().string() + ": " + path + " is not one number");
        return value[0];
      };
      for (std::size_t i = 0; i < y_.size(); ++i) y_[i] = read(loop_.state_names()[i]);
      initial_volume_ = read("initial_volume");
      beat.reset(); // a beat's figures need the whole beat: the next one starts them again
    };
    return run_time_loop(context, loop);
  }

  circulation::ClosedLoop loop_;
  circulation::ClosedLoop::State y_;
  double initial_volume_ = 0.0;
  std::optional<circulation::CycleFigures> last_beat_;
};

} // namespace

Model lumped_model()
{
  return Model{"lumped",
               "0-D valve (Mynard et al. 2012) between the LV pressure table and a three-element Windkessel, "
               "or inside the closed-loop circulation of circulation/; writes timeseries.csv and the "
               "report in seconds",
               add_bound_schema<LumpedKeys>, [](const io::Config& config) -> std::unique_ptr<PreparedRun> {
                 if (closed_loop(config)) return std::make_unique<CirculationRun>(config);
                 return std::make_unique<TableRun>(config);
               }};
}

} // namespace ibvalve::app
