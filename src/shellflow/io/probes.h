#pragma once
// Probes declared in a case file, sampled after every step and written to
// OUTDIR/probes.csv (`time,<probe names...>`).
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "shellflow/io/case.h"
#include "shellflow/io/case_meshes.h"
#include "shellflow/io/probe_writer.h"

namespace shellflow::io {

/// A point field of one mesh, as a solver exposes it to the probes: `components` values per
/// node, node after node in `values`, or, when `at` is set, computed on demand by
/// `at(node, out)` (writes the node's `components` values, at most 9, to out): the probes
/// then read their few nodes without the whole field being built.
struct FieldView {
  std::string_view mesh;      ///< "fluid", "space", "shell"
  std::string_view quantity;  ///< "displacement", "pressure", ...
  int components = 1;
  std::span<const double> values;
  std::function<void(Index node, double* out)> at;
};

class ProbeSet {
 public:
  /// Locates every probe in its mesh once: a point probe in a tetrahedral mesh must lie in
  /// a cell; in a shell mesh it is moved to the closest point of the surface, which must lie
  /// within 1e-6 of the mesh size. Throws InputError at the probe's line otherwise.
  ProbeSet(const std::vector<Probe>& probes, const CaseMeshes& meshes, const std::filesystem::path& csv_path,
           OutputMode mode = OutputMode::create);
  ~ProbeSet();

  /// Appends one CSV row and returns its values. Every probed field must be among `fields`
  /// (the first view of a mesh and quantity counts). A time equal to the last row's is not
  /// written again: a run whose solver fails records its last valid state once more (to
  /// write its fields), and probes.csv holds one row per state.
  std::vector<double> record(double time, std::span<const FieldView> fields);
  /// Values of the probes for these fields, in declaration order (what record() writes).
  std::vector<double> sample(std::span<const FieldView> fields) const;
  std::size_t size() const;
  /// The nodes of `mesh` the probes read (sorted, each once).
  std::vector<Index> nodes(std::string_view mesh) const;
  ProbeWriter& writer() { return writer_; }

 private:
  struct Located;
  std::vector<Located> probes_;
  ProbeWriter writer_;
  std::optional<double> last_time_;  ///< of the last row written
};

}  // namespace shellflow::io
