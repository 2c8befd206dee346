// `ibvalve fit --law W1 DATA.csv [more.csv ...]`: fit a law's parameters to planar biaxial data
// (materials/fitting.hpp), one sample per file, and print the parameters (kPa), the mean absolute
// error (kPa) and R^2 of each sample and their means over the samples, as Zhu et al. (2021) report.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "app/commands.hpp"
#include "base/errors.hpp"
#include "base/logger.hpp"
#include "io/files.hpp"
#include "materials/fitting.hpp"

namespace ibvalve::app {

namespace {

struct FitCommandOptions {
  std::string law;
  std::vector<std::filesystem::path> files;
  double fiber_angle_degrees = 0.0;
  std::string fiber_compression = "off";
  int starts = 4;
  std::filesystem::path curves;
};

std::string cell(double value, int width)
{
  const double magnitude = std::abs(value);
  if (magnitude != 0.0 && (magnitude < 1e-3 || magnitude >= 1e6))
    return fmt::format("{:>{}.4e}", value, width);
  return fmt::format("{:>{}.5g}", value, width);
}

std::string padded(const std::string& text, std::size_t width)
{
  return text.size() >= width ? text + " " : text + std::string(width - text.size(), ' ');
}

int fit(const FitCommandOptions& options)
{
  using namespace materials;
  auto& log = base::Logger::global();
  const auto kind = find_law(options.law);
  if (!kind) throw InputError("command line: --law: '" + options.law + "' is not one of " + law_names());
  if (options.fiber_compression != "off" && options.fiber_compression != "on")
    throw InputError("command line: --fiber-compression: '" + options.fiber_compression +
                     "' is not off or on");
  if (options.starts < 1) throw InputError("command line: --starts: must be at least 1");
  FitOptions fit_options;
  fit_options.setup.law = *kind;
  fit_options.setup.fiber_compression =
      options.fiber_compression == "on" ? FiberCompression::included : FiberCompression::excluded;
  fit_options.setup.fiber_angle = options.fiber_angle_degrees * M_PI / 180.0;
  if (*kind != LawKind::hgo && options.fiber_angle_degrees != 0.0)
    throw InputError("command line: --fiber-angle: law " + options.law +
                     " has one fiber family along axis 1; a fiber angle applies to hgo only");
  if (!(std::abs(options.fiber_angle_degrees) <= 90.0))
    throw InputError("command line: --fiber-angle: must lie in [-90, 90] degrees");

  // Read every file before printing anything: bad input stops with one line and no output.
  std::vector<BiaxialSample> samples;
  for (const auto& file : options.files) samples.push_back(read_biaxial_csv(file));

  const LawInfo& info = law_info(*kind);
  log.info("fit of " + info.name + ": W = " + info.formula);
  log.info("planar biaxial, incompressible (lambda3 = 1/(lambda1 lambda2), sigma33 = 0), fiber along axis 1" +
           std::string(*kind == LawKind::hgo ? " +- " + cell(options.fiber_angle_degrees, 0) + " deg" : "") +
           ", fibers " +
           (options.fiber_compression == "off" ? "in tension only" : "in tension and compression") +
           "; bounded least squares (Ceres), parameters >= 0");
  std::size_t name_width = 8;
  for (const auto& s : samples) name_width = std::max(name_width, s.name.size() + 2);
  std::string header = padded("sample", name_width);
  for (const auto& p : info.parameters) header += padded(p.name + (p.is_modulus ? " [kPa]" : ""), 14);
  header += padded("MAE [kPa]", 12) + padded("R^2", 10) + "points";
  log.info(header);

  std::vector<double> sum(info.parameters.size() + 2, 0.0);
  std::ostringstream curves;
  curves << "sample,lambda1,lambda2,sigma11_kPa,sigma22_kPa,model_sigma11_kPa,model_sigma22_kPa\n";
  curves.precision(10);
  for (const auto& sample : samples) {
    const FitResult result = fit_biaxial(sample, {fit_options.setup, options.starts, 1000});
    std::string row = padded(sample.name, name_width);
    for (std::size_t i = 0; i < result.parameters.size(); ++i) {
      row += padded(cell(result.parameters[i], 0), 14);
      sum[i] += result.parameters[i];
    }
    row += fmt::format("{}{}{}", padded(cell(result.quality.mae, 0), 12),
                       padded(cell(result.quality.r_squared, 0), 10), sample.points.size());
    if (!result.converged) row += "  (stopped at the iteration limit)";
    log.info(row);
    sum[info.parameters.size()] += result.quality.mae;
    sum[info.parameters.size() + 1] += result.quality.r_squared;
    for (const auto& pt : sample.points) {
      const auto model =
          biaxial_cauchy<double>(fit_options.setup, result.parameters.data(), pt.lambda1, pt.lambda2);
      curves << sample.name << "," << pt.lambda1 << "," << pt.lambda2 << "," << pt.sigma11 << ","
             << pt.sigma22 << "," << model[0] << "," << model[1] << "\n";
    }
  }
  const double n = static_cast<double>(samples.size());
  std::string mean = padded("mean", name_width);
  for (std::size_t i = 0; i < info.parameters.size(); ++i) mean += padded(cell(sum[i] / n, 0), 14);
  mean += padded(cell(sum[info.parameters.size()] / n, 0), 12) +
          padded(cell(sum[info.parameters.size() + 1] / n, 0), 10);
  mean.erase(mean.find_last_not_of(' ') + 1);
  if (samples.size() > 1) log.info(mean);
  if (!options.curves.empty()) {
    if (log.is_root()) io::write_file_atomically(options.curves, curves.str());
    log.info("data and fitted stresses written to " + options.curves.string());
  }
  return 0;
}

} // namespace

void add_fit_command(CLI::App& app, CommandAction& action)
{
  auto options = std::make_shared<FitCommandOptions>();
  CLI::App* sub = app.add_subcommand(
      "fit", "Fit a law to planar biaxial data: CSV files with the columns lambda1, lambda2, sigma11_kPa, "
             "sigma22_kPa (one sample per file; Cauchy stresses in kPa, axis 1 along the fibers)");
  sub->add_option("--law", options->law, "law: " + materials::law_names())->required();
  sub->add_option("files", options->files, "one CSV file per sample")->required();
  sub->add_option("--fiber-angle", options->fiber_angle_degrees,
                  "hgo only: its two families lie at +- this angle (degrees) from axis 1 (default 0)");
  sub->add_option("--fiber-compression", options->fiber_compression,
                  "off (default): fibers carry no load when shortened; on: the law as written");
  sub->add_option("--starts", options->starts,
                  "nonlinear solves from the best grid starting points (default 4)");
  sub->add_option("--curves", options->curves, "write data and fitted stresses to this CSV file");
  sub->callback([options, &action] { action = [options](const PetscArguments&) { return fit(*options); }; });
}

} // namespace ibvalve::app
