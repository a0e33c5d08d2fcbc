// Growth rate, frequency and limit cycle of synthetic signals.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <span>
#include <stdexcept>
#include <string>

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

// ---- analyse_response -----------------------------------------------------------------------

/// w(t) sampled at t = i dt, i = 0 ... n.
template <class F>
void sample(F&& f, double dt, int n, std::vector<double>& t, std::vector<double>& w) {
  t.clear();
  w.clear();
  for (int i = 0; i <= n; ++i) {
    t.push_back(i * dt);
    w.push_back(f(t.back()));
  }
}

TEST(ResponseAnalysis, GrowthAndFrequencyOfADampedConstantOrGrowingSineInAUserWindow) {
  for (const double sigma : {-20.0, 0.0, 51.6}) {
    std::vector<double> t, w;
    const double f = 123.4;
    sample([&](double x) { return 1e-3 * std::exp(sigma * x) * std::sin(2 * M_PI * f * x + 0.3); }, 1e-4, 1400, t, w);
    const ResponseAnalysis a = analyse_response(t, w, {.t_start = 0.01, .t_end = 0.12});
    EXPECT_EQ(a.t_start, 0.01);
    EXPECT_EQ(a.t_end, 0.12);
    EXPECT_GT(a.extrema, 20);
    EXPECT_EQ(a.peak_times.size(), std::size_t(a.extrema));
    EXPECT_GE(a.peak_times.front(), 0.01);
    EXPECT_LE(a.peak_times.back(), 0.12);
    EXPECT_NEAR(a.frequency_hz, f, 1e-3 * f) << "sigma " << sigma;
    EXPECT_NEAR(a.growth_rate, sigma, 0.01 * 51.6) << "sigma " << sigma;  // 1 % of the largest
    EXPECT_LT(a.growth_rate_error, 1e-3);
    // Only the constant amplitude is a limit cycle. Over the last 5 cycles (11 extrema) the
    // 6 peaks of one sign grow by q = exp(|sigma| / f) per cycle: (max - min) / mean =
    // 6 (q^5 - 1)(q - 1) / (q^6 - 1) = 0.80 (decaying) and 1.96 (growing).
    const double q = std::exp(std::abs(sigma) / f);
    const double change = sigma == 0.0 ? 0.0 : 6 * (std::pow(q, 5) - 1) * (q - 1) / (std::pow(q, 6) - 1);
    EXPECT_NEAR(a.envelope_change, change, 1e-3 * change + 1e-6) << "sigma " << sigma;
    EXPECT_EQ(a.saturated, sigma == 0.0) << "sigma " << sigma << ", envelope change " << a.envelope_change;
    EXPECT_EQ(a.lco.has_value(), sigma == 0.0);
  }
}

TEST(ResponseAnalysis, NoiseLeavesFrequencyAndGrowthWithinTheirTolerances) {
  // 1 % noise on the first peaks, 0.05 % on the last: the zero crossings keep the frequency,
  // the envelope fit the growth (noise lifts the small early peaks a little, sigma comes out
  // low by up to 0.7 % over 20 seeds).
  for (const unsigned seed : {1u, 2u, 3u, 6u, 13u}) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0.0, 1e-6);
    std::vector<double> t, w;
    sample([&](double x) { return 1e-4 * std::exp(30.0 * x) * std::cos(2 * M_PI * 80.0 * x) + noise(rng); }, 5e-5, 2000,
           t, w);
    const ResponseAnalysis a = analyse_response(t, w);
    EXPECT_EQ(a.t_start, 0.0);
    EXPECT_NEAR(a.t_end, 0.1, 1e-15);
    EXPECT_NEAR(a.frequency_hz, 80.0, 1e-3 * 80.0) << "seed " << seed;
    EXPECT_NEAR(a.growth_rate, 30.0, 0.01 * 30.0) << "seed " << seed;
    EXPECT_GT(a.growth_rate_error, 0.01);  // the noise shows in the error bar
    EXPECT_FALSE(a.saturated);
  }
}

TEST(ResponseAnalysis, ABeatHasTheStrongerFrequencyAWideErrorBarAndIsNotSaturated) {
  // Two close modes, 100 Hz and half as strong 110 Hz: the envelope beats between 0.5 and
  // 1.5 every 0.1 s (maxima at t = 0.1, 0.2, ...). The phase of the sum follows the stronger
  // mode (it wobbles within a beat and returns every beat), so the extrema and crossings give
  // about 100 Hz (not the mean 105 Hz); the envelope has no trend but does not fit a line.
  std::vector<double> t, w;
  sample(
      [](double x) { return 1e-3 * (std::sin(2 * M_PI * 100 * x + 0.3) + 0.5 * std::sin(2 * M_PI * 110 * x + 0.3)); },
      1e-4, 4000, t, w);
  const ResponseAnalysis a = analyse_response(t, w);
  EXPECT_NEAR(a.frequency_hz, 100.0, 0.005 * 100.0);
  EXPECT_LT(std::abs(a.growth_rate), 2.0 * a.growth_rate_error);
  EXPECT_GT(a.growth_rate_error, 0.1);  // a pure sine gives < 1e-6
  EXPECT_GT(a.envelope_change, 0.5);
  EXPECT_FALSE(a.saturated);
  EXPECT_FALSE(a.lco.has_value());
  // Ending the window at a beat maximum centres the last 5 cycles on it: the envelope is flat
  // on average there (a line through it has no slope), yet not constant.
  const ResponseAnalysis at_max = analyse_response(t, w, {.t_end = 0.2 + 2.5 / 100});
  EXPECT_GT(at_max.envelope_change, 0.2);
  EXPECT_FALSE(at_max.saturated);
}

TEST(ResponseAnalysis, ASaturatedResponseGivesTheLimitCycleAmplitudeAndFrequency) {
  // Exponential growth (60 1/s) into a limit cycle of amplitude A: A tanh(1e-3 exp(60 t)) sin.
  const double amplitude = 2.5e-3, f = 77.3, sigma = 60.0;
  std::vector<double> t, w;
  sample([&](double x) { return amplitude * std::tanh(1e-3 * std::exp(sigma * x)) * std::sin(2 * M_PI * f * x); }, 1e-4,
         3000, t, w);
  const ResponseAnalysis a = analyse_response(t, w, {.lco_cycles = 8});
  EXPECT_TRUE(a.saturated) << a.envelope_change;
  ASSERT_TRUE(a.lco.has_value());
  EXPECT_EQ(a.lco->cycles, 8);
  EXPECT_NEAR(a.lco->amplitude, amplitude, 0.01 * amplitude);
  EXPECT_LT(a.lco->amplitude_spread, 1e-3 * amplitude);
  EXPECT_NEAR(a.lco->frequency_hz, f, 1e-3 * f);
  EXPECT_LT(a.lco->frequency_spread, 1e-3 * f);
  EXPECT_NEAR(a.last_amplitude, amplitude, 0.01 * amplitude);
  // The growth phase in its own window (tanh x = x to 0.05 % there).
  const ResponseAnalysis growing = analyse_response(t, w, {.t_start = 0.005, .t_end = 0.06});
  EXPECT_NEAR(growing.growth_rate, sigma, 0.01 * sigma);
  EXPECT_NEAR(growing.frequency_hz, f, 1e-3 * f);
  EXPECT_FALSE(growing.saturated);
  // Just after the knee (about 0.115 s) the envelope still rises: not saturated yet.
  EXPECT_FALSE(analyse_response(t, w, {.t_end = 0.12}).saturated);
}

TEST(ResponseAnalysis, AnAsymmetricLimitCycleIsSaturatedWithTheMeanOfItsPeaks) {
  // Positive peaks 1.2 A, negative 0.8 A (a static offset that grows with the motion).
  const double amplitude = 1e-3, f = 50.0;
  std::vector<double> t, w;
  sample([&](double x) { return amplitude * std::tanh(2.0 * std::exp(10.0 * x)) * (std::sin(2 * M_PI * f * x) + 0.2); },
         2e-4, 2500, t, w);
  const ResponseAnalysis a = analyse_response(t, w, {.t_start = 0.3, .lco_cycles = 5});
  ASSERT_TRUE(a.lco.has_value()) << a.envelope_change;
  EXPECT_NEAR(a.lco->amplitude, amplitude, 0.01 * amplitude);
  EXPECT_NEAR(a.lco->amplitude_spread, 0.2 * amplitude * std::sqrt(10.0 / 9.0), 0.01 * amplitude);
  EXPECT_NEAR(a.lco->frequency_hz, f, 1e-3 * f);
}

TEST(ResponseAnalysis, OneCycleHasNoFrequencySpreadAndBadOptionsAreRefused) {
  std::vector<double> t, w;
  sample([](double x) { return std::sin(2 * M_PI * 10 * x); }, 1e-3, 1000, t, w);
  const ResponseAnalysis a = analyse_response(t, w, {.lco_cycles = 1});
  ASSERT_TRUE(a.lco.has_value());
  EXPECT_NEAR(a.lco->frequency_hz, 10.0, 1e-3 * 10.0);
  EXPECT_TRUE(std::isnan(a.lco->frequency_spread));
  EXPECT_THROW(analyse_response(t, w, {.lco_cycles = 0}), std::invalid_argument);
  EXPECT_THROW(analyse_response(t, std::span<const double>(w).first(10)), std::invalid_argument);
}

TEST(ResponseAnalysis, JsonWritesNonFiniteNumbersAsNull) {
  const std::vector<double> t = {0, 1, 2, 3}, w = {0, 1, 0, -1};
  const ResponseAnalysis few = analyse_response(t, w);
  EXPECT_LT(few.extrema, 3);
  EXPECT_TRUE(std::isnan(few.growth_rate));
  const std::string json = response_to_json(few, "w_x0600");
  EXPECT_NE(json.find("\"probe\": \"w_x0600\""), std::string::npos) << json;
  EXPECT_NE(json.find("\"window\": [0, 3]"), std::string::npos) << json;
  EXPECT_NE(json.find("\"growth_rate\": null"), std::string::npos) << json;
  EXPECT_NE(json.find("\"frequency_hz\": null"), std::string::npos) << json;
  EXPECT_NE(json.find("\"lco\": null"), std::string::npos) << json;
  EXPECT_NE(json.find("\"saturated\": false"), std::string::npos) << json;
  EXPECT_EQ(json.find("nan"), std::string::npos) << json;
  EXPECT_EQ(json.find("inf"), std::string::npos) << json;

  std::vector<double> t2, w2;
  sample([](double x) { return 2e-3 * std::sin(2 * M_PI * 10 * x); }, 1e-3, 1000, t2, w2);
  const ResponseAnalysis lco = analyse_response(t2, w2, {.lco_cycles = 1});
  const std::string j2 = response_to_json(lco, "a\"b");
  EXPECT_NE(j2.find("\"probe\": \"a\\\"b\""), std::string::npos) << j2;
  EXPECT_NE(j2.find("\"saturated\": true"), std::string::npos) << j2;
  EXPECT_NE(j2.find("\"lco\": {\"amplitude\": 0.002"), std::string::npos) << j2;
  EXPECT_NE(j2.find("\"frequency_spread\": null, \"cycles\": 1}"), std::string::npos) << j2;
  EXPECT_EQ(std::count(j2.begin(), j2.end(), '{'), std::count(j2.begin(), j2.end(), '}'));
}

}  // namespace
}  // namespace shellflow::coupling
