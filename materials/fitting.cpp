#include "materials/fitting.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fmt/format.h>
#include <fstream>
#include <limits>
#include <numeric>
#include <sstream>

#include <Eigen/Dense>
#include <ceres/ceres.h>

#include "materials/ceres_fit_options.hpp"

#include "base/errors.hpp"
#include "base/units.hpp"
#include "io/files.hpp"

namespace ibvalve::materials {

// ---------------------------------------------------------------------------------------------
// CSV

namespace {

bool parse_number(const std::string& text, double& value)
{
  if (text.empty()) return false;
  const char* begin = text.data();
  if (*begin == '+') ++begin;
  const auto [end, error] = std::from_chars(begin, text.data() + text.size(), value);
  return error == std::errc() && end == text.data() + text.size() && std::isfinite(value);
}

} // namespace

/// The largest stress a biaxial sample may hold, kPa.
constexpr double max_sample_stress_kpa = 1e6;

namespace {

/// A comment whose first word is "synthetic" (in any case): the data were generated, not measured.
bool declares_synthetic(const std::string& comment)
{
  constexpr std::string_view word = "synthetic";
  if (comment.size() < word.size()) return false;
  for (std::size_t i = 0; i < word.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(comment[i])) != word[i]) return false;
  return comment.size() == word.size() || !std::isalnum(static_cast<unsigned char>(comment[word.size()]));
}

} // namespace

BiaxialSample read_biaxial_csv(const std::filesystem::path& file)
{
  const std::string name = file.string();
  io::check_input_file(file, io::max_input_table_bytes);
  std::ifstream in(file);
  if (!in) throw InputError(name + ": cannot be read");
  static const std::array<std::string, 4> required{"lambda1", "lambda2", "sigma11_kPa", "sigma22_kPa"};
  const auto fail = [&](int line, const std::string& message) {
    throw InputError(fmt::format("{}:{}: {}", name, line, message));
  };
  BiaxialSample sample;
  sample.name = file.filename().string();
  std::array<std::size_t, 4> column{};
  std::size_t columns = 0;
  bool header_seen = false;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (number == 1 && line.starts_with("\xEF\xBB\xBF")) line.erase(0, 3); // a UTF-8 byte-order mark
    const std::string text = io::trim(line);
    if (!text.empty() && text.front() == '#') {
      const std::string comment = io::trim(text.substr(1));
      if (sample.synthetic.empty() && declares_synthetic(comment)) sample.synthetic = comment;
      continue;
    }
    if (text.empty()) continue;
    const auto fields = io::split_csv_line(text);
    if (!header_seen) {
      for (std::size_t k = 0; k < required.size(); ++k) {
        const auto it = std::find(fields.begin(), fields.end(), required[k]);
        if (it == fields.end())
          fail(number, "header lacks the column '" + required[k] +
                           "' (expected the columns lambda1, lambda2, sigma11_kPa, sigma22_kPa)");
        column[k] = static_cast<std::size_t>(it - fields.begin());
      }
      columns = fields.size();
      header_seen = true;
      continue;
    }
    if (fields.size() != columns)
      fail(number, fmt::format("expected {} comma-separated fields, got {}", columns, fields.size()));
    std::array<double, 4> v{};
    for (std::size_t k = 0; k < required.size(); ++k)
      if (!parse_number(fields[column[k]], v[k]))
        fail(number, required[k] + ": '" + fields[column[k]] + "' is not a finite number");
    if (!(v[0] > 0.0) || !(v[1] > 0.0)) fail(number, "stretches must be positive");
    // Tissue fails at some MPa: a stress beyond 1 GPa is another unit, and squared by the fit it overflows.
    for (std::size_t k = 2; k < 4; ++k)
      if (std::abs(v[k]) > max_sample_stress_kpa)
        fail(number,
             fmt::format("{}: {:g} kPa is beyond the {:g} kPa (1 GPa) a tissue sample holds (another unit?)",
                         required[k], v[k], max_sample_stress_kpa));
    sample.points.push_back({v[0], v[1], v[2], v[3]});
  }
  if (!header_seen)
    throw InputError(name + ":1: empty file (expected a header lambda1,lambda2,sigma11_kPa,sigma22_kPa)");
  if (sample.points.size() < 3)
    throw InputError(
        fmt::format("{}:{}: needs at least 3 data rows, got {}", name, number, sample.points.size()));
  return sample;
}

// ---------------------------------------------------------------------------------------------
// Quality

FitQuality fit_quality(const BiaxialSample& sample,
                       const std::function<std::array<double, 2>(const BiaxialPoint&)>& model)
{
  FitQuality q;
  double sum = 0.0, sum_abs = 0.0;
  for (const auto& pt : sample.points) sum += pt.sigma11 + pt.sigma22;
  const double n = 2.0 * static_cast<double>(sample.points.size());
  const double mean = sum / n;
  double sst = 0.0;
  for (const auto& pt : sample.points) {
    const std::array<double, 2> s = model(pt);
    const double e1 = s[0] - pt.sigma11, e2 = s[1] - pt.sigma22;
    q.sse += e1 * e1 + e2 * e2;
    sum_abs += std::abs(e1) + std::abs(e2);
    sst += (pt.sigma11 - mean) * (pt.sigma11 - mean) + (pt.sigma22 - mean) * (pt.sigma22 - mean);
  }
  q.mae = sum_abs / n;
  q.r_squared = sst > 0.0 ? 1.0 - q.sse / sst : 0.0;
  return q;
}

FitQuality fit_quality(const BiaxialSample& sample, const BiaxialSetup& setup,
                       std::span<const double> parameters)
{
  return fit_quality(sample, [&](const BiaxialPoint& pt) {
    return biaxial_cauchy<double>(setup, parameters.data(), pt.lambda1, pt.lambda2);
  });
}

FitQuality fit_quality(const BiaxialSample& sample, const StrainEnergy& law, const FiberFrame& frame)
{
  return fit_quality(sample, [&](const BiaxialPoint& pt) {
    const auto s = biaxial_cauchy_through_stress(law, frame, pt.lambda1, pt.lambda2); // dyn/cm^2
    return std::array<double, 2>{s[0] / units::kPa, s[1] / units::kPa};
  });
}

// ---------------------------------------------------------------------------------------------
// Fit

namespace {

template <int N>
struct BiaxialResidual {
  BiaxialSetup setup;
  BiaxialPoint point;
  template <class T>
  bool operator()(const T* p, T* r) const
  {
    const auto s = biaxial_cauchy<T>(setup, p, point.lambda1, point.lambda2);
    r[0] = s[0] - T(point.sigma11);
    r[1] = s[1] - T(point.sigma22);
    // A trial step may overflow an exponential (C01 or k2 far too large): report it as a failed
    // evaluation so that Ceres rejects the step and shrinks its trust region.
    using std::isfinite;
    return isfinite(r[0]) && isfinite(r[1]);
  }
};

template <int N>
void add_residuals(ceres::Problem& problem, const BiaxialSample& sample, const BiaxialSetup& setup, double* p)
{
  for (const auto& pt : sample.points)
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<BiaxialResidual<N>, 2, N>(new BiaxialResidual<N>{setup, pt}), nullptr,
        p);
}

struct Solve {
  std::vector<double> parameters;
  double cost = std::numeric_limits<double>::infinity();
  bool converged = false;
};

Solve solve_from(const BiaxialSample& sample, const FitOptions& options, std::vector<double> start)
{
  const LawInfo& info = law_info(options.setup.law);
  ceres::Problem problem;
  double* p = start.data();
  switch (start.size()) {
  case 1:
    add_residuals<1>(problem, sample, options.setup, p);
    break;
  case 3:
    add_residuals<3>(problem, sample, options.setup, p);
    break;
  case 4:
    add_residuals<4>(problem, sample, options.setup, p);
    break;
  default:
    throw std::logic_error("fit_biaxial: unsupported parameter count");
  }
  for (std::size_t i = 0; i < start.size(); ++i) {
    problem.SetParameterLowerBound(p, static_cast<int>(i), 0.0);
    if (info.parameters[i].upper < 1e300)
      problem.SetParameterUpperBound(p, static_cast<int>(i), info.parameters[i].upper);
  }
  const ceres::Solver::Options solver = fit_solver_options(options.max_iterations);
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);
  Solve result;
  result.parameters = std::move(start);
  result.cost = summary.final_cost;
  result.converged = summary.termination_type == ceres::CONVERGENCE;
  if (!std::isfinite(result.cost)) result.cost = std::numeric_limits<double>::infinity();
  return result;
}

/// Non-negative least squares for a handful of unknowns: the best of the unconstrained solutions
/// on every subset of free variables that is feasible (the KKT point is one of them).
Eigen::VectorXd small_nnls(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, double& residual)
{
  const int n = static_cast<int>(A.cols());
  Eigen::VectorXd best = Eigen::VectorXd::Zero(n);
  residual = b.squaredNorm();
  for (int mask = 1; mask < (1 << n); ++mask) {
    std::vector<int> free;
    for (int j = 0; j < n; ++j)
      if (mask & (1 << j)) free.push_back(j);
    Eigen::MatrixXd sub(A.rows(), static_cast<Eigen::Index>(free.size()));
    for (std::size_t k = 0; k < free.size(); ++k) sub.col(static_cast<Eigen::Index>(k)) = A.col(free[k]);
    const Eigen::VectorXd x = sub.colPivHouseholderQr().solve(b);
    if (!x.allFinite() || (x.array() < 0.0).any()) continue;
    const double r = (sub * x - b).squaredNorm();
    if (r < residual) {
      residual = r;
      best.setZero();
      for (std::size_t k = 0; k < free.size(); ++k) best(free[k]) = x(static_cast<Eigen::Index>(k));
    }
  }
  return best;
}

struct Start {
  std::vector<double> parameters;
  double cost;
};

/// Every grid point of the exponents with its optimal non-negative moduli.
std::vector<Start> grid_starts(const BiaxialSample& sample, const BiaxialSetup& setup)
{
  const LawInfo& info = law_info(setup.law);
  const std::size_t np = info.parameters.size();
  std::vector<std::size_t> moduli, exponents;
  for (std::size_t i = 0; i < np; ++i) (info.parameters[i].is_modulus ? moduli : exponents).push_back(i);
  const std::vector<double> exponent_values{0.1, 0.3, 1.0, 3.0, 10.0, 30.0, 100.0, 300.0, 1000.0};
  const std::vector<double> dispersion_values{0.0, 0.1, 0.2, 0.3};
  std::vector<std::vector<double>> values;
  for (const std::size_t e : exponents)
    values.push_back(info.parameters[e].upper < 1e300 ? dispersion_values : exponent_values);

  const auto m = static_cast<Eigen::Index>(2 * sample.points.size());
  Eigen::VectorXd b(m);
  for (std::size_t k = 0; k < sample.points.size(); ++k) {
    b(static_cast<Eigen::Index>(2 * k)) = sample.points[k].sigma11;
    b(static_cast<Eigen::Index>(2 * k + 1)) = sample.points[k].sigma22;
  }
  std::vector<Start> starts;
  std::vector<std::size_t> index(exponents.size(), 0);
  while (true) {
    std::vector<double> p(np, 0.0);
    for (std::size_t k = 0; k < exponents.size(); ++k) p[exponents[k]] = values[k][index[k]];
    // The stresses are linear in the moduli: one column per modulus (that modulus 1, the others 0).
    Eigen::MatrixXd A(m, static_cast<Eigen::Index>(moduli.size()));
    for (std::size_t j = 0; j < moduli.size(); ++j) {
      std::vector<double> q = p;
      q[moduli[j]] = 1.0;
      for (std::size_t k = 0; k < sample.points.size(); ++k) {
        const auto s =
            biaxial_cauchy<double>(setup, q.data(), sample.points[k].lambda1, sample.points[k].lambda2);
        A(static_cast<Eigen::Index>(2 * k), static_cast<Eigen::Index>(j)) = s[0];
        A(static_cast<Eigen::Index>(2 * k + 1), static_cast<Eigen::Index>(j)) = s[1];
      }
    }
    if (A.allFinite()) {
      double residual = 0.0;
      const Eigen::VectorXd x = small_nnls(A, b, residual);
      for (std::size_t j = 0; j < moduli.size(); ++j) p[moduli[j]] = x(static_cast<Eigen::Index>(j));
      // A zero modulus would leave its exponent unidentifiable; start slightly inside.
      for (const std::size_t j : moduli) p[j] = std::max(p[j], 1e-3);
      starts.push_back({p, residual});
    }
    std::size_t k = 0;
    while (k < index.size() && ++index[k] == values[k].size()) index[k++] = 0;
    if (k == index.size()) break;
  }
  std::sort(starts.begin(), starts.end(), [](const Start& a, const Start& b) { return a.cost < b.cost; });
  return starts;
}

} // namespace

FitResult fit_biaxial(const BiaxialSample& sample, const FitOptions& options)
{
  const LawInfo& info = law_info(options.setup.law);
  if (options.setup.law != LawKind::hgo && options.setup.fiber_angle != 0.0)
    throw InputError("fit: a fiber angle applies to the two-family law hgo only (" + info.name +
                     " has its fiber along axis 1)");
  if (2 * sample.points.size() < info.parameters.size())
    throw InputError(fmt::format("{}: too few data points for the {} parameters of {}", sample.name,
                                 info.parameters.size(), info.name));
  const auto starts = grid_starts(sample, options.setup);
  Solve best;
  FitResult result;
  const std::size_t count =
      std::min<std::size_t>(starts.size(), static_cast<std::size_t>(std::max(1, options.starts)));
  for (std::size_t s = 0; s < count; ++s) {
    Solve solve = solve_from(sample, options, starts[s].parameters);
    ++result.solves;
    if (solve.cost < best.cost) best = std::move(solve);
  }
  if (best.parameters.empty()) throw RunError("fit: no start gave finite stresses for " + info.name);
  result.parameters = best.parameters;
  result.converged = best.converged;
  result.quality = fit_quality(sample, options.setup, result.parameters);
  return result;
}

} // namespace ibvalve::materials
