#pragma once
// The response analysis of a coupled run: the history of the probe coupling.response.probe
// names (by default the first probe of shell.displacement), analysed at the end into
// OUTDIR/response.json (growth rate, frequency, limit cycle).
#include <filesystem>
#include <optional>
#include <span>
#include <vector>

#include "shellflow/core/archive.h"
#include "shellflow/io/case.h"

namespace shellflow::run {

class ResponseOutput {
 public:
  /// Throws InputError when coupling.response.probe names no probe.
  ResponseOutput(const io::Case& c, std::filesystem::path outdir);
  /// Records the response probe's value of a probe row.
  void sample(double t, std::span<const double> probes);
  /// Analyses the history and writes response.json (nothing without a response probe).
  void write() const;
  /// The same for a run stopped by an error, which must not hide that error.
  void write_on_error() const noexcept;
  void save(ArchiveWriter& out) const;
  void restore(ArchiveReader& in);

 private:
  const io::Case& case_;
  std::filesystem::path outdir_;
  std::optional<std::size_t> index_;
  std::vector<double> t_, w_;
};

}  // namespace shellflow::run
