#include "field_writers.h"

#include <fmt/format.h>

#include "shellflow/io/mesh_output.h"
#include "shellflow/shell/shell_stress.h"

namespace shellflow::app {
namespace {

/// One nodal field for the VTU: name, components, values (owned).
using OwnedField = std::tuple<std::string, int, std::vector<double>>;

/// Nodal stress tensors (9 components, row-major) and their von Mises values on the bottom,
/// middle and top surfaces, for the VTU.
std::vector<OwnedField> stress_fields(const shell::ShellModel& model, const Eigen::VectorXd& u,
                                      io::OutputSection::ShellStress kind) {
  std::vector<OwnedField> out;
  if (kind == io::OutputSection::ShellStress::none) return out;
  const bool cauchy = kind == io::OutputSection::ShellStress::cauchy;
  const auto measure =
      cauchy ? shell::StressMeasure::cauchy : shell::StressMeasure::second_piola_kirchhoff;
  const std::string prefix = cauchy ? "cauchy_stress" : "pk2_stress";
  for (const auto& [side, side_name] : {std::pair{shell::SurfaceSide::bottom, "bottom"},
                                        std::pair{shell::SurfaceSide::middle, "middle"},
                                        std::pair{shell::SurfaceSide::top, "top"}}) {
    const shell::NodalStresses nodal = shell::nodal_stresses(model, u, measure, side);
    std::vector<double> tensor(9 * nodal.tensor.size());
    for (std::size_t k = 0; k < nodal.tensor.size(); ++k)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          tensor[9 * k + static_cast<std::size_t>(3 * i + j)] = nodal.tensor[k](i, j);
    out.emplace_back(fmt::format("{}_{}", prefix, side_name), 9, std::move(tensor));
    out.emplace_back(fmt::format("von_mises_{}", side_name), 1, nodal.von_mises);
  }
  return out;
}

}  // namespace

std::vector<double> nodal_part(const Eigen::VectorXd& u, Index nodes, int offset) {
  std::vector<double> out(3 * static_cast<std::size_t>(nodes));
  for (Index n = 0; n < nodes; ++n)
    for (int i = 0; i < 3; ++i)
      out[3 * static_cast<std::size_t>(n) + static_cast<std::size_t>(i)] =
          u[shell::dofs_per_node * n + offset + i];
  return out;
}

std::vector<double> flatten(std::span<const Vec3> v) {
  std::vector<double> out;
  out.reserve(3 * v.size());
  for (const Vec3& x : v) out.insert(out.end(), x.data(), x.data() + 3);
  return out;
}

ShellWriter::ShellWriter(const shell::ShellModel& model, const std::filesystem::path& outdir,
                         io::OutputSection::ShellStress stress, io::OutputMode mode)
    : model_(model), outdir_(outdir), stress_(stress), pvd_(outdir, "shell", mode) {}

std::vector<io::FieldView> ShellWriter::update(const Eigen::VectorXd& u, const Eigen::VectorXd* v) {
  const Index n = model_.num_nodes();
  const auto nn = static_cast<std::size_t>(n);
  displacement_ = nodal_part(u, n, 0);
  director_ = nodal_part(u, n, 3);
  position_.resize(3 * nn);
  thickness_.resize(nn);
  for (std::size_t k = 0; k < nn; ++k) {
    for (std::size_t i = 0; i < 3; ++i) {
      director_[3 * k + i] += model_.directors()[k][Eigen::Index(i)];
      position_[3 * k + i] = model_.mesh().nodes[k][Eigen::Index(i)] + displacement_[3 * k + i];
    }
    thickness_[k] = u[shell::dofs_per_node * Eigen::Index(k) + 6];
  }
  velocity_ = v ? nodal_part(*v, n, 0) : std::vector<double>(3 * nn, 0.0);
  return {{"shell", "displacement", 3, displacement_},
          {"shell", "velocity", 3, velocity_},
          {"shell", "position", 3, position_}};
}

void ShellWriter::write(long step, double t, const Eigen::VectorXd& u) {
  const auto nn = static_cast<std::size_t>(model_.num_nodes());
  std::vector<Vec3> x(nn);
  for (std::size_t k = 0; k < nn; ++k) x[k] = Vec3(position_[3 * k], position_[3 * k + 1], position_[3 * k + 2]);
  const std::string name = fmt::format("shell_{:06}.vtu", step);
  std::vector<io::VtuField> fields = {{"displacement", 3, displacement_},
                                      {"velocity", 3, velocity_},
                                      {"director", 3, director_},
                                      {"thickness_parameter", 1, thickness_}};
  const std::vector<OwnedField> stress = stress_fields(model_, u, stress_);
  for (const auto& [field_name, components, values] : stress) fields.push_back({field_name, components, values});
  io::write_mesh_vtu(outdir_ / name, model_.mesh(), std::move(fields), t, x);
  pvd_.add(t, name);
}

FluidWriter::FluidWriter(const mesh::Mesh& case_mesh, std::vector<Index> new_index,
                         const std::filesystem::path& outdir, io::OutputMode mode)
    : mesh_(case_mesh), new_index_(std::move(new_index)), outdir_(outdir), pvd_(outdir, "fluid", mode),
      positions_(case_mesh.nodes.size()) {}

std::vector<io::FieldView> FluidWriter::update(const fluid::FluidModel& model) {
  const auto& gas = model.options().gas;
  const std::size_t n = new_index_.size();
  FluidFields& f = fields_;
  for (auto* v : {&f.density, &f.pressure, &f.temperature, &f.mach, &f.energy}) v->resize(n);
  for (auto* v : {&f.velocity, &f.momentum, &f.mesh_velocity}) v->resize(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const Index k = new_index_[i];
    const fluid::Primitive p = model.primitive(k);
    const auto q = model.state().get(k);
    f.density[i] = p.rho;
    f.pressure[i] = p.pressure;
    f.temperature[i] = gas.temperature(p.rho, p.pressure);
    f.mach[i] = p.velocity.norm() / gas.sound_speed(p.rho, p.pressure);
    f.energy[i] = q.energy;
    for (std::size_t d = 0; d < 3; ++d) {
      f.velocity[3 * i + d] = p.velocity[Eigen::Index(d)];
      f.momentum[3 * i + d] = q.momentum[Eigen::Index(d)];
      f.mesh_velocity[3 * i + d] = model.mesh_velocity()[static_cast<std::size_t>(k)][Eigen::Index(d)];
    }
  }
  return f.views();
}

void FluidWriter::write(long step, fluid::FluidModel& model) {
  for (std::size_t i = 0; i < positions_.size(); ++i)
    positions_[i] = model.positions()[static_cast<std::size_t>(new_index_[i])];
  const std::vector<double> model_nu = model.nodal_artificial_viscosity();
  std::vector<double> nu(new_index_.size());
  for (std::size_t i = 0; i < nu.size(); ++i) nu[i] = model_nu[static_cast<std::size_t>(new_index_[i])];
  const std::string name = fmt::format("fluid_{:06}.vtu", step);
  const FluidFields& f = fields_;
  io::write_mesh_vtu(outdir_ / name, mesh_,
                     {{"density", 1, f.density},
                      {"velocity", 3, f.velocity},
                      {"pressure", 1, f.pressure},
                      {"mach", 1, f.mach},
                      {"temperature", 1, f.temperature},
                      {"mesh_velocity", 3, f.mesh_velocity},
                      {"artificial_viscosity", 1, nu}},
                     model.time(), positions_);
  pvd_.add(model.time(), name);
}

}  // namespace shellflow::app
