#include "shellflow/run/response_output.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>

#include "shellflow/core/error.h"
#include "shellflow/core/output_file.h"
#include "shellflow/coupling/response.h"

namespace shellflow::run {

namespace {
/// Fewer shell steps per period of the response get a warning (Newmark's period error
/// (omega dt)^2 / 12 is 0.8 % at 20).
constexpr double kMinStepsPerPeriod = 20.0;
}  // namespace

ResponseOutput::ResponseOutput(const io::Case& c, std::filesystem::path outdir)
    : case_(c), outdir_(std::move(outdir)), index_(io::response_probe(c)) {}

void ResponseOutput::sample(double t, std::span<const double> probes) {
  if (!index_) return;
  t_.push_back(t);
  w_.push_back(probes[*index_]);
}

void ResponseOutput::write() const {
  if (!index_) {
    spdlog::info(
        "no response analysis: the case has no probe of shell.displacement; name the probe to analyse in "
        "coupling.response.probe");
    return;
  }
  const io::ResponseSection& rs = case_.coupling->response;
  const std::string& name = case_.probes[*index_].name;
  const coupling::ResponseAnalysis a =
      coupling::analyse_response(t_, w_, {.t_start = rs.t_start, .t_end = rs.t_end, .lco_cycles = rs.lco_cycles});
  write_file_atomically(outdir_ / "response.json", coupling::response_to_json(a, name) + '\n');
  if (a.extrema < 3) {
    spdlog::info(
        "response of {} on [{:.6g}, {:.6g}] s: {} extrema, too few for a growth rate and a frequency (3 "
        "needed)",
        name, a.t_start, a.t_end, a.extrema);
    return;
  }
  spdlog::info("response of {} on [{:.6g}, {:.6g}] s ({} extrema): growth rate {:.4g} ± {:.2g} 1/s, {:.5g} Hz; {}",
               name, a.t_start, a.t_end, a.extrema, a.growth_rate, a.growth_rate_error, a.frequency_hz,
               a.lco ? fmt::format("limit cycle amplitude {:.4g} ± {:.2g} at {:.5g} ± {:.2g} Hz (last {} cycles)",
                                   a.lco->amplitude, a.lco->amplitude_spread, a.lco->frequency_hz,
                                   a.lco->frequency_spread, a.lco->cycles)
                     : fmt::format("not saturated (envelope change {:.3g} over the last {} cycles)", a.envelope_change,
                                   rs.lco_cycles));
  // The shell step against the period found: with too few steps per period Newmark's period
  // error and the coupling's lag change the growth rate, even its sign.
  const double dt = case_.time ? case_.time->step : 0.0;
  if (dt > 0.0 && a.frequency_hz > 0.0 && 1.0 / (a.frequency_hz * dt) < kMinStepsPerPeriod)
    spdlog::warn(
        "time.step {:.6g} s gives {:.1f} steps per period of the response ({:.5g} Hz, period {:.6g} s), fewer than "
        "{:.0f}: the growth rate is not resolved (its sign may be wrong); use time.step <= {:.3g} s",
        dt, 1.0 / (a.frequency_hz * dt), a.frequency_hz, 1.0 / a.frequency_hz, kMinStepsPerPeriod,
        1.0 / (a.frequency_hz * kMinStepsPerPeriod));
}

void ResponseOutput::write_on_error() const noexcept {
  try {
    write();
  } catch (...) {  // the error on its way out is the one to report
  }
}

void ResponseOutput::save(ArchiveWriter& out) const {
  out.put(t_);
  out.put(w_);
}

void ResponseOutput::restore(ArchiveReader& in) {
  t_ = in.get_vector<double>();
  w_ = in.get_vector<double>();
  if (t_.size() != w_.size())
    throw Error(
        fmt::format("{}: damaged (a response history of {} times and {} values)", in.what(), t_.size(), w_.size()));
  for (std::size_t i = 0; i < t_.size(); ++i)
    if (!std::isfinite(t_[i]) || (i > 0 && t_[i] < t_[i - 1]))
      throw Error(fmt::format("{}: damaged (the response history's times are not finite and increasing)", in.what()));
}

}  // namespace shellflow::run
