// `ibvalve fit --law W1 DATA.csv [more.csv ...]`: fit a law's parameters to planar biaxial data
// (materials/fitting.hpp), one sample per file, and print the parameters (kPa), the mean absolute
// error (kPa) and R^2 of each sample and their means over the samples, as Zhu et al. (2021) report.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "app/commands.hpp"
#include "base/errors.hpp"
#include "base/logger.hpp"
#include "base/units.hpp"
#include "io/files.hpp"
#include "materials/expression_checks.hpp"
#include "materials/expression_fitting.hpp"
#include "materials/fitting.hpp"
#include "materials/settings.hpp"

namespace ibvalve::app {

namespace {

struct FitCommandOptions {
  std::string law;
  std::string energy;     ///< --law expression: the formula
  std::string parameters; ///< "name=start[:lower:upper], ..."
  std::string moduli;     ///< "name,name": the parameters in kPa
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

std::vector<std::string> split(const std::string& text, char separator)
{
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(text);
  while (std::getline(in, part, separator)) parts.push_back(io::trim(part));
  return parts;
}

double number(const std::string& text, const std::string& what)
{
  std::size_t used = 0;
  double value = 0.0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || !std::isfinite(value))
    throw InputError("command line: --parameters: " + what + ": '" + text + "' is not a finite number");
  return value;
}

/// --parameters "C10=2, k2=30:0:100" (start, then optional lower and upper bounds; an empty bound is
/// none) and --moduli "C10,k1": a modulus's default lower bound is 0.
std::vector<materials::FittedParameter> fitted_parameters(const FitCommandOptions& options)
{
  const std::vector<std::string> moduli =
      options.moduli.empty() ? std::vector<std::string>{} : split(options.moduli, ',');
  std::vector<materials::FittedParameter> out;
  for (const std::string& item : split(options.parameters, ',')) {
    const auto equals = item.find('=');
    if (equals == std::string::npos)
      throw InputError("command line: --parameters: '" + item + "' is not name=start[:lower:upper]");
    materials::FittedParameter p;
    p.name = io::trim(item.substr(0, equals));
    const std::vector<std::string> values = split(item.substr(equals + 1) + ":", ':'); // keeps an empty upper
    if (values.empty() || values.size() > 3 || values[0].empty())
      throw InputError("command line: --parameters: '" + item + "' is not name=start[:lower:upper]");
    p.start = number(values[0], p.name);
    p.is_modulus = std::find(moduli.begin(), moduli.end(), p.name) != moduli.end();
    if (p.is_modulus) p.lower = 0.0;
    if (values.size() > 1 && !values[1].empty()) p.lower = number(values[1], p.name);
    if (values.size() > 2 && !values[2].empty()) p.upper = number(values[2], p.name);
    out.push_back(p);
  }
  for (const std::string& name : moduli)
    if (std::none_of(out.begin(), out.end(), [&](const auto& p) { return p.name == name; }))
      throw InputError("command line: --moduli: '" + name + "' is not one of the --parameters");
  return out;
}

/// The table of fitted parameters, MAE and R^2 per sample and their means; the curves file.
void report_fits(
    const std::vector<std::string>& names, const std::vector<bool>& moduli,
    const std::vector<materials::BiaxialSample>& samples, const std::vector<materials::FitResult>& results,
    const std::function<std::array<double, 2>(std::size_t, const materials::BiaxialPoint&)>& model,
    const std::filesystem::path& curves_file);

/// The checks of a case file's expression law (materials/expression_checks.hpp) at the starting values.
void check_before_fit(const materials::ExpressionFitOptions& options)
{
  using namespace materials;
  std::vector<ExpressionParameter> start;
  for (const auto& p : options.parameters)
    start.push_back({p.name, p.is_modulus ? p.start * units::kPa : p.start, p.is_modulus});
  const auto at = [](std::size_t position) {
    return position == std::string::npos ? std::string() : fmt::format("character {}: ", position + 1);
  };
  try {
    const ExpressionLaw law(options.energy, start, {options.fiber_compression});
    for (std::size_t i = 0; i < start.size(); ++i)
      if (!law.formula().uses(static_cast<int>(expression_invariants.size() + i)))
        throw InputError("command line: --parameters: " + start[i].name + " is not used in the energy");
    if (const auto problem = check_expression_law(law))
      throw InputError("command line: --energy: " + at(problem->position) + problem->message);
  } catch (const FormulaError& e) {
    throw InputError("command line: --energy: " + at(e.position()) + e.what());
  }
}

int fit_expression_law(const FitCommandOptions& options, const std::vector<materials::BiaxialSample>& samples)
{
  using namespace materials;
  if (options.energy.empty()) throw InputError("command line: --energy: --law expression needs the formula");
  ExpressionFitOptions fit_options;
  fit_options.energy = options.energy;
  fit_options.parameters = fitted_parameters(options);
  fit_options.fiber_compression =
      options.fiber_compression == "on" ? FiberCompression::included : FiberCompression::excluded;
  fit_options.fiber_angle = options.fiber_angle_degrees * M_PI / 180.0;
  check_before_fit(fit_options); // bad input stops here, before any output
  std::vector<std::string> names;
  std::vector<bool> moduli;
  std::vector<ExpressionParameter> start;
  for (const auto& p : fit_options.parameters) {
    names.push_back(p.name);
    moduli.push_back(p.is_modulus);
    start.push_back({p.name, p.start, p.is_modulus});
  }
  const ExpressionLaw law(options.energy, start, {fit_options.fiber_compression});
  auto& log = base::Logger::global();
  const std::string angle = cell(options.fiber_angle_degrees, 0) + " deg from axis 1";
  log.info("fit of expression: W = " + options.energy);
  log.info("planar biaxial, incompressible (lambda3 = 1/(lambda1 lambda2), sigma33 = 0), " +
           (law.fiber_families() == 2 ? "fiber families at +- " + angle : "fiber at " + angle) + ", fibers " +
           (options.fiber_compression == "off" ? "in tension only" : "in tension and compression") +
           "; bounded least squares (Ceres) from the given starting values");
  std::vector<FitResult> results;
  for (const auto& sample : samples) results.push_back(fit_expression(sample, fit_options));
  report_fits(
      names, moduli, samples, results,
      [&](std::size_t k, const BiaxialPoint& pt) {
        return expression_biaxial_cauchy(law, results[k].parameters, fit_options.fiber_angle, pt.lambda1,
                                         pt.lambda2);
      },
      options.curves);
  return 0;
}

int fit(const FitCommandOptions& options)
{
  using namespace materials;
  auto& log = base::Logger::global();
  if (options.law == expression_law_name) {
    if (options.fiber_compression != "off" && options.fiber_compression != "on")
      throw InputError("command line: --fiber-compression: '" + options.fiber_compression +
                       "' is not off or on");
    std::vector<BiaxialSample> samples;
    for (const auto& file : options.files) samples.push_back(read_biaxial_csv(file));
    return fit_expression_law(options, samples);
  }
  if (!options.energy.empty() || !options.parameters.empty() || !options.moduli.empty())
    throw InputError("command line: --energy, --parameters and --moduli go with --law expression");
  const auto kind = find_law(options.law);
  if (!kind)
    throw InputError("command line: --law: '" + options.law + "' is not one of " + law_names() +
                     ", expression");
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
  std::vector<FitResult> results;
  for (const auto& sample : samples)
    results.push_back(fit_biaxial(sample, {fit_options.setup, options.starts, 1000}));
  std::vector<std::string> names;
  std::vector<bool> moduli;
  for (const auto& p : info.parameters) {
    names.push_back(p.name);
    moduli.push_back(p.is_modulus);
  }
  report_fits(
      names, moduli, samples, results,
      [&](std::size_t k, const BiaxialPoint& pt) {
        return biaxial_cauchy<double>(fit_options.setup, results[k].parameters.data(), pt.lambda1,
                                      pt.lambda2);
      },
      options.curves);
  return 0;
}

void report_fits(
    const std::vector<std::string>& names, const std::vector<bool>& moduli,
    const std::vector<materials::BiaxialSample>& samples, const std::vector<materials::FitResult>& results,
    const std::function<std::array<double, 2>(std::size_t, const materials::BiaxialPoint&)>& model,
    const std::filesystem::path& curves_file)
{
  auto& log = base::Logger::global();
  std::size_t name_width = 8;
  for (const auto& s : samples) name_width = std::max(name_width, s.name.size() + 2);
  std::string header = padded("sample", name_width);
  for (std::size_t i = 0; i < names.size(); ++i) header += padded(names[i] + (moduli[i] ? " [kPa]" : ""), 14);
  header += padded("MAE [kPa]", 12) + padded("R^2", 10) + "points";
  log.info(header);

  std::vector<double> sum(names.size() + 2, 0.0);
  std::ostringstream curves;
  curves << "sample,lambda1,lambda2,sigma11_kPa,sigma22_kPa,model_sigma11_kPa,model_sigma22_kPa\n";
  curves.precision(10);
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const auto& sample = samples[k];
    const auto& result = results[k];
    std::string row = padded(sample.name, name_width);
    for (std::size_t i = 0; i < result.parameters.size(); ++i) {
      row += padded(cell(result.parameters[i], 0), 14);
      sum[i] += result.parameters[i];
    }
    row += fmt::format("{}{}{}", padded(cell(result.quality.mae, 0), 12),
                       padded(cell(result.quality.r_squared, 0), 10), sample.points.size());
    if (!result.converged) row += "  (stopped at the iteration limit)";
    log.info(row);
    sum[names.size()] += result.quality.mae;
    sum[names.size() + 1] += result.quality.r_squared;
    for (const auto& pt : sample.points) {
      const auto s = model(k, pt);
      curves << sample.name << "," << pt.lambda1 << "," << pt.lambda2 << "," << pt.sigma11 << ","
             << pt.sigma22 << "," << s[0] << "," << s[1] << "\n";
    }
  }
  const double n = static_cast<double>(samples.size());
  std::string mean = padded("mean", name_width);
  for (std::size_t i = 0; i < names.size(); ++i) mean += padded(cell(sum[i] / n, 0), 14);
  mean += padded(cell(sum[names.size()] / n, 0), 12) + padded(cell(sum[names.size() + 1] / n, 0), 10);
  mean.erase(mean.find_last_not_of(' ') + 1);
  if (samples.size() > 1) log.info(mean);
  if (!curves_file.empty()) {
    if (log.is_root()) io::write_file_atomically(curves_file, curves.str());
    log.info("data and fitted stresses written to " + curves_file.string());
  }
}

} // namespace

void add_fit_command(CLI::App& app, CommandAction& action)
{
  auto options = std::make_shared<FitCommandOptions>();
  CLI::App* sub = app.add_subcommand(
      "fit", "Fit a law to planar biaxial data: CSV files with the columns lambda1, lambda2, sigma11_kPa, "
             "sigma22_kPa (one sample per file; Cauchy stresses in kPa, axis 1 along the fibers)");
  sub->add_option("--law", options->law, "law: " + materials::law_names() + ", or expression (with --energy)")
      ->required();
  sub->add_option("--energy", options->energy,
                  "--law expression: the strain energy, a formula of I1, I1bar, I2, I4, I6, I8, J and the "
                  "parameters (docs/materials.md)");
  sub->add_option("--parameters", options->parameters,
                  "--law expression: \"name=start[:lower:upper], ...\" (kPa for a modulus; an empty bound is "
                  "none)");
  sub->add_option("--moduli", options->moduli,
                  "--law expression: the parameters in kPa, comma-separated (lower bound 0 unless given)");
  sub->add_option("files", options->files, "one CSV file per sample")->required();
  sub->add_option(
      "--fiber-angle", options->fiber_angle_degrees,
      "hgo and expression: the two families lie at +- this angle (degrees) from axis 1 (default 0)");
  sub->add_option("--fiber-compression", options->fiber_compression,
                  "off (default): fibers carry no load when shortened; on: the law as written");
  sub->add_option("--starts", options->starts,
                  "nonlinear solves from the best grid starting points (default 4)");
  sub->add_option("--curves", options->curves, "write data and fitted stresses to this CSV file");
  sub->callback([options, &action] { action = [options](const PetscArguments&) { return fit(*options); }; });
}

} // namespace ibvalve::app
