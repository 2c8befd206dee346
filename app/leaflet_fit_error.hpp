#pragma once
// The leaflet law's fit error, the first criterion of the study's ranking: the mean absolute error of
// the law's biaxial stresses with the case's parameters against planar biaxial samples
// (docs/reference.md, "Constitutive fitting"), and whether those samples are synthetic (drawn from a
// law's own curves, which that law fits by construction).
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "materials/settings.hpp"

namespace ibvalve::app {

struct LeafletFitError {
  double value = 0.0; ///< kPa
  /// "sample1.csv: SYNTHETIC ..." for each sample that declares itself synthetic (a comment line whose
  /// first word is SYNTHETIC, materials::read_biaxial_csv).
  std::vector<std::string> synthetic;
  std::size_t samples = 0;
};

/// The mean over the samples of the mean absolute error (kPa) of the leaflet law's biaxial stresses
/// with its parameters, through its 3-D stress for a law written as a formula.
LeafletFitError leaflet_fit_error(const materials::MaterialSettings& material,
                                  const std::vector<std::filesystem::path>& files);

/// The fit error as extra_metrics.json holds it (docs/hemodynamics.md, "Extra metrics"): value, unit,
/// symbol, a description naming `key` (the case-file key of the samples) and, when some samples are
/// synthetic, "synthetic_data": true and a note naming them, which every page showing the figure shows.
nlohmann::ordered_json fit_error_metric(const LeafletFitError& error, const std::string& key);

} // namespace ibvalve::app
