#include <ctime>

#include <fmt/chrono.h>
#include <fmt/format.h>

#include "base/build_info.hpp"

namespace ibvalve::base {

std::string utc_now()
{
  return fmt::format("{:%Y-%m-%dT%H:%M:%SZ}", fmt::gmtime(std::time(nullptr)));
}

} // namespace ibvalve::base
