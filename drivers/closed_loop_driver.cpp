#include "drivers/closed_loop_driver.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "base/units.hpp"

namespace ibvalve::drivers {

using namespace circulation;

ClosedLoopCoupling::ClosedLoopCoupling(const CirculationParameters& parameters, int start_beats,
                                       long steps_per_beat)
    : loop_(parameters), y_(loop_.initial_state()), start_beats_(start_beats)
{
  if (parameters.aortic_kind != AorticValveKind::diode)
    throw std::invalid_argument("closed-loop driver: the loop's own aortic valve must be the diode");
  const double dt = loop_.period() / static_cast<double>(steps_per_beat);
  const long steps = static_cast<long>(start_beats) * steps_per_beat;
  // Each beat starts at a multiple of the period; the run's t = 0 is a beat's start.
  for (long n = 0; n < steps; ++n) loop_.step(static_cast<double>(n % steps_per_beat) * dt, y_, dt);
}

double ClosedLoopCoupling::ventricle_pressure(double t) const
{
  return loop_.parameters().left_ventricle.pressure(t, loop_.period(), y_[V_LV]);
}

void ClosedLoopCoupling::give_flow(Side side, double t, double dt, double flow)
{
  pending_[index(side)] = flow;
  if (!pending_[0] || !pending_[1]) return;
  ExternalAorticFlow external;
  external.t = t;
  external.dt = dt;
  external.ventricle_start = flow_[0];
  external.ventricle_end = *pending_[0];
  external.arteries_start = flow_[1];
  external.arteries_end = *pending_[1];
  loop_.step(t, y_, dt, &external);
  time_ = t + dt;
  flow_ = {*pending_[0], *pending_[1]};
  pending_ = {};
}

std::vector<Column> ClosedLoopCoupling::columns() const
{
  std::vector<Column> c;
  for (const char* name : {"V_LA", "V_LV", "V_RA", "V_RV"}) c.push_back({name, "mL"});
  for (const char* name : {"p_LA", "p_LV", "p_RA", "p_RV", "p_AR_SYS", "p_VEN_SYS", "p_AR_PUL", "p_VEN_PUL"})
    c.push_back({name, "mmHg"});
  for (const char* name : {"Q_MV", "Q_TV", "Q_PV", "Q_AR_SYS", "Q_VEN_SYS", "Q_AR_PUL", "Q_VEN_PUL"})
    c.push_back({name, "mL/s"});
  c.push_back({"V_blood", "mL"});
  return c;
}

std::vector<double> ClosedLoopCoupling::row(double t) const
{
  const Derived d = loop_.derived(t, y_);
  const double mmHg = units::mmHg, mL = units::mL;
  std::vector<double> r;
  for (const double v : {y_[V_LA], y_[V_LV], y_[V_RA], y_[V_RV]}) r.push_back(v / mL);
  for (const double p :
       {d.p_LA, d.p_LV, d.p_RA, d.p_RV, y_[p_AR_SYS], y_[p_VEN_SYS], y_[p_AR_PUL], y_[p_VEN_PUL]})
    r.push_back(p / mmHg);
  for (const double q : {d.Q_MV, d.Q_TV, d.Q_PV, y_[Q_AR_SYS], y_[Q_VEN_SYS], y_[Q_AR_PUL], y_[Q_VEN_PUL]})
    r.push_back(q / mL);
  r.push_back(loop_.total_volume(y_) / mL);
  return r;
}

void ClosedLoopCoupling::save(io::Hdf5File& h5, const std::string& group) const
{
  for (std::size_t i = 0; i < y_.size(); ++i) save_number(h5, group, loop_.state_names()[i], y_[i]);
  save_number(h5, group, "time", time_);
  save_number(h5, group, "Q_upstream", flow_[0]);
  save_number(h5, group, "Q_downstream", flow_[1]);
}

void ClosedLoopCoupling::restore(const io::Hdf5File& h5, const std::string& group)
{
  for (std::size_t i = 0; i < y_.size(); ++i) y_[i] = read_number(h5, group, loop_.state_names()[i]);
  time_ = read_number(h5, group, "time");
  flow_ = {read_number(h5, group, "Q_upstream"), read_number(h5, group, "Q_downstream")};
  pending_ = {};
}

std::string ClosedLoopCoupling::describe() const
{
  return fmt::format(
      "closed-loop circulation (Regazzoni et al. 2022) at {:g} beats/min, settled by {} beat(s) "
      "on its own before t = 0: V_LV {:.1f} mL, p_AR_SYS {:.1f} mmHg, blood {:.1f} mL",
      60.0 / loop_.period(), start_beats_, y_[V_LV] / units::mL, y_[p_AR_SYS] / units::mmHg,
      loop_.total_volume(y_) / units::mL);
}

ClosedLoopSide::ClosedLoopSide(Side side, std::shared_ptr<ClosedLoopCoupling> coupling)
    : BoundaryDriver(side), coupling_(std::move(coupling))
{
}

double ClosedLoopSide::pressure(double t) const
{
  return side() == Side::upstream ? coupling_->ventricle_pressure(t) : coupling_->arterial_pressure();
}

std::vector<Column> ClosedLoopSide::columns() const
{
  return {{"P_" + side_name(side()), "mmHg"}, {"Q_" + side_name(side()), "mL/s"}};
}

std::vector<double> ClosedLoopSide::row(double t) const
{
  return {pressure(t) / units::mmHg, coupling_->flow(side()) / units::mL};
}

std::string ClosedLoopSide::describe() const
{
  return side() == Side::upstream ? "upstream: the loop's left ventricle (elastance)"
                                  : "downstream: the loop's systemic arteries";
}

} // namespace ibvalve::drivers
