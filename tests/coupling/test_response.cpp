// Growth rate and frequency of synthetic signals.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "shellflow/coupling/response.h"

namespace shellflow::coupling {
namespace {

TEST(ResponseFit, RecoversGrowthAndFrequencyOfADampedOrGrowingSine) {
  for (const double sigma : {-20.0, 0.0, 51.6}) {
    std::vector<double> t, w;
    const double f = 123.4, dt = 1e-4;
    for (int i = 0; i <= 1400; ++i) {
      t.push_back(i * dt);
      w.push_back(1e-3 * std::exp(sigma * t.back()) * std::sin(2 * M_PI * f * t.back() + 0.3));
    }
    const ResponseFit fit = fit_response(t, w, 0.01, 0.14);
    EXPECT_GT(fit.extrema, 20);
    EXPECT_NEAR(fit.growth_rate, sigma, 0.05) << "sigma " << sigma;
    EXPECT_NEAR(fit.frequency_hz, f, 0.01 * f);
  }
}

TEST(ResponseFit, NoiseWidensTheErrorBarButNotTheEstimate) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 1e-6);
  std::vector<double> t, w;
  for (int i = 0; i <= 2000; ++i) {
    t.push_back(i * 5e-5);
    w.push_back(1e-4 * std::exp(30.0 * t.back()) * std::cos(2 * M_PI * 80.0 * t.back()) + noise(rng));
  }
  const ResponseFit fit = fit_response(t, w, 0.0, 0.1);
  EXPECT_NEAR(fit.growth_rate, 30.0, 1.0);
  EXPECT_GT(fit.growth_rate_error, 0.0);
  EXPECT_LT(std::abs(fit.growth_rate - 30.0), 5.0 * fit.growth_rate_error + 0.5);
  EXPECT_NEAR(fit.frequency_hz, 80.0, 0.5);
}

TEST(ResponseFit, TooFewExtremaGiveNoRates) {
  const std::vector<double> t = {0, 1, 2, 3}, w = {0, 1, 0, -1};
  const ResponseFit fit = fit_response(t, w, 0, 3);
  EXPECT_LT(fit.extrema, 3);
  EXPECT_EQ(fit.growth_rate, 0.0);
}

}  // namespace
}  // namespace shellflow::coupling
