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
#include "shellflow/io/case_fluid.h"
#include "shellflow/io/case_motion.h"
#include "shellflow/io/case_shell.h"
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

// ---- shell, fluid, mesh motion: in case_shell.h, case_fluid.h, case_motion.h ------------------

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
  /// Coupling iterations per shell step (1: the explicit staggered scheme) and the relative
  /// load residual that ends them (docs/coupling.md "Implicit coupling").
  int iterations = 1;
  double tolerance = 1e-6;
  /// `coupling.acceleration`: a name, or a map with `type` and the parameters.
  struct Acceleration {
    enum class Type { none, constant, aitken, iqn_ils } type = Type::none;
    double relaxation = 0.5;  ///< constant: w; aitken, iqn_ils: the first step's w
    int columns = 100;        ///< iqn_ils: most columns used
    int reuse = 8;            ///< iqn_ils: past shell steps whose columns are reused
    double filter = 1e-10;    ///< iqn_ils: QR filter (relative)
    SourceLocation where;
  } acceleration;
  enum class MeshVelocity { positions, interpolated } mesh_velocity = MeshVelocity::positions;
  /// Absolute pressure on the shell's dry face [Pa]; absent: the free-stream pressure.
  std::optional<TimeFunction> cavity_pressure;
  double max_gap = 1e-6;           ///< [m] largest distance between the shell and the fluid wet boundary
  std::string fluid_group;         ///< the fluid mesh's wet boundary (euler, mesh motion)
  Vec3 wet_normal = Vec3::Zero();  ///< piston theory: from the shell into the flow (unit)
  ResponseSection response;
  /// `coupling.identification`: the run is a forced-motion identification of the aerodynamic
  /// forces (docs/flutter.md, "Identified aerodynamics"): the wall follows pulses of the
  /// shell's first `modes` in-vacuo modes, no shell solve; gaf_record.csv and gaf.json.
  struct Identification {
    int modes = 6;
    double pulse_width = 0.0;  ///< [s]; 0: auto (one period of the highest mode's frequency)
    double gap = 0.0;          ///< [s] rest after each pulse; 0: auto (3 a / (c_inf (M - 1)))
    double amplitude = 1e-6;   ///< [m] peak mid-surface deflection of a pulse
    SourceLocation where;
  };
  std::optional<Identification> identification;
  SourceLocation where;
};

// ---- time -----------------------------------------------------------------------------------

/// The most steps a case's time section may ask for (time.end / time.step).
inline constexpr double kMaxSteps = 1e9;
/// The lowest free-stream Mach number of a piston-theory case (coupling::kPistonTheoryMinMach;
/// docs/coupling.md, "Validity limits").
inline constexpr double kPistonTheoryMinMach = 1.2;

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
    std::string label;  ///< legend text; default: the file's name and the column
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
std::string_view to_string(FluidSlipWalls w);
std::string_view to_string(ProbeComponent c);
std::string_view to_string(ProbeLocation l);
std::string_view to_string(ProbeReduce r);
std::string_view to_string(MotionMethod m);
std::string_view to_string(ShellLoadType t);
std::string_view to_string(StudySection::Parameter p);
std::string_view to_string(MotionWeighting w);
std::string_view to_string(CouplingSection::Acceleration::Type t);

}  // namespace shellflow::io
