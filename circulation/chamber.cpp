#include "circulation/chamber.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace ibvalve::circulation {

namespace {
/// x mod period in [0, period).
double wrap(double x, double period)
{
  const double r = std::fmod(x, period);
  return r < 0.0 ? r + period : r;
}
} // namespace

double ChamberParameters::activation(double t, double period) const
{
  const double t_c = contraction_start * period, t_contract = contraction_time * period;
  const double t_relax = relaxation_time * period;
  const double s = wrap(t - t_c, period);
  if (s < t_contract) return 0.5 * (1.0 - std::cos(std::numbers::pi * s / t_contract));
  const double r = wrap(t - t_c - t_contract, period);
  if (r < t_relax) return 0.5 * (1.0 + std::cos(std::numbers::pi * r / t_relax));
  return 0.0;
}

void ChamberParameters::check(const char* chamber) const
{
  const std::string name(chamber);
  if (!(active_elastance >= 0.0)) throw std::invalid_argument(name + ": E_A must be >= 0");
  if (!(passive_elastance > 0.0)) throw std::invalid_argument(name + ": E_B must be > 0");
  if (!(contraction_time > 0.0) || !(relaxation_time > 0.0))
    throw std::invalid_argument(name + ": contraction and relaxation times must be > 0");
  if (contraction_time + relaxation_time > 1.0)
    throw std::invalid_argument(name + ": contraction + relaxation must fit in one heartbeat");
}

} // namespace ibvalve::circulation
