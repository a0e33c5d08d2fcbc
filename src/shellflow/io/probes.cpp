#include "shellflow/io/probes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <memory>

#include "shellflow/fem/reference_element.h"
#include "shellflow/mesh/spatial_index.h"

namespace shellflow::io {

/// A probe reduced to: which nodes, with which weights (interpolation) or which
/// reduction (group), and which component.
struct ProbeSet::Located {
  Probe probe;
  std::vector<Index> nodes;
  std::vector<double> weights;  ///< interpolation weights (point/node); empty for groups
};

namespace {

std::vector<double> shape_values(int gmsh_type, const double* xi) {
  const auto& ref = fem::reference_element(gmsh_type);
  std::vector<double> n(static_cast<std::size_t>(ref.num_nodes));
  ref.eval(xi, n.data());
  return n;
}

double mesh_size(const mesh::Mesh& m) {
  mesh::Box box;
  for (const auto& x : m.nodes) box.extend(x);
  return box.extent().norm();
}

double component_of(const double* value, int components, ProbeComponent c) {
  switch (c) {
    case ProbeComponent::x:
      return value[0];
    case ProbeComponent::y:
      return value[1];
    case ProbeComponent::z:
      return value[2];
    case ProbeComponent::magnitude: {
      double s = 0;
      for (int k = 0; k < components; ++k) s += value[k] * value[k];
      return std::sqrt(s);
    }
    case ProbeComponent::scalar:
      return value[0];
  }
  return 0.0;
}

std::vector<std::string> probe_names(const std::vector<Probe>& probes) {
  std::vector<std::string> names;
  for (const auto& p : probes) names.push_back(p.name);
  return names;
}

/// Search trees of the meshes, built on the first point probe of each mesh: one tree over a
/// 1e6-tet mesh costs far more than locating any number of points in it.
class Locators {
 public:
  const mesh::CellLocator& cells(const mesh::Mesh& m) {
    auto& locator = cell_locators_[&m];
    if (!locator) locator = std::make_unique<mesh::CellLocator>(m);
    return *locator;
  }

  struct Surface {
    mesh::SurfaceLocator locator;
    double size;  ///< diagonal of the bounding box, scales the distance check
  };
  const Surface& surface(const mesh::Mesh& m) {
    auto& surface = surfaces_[&m];
    if (!surface) surface = std::make_unique<Surface>(Surface{{m.nodes, m.cells}, mesh_size(m)});
    return *surface;
  }

 private:
  std::map<const mesh::Mesh*, std::unique_ptr<mesh::CellLocator>> cell_locators_;
  std::map<const mesh::Mesh*, std::unique_ptr<Surface>> surfaces_;
};

}  // namespace

ProbeSet::ProbeSet(const std::vector<Probe>& probes, const CaseMeshes& meshes, const std::filesystem::path& csv_path,
                   OutputMode mode)
    : writer_(csv_path, probe_names(probes), mode) {
  Locators locators;
  for (const Probe& p : probes) {
    const mesh::Mesh* m = meshes.find(p.mesh);
    if (!m) throw_at(p.where, fmt::format("the case has no {} mesh", p.mesh));
    Located located{p, {}, {}};
    switch (p.location) {
      case ProbeLocation::node:
        if (p.node < 0 || p.node >= m->num_nodes()) {
          throw_at(p.where, fmt::format("node {} does not exist: the {} mesh has nodes 0 to {}", p.node, p.mesh,
                                        m->num_nodes() - 1));
        }
        located.nodes = {p.node};
        located.weights = {1.0};
        break;
      case ProbeLocation::group:
        located.nodes = m->group(p.group).nodes;
        break;
      case ProbeLocation::point: {
        if (m->dim() == 3) {
          const auto hit = locators.cells(*m).locate(p.point, 1e-9);
          if (!hit) {
            throw_at(p.where, fmt::format("point ({}, {}, {}) lies outside the {} mesh; move it "
                                          "into the domain",
                                          p.point.x(), p.point.y(), p.point.z(), p.mesh));
          }
          const auto cell = m->cells.element(hit->cell);
          located.nodes.assign(cell.begin(), cell.end());
          located.weights = shape_values(static_cast<int>(m->cells.type), hit->xi.data());
        } else {
          const auto& surface = locators.surface(*m);
          const auto hit = surface.locator.closest(p.point);
          if (hit.distance > 1e-6 * surface.size) {
            throw_at(p.where, fmt::format("point ({}, {}, {}) is {:.3g} m away from the {} "
                                          "surface; put it on the surface",
                                          p.point.x(), p.point.y(), p.point.z(), hit.distance, p.mesh));
          }
          const auto cell = m->cells.element(hit.element);
          located.nodes.assign(cell.begin(), cell.end());
          located.weights = shape_values(static_cast<int>(m->cells.type), hit.xi.data());
        }
        break;
      }
    }
    probes_.push_back(std::move(located));
  }
}

ProbeSet::~ProbeSet() = default;

std::size_t ProbeSet::size() const { return probes_.size(); }

std::vector<Index> ProbeSet::nodes(std::string_view mesh) const {
  std::vector<Index> out;
  for (const Located& l : probes_)
    if (l.probe.mesh == mesh) out.insert(out.end(), l.nodes.begin(), l.nodes.end());
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::vector<double> ProbeSet::sample(std::span<const FieldView> fields) const {
  std::vector<double> values;
  values.reserve(probes_.size());
  for (const Located& l : probes_) {
    const auto field = std::find_if(fields.begin(), fields.end(), [&](const FieldView& f) {
      return f.mesh == l.probe.mesh && f.quantity == l.probe.quantity;
    });
    if (field == fields.end()) {
      throw_at(l.probe.where, fmt::format("field '{}' is not computed by this run", l.probe.field));
    }
    const int nc = field->components;
    std::array<double, 9> computed{};
    auto value_at = [&](Index node) -> const double* {
      if (!field->at) return field->values.data() + static_cast<std::ptrdiff_t>(node) * nc;
      field->at(node, computed.data());
      return computed.data();
    };
    if (!l.weights.empty()) {
      // Interpolate the vector first, then take the component (magnitude of the
      // interpolated vector, not the interpolated magnitude).
      std::vector<double> v(static_cast<std::size_t>(nc), 0.0);
      for (std::size_t a = 0; a < l.nodes.size(); ++a) {
        const double* value = value_at(l.nodes[a]);
        for (int k = 0; k < nc; ++k) v[static_cast<std::size_t>(k)] += l.weights[a] * value[k];
      }
      values.push_back(component_of(v.data(), nc, l.probe.component));
    } else {
      double acc = l.probe.reduce == ProbeReduce::min   ? std::numeric_limits<double>::infinity()
                   : l.probe.reduce == ProbeReduce::max ? -std::numeric_limits<double>::infinity()
                                                        : 0.0;
      for (Index n : l.nodes) {
        const double c = component_of(value_at(n), nc, l.probe.component);
        acc = l.probe.reduce == ProbeReduce::min   ? std::min(acc, c)
              : l.probe.reduce == ProbeReduce::max ? std::max(acc, c)
                                                   : acc + c;
      }
      if (l.probe.reduce == ProbeReduce::mean && !l.nodes.empty()) acc /= static_cast<double>(l.nodes.size());
      values.push_back(acc);
    }
  }
  return values;
}

std::vector<double> ProbeSet::record(double time, std::span<const FieldView> fields) {
  std::vector<double> values = sample(fields);
  if (last_time_ == time) return values;  // the same state again (see the header)
  writer_.append(time, values);
  last_time_ = time;
  return values;
}

}  // namespace shellflow::io
