#include "drivers/boundary_driver.hpp"

#include <array>
#include <span>

#include "base/errors.hpp"

namespace ibvalve::drivers {

std::string side_name(Side side)
{
  return side == Side::upstream ? "upstream" : "downstream";
}

void save_number(io::Hdf5File& h5, const std::string& group, const std::string& name, double value)
{
  const std::array<hsize_t, 1> one{1};
  h5.write_root(group + "/" + name, std::span<const double>(&value, 1), one);
}

double read_number(const io::Hdf5File& h5, const std::string& group, const std::string& name)
{
  const std::string path = group + "/" + name;
  if (!h5.has(path))
    throw InputError(h5.path().string() + ": " + path +
                     " is missing: the checkpoint is of another boundary driver, or of a run before the "
                     "drivers (docs/drivers.md, \"Checkpoints\"), and cannot be continued by this case");
  const std::vector<double> value = h5.read(path);
  if (value.size() != 1) throw InputError(h5.path().string() + ": " + path + " is not one number");
  return value[0];
}

} // namespace ibvalve::drivers
