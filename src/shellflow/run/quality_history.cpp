#include "shellflow/run/quality_history.h"

namespace shellflow::run {
namespace {

std::vector<std::string> columns(std::vector<std::string> leading, bool space) {
  for (auto name : {"fluid_min_quality", "fluid_mean_quality", "fluid_min_quality_ratio", "fluid_inverted"})
    leading.emplace_back(name);
  if (space)
    for (auto name : {"space_min_quality", "space_min_relative_jacobian"}) leading.emplace_back(name);
  return leading;
}

}  // namespace

QualityHistory::QualityHistory(const std::filesystem::path& csv, std::vector<std::string> leading,
                               const mesh::Mesh& fluid, const motion::SpaceMesh* space, io::OutputMode mode)
    : fluid_(fluid),
      space_(space),
      reference_(mesh::cell_qualities(fluid)),
      csv_(csv, columns(std::move(leading), space != nullptr), mode) {}

mesh::QualitySummary QualityHistory::fluid(std::span<const Vec3> x) const {
  return mesh::summarize_quality(fluid_, x, reference_);
}

void QualityHistory::append(double t, const mesh::QualitySummary& q, std::span<const double> leading) {
  std::vector<double> row(leading.begin(), leading.end());
  row.insert(row.end(), {q.min, q.mean, q.min_ratio, static_cast<double>(q.inverted)});
  if (space_) {
    row.push_back(mesh::summarize_quality(space_->mesh(), space_->current_positions()).min);
    row.push_back(space_->min_relative_jacobian());
  }
  csv_.append(t, row);
}

}  // namespace shellflow::run
