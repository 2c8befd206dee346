#pragma once
// How a report is laid out for its reader: the headline figures it opens with, each beside a healthy
// adult native aortic valve's published range, the checks that flag a figure no valve can have, and the
// groups of the full metric table (docs/hemodynamics.md, "What the report opens with").
#include <optional>
#include <span>
#include <string>

#include <nlohmann/json.hpp>

#include "hemodynamics/cycle_table.hpp"

namespace ibvalve::hemodynamics {

/// A published bound of a healthy (or at most mildly diseased) adult native aortic valve, in the
/// metric's report unit: the value lies below `upper` (or at it, when `upper_included`) and above
/// `lower`.
struct ReferenceRange {
  std::optional<double> upper, lower;
  bool upper_included;
  const char* text;   // the range as the page shows it, with what it grades: "< 20 (at most mild stenosis)"
  const char* source; // the short citation; reference_sources() holds the full one
};

/// A figure the report opens with.
struct HeadlineFigure {
  const char* key;  // metrics.json key
  const char* name; // "mean transvalvular pressure gradient"
  std::optional<ReferenceRange> range;
};

/// The headline figures, in the order the report shows them: V_F, RF, TPG, EOA, E_L, Q_max, GOA_max and
/// the peak velocity.
std::span<const HeadlineFigure> headline_figures();

/// A cited source: its short name (ReferenceRange::source) and its full citation.
struct ReferenceSource {
  const char* name;
  const char* citation;
};
std::span<const ReferenceSource> reference_sources();

/// metrics.json's "headline" from its "metrics" object: per figure key, name, symbol, value (null when
/// the run has none), unit, range and source (empty without one), and assessment: "within", "outside"
/// or "" (no range or no value).
nlohmann::ordered_json headline_document(const nlohmann::ordered_json& metrics);

/// metrics.json's "checks" from its "metrics" object: one {"check", "text"} for each figure no valve
/// can have: an EOA above the largest geometric orifice ("eoa_above_goa"), a cycle whose Windkessel
/// pressure ends more than periodic_pressure_tolerance (cycle_table.hpp) from where it started
/// ("not_periodic").
nlohmann::ordered_json plausibility_checks(const nlohmann::ordered_json& metrics);

/// The group of the full metric table a metric belongs to: "flow and pressure", "valve motion",
/// "leaflet mechanics", or "other" for a key ibvalve does not compute itself.
std::string metric_group(const std::string& key);
/// The groups, in the order the report shows them.
std::span<const char* const> metric_groups();

} // namespace ibvalve::hemodynamics
