#pragma once
// Measures of scalar fields on triangle meshes and of facet sizes, for resolution reports
// (docs/fluid.md, "Cells per wavelength"): the wavenumber of a nodal field along a
// direction and the mean size of a group of facets along a direction.
#include <span>

#include "shellflow/core/types.h"
#include "shellflow/mesh/mesh.h"

namespace shellflow::mesh {

/// k = sqrt( ∫ (∇_s f · d)² dA / ∫ f² dA ) of the nodal field f on a triangle mesh (3, 6
/// or 10 nodes, curved by its nodes), ∇_s the surface gradient, d a unit direction. For
/// f = sin(k x) over whole periods along d it is k, so 2π/k is the field's wavelength along
/// d. Throws InputError when the mesh is not of triangles, when f does not hold one value
/// per node, or when ∫ f² is zero.
double directional_wavenumber(const Mesh& surface, std::span<const double> f, const Vec3& direction);

/// Mean extent of the facets along a unit direction d: max − min of x·d over each facet's
/// vertices, averaged over the facets. On a structured strip it is the spacing along d; on
/// an isotropic unstructured surface about 0.9 times the edge length.
double mean_extent(const Mesh& mesh, const ElementBlock& facets, const Vec3& direction);

}  // namespace shellflow::mesh
