#pragma once
// The explicit one-step Taylor–Galerkin ALE residual on P1 tetrahedra (fluid.md §3–4):
// r_a such that U_a^{n+1} = U_a^n + r_a / M_a before boundary conditions. It knows nothing
// of boundary conditions or output; the only boundary term (C3, on natural boundaries) is
// a separate function applied to the faces the caller lists.
#include <array>
#include <span>
#include <string_view>

#include "shellflow/core/types.h"
#include "shellflow/fluid/element_loop.h"
#include "shellflow/fluid/gas.h"
#include "shellflow/fluid/geometry.h"
#include "shellflow/fluid/state.h"

namespace shellflow::fluid {

/// Velocity in the Δt²/2 term: `relative` uses (A_k - w̄_k I) (C1, default); `fluid` drops
/// the -w̄_k I part as the paper prints it (kept for comparison only).
enum class TgVelocity { relative, fluid };

struct ResidualParameters {
  IdealGas gas;
  double dt = 0.0;
  TgVelocity tg_velocity = TgVelocity::relative;
  bool moving_mesh_correction = true;  ///< the C2 term
  bool mesh_moves = true;              ///< false promises w = 0 at every node (skips the ALE terms)
  /// Local time stepping (steady runs only): per-element and per-node steps; empty: the
  /// global dt. dt^2 becomes dt_a dt_e (fluid.md §4.3).
  std::span<const double> element_dt;
  std::span<const double> nodal_dt;
};

/// Instruction set of the element pass. `sse2` (2 elements per instruction, the x86-64
/// baseline) is the reference; `avx2` (4 elements) gives the same bits; `avx2_fma` adds fused
/// multiply-adds, whose rounding differs from the reference in the last bits (a uniform
/// state still gives exactly zero); `avx512` (8 elements, AVX-512F/DQ/VL with FMA).
enum class SimdPath { sse2, avx2, avx2_fma, avx512 };

/// The element pass's instruction set: set_simd_path's, else the environment variable
/// SHELLFLOW_SIMD (auto, sse2, avx2, avx2-fma, avx512), else the best this CPU has. Throws InputError
/// for an unknown name or a set the CPU lacks.
SimdPath simd_path();
void set_simd_path(SimdPath path);
/// "sse2", "avx2", "avx2-fma", "avx512".
std::string_view to_string(SimdPath path);
/// `name` as in SHELLFLOW_SIMD; `origin` names where it came from, for the error message.
SimdPath parse_simd_path(std::string_view name, std::string_view origin);

/// Sets r to the element-pass residual (all five rows): convective flux in group form,
/// ALE mesh term, Taylor–Galerkin term with the full relative Jacobian (C1), its moving-mesh
/// correction (C2) and the artificial diffusion with element viscosity `element_viscosity`
/// (empty: none). Geometry is that of x^n, `w` the mesh velocity of the step.
void assemble_residual(const ResidualParameters& p, const ElementLoop& loop, const TetGeometry& geometry,
                       const FluidState& u, std::span<const Vec3> w, std::span<const double> element_viscosity,
                       FluidState& r);

/// A face of a natural (outflow) boundary: its nodes, the element that owns it and the
/// element's fourth node (to orient the normal outward).
struct BoundaryFace {
  std::array<Index, 3> nodes{};
  Index element = 0;
  Index opposite_node = 0;
};

/// Outward area vector A_f n_f of `face` at positions x.
Vec3 face_area_vector(std::span<const Vec3> x, const BoundaryFace& face);

/// Adds the boundary integral of the Taylor–Galerkin term on natural boundaries (C3):
/// each face node receives -Δt²/2 (A_f/3) n_k Ã_k(Ū_e) R̂_e.
void add_natural_boundary_term(const ResidualParameters& p, const ElementLoop& loop, std::span<const Vec3> x,
                               const TetGeometry& geometry, const FluidState& u, std::span<const Vec3> w,
                               std::span<const BoundaryFace> faces, FluidState& r);

}  // namespace shellflow::fluid
