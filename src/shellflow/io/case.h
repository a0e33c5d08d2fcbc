#pragma once
// A case file (YAML, one file per case) read into plain structs. The schema, with every key,
// its unit and its default, is documented in docs/case-format.md; keep the two in step.
//
//   Case c = read_case("cases/panel_flutter_coarse.yaml");   // throws InputError
//   check_physical_groups(c, [&](std::string_view mesh) { return meshes.at(mesh).group_names(); });
//
// read_case() checks everything that can be checked without meshing: keys, types, ranges,
// that mesh files exist. Physical group names are checked by check_physical_groups() once the
// meshes are loaded; every group reference keeps the file, line and key path it came from.
//
// Adding a section (a later module's parameters): add a struct and an
// `std::optional<Section>` member to Case, read it in a case_<section>.cpp of its own with a
// `read_<section>()` that uses YamlNode and ends with `finish()` (declared in case_sections.h,
// called from read_case() in case.cpp), and document it in docs/case-format.md.
#include <array>
#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "shellflow/core/expression.h"
#include "shellflow/core/time_function.h"
#include "shellflow/core/types.h"
#include "shellflow/io/checkpoint.h"
#include "shellflow/io/yaml_reader.h"

namespace shellflow::io {

// ---- meshes -----------------------------------------------------------------------------------

/// The three meshes a case may use, by their key in `meshes:`.
inline constexpr std::string_view kMeshKeys[] = {"fluid", "space", "shell"};

enum class MeshFormat { geo, msh };

/// One mesh: a Gmsh `.geo` to mesh on the fly, or a ready `.msh`.
struct MeshSpec {
  std::string key;  ///< "fluid", "space" or "shell"
  MeshFormat format = MeshFormat::geo;
  std::filesystem::path file;  ///< resolved: case directory / as_written, normalised; exists
  std::string as_written;      ///< the path as written in the case file (for messages)
  int order = 1;               ///< element order 1, 2 or 3; 0 for a `.msh` (used as it is)
  double size_factor = 1.0;    ///< Gmsh Mesh.MeshSizeFactor (`.geo` only; 1 for a `.msh`)
  SourceLocation where;        ///< the `meshes.<key>` entry
};

struct MeshesSection {
  std::optional<MeshSpec> fluid;  ///< default order 1
  std::optional<MeshSpec> space;  ///< default order 3
  std::optional<MeshSpec> shell;  ///< default order 3

  /// The mesh with key "fluid", "space" or "shell"; nullptr if the case has none.
  const MeshSpec* find(std::string_view key) const;
};

// ---- shell ------------------------------------------------------------------------------------

struct Material {
  double young_modulus = 0.0;  ///< E [Pa], > 0
  double poisson_ratio = 0.0;  ///< nu [-], -1 < nu < 0.5
  double density = 0.0;        ///< rho [kg/m^3], >= 0
};

enum class SupportType {
  clamped,
  simply_supported,  ///< soft: positions fixed, directors free
  symmetry,
  sliding,
  prescribed,
  simply_supported_hard,  ///< positions fixed and the director kept normal to the edge
};

struct Support {
  std::string group;  ///< physical group of the shell mesh
  SupportType type = SupportType::clamped;
  Vec3 direction = Vec3::Zero();  ///< `sliding` only: unit vector of the allowed motion
  bool clamp_director = true;     ///< `sliding` only: director fixed (clamped-sliding)
  Vec3 normal = Vec3::Zero();     ///< `symmetry` only: unit normal of the symmetry plane
  /// `prescribed` only: x = X + f(t) d and, with a rotation axis, G = R(g(t)) V.
  Vec3 displacement = Vec3::Zero();                 ///< d [m]
  std::optional<TimeFunction> displacement_history;  ///< f; absent: the analysis' load factor
  Vec3 rotation_axis = Vec3::Zero();                ///< unit axis, or zero (director free)
  TimeFunction rotation_angle = TimeFunction::constant(0.0);  ///< g [rad]
  SourceLocation where;           ///< the list item `shell.supports[i]`
};

enum class ShellLoadType { line, point, edge_couple, pressure, gravity, surface };

/// A load at load factor 1 (static) or scaled by the analysis' load function (dynamic).
struct ShellLoad {
  ShellLoadType type = ShellLoadType::line;
  std::string group;             ///< line, edge_couple: a line group; pressure: a surface
                                 ///< group or empty (the whole shell)
  Vec3 vector = Vec3::Zero();    ///< line: force per length [N/m]; point: force [N];
                                 ///< gravity: acceleration [m/s^2]; edge_couple: axis (unit);
                                 ///< surface: traction per reference area [Pa]
  double value = 0.0;            ///< edge_couple: moment per length [N]; pressure [Pa]
  Vec3 point = Vec3::Zero();     ///< point: where (the nearest shell node takes the force)
  SourceLocation where;
};

enum class ShellAnalysisType { static_load, dynamic, modal };

/// How a static analysis follows the equilibrium path.
enum class PathControl {
  load,          ///< equal load increments
  displacement,  ///< equal increments of one displacement component (through load limits)
  arc_length,    ///< Crisfield's cylindrical arc length (through load and displacement limits)
};
enum class TimeScheme { newmark, midpoint };

struct ShellAnalysis {
  ShellAnalysisType type = ShellAnalysisType::static_load;
  int steps = 10;                ///< static: increments (arc length: at most this many)
  PathControl control = PathControl::load;
  /// control: displacement: the controlled component of a node or of a group's mean.
  std::string controlled_group;
  Index controlled_node = -1;
  int controlled_component = 2;  ///< 0, 1, 2 = x, y, z
  double final_displacement = 0.0;       ///< [m] displacement control: value at the last step
  double initial_load_increment = 0.1;   ///< arc length: first load-factor increment
  double final_load_factor = 1.0;        ///< arc length: stop once reached
  TimeFunction load_function = TimeFunction::constant(1.0);  ///< dynamic: load factor(t)
  double mass_damping = 0.0;     ///< dynamic: c_m in C = c_m M [1/s]
  TimeScheme scheme = TimeScheme::newmark;  ///< dynamic
  bool modified_newton = false;  ///< load control, dynamic: keep the iteration matrix (NewtonOptions::modified)
  int modes = 10;                ///< modal: number of natural frequencies and modes (1..200)
  double modal_tolerance = 1e-8; ///< modal: ModalOptions::tolerance (relative eigenvalue change)
  int modal_max_iterations = 300;  ///< modal: ModalOptions::max_iterations
  SourceLocation where;
};

struct ShellSection {
  double thickness = 0.0;  ///< h [m], > 0
  Material material;
  std::vector<Support> supports;
  std::vector<ShellLoad> loads;
  std::optional<ShellAnalysis> analysis;  ///< absent: the shell is not solved
};

// ---- fluid ------------------------------------------------------------------------------------

enum class ViscosityLaw { none, constant, sutherland };

/// Dynamic viscosity mu(T) and heat conduction k = mu c_p / Pr (Navier–Stokes runs).
struct Viscosity {
  ViscosityLaw law = ViscosityLaw::none;  ///< none: inviscid (Euler)
  double mu_ref = 1.716e-5;               ///< [Pa s] mu (constant) or mu at t_ref (Sutherland)
  double t_ref = 273.15;                  ///< [K]
  double sutherland = 110.4;              ///< Sutherland's constant S [K]
  double prandtl = 0.72;
};

struct Gas {
  double gamma = 1.4;            ///< ratio of specific heats [-], > 1
  double gas_constant = 287.05;  ///< R [J/(kg K)], > 0
  Viscosity viscosity;
};

struct FreeStream {
  double density = 0.0;            ///< [kg/m^3], > 0
  double pressure = 0.0;           ///< [Pa], > 0
  double mach = 0.0;               ///< [-], >= 0
  Vec3 direction = Vec3::UnitX();  ///< unit vector (normalised when read)
};

enum class FluidBoundaryType {
  supersonic_inflow,
  supersonic_outflow,
  far_field,
  slip_wall,
  no_slip_wall,
  symmetry
};

/// A scalar field written in a case file as a number or as an expression (expression.h) of
/// the node's initial coordinates x, y, z [m] and the time t [s].
///
/// With a `where` (the key it was read from, `case.yaml:12: fluid.analysis.initial.density`)
/// every evaluation checks its result: one that is not finite throws InputError naming the
/// key, the point, the time and the likely cause, so that a NaN or an overflow in an initial
/// state, a boundary state or a mesh motion stops the run where it enters.
class SpaceTimeScalar {
 public:
  SpaceTimeScalar() = default;
  explicit SpaceTimeScalar(Expression expression, std::string where = {})
      : expression_(std::move(expression)), where_(std::move(where)) {}
  double operator()(const Vec3& X, double t) const {
    const double point[4] = {X.x(), X.y(), X.z(), t};
    const double v = expression_.value(point);
    if (!where_.empty() && !std::isfinite(v)) fail_non_finite(X, t, v, false);
    return v;
  }
  /// Partial derivative with respect to t (exact: automatic differentiation).
  double time_derivative(const Vec3& X, double t) const {
    const double point[4] = {X.x(), X.y(), X.z(), t};
    const double d = expression_.evaluate(point, 3).derivative;
    if (!where_.empty() && !std::isfinite(d)) fail_non_finite(X, t, d, true);
    return d;
  }
  const Expression& expression() const { return expression_; }
  const std::string& where() const { return where_; }

 private:
  Expression expression_;
  std::string where_;  ///< empty: unchecked
  [[noreturn]] void fail_non_finite(const Vec3& X, double t, double value, bool is_derivative) const;
};

/// A gas state varying in space and time: density, velocity, pressure.
struct SpaceTimeState {
  SpaceTimeScalar density;
  std::array<SpaceTimeScalar, 3> velocity;
  SpaceTimeScalar pressure;
  SourceLocation where;
};

struct FluidBoundary {
  std::string group;  ///< physical group of the fluid mesh
  FluidBoundaryType type = FluidBoundaryType::slip_wall;
  /// Inflow / far-field state; absent: the free stream.
  std::optional<SpaceTimeState> state;
  Vec3 wall_velocity = Vec3::Zero();   ///< no-slip walls [m/s] (on a moving mesh: the mesh's)
  std::optional<double> wall_temperature;  ///< no-slip walls [K]; absent: adiabatic
  SourceLocation where;  ///< the list item `fluid.boundaries[i]`
};

/// A prescribed motion of every fluid node: x = X + d(X, t). The mesh velocity of a step is
/// (x^{n+1} - x^n) / dt, the choice that keeps a uniform flow exactly uniform; slip walls on
/// a moving mesh move with the mesh.
struct FluidMeshMotion {
  std::array<SpaceTimeScalar, 3> displacement;
  SourceLocation where;
};

/// A gas state given by density, velocity and pressure.
struct GasState {
  double density = 0.0;          ///< [kg/m^3], > 0
  Vec3 velocity = Vec3::Zero();  ///< [m/s]
  double pressure = 0.0;         ///< [Pa], > 0
};

/// Initial condition of a Riemann problem: `left` where (x - position n) . n < 0.
struct RiemannInitial {
  Vec3 normal = Vec3::UnitX();  ///< unit
  double position = 0.0;        ///< [m] along normal
  GasState left, right;
};

enum class FluidAnalysisType { transient, steady };

struct FluidAnalysis {
  FluidAnalysisType type = FluidAnalysisType::transient;
  double cfl = 0.5;                    ///< (0, 1] lumped mass, (0, 0.6] consistent
  int steps = 1000;                    ///< steady: local time steps (at most)
  /// steady: stop once the density rate is below this fraction of its first-step value
  std::optional<double> residual_drop;
  double q_dif = 0.0;                  ///< artificial viscosity coefficient (paper eq. 28)
  int consistent_mass_iterations = 0;  ///< 0: lumped mass
  std::optional<RiemannInitial> riemann;  ///< initial state; absent: `initial` or the free stream
  std::optional<SpaceTimeState> initial;  ///< initial state as fields of x, y, z (t = 0)
  SourceLocation where;
};

/// How the gas acts on the shell in a coupled run.
enum class FluidModelType {
  euler,          ///< the flow solver on the fluid mesh (Euler or Navier–Stokes by gas.viscosity)
  piston_theory,  ///< first-order piston theory from the shell's motion (no fluid mesh)
};

struct FluidSection {
  FluidModelType model = FluidModelType::euler;
  Gas gas;
  FreeStream free_stream;
  std::vector<FluidBoundary> boundaries;
  std::optional<FluidMeshMotion> mesh_motion;  ///< absent: the mesh stays
  std::optional<FluidAnalysis> analysis;  ///< absent: the flow is not solved
};

// ---- mesh motion ------------------------------------------------------------------------------

/// How the fluid mesh follows the moving boundary.
enum class MotionMethod {
  space_mesh,  ///< the coarse cubic space mesh (the paper's method)
  direct_idw,  ///< inverse-distance weighting on every fluid node (baseline)
  laplace,     ///< Laplacian smoothing on the fluid mesh (baseline)
};
enum class MotionWeighting { plain, area };

/// A prescribed panel deflection w(s, t) = sum_m A_m(t) sin(m pi s / L) along `normal`, s the
/// distance from `leading_edge` along `direction` (0 <= s <= length).
struct PanelModesSpec {
  Vec3 leading_edge = Vec3::Zero();  ///< [m]
  Vec3 direction = Vec3::UnitX();    ///< unit vector along the panel
  double length = 0.0;               ///< [m], > 0
  Vec3 normal = Vec3::UnitY();       ///< unit vector of the deflection
  struct Mode {
    int wave_number = 1;             ///< m >= 1
    TimeFunction amplitude;          ///< A_m(t) [m]
  };
  std::vector<Mode> modes;
  SourceLocation where;
};

struct MotionSection {
  MotionMethod method = MotionMethod::space_mesh;
  std::vector<std::string> interface_groups;  ///< moving boundary (fluid and space mesh)
  std::vector<std::string> fixed_groups;
  std::vector<std::string> sliding_groups;    ///< symmetry / slip planes
  double interface_exponent = 4.0;            ///< e1 of the IDW weights
  double fixed_exponent = 4.0;                ///< e2
  MotionWeighting weighting = MotionWeighting::plain;
  /// The boundary motion when no shell solver drives it.
  std::optional<PanelModesSpec> prescribed;
  SourceLocation where;
};

// ---- coupling ---------------------------------------------------------------------------------

/// `coupling.response`: the response analysis of one probe history, written at the end of the
/// run to OUTDIR/response.json (docs/coupling.md "Response analysis").
struct ResponseSection {
  std::string probe;  ///< empty: the first probe of field shell.displacement
  /// The window of the fit [s]; default the whole run.
  double t_start = -std::numeric_limits<double>::infinity();
  double t_end = std::numeric_limits<double>::infinity();
  int lco_cycles = 5;    ///< the last N cycles of the window: saturation and limit cycle
  SourceLocation where;  ///< `coupling.response.probe` when given, else the section
};

/// The coupled fluid–shell run (docs/coupling.md, docs/case-format.md "coupling").
struct CouplingSection {
  enum class Scheme { staggered, monolithic } scheme = Scheme::staggered;
  int substeps = 0;  ///< fluid steps per shell step; 0 = auto (from the stable step and cfl)
  enum class Predictor { none, linear } predictor = Predictor::linear;
  enum class MeshVelocity { positions, interpolated } mesh_velocity = MeshVelocity::positions;
  /// Absolute pressure on the shell's dry face [Pa]; absent: the free-stream pressure.
  std::optional<TimeFunction> cavity_pressure;
  double max_gap = 1e-6;    ///< [m] largest distance between the shell and the fluid wet boundary
  std::string fluid_group;  ///< the fluid mesh's wet boundary (euler, mesh motion)
  Vec3 wet_normal = Vec3::Zero();  ///< piston theory: from the shell into the flow (unit)
  ResponseSection response;
  SourceLocation where;
};

// ---- time -----------------------------------------------------------------------------------

struct TimeSection {
  double end = 0.0;   ///< [s], > 0
  double step = 0.0;  ///< [s], > 0; 0 when not given (a flow run takes its step from cfl)
};

// ---- probes -----------------------------------------------------------------------------------

/// A quantity a probe can record: `<mesh>.<quantity>`, scalar or vector.
struct ProbeQuantity {
  std::string_view mesh;      ///< "shell", "fluid" or "space"
  std::string_view quantity;  ///< e.g. "displacement"
  bool is_vector;
};
/// Every quantity probes may name (extend it when a module adds an output field).
std::span<const ProbeQuantity> probe_quantities();

enum class ProbeComponent { x, y, z, magnitude, scalar };  ///< `scalar`: the field is a scalar
enum class ProbeLocation { point, node, group };
enum class ProbeReduce { mean, min, max };

struct Probe {
  std::string name;      ///< unique, [A-Za-z0-9_.-]+; the CSV column title
  std::string field;     ///< "shell.displacement"
  std::string mesh;      ///< "shell" (the part before the dot)
  std::string quantity;  ///< "displacement" (the part after the dot)
  ProbeComponent component = ProbeComponent::scalar;
  ProbeLocation location = ProbeLocation::point;
  Vec3 point = Vec3::Zero();               ///< location == point [m]
  Index node = 0;                          ///< location == node: 0-based node index in that mesh
  std::string group;                       ///< location == group: physical group of that mesh
  ProbeReduce reduce = ProbeReduce::mean;  ///< location == group
  /// A curve to draw beside the probe in probes.png (`reference:`): a column of a CSV file
  /// whose first column is the abscissa (time, or a static run's load factor), times `scale`.
  struct Reference {
    std::filesystem::path file;  ///< resolved from the case file's folder; checked to exist
    std::string column;          ///< a column of its header (not the first)
    double scale = 1.0;
    std::string label;           ///< legend text; default: the file's name and the column
  };
  std::optional<Reference> reference;
  SourceLocation where;  ///< the list item `probes[i]`
};

// ---- output -----------------------------------------------------------------------------------

struct OutputSection {
  /// Output directory, relative to the current working directory (not to the case file).
  /// Default `out/<name>`; the command line's `-o` overrides it.
  std::filesystem::path directory;
  int every = 1;  ///< write fields every N steps (probes are written every step)
  /// Write a checkpoint every N steps (docs/restart.md); 0: only when a run is stopped
  /// (--stop-after, --stop-at-wall, SIGINT/SIGTERM).
  long checkpoint_every = 0;
  /// Stress written in the shell VTU at the bottom, middle and top surfaces.
  enum class ShellStress { cauchy, second_piola_kirchhoff, none } shell_stress = ShellStress::cauchy;
};

// ---- study ------------------------------------------------------------------------------------

/// A parameter study of a coupled case (`shellflow study`, docs/flutter.md): runs at several
/// values of one parameter, growth rates from response.json, the zero crossing bracketed
/// and refined.
struct StudySection {
  enum class Parameter { mach, density, dynamic_pressure, thickness } parameter = Parameter::mach;
  double lo = 0.0, hi = 0.0;  ///< the range, lo < hi
  int points = 5;             ///< runs of the first sweep (>= 2)
  double tolerance = 0.0;     ///< width of the final bracket, in the parameter's unit (> 0)
  int max_refinements = 12;   ///< refinement rounds at most
  /// `set`: case keys replaced in every run (KEY: VALUE, like `run --set`), e.g. a longer
  /// time.end, another fluid.model, a smaller start-up pulse. In file order.
  std::vector<KeyOverride> set;
  SourceLocation where;
};

// ---- the case -----------------------------------------------------------------------------------

/// A physical group named in the case file, and where (for a message if the mesh lacks it).
struct GroupReference {
  std::string group;
  std::string mesh;      ///< "fluid", "space" or "shell"
  SourceLocation where;  ///< e.g. `case.yaml:21: shell.supports[0].group`
};

struct Case {
  std::filesystem::path file;  ///< the case file as given
  std::string name;            ///< [A-Za-z0-9_.-]+
  std::string description;
  MeshesSection meshes;
  std::optional<ShellSection> shell;
  std::optional<FluidSection> fluid;
  std::optional<MotionSection> motion;
  std::optional<TimeSection> time;
  std::optional<CouplingSection> coupling;
  std::optional<StudySection> study;  ///< read by `shellflow study`; `run` ignores it
  std::vector<Probe> probes;
  OutputSection output;
  /// Every physical group the case names, in file order.
  std::vector<GroupReference> group_references;
  /// Digests of the case file's sections, after the overrides (io/checkpoint.h): what a
  /// restart compares with its checkpoint's.
  std::vector<SectionDigest> digests;
};

/// Reads and checks a case file, with `overrides` (`--set KEY=VALUE`) applied to its keys
/// first. Throws InputError `FILE:LINE: key.path: message`.
Case read_case(const std::filesystem::path& file, std::span<const KeyOverride> overrides = {});
/// Same, from text; `file` names it in messages and relative paths are resolved from its
/// directory.
Case read_case_string(std::string_view text, const std::filesystem::path& file,
                      std::span<const KeyOverride> overrides = {});

/// The probe of the response analysis of a coupled case, as an index into c.probes: the one
/// coupling.response.probe names, else the first probe of field shell.displacement; nullopt
/// when neither is there. Throws InputError at coupling.response.probe for an unknown name.
std::optional<std::size_t> response_probe(const Case& c);

/// Physical group names of a mesh, by its key ("fluid", "space", "shell").
using GroupNamesOfMesh = std::function<std::vector<std::string>(std::string_view mesh_key)>;

/// Checks that every group the case names exists in its mesh. Throws InputError
/// `FILE:LINE: shell.supports[0].group: physical group 'leadng_edge' not found in mesh 'shell'
/// (panel_strip.geo); did you mean 'leading_edge'? available: leading_edge, trailing_edge`.
/// `groups_of_mesh` is called at most once per mesh, and only for meshes the case references.
void check_physical_groups(const Case& c, const GroupNamesOfMesh& groups_of_mesh);

// ---- names of enumerations (as written in case files) -------------------------------------------

std::string_view to_string(MeshFormat f);
std::string_view to_string(SupportType t);
std::string_view to_string(FluidBoundaryType t);
std::string_view to_string(ProbeComponent c);
std::string_view to_string(ProbeLocation l);
std::string_view to_string(ProbeReduce r);
std::string_view to_string(MotionMethod m);
std::string_view to_string(ShellLoadType t);
std::string_view to_string(StudySection::Parameter p);
std::string_view to_string(MotionWeighting w);

}  // namespace shellflow::io
