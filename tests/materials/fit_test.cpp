// Fitting (materials/fitting.hpp): known parameters are recovered from noise-free data of each law;
// on noisy W1 data W1 fits better than W3; bad CSV files give one line naming file:line.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <iostream>
#include <random>

#include <gtest/gtest.h>

#include "base/errors.hpp"
#include "materials/fitting.hpp"

namespace ibvalve::materials {
namespace {

/// Stretch-controlled protocols: straight paths from (1, 1) to (l1max, l2max), 15 points each.
BiaxialSample synthetic_sample(const BiaxialSetup& setup, const std::vector<double>& parameters,
                               double noise_relative, double noise_absolute, unsigned seed)
{
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  BiaxialSample sample;
  sample.name = "synthetic";
  const double ends[][2] = {{1.10, 1.25}, {1.10, 1.15}, {1.10, 1.05}, {1.06, 1.25}, {1.03, 1.25}};
  for (const auto& end : ends)
    for (int k = 1; k <= 15; ++k) {
      const double t = k / 15.0;
      BiaxialPoint p{1.0 + t * (end[0] - 1.0), 1.0 + t * (end[1] - 1.0), 0.0, 0.0};
      const auto s = biaxial_cauchy<double>(setup, parameters.data(), p.lambda1, p.lambda2);
      p.sigma11 = s[0] * (1.0 + noise_relative * normal(rng)) + noise_absolute * normal(rng);
      p.sigma22 = s[1] * (1.0 + noise_relative * normal(rng)) + noise_absolute * normal(rng);
      sample.points.push_back(p);
    }
  return sample;
}

struct RecoveryCase {
  const char* label;
  BiaxialSetup setup;
  std::vector<double> parameters; // kPa for moduli
};

class Recovery : public ::testing::TestWithParam<RecoveryCase> {};

TEST_P(Recovery, NoiseFreeDataGiveBackTheParameters)
{
  const auto& c = GetParam();
  const BiaxialSample sample = synthetic_sample(c.setup, c.parameters, 0.0, 0.0, 1);
  FitOptions options;
  options.setup = c.setup;
  const auto start = std::chrono::steady_clock::now();
  const FitResult fit = fit_biaxial(sample, options);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  double worst = 0.0;
  for (std::size_t i = 0; i < c.parameters.size(); ++i)
    worst = std::max(worst, std::abs(fit.parameters[i] - c.parameters[i]) / c.parameters[i]);
  std::cout << c.label << ": max relative parameter error " << worst << ", R^2 = " << fit.quality.r_squared
            << ", MAE = " << fit.quality.mae << " kPa, " << fit.solves << " solves, " << seconds << " s\n";
  EXPECT_LT(worst, 1e-4);
  EXPECT_GT(fit.quality.r_squared, 0.9999);
}

INSTANTIATE_TEST_SUITE_P(Laws, Recovery,
                         ::testing::Values(RecoveryCase{"neo_hookean", {LawKind::neo_hookean}, {50.0}},
                                           RecoveryCase{"W1", {LawKind::W1}, {1.21, 7.99, 24.23, 57.62}},
                                           RecoveryCase{"W2", {LawKind::W2}, {1.18, 55.04, 8.08, 54.0}},
                                           RecoveryCase{"W3", {LawKind::W3}, {19.59, 12.94, 77.79}},
                                           RecoveryCase{"hgo",
                                                        {LawKind::hgo, FiberCompression::excluded,
                                                         40.0 * M_PI / 180.0},
                                                        {5.0, 20.0, 10.0, 0.1}}),
                         [](const auto& info) { return std::string(info.param.label); });

TEST(Fit, OnNoisyW1DataW1FitsBetterThanW3)
{
  // 3 % relative and 0.5 kPa absolute Gaussian noise on W1 data with the study's W1 parameters.
  const BiaxialSample sample = synthetic_sample({LawKind::W1}, {1.21, 7.99, 24.23, 57.62}, 0.03, 0.5, 2021);
  FitOptions w1, w3;
  w1.setup.law = LawKind::W1;
  w3.setup.law = LawKind::W3;
  const FitResult a = fit_biaxial(sample, w1), b = fit_biaxial(sample, w3);
  std::cout << "noisy W1 data: W1 fit R^2 = " << a.quality.r_squared << ", MAE = " << a.quality.mae
            << " kPa; W3 fit R^2 = " << b.quality.r_squared << ", MAE = " << b.quality.mae << " kPa\n";
  EXPECT_GT(a.quality.r_squared, b.quality.r_squared);
  EXPECT_LT(a.quality.mae, b.quality.mae);
  // The noise is small: W1's parameters come back to within a few per cent.
  const double truth[] = {1.21, 7.99, 24.23, 57.62};
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(a.parameters[i], truth[i], 0.1 * truth[i]);
}

TEST(Fit, TheDefaultFourStartsReachTheOptimumOfFortyStarts)
{
  // Noisy W1 data fitted by every law: a misfit law has the hardest landscape. The default multi-start
  // must find the same least-squares optimum as ten times more starts.
  const BiaxialSample sample = synthetic_sample({LawKind::W1}, {1.21, 7.99, 24.23, 57.62}, 0.03, 0.5, 7);
  for (const LawKind kind : {LawKind::neo_hookean, LawKind::W1, LawKind::W2, LawKind::W3, LawKind::hgo}) {
    FitOptions few, many;
    few.setup.law = many.setup.law = kind;
    many.starts = 40;
    const FitResult a = fit_biaxial(sample, few), b = fit_biaxial(sample, many);
    std::cout << law_info(kind).name << " on noisy W1 data: SSE with 4 starts " << a.quality.sse << ", with "
              << b.solves << " starts " << b.quality.sse << " kPa^2\n";
    EXPECT_LE(a.quality.sse, b.quality.sse * (1.0 + 1e-8)) << law_info(kind).name;
  }
}

TEST(Fit, QualityOfTheExactParametersIsPerfect)
{
  const BiaxialSample sample = synthetic_sample({LawKind::W3}, {19.59, 12.94, 77.79}, 0.0, 0.0, 1);
  const std::vector<double> exact{19.59, 12.94, 77.79};
  const FitQuality q = fit_quality(sample, {LawKind::W3}, exact);
  EXPECT_LT(q.mae, 1e-12);
  EXPECT_DOUBLE_EQ(q.r_squared, 1.0);
}

class Csv : public ::testing::Test {
 protected:
  std::filesystem::path write(const std::string& name, const std::string& text)
  {
    const auto dir =
        std::filesystem::temp_directory_path() / (fmt::format("ibvalve_fit_test_{}", ::getpid()));
    std::filesystem::create_directories(dir);
    const auto path = dir / name;
    std::ofstream(path) << text;
    return path;
  }
  std::string error_of(const std::filesystem::path& path)
  {
    try {
      read_biaxial_csv(path);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
};

TEST_F(Csv, ReadsColumnsInAnyOrderWithCommentsAndExtraColumns)
{
  const auto path = write("good.csv", "# synthetic\nprotocol,sigma22_kPa,lambda1,lambda2,sigma11_kPa\n"
                                      "1,0.5,1.01,1.02,3.0\n1,1.5,1.02,1.04,7.0\n\n1,2.5,1.03,1.06,12.0\n");
  const BiaxialSample s = read_biaxial_csv(path);
  ASSERT_EQ(s.points.size(), 3u);
  EXPECT_DOUBLE_EQ(s.points[1].lambda1, 1.02);
  EXPECT_DOUBLE_EQ(s.points[1].lambda2, 1.04);
  EXPECT_DOUBLE_EQ(s.points[1].sigma11, 7.0);
  EXPECT_DOUBLE_EQ(s.points[1].sigma22, 1.5);
  // Spreadsheet exports: a byte-order mark and CRLF line ends.
  const auto bom =
      write("bom.csv", "\xEF\xBB\xBFlambda1,lambda2,sigma11_kPa,sigma22_kPa\r\n1.01,1.02,3.0,0.5\r\n"
                       "1.02,1.04,7.0,1.5\r\n1.03,1.06,12.0,2.5\r\n");
  EXPECT_EQ(read_biaxial_csv(bom).points.size(), 3u);
}

TEST_F(Csv, ACommentWhoseFirstWordIsSyntheticDeclaresTheDataGeneratedNotMeasured)
{
  const std::string rows = "lambda1,lambda2,sigma11_kPa,sigma22_kPa\n1.01,1.02,3,0.5\n1.02,1.04,7,1.5\n"
                           "1.03,1.06,12,2.5\n";
  EXPECT_EQ(read_biaxial_csv(write("declared.csv", "# porcine sample 4\n# SYNTHETIC: drawn from W1\n" + rows))
                .synthetic,
            "SYNTHETIC: drawn from W1");
  EXPECT_EQ(read_biaxial_csv(write("lower.csv", "#synthetic\n" + rows)).synthetic, "synthetic");
  EXPECT_EQ(read_biaxial_csv(write("measured.csv", "# measured, not synthetic\n" + rows)).synthetic, "");
  EXPECT_EQ(read_biaxial_csv(write("word.csv", "# synthetically aged tissue\n" + rows)).synthetic, "");
  // The bundled samples are drawn from W1's own curves, and say so.
  for (const char* name : {"sample1.csv", "sample2.csv", "sample3.csv"}) {
    const BiaxialSample sample = read_biaxial_csv(std::filesystem::path(IBVALVE_BIAXIAL_EXAMPLES) / name);
    EXPECT_NE(sample.synthetic.find("(not measured): W1 with"), std::string::npos) << name;
  }
}

TEST_F(Csv, BadFilesNameFileAndLine)
{
  auto p = write("bad_number.csv", "lambda1,lambda2,sigma11_kPa,sigma22_kPa\n1.0,1.0,0,0\n1.1,1.1,abc,2\n");
  EXPECT_EQ(error_of(p), p.string() + ":3: sigma11_kPa: 'abc' is not a finite number");
  p = write("bad_header.csv", "# c\nlambda1,lambda2,sigma11,sigma22_kPa\n");
  EXPECT_EQ(error_of(p).rfind(p.string() + ":2: header lacks the column 'sigma11_kPa'", 0), 0u)
      << error_of(p);
  p = write("bad_fields.csv", "lambda1,lambda2,sigma11_kPa,sigma22_kPa\n1.0,1.0,0\n");
  EXPECT_EQ(error_of(p), p.string() + ":2: expected 4 comma-separated fields, got 3");
  p = write("bad_stretch.csv", "lambda1,lambda2,sigma11_kPa,sigma22_kPa\n1.0,1.0,0,0\n-1.0,1.0,0,0\n");
  EXPECT_EQ(error_of(p), p.string() + ":3: stretches must be positive");
  EXPECT_EQ(error_of("/nonexistent/data.csv"), "/nonexistent/data.csv: no such file");
}

} // namespace
} // namespace ibvalve::materials
