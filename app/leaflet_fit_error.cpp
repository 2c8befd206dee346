#include "app/leaflet_fit_error.hpp"

#include <optional>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "materials/fitting.hpp"

namespace ibvalve::app {

LeafletFitError leaflet_fit_error(const materials::MaterialSettings& material,
                                  const std::vector<std::filesystem::path>& files)
{
  const materials::BiaxialSetup setup{material.law, material.options.fiber_compression, 0.0};
  LeafletFitError error;
  std::optional<materials::ExpressionLaw> law; // a law written as a formula: through its 3-D stress
  if (material.expression) law = material.expression_law();
  const std::vector<double> parameters =
      law ? std::vector<double>{} : materials::to_user_units(material.law, material.parameters);
  for (const auto& file : files) {
    const materials::BiaxialSample sample = materials::read_biaxial_csv(file);
    error.value += law ? materials::fit_quality(sample, *law, materials::biaxial_frame(setup)).mae
                       : materials::fit_quality(sample, setup, parameters).mae;
    if (!sample.synthetic.empty()) error.synthetic.push_back(sample.name + ": " + sample.synthetic);
  }
  error.samples = files.size();
  error.value /= static_cast<double>(files.size());
  return error;
}

nlohmann::ordered_json fit_error_metric(const LeafletFitError& error, const std::string& key)
{
  nlohmann::ordered_json metric{
      {"value", error.value},
      {"unit", "kPa"},
      {"symbol", "e_fit"},
      {"description", fmt::format("mean absolute error of the leaflet law's stresses "
                                  "against the {} planar biaxial sample(s) of {}",
                                  error.samples, key)}};
  // Samples generated from a law's curves favour that law: every page that shows the figure says so.
  if (!error.synthetic.empty()) {
    metric["synthetic_data"] = true;
    metric["note"] =
        fmt::format("{} of {} sample(s) synthetic, drawn from a law's own curves ({}): the law they "
                    "were drawn from fits them by construction, so this is no test against "
                    "measured tissue",
                    error.synthetic.size(), error.samples, fmt::join(error.synthetic, "; "));
  }
  return metric;
}

} // namespace ibvalve::app
