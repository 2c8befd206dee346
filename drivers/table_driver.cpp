#include "drivers/table_driver.hpp"

#include <fmt/format.h>

namespace ibvalve::drivers {

TableDriver::TableDriver(Side side, windkessel::PeriodicWaveform table, std::string what)
    : BoundaryDriver(side), table_(std::move(table)), what_(std::move(what))
{
}

std::string TableDriver::describe() const
{
  return fmt::format("{} {}: {:g} s period", side_name(side()), what_, table_.period());
}

} // namespace ibvalve::drivers
