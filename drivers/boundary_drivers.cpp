#include "drivers/boundary_drivers.hpp"

#include "base/errors.hpp"

namespace ibvalve::drivers {

BoundaryDrivers::BoundaryDrivers(std::unique_ptr<BoundaryDriver> upstream,
                                 std::unique_ptr<BoundaryDriver> downstream,
                                 std::shared_ptr<ClosedLoopCoupling> loop)
    : upstream_(std::move(upstream)), downstream_(std::move(downstream)), loop_(std::move(loop))
{
}

std::optional<double> BoundaryDrivers::period() const
{
  if (const auto p = upstream_->period()) return p;
  return downstream_->period();
}

void BoundaryDrivers::advance(double t, double dt, double upstream_flow, double downstream_flow)
{
  upstream_->advance(t, dt, upstream_flow);
  downstream_->advance(t, dt, downstream_flow);
}

std::vector<Column> BoundaryDrivers::columns() const
{
  std::vector<Column> c = upstream_->columns();
  for (Column& column : downstream_->columns()) c.push_back(std::move(column));
  if (loop_)
    for (Column& column : loop_->columns()) c.push_back(std::move(column));
  return c;
}

std::vector<double> BoundaryDrivers::row(double t) const
{
  std::vector<double> r = upstream_->row(t);
  for (double v : downstream_->row(t)) r.push_back(v);
  if (loop_)
    for (double v : loop_->row(t)) r.push_back(v);
  return r;
}

void BoundaryDrivers::save(io::Hdf5File& h5) const
{
  upstream_->save(h5, "drivers/upstream");
  downstream_->save(h5, "drivers/downstream");
  if (loop_) loop_->save(h5, "drivers/loop");
}

void BoundaryDrivers::restore(const io::Hdf5File& h5)
{
  if (h5.has("aortic_valve/outlet"))
    throw InputError(h5.path().string() +
                     ": a checkpoint of the layout before the boundary drivers (the outlet's numbers by "
                     "position in aortic_valve/outlet): it cannot be continued by this version; run the case "
                     "again from its start (docs/drivers.md, \"Checkpoints\")");
  upstream_->restore(h5, "drivers/upstream");
  downstream_->restore(h5, "drivers/downstream");
  if (loop_) loop_->restore(h5, "drivers/loop");
}

std::vector<std::string> BoundaryDrivers::describe() const
{
  std::vector<std::string> lines{upstream_->describe(), downstream_->describe()};
  if (loop_) lines.push_back(loop_->describe());
  return lines;
}

} // namespace ibvalve::drivers
