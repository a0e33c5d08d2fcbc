#pragma once
// The quality history of a moving fluid mesh (motion_quality.csv of a mesh-motion run,
// mesh_quality.csv of a coupled run): per step the fluid mesh's smallest and mean
// mean-ratio quality, the smallest ratio to the initial quality, the inverted count and,
// with a space mesh, its smallest vertex quality and relative Jacobian (the early warning:
// it turns negative before the fluid mesh inverts).
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "shellflow/io/probe_writer.h"
#include "shellflow/mesh/quality.h"
#include "shellflow/motion/space_mesh.h"

namespace shellflow::run {

class QualityHistory {
 public:
  /// `leading`: columns the run puts in front (a mesh-motion run's mode amplitudes).
  /// `fluid`: the mesh whose nodes the positions of fluid() follow; its initial quality is
  /// the reference of the ratio.
  QualityHistory(const std::filesystem::path& csv, std::vector<std::string> leading, const mesh::Mesh& fluid,
                 const motion::SpaceMesh* space, io::OutputMode mode);
  /// The fluid mesh's quality at positions x.
  mesh::QualitySummary fluid(std::span<const Vec3> x) const;
  /// Appends the row of time t: the leading values, then the fluid's and space mesh's figures.
  void append(double t, const mesh::QualitySummary& fluid, std::span<const double> leading = {});
  io::ProbeWriter& csv() { return csv_; }

 private:
  const mesh::Mesh& fluid_;
  const motion::SpaceMesh* space_;
  std::vector<double> reference_;
  io::ProbeWriter csv_;
};

}  // namespace shellflow::run
