#pragma once
// What the report's templates fill in, from metrics.json's document (the names
// templates/report.md.tpl lists).
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <kainjow/mustache.hpp>
#include <nlohmann/json.hpp>

#include "hemodynamics/plotting.hpp"

namespace ibvalve::hemodynamics {

/// The report's plots: their files and captions, in the order the pages show them.
std::span<const PlotCaption> report_plots();

/// The template values of one report page. `report_root` is the path from the page's folder to the
/// report folder ("" for report/ itself, "../" for report/cycle_N/): the cycle table links each
/// cycle's page through it.
kainjow::mustache::data report_template_values(const nlohmann::ordered_json& doc,
                                               const std::vector<std::filesystem::path>& plots,
                                               const std::string& report_root);

} // namespace ibvalve::hemodynamics
