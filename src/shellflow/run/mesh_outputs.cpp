#include "shellflow/run/mesh_outputs.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <tuple>

#include "shellflow/core/output_file.h"
#include "shellflow/io/mesh_output.h"
#include "shellflow/run/fluid_pieces.h"
#include "shellflow/setup/fluid_setup.h"
#include "shellflow/shell/shell_stress.h"

namespace shellflow::run {
namespace {

/// The flow's probe and output quantities (case-format.md's `fluid.*`), in the order of the
/// probe views.
enum class FluidQuantity { density, pressure, temperature, mach, energy, velocity, momentum, mesh_velocity };
struct FluidQuantityName {
  FluidQuantity q;
  std::string_view name;
  int components;
};
constexpr std::array<FluidQuantityName, 8> kFluidQuantities{{{FluidQuantity::density, "density", 1},
                                                             {FluidQuantity::pressure, "pressure", 1},
                                                             {FluidQuantity::temperature, "temperature", 1},
                                                             {FluidQuantity::mach, "mach", 1},
                                                             {FluidQuantity::energy, "energy", 1},
                                                             {FluidQuantity::velocity, "velocity", 3},
                                                             {FluidQuantity::momentum, "momentum", 3},
                                                             {FluidQuantity::mesh_velocity, "mesh_velocity", 3}}};

/// One quantity of the flow at one node, from its state: the one conversion behind the
/// probes, the frames and the initial state.
void fluid_value(FluidQuantity q, const fluid::IdealGas& gas, const fluid::Primitive& p, const fluid::Conservative& u,
                 const Vec3& w, double* out) {
  const auto put = [&](const Vec3& v) { std::copy(v.data(), v.data() + 3, out); };
  switch (q) {
    case FluidQuantity::density:
      *out = p.rho;
      return;
    case FluidQuantity::pressure:
      *out = p.pressure;
      return;
    case FluidQuantity::temperature:
      *out = gas.temperature(p.rho, p.pressure);
      return;
    case FluidQuantity::mach:
      *out = p.velocity.norm() / gas.sound_speed(p.rho, p.pressure);
      return;
    case FluidQuantity::energy:
      *out = u.energy;
      return;
    case FluidQuantity::velocity:
      put(p.velocity);
      return;
    case FluidQuantity::momentum:
      put(u.momentum);
      return;
    case FluidQuantity::mesh_velocity:
      put(w);
      return;
  }
}

/// A whole field of `components` values per node from value(node, out).
std::vector<double> whole_field(std::size_t nodes, int components, const std::function<void(Index, double*)>& value) {
  std::vector<double> out(nodes * static_cast<std::size_t>(components));
  for (std::size_t i = 0; i < nodes; ++i) value(static_cast<Index>(i), out.data() + i * std::size_t(components));
  return out;
}

/// One nodal field for the VTU: name, components, values (owned).
using OwnedField = std::tuple<std::string, int, std::vector<double>>;

/// Nodal stress tensors (9 components, row-major) and their von Mises values on the bottom,
/// middle and top surfaces, for the VTU.
std::vector<OwnedField> stress_fields(const shell::ShellModel& model, const Eigen::VectorXd& u,
                                      io::OutputSection::ShellStress kind) {
  std::vector<OwnedField> out;
  if (kind == io::OutputSection::ShellStress::none) return out;
  const bool cauchy = kind == io::OutputSection::ShellStress::cauchy;
  const auto measure = cauchy ? shell::StressMeasure::cauchy : shell::StressMeasure::second_piola_kirchhoff;
  const std::string prefix = cauchy ? "cauchy_stress" : "pk2_stress";
  for (const auto& [side, side_name] :
       {std::pair{shell::SurfaceSide::bottom, "bottom"}, std::pair{shell::SurfaceSide::middle, "middle"},
        std::pair{shell::SurfaceSide::top, "top"}}) {
    const shell::NodalStresses nodal = shell::nodal_stresses(model, u, measure, side);
    std::vector<double> tensor(9 * nodal.tensor.size());
    for (std::size_t k = 0; k < nodal.tensor.size(); ++k)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) tensor[9 * k + static_cast<std::size_t>(3 * i + j)] = nodal.tensor[k](i, j);
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
      out[3 * static_cast<std::size_t>(n) + static_cast<std::size_t>(i)] = u[shell::dofs_per_node * n + offset + i];
  return out;
}

std::vector<double> flatten(std::span<const Vec3> v) {
  std::vector<double> out;
  out.reserve(3 * v.size());
  for (const Vec3& x : v) out.insert(out.end(), x.data(), x.data() + 3);
  return out;
}

// ---------------------------------------------------------------------------------------------

MeshOutput::MeshOutput(const mesh::Mesh& mesh, const std::filesystem::path& outdir, io::OutputMode mode)
    : mesh_(mesh), outdir_(outdir), pvd_(outdir, mesh.name, mode) {}

void MeshOutput::set_pieces(const mesh::Mesh& piece, int rank, int count) { pieces_ = Pieces{&piece, rank, count}; }

void MeshOutput::write_frame(long step, double t, std::vector<io::VtuField> fields, std::span<const Vec3> positions) {
  if (!pieces_) {
    const std::string name = fmt::format("{}_{:06}.vtu", mesh_.name, step);
    io::write_mesh_vtu(outdir_ / name, mesh_, std::move(fields), t, positions);
    pvd_.add(t, name);
    return;
  }
  const auto piece_name = [&](int rank) { return fmt::format("{}_{:06}_p{}.vtu", mesh_.name, step, rank); };
  std::vector<io::PvtuArray> point_arrays;
  for (const io::VtuField& f : fields) point_arrays.push_back({f.name, f.components});
  {
    const PieceOutput every_rank;  // each rank writes its own piece
    io::write_mesh_vtu(outdir_ / piece_name(pieces_->rank), *pieces_->mesh, std::move(fields), t, positions);
  }
  std::vector<std::string> pieces;
  for (int r = 0; r < pieces_->count; ++r) pieces.push_back(piece_name(r));
  const std::string name = fmt::format("{}_{:06}.pvtu", mesh_.name, step);
  io::write_pvtu(outdir_ / name, pieces, point_arrays, {{"quality", 1}});  // rank 0 only (core/output_file.h)
  pvd_.add(t, name);
}

// ---------------------------------------------------------------------------------------------

// OutputMode::resume: <mesh>.pvd is written when frame 0 is added, not before (a restarted run
// keeps the one of its first invocation).
InitialOutput::InitialOutput(const io::Case& c, const mesh::Mesh& mesh, const std::filesystem::path& outdir)
    : MeshOutput(mesh, outdir, io::OutputMode::resume) {
  const std::size_t n = mesh.nodes.size();
  const auto constant = [&](std::string name, int components, double value) {
    names_.emplace_back(std::move(name), components);
    values_.emplace_back(n * static_cast<std::size_t>(components), value);
  };
  if (mesh.name == "shell") {
    for (auto q : {"displacement", "velocity", "acceleration"}) constant(q, 3, 0.0);
    names_.emplace_back("position", 3);
    values_.push_back(flatten(mesh.nodes));
  } else if (mesh.name == "fluid" && c.fluid) {
    const fluid::IdealGas gas = setup::fluid_options(*c.fluid).gas;
    const fluid::Primitive p = setup::free_stream(*c.fluid);
    const fluid::Conservative u = fluid::to_conservative(gas, p);
    for (const auto& f : kFluidQuantities) {
      names_.emplace_back(f.name, f.components);
      values_.push_back(
          whole_field(n, f.components, [&](Index, double* out) { fluid_value(f.q, gas, p, u, Vec3::Zero(), out); }));
    }
  } else if (mesh.name == "space") {
    for (auto q : {"displacement", "velocity"}) constant(q, 3, 0.0);
  }
}

std::vector<io::FieldView> InitialOutput::views() const {
  std::vector<io::FieldView> v;
  for (std::size_t k = 0; k < names_.size(); ++k)
    v.push_back({key(), names_[k].first, names_[k].second, values_[k], {}});
  return v;
}

void InitialOutput::write(long step, double t) {
  std::vector<io::VtuField> fields;
  for (std::size_t k = 0; k < names_.size(); ++k) fields.push_back({names_[k].first, names_[k].second, values_[k]});
  write_frame(step, t, std::move(fields));
}

// ---------------------------------------------------------------------------------------------

ShellOutput::ShellOutput(const shell::ShellModel& model, const std::filesystem::path& outdir,
                         io::OutputSection::ShellStress stress, io::OutputMode mode, State u, Velocity v)
    : MeshOutput(model.mesh(), outdir, mode), model_(model), stress_(stress), u_(std::move(u)), v_(std::move(v)) {}

std::vector<io::FieldView> ShellOutput::views() const {
  const auto dof = [](Index node, int i) { return shell::dofs_per_node * node + i; };
  return {{"shell",
           "displacement",
           3,
           {},
           [this, dof](Index n, double* out) {
             for (int i = 0; i < 3; ++i) out[i] = u_()[dof(n, i)];
           }},
          {"shell",
           "velocity",
           3,
           {},
           [this, dof](Index n, double* out) {
             const Eigen::VectorXd* v = v_();
             for (int i = 0; i < 3; ++i) out[i] = v ? (*v)[dof(n, i)] : 0.0;
           }},
          {"shell", "position", 3, {}, [this, dof](Index n, double* out) {
             for (int i = 0; i < 3; ++i) out[i] = mesh_.nodes[std::size_t(n)][i] + u_()[dof(n, i)];
           }}};
}

void ShellOutput::write(long step, double t) {
  const Eigen::VectorXd& u = u_();
  const Eigen::VectorXd* v = v_();
  const Index n = model_.num_nodes();
  const auto nn = static_cast<std::size_t>(n);
  const std::vector<double> displacement = nodal_part(u, n, 0);
  std::vector<double> director = nodal_part(u, n, 3), thickness(nn);
  std::vector<Vec3> x(nn);
  for (std::size_t k = 0; k < nn; ++k) {
    for (std::size_t i = 0; i < 3; ++i) {
      director[3 * k + i] += model_.directors()[k][Eigen::Index(i)];
      x[k][Eigen::Index(i)] = mesh_.nodes[k][Eigen::Index(i)] + displacement[3 * k + i];
    }
    thickness[k] = u[shell::dofs_per_node * Eigen::Index(k) + 6];
  }
  const std::vector<double> velocity = v ? nodal_part(*v, n, 0) : std::vector<double>(3 * nn, 0.0);
  std::vector<io::VtuField> fields = {{"displacement", 3, displacement},
                                      {"velocity", 3, velocity},
                                      {"director", 3, director},
                                      {"thickness_parameter", 1, thickness}};
  const std::vector<OwnedField> stress = stress_fields(model_, u, stress_);
  for (const auto& [field_name, components, values] : stress) fields.push_back({field_name, components, values});
  write_frame(step, t, std::move(fields), x);
}

// ---------------------------------------------------------------------------------------------

FluidOutput::FluidOutput(const mesh::Mesh& case_mesh, std::span<const Index> new_index, fluid::FluidModel& model,
                         const std::filesystem::path& outdir, io::OutputMode mode)
    : MeshOutput(case_mesh, outdir, mode), new_index_(new_index), model_(model) {}

FluidOutput::FluidOutput(const mesh::Mesh& case_mesh, const FluidPieces& pieces, fluid::FluidModel& model,
                         const std::filesystem::path& outdir, io::OutputMode mode)
    : MeshOutput(case_mesh, outdir, mode), new_index_(pieces.case_to_model), model_(model), pieces_(&pieces) {
  set_pieces(pieces.piece, pieces.ranks->rank(), pieces.ranks->size());
  std::vector<ProbeGather::Quantity> quantities;
  for (const auto& f : kFluidQuantities) quantities.push_back({f.name, f.components});
  gather_ = std::make_unique<ProbeGather>(pieces, std::move(quantities),
                                          [this](std::size_t q, Index k, double* out) { value(q, k, out); });
}

FluidOutput::~FluidOutput() = default;

void FluidOutput::value(std::size_t q, Index k, double* out) const {
  const fluid::Conservative u = model_.state().get(k);
  fluid_value(kFluidQuantities[q].q, model_.options().gas, fluid::to_primitive(model_.options().gas, u), u,
              model_.mesh_velocity()[std::size_t(k)], out);
}

std::vector<io::FieldView> FluidOutput::views() const {
  if (gather_) return gather_->views();
  std::vector<io::FieldView> v;
  for (std::size_t q = 0; q < kFluidQuantities.size(); ++q)
    v.push_back(
        {"fluid", kFluidQuantities[q].name, kFluidQuantities[q].components, {}, [this, q](Index i, double* out) {
           value(q, new_index_[std::size_t(i)], out);
         }});
  return v;
}

void FluidOutput::prepare_sample() {
  if (gather_) gather_->refresh();
}

void FluidOutput::write(long step, double) {
  // The flow's own time (the coupled driver's shell time may differ from it in the last bit).
  const double t = model_.time();
  // The case's nodes, or this rank's piece's.
  const std::span<const Index> model_node = pieces_ ? std::span<const Index>(pieces_->piece_to_model) : new_index_;
  const std::size_t n = model_node.size();
  std::vector<Vec3> positions(n);
  const std::vector<double> model_nu = model_.nodal_artificial_viscosity();
  std::vector<double> nu(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(model_node[i]);
    positions[i] = model_.positions()[k];
    nu[i] = model_nu[k];
  }
  const auto field = [&](std::string_view name) {
    const auto q = std::size_t(std::find_if(kFluidQuantities.begin(), kFluidQuantities.end(),
                                            [&](const FluidQuantityName& f) { return f.name == name; }) -
                               kFluidQuantities.begin());
    return whole_field(n, kFluidQuantities[q].components,
                       [&](Index i, double* out) { value(q, model_node[std::size_t(i)], out); });
  };
  const std::vector<double> density = field("density"), velocity = field("velocity"), pressure = field("pressure"),
                            mach = field("mach"), temperature = field("temperature"),
                            mesh_velocity = field("mesh_velocity");
  write_frame(step, t,
              {{"density", 1, density},
               {"velocity", 3, velocity},
               {"pressure", 1, pressure},
               {"mach", 1, mach},
               {"temperature", 1, temperature},
               {"mesh_velocity", 3, mesh_velocity},
               {"artificial_viscosity", 1, nu}},
              positions);
}

// ---------------------------------------------------------------------------------------------

FluidMeshOutput::FluidMeshOutput(const mesh::Mesh& case_mesh, std::span<const Index> new_index,
                                 std::span<const Vec3> reference, Nodal positions, Nodal velocity,
                                 const std::filesystem::path& outdir, io::OutputMode mode)
    : MeshOutput(case_mesh, outdir, mode),
      new_index_(new_index),
      reference_(reference),
      positions_(std::move(positions)),
      velocity_(std::move(velocity)) {}

std::vector<io::FieldView> FluidMeshOutput::views() const {
  return {{"fluid", "mesh_velocity", 3, {}, [this](Index i, double* out) {
             const Vec3& w = velocity_()[node(i)];
             std::copy(w.data(), w.data() + 3, out);
           }}};
}

void FluidMeshOutput::write(long step, double t) {
  const std::size_t n = mesh_.nodes.size();
  const auto x = positions_();
  const auto w = velocity_();
  std::vector<Vec3> positions(n);
  std::vector<double> displacement(3 * n), velocity(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t k = node(Index(i));
    positions[i] = x[k];
    for (Eigen::Index d = 0; d < 3; ++d) {
      displacement[3 * i + std::size_t(d)] = x[k][d] - reference_[k][d];
      velocity[3 * i + std::size_t(d)] = w[k][d];
    }
  }
  write_frame(step, t, {{"displacement", 3, displacement}, {"mesh_velocity", 3, velocity}}, positions);
}

// ---------------------------------------------------------------------------------------------

SpaceMeshOutput::SpaceMeshOutput(const mesh::Mesh& case_mesh, const motion::SpaceMesh& space,
                                 const std::filesystem::path& outdir, io::OutputMode mode)
    : MeshOutput(case_mesh, outdir, mode), space_(space) {}

std::vector<io::FieldView> SpaceMeshOutput::views() const {
  const auto nodal = [](std::span<const Vec3> (motion::SpaceMesh::*of)() const, const motion::SpaceMesh& s) {
    return [of, &s](Index i, double* out) {
      const Vec3& v = (s.*of)()[std::size_t(i)];
      std::copy(v.data(), v.data() + 3, out);
    };
  };
  return {{"space", "displacement", 3, {}, nodal(&motion::SpaceMesh::displacement, space_)},
          {"space", "velocity", 3, {}, nodal(&motion::SpaceMesh::velocity, space_)}};
}

void SpaceMeshOutput::write(long step, double t) {
  const std::vector<double> u = flatten(space_.displacement()), v = flatten(space_.velocity());
  write_frame(step, t, {{"displacement", 3, u}, {"velocity", 3, v}}, space_.current_positions());
}

}  // namespace shellflow::run
