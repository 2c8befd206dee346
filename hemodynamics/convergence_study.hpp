#pragma once
// `ibvalve convergence RUN_DIR...`: the grid convergence of every metric of runs of one case on
// different grids (hemodynamics/grid_convergence.hpp, Celik et al. 2008), as Markdown, CSV and JSON.
//
// Each run's grid spacing is the finest level's cell size its config.toml records:
// (fluid.upper - fluid.lower) / fluid.cells along each axis, divided by the product of nested.ratios (no
// nested.ratios: one level). The study needs cubic cells, one spacing per grid. The runs are sorted by
// spacing, finest first; a metric enters when every run's metrics.json has it as a finite number.
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "hemodynamics/compare.hpp"
#include "hemodynamics/grid_convergence.hpp"

namespace ibvalve::hemodynamics {

/// Two spacings (or a cell's sides) closer than this, relative to the larger, are the same: far above
/// the round-off of a spacing computed from the case's numbers (1e-16), far below any refinement.
inline constexpr double spacing_tolerance = 1e-9;

/// The finest level's cell size, in cm, of the resolved case `config_file` (a run's config.toml). An
/// InputError naming the file, line and key for a missing or malformed fluid.cells, fluid.lower,
/// fluid.upper or nested.ratios, and for cells that are not cubes.
double finest_grid_spacing(const std::filesystem::path& config_file);

struct GridRun {
  CaseResult run;
  double spacing = 0.0; // cm
};

struct MetricConvergence {
  std::string key, symbol, unit;
  std::vector<double> values; // one per run, finest first
  GridConvergence result;
};

struct ConvergenceStudy {
  std::vector<GridRun> runs; // finest first
  std::vector<MetricConvergence> metrics;
  /// Metrics some run lacks or gives no finite number for: "key (missing in: a, b)".
  std::vector<std::string> left_out;
};

/// Loads every run folder (load_case and finest_grid_spacing of its config.toml) and studies every
/// metric the runs share. An InputError for fewer than two runs, a run folder without config.toml or
/// metrics, and two runs with the same spacing (naming both).
ConvergenceStudy study_grid_convergence(std::span<const std::filesystem::path> run_directories);

struct ConvergenceFiles {
  std::filesystem::path markdown, csv, json;
};
/// Writes convergence.md, convergence.csv and convergence.json into `output_directory` (created).
ConvergenceFiles write_grid_convergence(const ConvergenceStudy& study,
                                        const std::filesystem::path& output_directory);

} // namespace ibvalve::hemodynamics
