#!/usr/bin/env python3
"""The bad-input catalogue (issue 14, item 10): `shellflow` on broken case files, meshes and
runs that fail, one table entry each.

Every entry must end with exit code != 0 and exactly one line `shellflow: error: ...` on
stderr naming where (FILE:LINE of the case file when the reader gives one, else the file or
the entity), what (the key, group, node ...) and the fix; what a run wrote before it stopped
must still parse: the .pvd files, every .vtu they list, whole rows in probes.csv and no
leftover *.tmp. A run killed with SIGKILL must leave the same readable state.

Run: SHELLFLOW_EXE=build/release/app/shellflow python3 tests/app/test_bad_inputs.py -v
(CTest: cli.bad_input_catalogue, label unit).
"""
import csv
import os
import re
import signal
import struct
import subprocess
import tempfile
import time
import unittest
import xml.etree.ElementTree as ET

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EXE = os.path.abspath(os.environ.get("SHELLFLOW_EXE", os.path.join(ROOT, "build", "release", "app", "shellflow")))
CASES = os.path.join(ROOT, "cases")

# Base cases the entries modify (their relative file names are made absolute).
STRIP_DYNAMIC = "shell/strip_free_vibration.yaml"
SZE31 = "shell/sze31_end_shear.yaml"
PRESCRIBED = "shell/cantilever_prescribed_rotation.yaml"
SOD = "fluid/sod.yaml"
MOTION = "motion/panel_single_mode.yaml"
PISTON = "panel_flutter/clamped_clamped_piston.yaml"
PANEL = "panel_flutter/clamped_clamped.yaml"
MODAL = "shell/strip_modal.yaml"


def base_text(base):
    """The base case's text with its file names (geo, msh, reference file) made absolute."""
    path = os.path.join(CASES, base)
    folder = os.path.dirname(path)
    with open(path) as f:
        text = f.read()
    return re.sub(r"\b(geo|msh|file): ([\w./-]+\.(?:geo|msh|csv))",
                  lambda m: f"{m.group(1)}: {os.path.normpath(os.path.join(folder, m.group(2)))}", text)


class Entry:
    """One bad input.

    base: a case under cases/ (or None: `text` is the whole case file); edit: (old, new) text
    replacements, each `old` found exactly once; sets: --set overrides; command: check, run
    or mesh; files: extra files written beside the case {name: text}; expect: substrings of
    the error line (`{case}` is the case file's name, `{line}` the line where the first
    edit's `new` text starts, `{dir}` the folder of the entry); fix: the substring that says
    what to do; run_output: after a run, the output folder must hold a readable state with at
    least this many probe rows; at: `{line}` is instead the line of the first line of the case
    that starts with this text; env: environment variables set for the run; exit: the exit code
    (1, or 4 for a run the physics stopped: a SolverError).
    """

    def __init__(self, name, base=None, edit=(), sets=(), command="check", files=None, text=None,
                 expect=(), fix=None, run_output=None, timeout=120, case_name="case.yaml", at=None,
                 env=None, exit=1):
        self.name, self.base, self.sets, self.command = name, base, list(sets), command
        self.edit = [edit] if edit and isinstance(edit[0], str) else list(edit)
        self.files, self.text, self.expect, self.fix = files or {}, text, list(expect), fix
        self.run_output, self.timeout, self.case_name, self.at = run_output, timeout, case_name, at
        self.env = env or {}
        self.exit = exit


def panel_msh_lines(name="strip_20x1.msh"):
    """A good .msh (tests/fuzz/seeds: written by Gmsh 4.8, format 4.1 ASCII)."""
    with open(os.path.join(ROOT, "tests", "fuzz", "seeds", "msh", name)) as f:
        return f.read().splitlines()


def damaged_msh(change):
    lines = panel_msh_lines()
    change(lines)
    return "\n".join(lines) + "\n"


def replace_line(marker, offset, text):
    def change(lines):
        lines[lines.index(marker) + offset] = text
    return change


def inverted_msh():
    """The unit cube's tetrahedra with two nodes of the first one swapped (one inverted element)."""
    lines = panel_msh_lines("unit_cube.msh")
    start, end = lines.index("$Elements"), lines.index("$EndElements")
    i = start + 2
    while i < end:
        dim, _, etype, count = (int(v) for v in lines[i].split())
        if dim == 3 and etype == 4:
            tag, a, b, *rest = lines[i + 1].split()
            lines[i + 1] = " ".join([tag, b, a, *rest])
            return "\n".join(lines) + "\n"
        i += 1 + count
    raise AssertionError("no tetrahedra in unit_cube.msh")


def last_node_replaced(lines):
    i = lines.index("$EndElements") - 1
    lines[i] = " ".join(lines[i].split()[:-1] + ["99999"])


STRIP_MSH_CASE = """name: strip_msh
meshes:
  shell: { msh: %s }
shell:
  thickness: 1.0e-3
  material: { young_modulus: 7.0e10, poisson_ratio: 0.3, density: 2700 }
  supports:
    - { group: leading_edge, type: clamped }
"""

RIEMANN_VACUUM = (
    "      left: { density: 1.0, pressure: 1.0 }\n      right: { density: 0.125, pressure: 0.1 }",
    "      left: { density: 1.0, velocity: [-8, 0, 0], pressure: 1.0 }\n"
    "      right: { density: 1.0, velocity: [8, 0, 0], pressure: 1.0 }")

CATALOGUE = [
    # ---- the environment ----
    Entry("simd_unknown_instruction_set", base=SOD, command="run", env={"SHELLFLOW_SIMD": "avx9"},
          expect=["environment variable SHELLFLOW_SIMD", "'avx9'"], fix="use auto, sse2, avx2, avx2-fma or avx512"),
    # Launcher variables left over, no launcher: MPI starts one rank (issue 39).
    Entry("mpi_ranks_from_the_environment_run", base=PISTON, command="run", env={"OMPI_COMM_WORLD_SIZE": "2"},
          expect=["one of 2 MPI ranks", "but MPI started 1"], fix="start it with 'mpirun -np 2', or unset"),
    Entry("mpi_ranks_from_the_environment_check", base=PISTON, command="check", env={"PMI_SIZE": "3"},
          expect=["one of 3 MPI ranks", "but MPI started 1"], fix="start it with 'mpirun -np 3', or unset"),
    # ---- issue 14's classes: .geo commands, damaged and hostile .msh files, malformed YAML ----
    Entry("geo_system_command", files={"strip.geo": "Point(1) = {0, 0, 0};\nSystem \"touch INJECTED\";\n"},
          text="name: s\nmeshes:\n  shell: { geo: strip.geo }\n",
          expect=["strip.geo:2:", "'System'"], fix="remove it"),
    Entry("geo_include_absolute", files={"strip.geo": 'Include "/etc/hostname";\n'},
          text="name: s\nmeshes:\n  shell: { geo: strip.geo }\n",
          expect=["strip.geo:1:", "absolute path"], fix="copy the file next to the .geo"),
    Entry("geo_script_named_msh", files={"strip.msh": 'Point(1) = {0, 0, 0};\nSystem "touch INJECTED";\n'},
          text=STRIP_MSH_CASE % "strip.msh", expect=["strip.msh:1:", "not a Gmsh mesh file"], fix="'geo:'"),
    Entry("msh_physical_dim_99", files={"m.msh": damaged_msh(replace_line("$PhysicalNames", 2, '99 1 "bad"'))},
          text=STRIP_MSH_CASE % "m.msh", expect=["m.msh", "damaged $PhysicalNames section (line 6)", "dimension"],
          fix="re-export the mesh from Gmsh"),
    Entry("msh_damaged_end_marker", files={"m.msh": damaged_msh(replace_line("$EndNodes", 0, "$EndNode"))},
          text=STRIP_MSH_CASE % "m.msh", expect=["m.msh", "damaged $Nodes section", "expected $EndNodes"],
          fix="re-export the mesh from Gmsh"),
    Entry("msh_cut_in_half", files={"m.msh": "\n".join(panel_msh_lines()[:60]) + "\n"},
          text=STRIP_MSH_CASE % "m.msh", expect=["m.msh", "damaged $Nodes section"], fix="re-export the mesh from Gmsh"),
    Entry("msh_element_unknown_node", files={"m.msh": damaged_msh(last_node_replaced)},
          text=STRIP_MSH_CASE % "m.msh", expect=["m.msh", "$Elements", "node 99999"], fix="re-export the mesh from Gmsh"),
    Entry("msh_binary", files={"m.msh": damaged_msh(replace_line("$MeshFormat", 1, "4.1 1 8"))},
          text=STRIP_MSH_CASE % "m.msh", expect=["m.msh", "binary .msh files are not supported"], fix="as ASCII"),
    Entry("msh_version_2", files={"m.msh": damaged_msh(replace_line("$MeshFormat", 1, "2.2 0 8"))},
          text=STRIP_MSH_CASE % "m.msh", expect=["m.msh", "format '2.2'"], fix="format 4.1 ASCII"),
    Entry("msh_control_bytes_in_a_section_name", files={"m.msh": damaged_msh(replace_line("$Nodes", 0, "$No\x1b[31mdes"))},
          text=STRIP_MSH_CASE % "m.msh", expect=["m.msh", "\\x1b"], fix="re-export the mesh from Gmsh"),
    Entry("msh_empty", files={"m.msh": ""}, text=STRIP_MSH_CASE % "m.msh", expect=["m.msh", "empty file"],
          fix="re-export the mesh from Gmsh"),
    Entry("msh_inverted_elements", files={"m.msh": inverted_msh()}, command="mesh",
          text="name: cube\nmeshes:\n  fluid: { msh: m.msh }\n", expect=["{case}:3:", "meshes.fluid", "1 inverted element"],
          fix="fix the geometry's orientation"),
    Entry("yaml_lone_comma", text=",", expect=["{case}:1:", "YAML syntax error: unexpected ','"],
          fix="check the brackets", timeout=10),
    Entry("yaml_two_documents", base=SZE31, edit=("\nprobes:", "\n---\nprobes:"),
          expect=["{case}:{next}:", "found 2"], fix="remove the '---' separators"),
    Entry("yaml_tab_indentation", base=SZE31, edit=("  thickness: 0.1", "\tthickness: 0.1"),
          expect=["{case}:{line}:", "YAML syntax error"], fix="indent with spaces"),
    Entry("yaml_control_bytes_in_a_value", base=SZE31,
          edit=("{ group: clamped, type: clamped }", '{ group: clamped, type: "clamp\\e[31med" }'),
          expect=["{case}:{line}:", "shell.supports[0].type", "clamp\\x1b[31med"], fix="expected one of"),
    Entry("yaml_high_bytes_in_a_value", base=SZE31,
          edit=("{ group: clamped, type: clamped }", '{ group: clamped, type: "clamp\\xff\\x9bed" }'),
          expect=["{case}:{line}:", "shell.supports[0].type", "clamp\\xc3\\xbf\\xc2\\x9bed"], fix="expected one of"),
    # ---- typos at every depth (each with the closest key) ----
    Entry("typo_top_level", base=SZE31, edit=("\nprobes:", "\nprobe:"),
          expect=["{case}:{line}: probe: unknown key"], fix="did you mean 'probes'"),
    Entry("typo_depth_2", base=SZE31, edit=("  thickness: 0.1", "  thicknes: 0.1"),
          expect=["{case}:{line}: shell.thicknes: unknown key"], fix="did you mean 'thickness'"),
    Entry("typo_depth_3", base=SZE31, edit=("young_modulus: 1.2e6", "youngs_modulus: 1.2e6"),
          expect=["{case}:{line}: shell.material.youngs_modulus: unknown key"], fix="did you mean 'young_modulus'"),
    Entry("typo_in_a_list_item", base=SZE31, edit=("{ group: clamped, type: clamped }", "{ group: clamped, tpye: clamped }"),
          expect=["{case}:{line}: shell.supports[0].tpye: unknown key"], fix="did you mean 'type'"),
    Entry("typo_in_an_enumeration", base=SZE31, edit=("{ group: clamped, type: clamped }", "{ group: clamped, type: clampd }"),
          expect=["{case}:{line}:", "shell.supports[0].type", "'clampd'"], fix="did you mean 'clamped'"),
    Entry("typo_in_a_field_name", base=SZE31, edit=("field: shell.displacement, component: z", "field: shell.displacment, component: z"),
          expect=["{case}:{line}:", "probes[1].field"], fix="did you mean 'shell.displacement'"),
    Entry("typo_in_a_set_key", base=SZE31, sets=["shell.analysis.stpes=3"],
          expect=["{case}:", "shell.analysis.stpes: unknown key"], fix="did you mean 'steps'"),
    # ---- wrong types ----
    Entry("string_for_a_number", base=SZE31, edit=("thickness: 0.1", "thickness: thin"),
          expect=["{case}:{line}:", "shell.thickness", "'thin'"], fix="expected a number"),
    Entry("fraction_for_an_integer", base=SZE31, edit=("steps: 20", "steps: 2.5"),
          expect=["{case}:{line}:", "shell.analysis.steps"], fix="integer"),
    Entry("map_for_a_list", base=SZE31, edit=("  supports:\n    - { group: clamped, type: clamped }",
                                              "  supports: { group: clamped, type: clamped }"),
          expect=["{case}:{line}:", "shell.supports"], fix="expected a list"),
    Entry("scalar_for_a_map", base=SZE31, edit=("  material: { young_modulus: 1.2e6, poisson_ratio: 0.0, density: 0.0 }",
                                                "  material: steel"),
          expect=["{case}:{line}:", "shell.material"], fix="expected a map"),
    Entry("two_components_for_a_vector", base=SZE31, edit=("force_per_length: [0, 0, 4.0]", "force_per_length: [0, 4.0]"),
          expect=["{case}:{line}:", "shell.loads[0].force_per_length"], fix="3"),
    # ---- values out of range ----
    Entry("poisson_ratio_one_half", base=SZE31, edit=("poisson_ratio: 0.0", "poisson_ratio: 0.5"),
          expect=["{case}:{line}:", "shell.material.poisson_ratio", "0.5"], fix="(-1, 0.5)"),
    Entry("negative_thickness", base=SZE31, edit=("thickness: 0.1", "thickness: -0.1"),
          expect=["{case}:{line}:", "shell.thickness"], fix="> 0"),
    Entry("output_every_zero", base=SZE31, edit=("output: { every: 5 }", "output: { every: 0 }"),
          expect=["{case}:{line}:", "output.every"], fix=">= 1"),
    Entry("time_step_above_the_end", base=STRIP_DYNAMIC, edit=("time: { end: 0.1, step: 5.0e-4 }", "time: { end: 0.1, step: 0.5 }"),
          expect=["{case}:{line}:", "time.step"], fix="must not exceed time.end"),
    Entry("mesh_order_4", base=SZE31, edit=("order: 3", "order: 4"),
          expect=["{case}:{line}:", "meshes.shell.order"], fix="[1, 3]"),
    Entry("gamma_one", base=SOD, edit=("gamma: 1.4", "gamma: 1.0"),
          expect=["{case}:{line}:", "fluid.gas.gamma"], fix="> 1"),
    Entry("cfl_above_one", base=SOD, edit=("cfl: 0.5", "cfl: 1.5"),
          expect=["{case}:{line}:", "fluid.analysis.cfl"], fix="1"),
    Entry("zero_density_of_a_dynamic_shell", base=STRIP_DYNAMIC, sets=["shell.material.density=0"],
          expect=["{case}:", "shell.analysis.type", "mass"], fix="set shell.material.density > 0"),
    Entry("zero_direction", base=PRESCRIBED, edit=("rotation_axis: [0, 1, 0]", "rotation_axis: [0, 0, 0]"),
          expect=["{case}:{line}:", "shell.supports[0].rotation_axis"], fix="non-zero vector"),
    # ---- missing keys and sections ----
    Entry("missing_name", base=SZE31, edit=("name: sze31_end_shear\n", "\n"),
          expect=["{case}:", "'name'"], fix="name"),
    Entry("missing_young_modulus", base=SZE31, edit=("young_modulus: 1.2e6, ", ""),
          expect=["{case}:{line}:", "shell.material", "young_modulus"], fix="young_modulus"),
    Entry("missing_meshes", base=SZE31, edit=("meshes:\n  shell: { geo:", "mesh_files:\n  shell: { geo:"),
          expect=["{case}:", "meshes"], fix="meshes"),
    Entry("dynamic_without_time", base=STRIP_DYNAMIC, edit=("time: { end: 0.1, step: 5.0e-4 }", ""),
          expect=["{case}:", "shell.analysis", "'time' section"], fix="(end, step)"),
    Entry("missing_free_stream_density", base=SOD, edit=("free_stream: { density: 1.0, pressure", "free_stream: { pressure"),
          expect=["{case}:{line}:", "fluid.free_stream", "density"], fix="density"),
    # ---- physical groups and meshes ----
    Entry("unknown_support_group", base=SZE31, edit=("{ group: clamped, type: clamped }", "{ group: clampd, type: clamped }"),
          expect=["{case}:{line}:", "physical group 'clampd'"], fix="did you mean 'clamped'"),
    Entry("unknown_fluid_boundary_group", base=SOD, edit=("{ group: right, type: slip_wall }", "{ group: rigth, type: slip_wall }"),
          expect=["{case}:{line}:", "physical group 'rigth'"], fix="did you mean 'right'"),
    Entry("geo_file_not_found", base=SZE31, edit=("sze31_cantilever_8x1.geo", "sze31_cantilever_9x1.geo"),
          expect=["{case}:{line}:", "meshes.shell.geo", "file not found"], fix="relative to the case file's directory"),
    Entry("msh_file_not_found", text=STRIP_MSH_CASE % "none.msh",
          expect=["{case}:3:", "meshes.shell.msh", "file not found"], fix="relative to the case file's directory"),
    Entry("shell_section_without_a_shell_mesh", base=SOD, edit=("\ntime: { end: 0.2 }", "\nshell: { thickness: 1 }\ntime: { end: 0.2 }"),
          expect=["{case}:{line}:", "shell", "needs a shell mesh"], fix="'meshes.shell'"),
    Entry("fluid_probe_without_a_fluid_mesh", base=SZE31, edit=("field: shell.displacement, component: z", "field: fluid.pressure, component: z"),
          expect=["{case}:{line}:", "probes[1].field", "no fluid mesh"], fix="'meshes.fluid'"),
    Entry("reference_column_unknown", base=SZE31, edit=("column: w_tip", "column: w_top"),
          expect=["{case}:{line}:", "probes[1].reference.column", "'w_top'"], fix="did you mean 'w_tip'"),
    Entry("reference_file_not_found", base=SZE31, edit=("reference_sze31.csv, column: w_tip", "reference_sze99.csv, column: w_tip"),
          expect=["{case}:{line}:", "probes[1].reference.file", "file not found"], fix="relative to the case file's directory"),
    # ---- rules `run` applies before it starts, applied by `check` ----
    Entry("prescribed_support_with_arc_length", base=PRESCRIBED, edit=("{ type: static, steps: 5 }", "{ type: static, steps: 5, control: arc_length }"),
          expect=["{case}:{line}:", "shell.analysis.control", "prescribed support shell.supports[0]"], fix="use control: load"),
    Entry("prescribed_support_with_arc_length_run", base=PRESCRIBED, command="run",
          edit=("{ type: static, steps: 5 }", "{ type: static, steps: 5, control: arc_length }"),
          expect=["{case}:{line}:", "shell.analysis.control"], fix="use control: load"),
    Entry("mesh_motion_without_a_prescribed_motion", base=MOTION,
          edit=("  prescribed:\n    type: panel_modes\n", "  prescribed_motion:\n    type: panel_modes\n"),
          expect=["{case}:{line}:", "motion.prescribed_motion: unknown key"], fix="did you mean 'prescribed'"),
    Entry("mesh_motion_without_its_prescribed_section", base=MOTION, edit=(
          "  prescribed:\n    type: panel_modes\n    leading_edge: [0.25, 0.0, 0.0]\n    direction: [1, 0, 0]\n"
          "    length: 0.5\n    normal: [0, 1, 0]\n    modes:\n"
          "      - { wave_number: 1, amplitude: { type: ramp, value: 0.12, duration: 1.0 } }\n", ""),
          at="motion:", expect=["{case}:{line}: motion: a mesh-motion run without a 'coupling' section needs "
                                "'prescribed'"], fix="add it"),
    # ---- issue 24: physics outside the model's validity, messages ----
    Entry("piston_theory_below_its_mach_margin", base=PISTON, sets=["fluid.free_stream.mach=1.1"],
          expect=["{case}:", "fluid.free_stream.mach 1.1", "shellflow refuses M < 1.2"], fix="use fluid.model: euler"),
    Entry("piston_theory_wet_normal_in_the_panel_plane", base=PISTON, command="run",
          sets=["coupling.wet_normal=[1, 0, 0]", "time.end=0.001"],
          expect=["coupling.wet_normal [1, 0, 0] lies 90.0 degrees from the panel's normal"],
          fix="across the panel"),
    Entry("piston_theory_stream_into_the_panel", base=PISTON, command="run",
          sets=["fluid.free_stream.direction=[1, -0.1, 0]", "time.end=0.001"],
          expect=["fluid.free_stream.direction", "5.71 degrees into the panel"], fix="turn the direction"),
    Entry("poisson_ratio_near_minus_one", base=STRIP_DYNAMIC, sets=["shell.material.poisson_ratio=-0.999"],
          expect=["{case}:", "shell.material.poisson_ratio: -0.999 is too close to -1"], fix="accepts -0.9 < nu"),
    Entry("shell_density_near_zero", base=STRIP_DYNAMIC, sets=["shell.material.density=1e-30"],
          expect=["{case}:", "shell.material.density: 1e-30 kg/m^3", "near-singular mass matrix"],
          fix="check the units"),
    Entry("geo_that_sleeps_an_hour", files={"slow.geo": "Point(1) = {0, 0, 0};\nSleep 3600;\n"},
          text="name: s\nmeshes:\n  shell: { geo: slow.geo }\n", env={"SHELLFLOW_GEO_TIMEOUT": "2"}, timeout=60,
          command="mesh",
          expect=["slow.geo: Gmsh did not finish reading it within 2 s"], fix="SHELLFLOW_GEO_TIMEOUT=seconds"),
    Entry("geo_timeout_not_a_number", files={"s.geo": "Point(1) = {0, 0, 0};\n"},
          text="name: s\nmeshes:\n  shell: { geo: s.geo }\n", env={"SHELLFLOW_GEO_TIMEOUT": "nan"}, command="mesh",
          expect=["SHELLFLOW_GEO_TIMEOUT='nan'"], fix="(> 0)"),
    Entry("study_set_misspelt_key", base=PISTON, edit=("    time.end: 0.25", "    time.edn: 0.25"),
          expect=["study at mach = 1.8 (study.set and the parameter applied)", "time.edn: unknown key"],
          fix="did you mean 'end'?"),
    # ---- runs that fail: Newton, negative pressure, inverted elements, non-finite values ----
    # A static run whose first level fails keeps one frame and one probe row at load factor 0.
    Entry("newton_fails_at_the_first_load_level", base=SZE31, command="run",
          edit=("{ type: static, steps: 20, newton: modified }",
                "{ type: static, steps: 1, control: displacement, controlled: { group: tip, component: x }, "
                "final_value: -30 }"),
          expect=["displacement control did not converge", "step 1 of 1", "last converged state (load factor 0)"],
          fix="use more steps", run_output=1, exit=4),
    Entry("newton_fails_in_a_dynamic_step", base=STRIP_DYNAMIC, command="run", sets=["time.end=0.0015"],
          edit=("{ type: pressure, pressure: 1.0 }", "{ type: pressure, pressure: 1.0e8 }"),
          expect=["Newton did not converge at t = ", "the last valid state"], fix="reduce the time step", run_output=2, exit=4),
    Entry("negative_pressure_in_a_vacuum", base=SOD, command="run", edit=RIEMANN_VACUUM,
          expect=["fluid state not physical", "node", "p = "], fix="q_dif", run_output=1, exit=4),
    Entry("inverting_mesh_motion", base=MOTION, command="run", sets=["time.end=0.3", "time.step=0.05",
          "motion.prescribed.modes=[{wave_number: 1, amplitude: {type: ramp, value: 3.0, duration: 0.3}}]"],
          expect=["t = 0.05 s: the mesh motion inverts", "fluid element(s), the worst", "(step 1)", "last valid state (t = 0 s)"],
          fix="reduce the amplitude or change motion.method", run_output=1, exit=4),
    Entry("nan_shell_load_at_t0", base=STRIP_DYNAMIC, command="run",
          sets=["time.end=0.002", 'shell.analysis.load_function={type: expression, value: "sqrt(-1)"}'],
          expect=["{case}:", "shell.analysis.load_function: is NaN at t = 0 s"], fix="must stay finite", run_output=0),
    # ---- issue 25: the coupled no-slip wall moves with the shell ----
    Entry("velocity_on_the_coupled_wet_wall", base="viscous_coupling/couette_strip.yaml",
          edit=("- { group: strip, type: no_slip_wall, temperature: 300.3 }",
                "- { group: strip, type: no_slip_wall, velocity: [1, 0, 0], temperature: 300.3 }"),
          expect=["{case}:", "the wet wall 'strip' moves with the shell"], fix="remove its 'velocity'"),
    Entry("power_law_exponent_out_of_range", base="viscous_coupling/boundary_layer_panel.yaml",
          edit=("law: power, exponent: 1.0,", "law: power, exponent: 5.0,"),
          expect=["{case}:{line}:", "fluid.gas.viscosity.exponent"], fix="2"),
    Entry("infinite_initial_density", base=SOD, command="run", edit=(
          "    riemann:\n      normal: [1, 0, 0]\n      position: 0.5\n"
          "      left: { density: 1.0, pressure: 1.0 }\n      right: { density: 0.125, pressure: 0.1 }",
          '    initial: { density: "1e200*1e200", pressure: 1 }'),
          expect=["{case}:{line}:", "fluid.analysis.initial.density: is inf"], fix="must stay finite", run_output=None),
    # ---- issue 39: keys a run would read and then ignore ----
    # ---- issue 39: a size factor that would make a mesh beyond the machine (estimated from
    # the meshes at factors 1 and 0.5, before the mesh asked is begun) ----
    Entry("size_factor_beyond_the_machine_check", base=PANEL, sets=["meshes.fluid.size_factor=1e-3"],
          expect=["fluid_slab.geo: meshes.fluid.size_factor 0.001 would make about ", "elements"],
          fix="raise it to "),
    Entry("size_factor_beyond_the_machine_run", base=PANEL, command="run", sets=["meshes.fluid.size_factor=1e-3"],
          expect=["fluid_slab.geo: meshes.fluid.size_factor 0.001 would make about "], fix="raise it to ",
          timeout=30),
    Entry("monolithic_scheme_with_a_predictor", base=PISTON,
          sets=["coupling.scheme=monolithic", "coupling.predictor=linear"],
          expect=["{case}:", "coupling.predictor: the monolithic scheme", "predicts none"], fix="remove 'predictor'"),
    Entry("symmetry_plane_that_cannot_hold_its_edge", base="panel_3d/clamped_square_coarse.yaml", command="run",
          edit=("{ group: mid_span, type: symmetry, normal: [0, 0, 1] }",
                "{ group: mid_span, type: symmetry, normal: [1, 0, 0] }"),
          sets=["time.end=0.0002"],
          expect=["{case}:{line}:", "shell.supports[3]: symmetry support on 'mid_span'",
                  "does not lie in a plane with normal (1, 0, 0)"], fix="give the normal of the symmetry plane"),
    Entry("set_value_with_two_documents", base=PISTON, sets=["time.end=0.01\n---\n5"],
          expect=["{case}:", "--set time.end=0.01\\x0a---\\x0a5: the value holds more than one YAML document"],
          fix="no '---' separators"),
    Entry("set_value_with_a_terminal_escape", base=PISTON, sets=["time.end=[\x1b[31m"],
          expect=["{case}:", "--set time.end=[\\x1b[31m: the value is not valid YAML"], fix="not valid YAML"),
    Entry("piston_theory_with_a_viscosity", base=PISTON,
          sets=["fluid.gas.viscosity={law: constant, mu_ref: 1e-5}"],
          expect=["{case}:", "fluid.gas.viscosity: piston theory is inviscid"], fix="remove it"),
]


def read_vtu(path):
    """Checks a .vtu written by shellflow: XML header, and every appended array (UInt64 byte
    count, then the data) inside the file. Returns the number of points."""
    with open(path, "rb") as f:
        data = f.read()
    marker = data.index(b'<AppendedData encoding="raw">')
    header = data[:marker].decode() + "</VTKFile>"
    root = ET.fromstring(header)
    piece = root.find("./UnstructuredGrid/Piece")
    start = data.index(b"_", marker) + 1
    for array in root.iter("DataArray"):
        if array.get("format") != "appended":
            continue
        offset = int(array.get("offset"))
        (size,) = struct.unpack_from("<Q", data, start + offset)
        if start + offset + 8 + size > len(data):
            raise AssertionError(f"{path}: array {array.get('Name')} runs past the end of the file")
    if not data.rstrip().endswith(b"</VTKFile>"):
        raise AssertionError(f"{path}: no closing </VTKFile>")
    import meshio  # an independent reader (Debian's python3-meshio)
    points = len(meshio.read(path).points)
    if points != int(piece.get("NumberOfPoints")):
        raise AssertionError(f"{path}: meshio reads {points} points")
    return points


def check_output(test, out, min_rows, killed=False):
    """What a run wrote before it stopped parses: .pvd series, their .vtu files, probes.csv.
    A run that failed leaves no *.tmp; one killed (SIGKILL) may leave the <file>.tmp of the
    one file it was writing whole (a frame's .vtu or the .pvd that lists it, docs/output.md),
    never listed in a .pvd, the <file> itself untouched (the next write unlinks it)."""
    files = os.listdir(out)
    temporary = [f for f in files if f.endswith(".tmp")]
    if killed:
        test.assertTrue(all(f.endswith((".vtu.tmp", ".pvd.tmp")) for f in temporary), temporary)
        test.assertLessEqual(len(temporary), 1, temporary)
    else:
        test.assertEqual(temporary, [], "leftover temporary files")
    listed_all = []
    for pvd in [f for f in files if f.endswith(".pvd")]:
        listed = [d.get("file") for d in ET.parse(os.path.join(out, pvd)).getroot().iter("DataSet")]
        listed_all += listed
        test.assertGreater(len(listed), 0, pvd)
        times = [float(d.get("timestep")) for d in ET.parse(os.path.join(out, pvd)).getroot().iter("DataSet")]
        test.assertEqual(len(set(times)), len(times), f"{pvd}: a time listed twice: {times}")
        for name in listed:
            test.assertGreater(read_vtu(os.path.join(out, name)), 0, name)
    probes = os.path.join(out, "probes.csv")
    if min_rows is not None or os.path.exists(probes):
        with open(probes, newline="") as f:
            text = f.read()
        test.assertTrue(text.endswith("\n"), "probes.csv ends inside a row")
        rows = list(csv.reader(text.splitlines()))
        test.assertEqual(rows[0][0], "time")
        for row in rows[1:]:
            test.assertEqual(len(row), len(rows[0]), row)
            for value in row:
                float(value)
        times = [float(r[0]) for r in rows[1:]]
        test.assertEqual(len(set(times)), len(times), f"probes.csv: a row written twice: {times}")
        test.assertGreaterEqual(len(rows) - 1, min_rows or 0)
    for name in temporary:
        test.assertNotIn(name[:-4], listed_all, name)


class BadInputCatalogue(unittest.TestCase):
    """Each entry of CATALOGUE is a subtest; the table must hold at least 40."""

    def test_the_catalogue_has_at_least_40_entries(self):
        self.assertGreaterEqual(len(CATALOGUE) + 1, 40)  # + the SIGKILL test below
        self.assertEqual(len({e.name for e in CATALOGUE}), len(CATALOGUE))

    def run_entry(self, e, folder):
        for name, content in e.files.items():
            with open(os.path.join(folder, name), "w") as f:
                f.write(content)
        text = e.text if e.text is not None else base_text(e.base)
        line = None
        for old, new in e.edit:
            self.assertEqual(text.count(old), 1, f"{e.name}: '{old}' must occur once in {e.base}")
            if line is None:
                line = text[:text.index(old)].count("\n") + 1 + (len(new) - len(new.lstrip("\n")))
            text = text.replace(old, new)
        if e.at is not None:
            line = next(i for i, l in enumerate(text.splitlines(), start=1) if l.startswith(e.at))
        case = os.path.join(folder, e.case_name)
        with open(case, "w") as f:
            f.write(text)
        out = os.path.join(folder, "out")
        args = [EXE, e.command, case]
        if e.command in ("run", "mesh"):
            args += ["-o", out, "--no-plot"]
        for s in e.sets:
            args += ["--set", s]
        start = time.monotonic()
        r = subprocess.run(args, capture_output=True, text=True, timeout=e.timeout, cwd=folder,
                           env={**os.environ, **e.env})
        elapsed = time.monotonic() - start
        return r, line, out, elapsed

    def test_every_entry_fails_with_one_line_naming_the_cause_and_the_fix(self):
        for e in CATALOGUE:
            with self.subTest(e.name), tempfile.TemporaryDirectory() as folder:
                r, line, out, _ = self.run_entry(e, folder)
                self.assertGreater(r.returncode, 0, f"{e.name}: exit {r.returncode}\n{r.stderr}")
                self.assertEqual(r.returncode, e.exit, f"{e.name}: exit {r.returncode}\n{r.stderr}")
                lines = r.stderr.strip().splitlines()
                errors = [l for l in lines if l.startswith("shellflow: error: ")]
                self.assertEqual(len(errors), 1, r.stderr)
                others = [l for l in lines if l not in errors and not re.match(r"\[\d\d:\d\d:\d\d\] (info|warning): ", l)]
                self.assertEqual(others, [], r.stderr)
                message = errors[0]
                self.assertFalse(any(ord(ch) < 0x20 for ch in message), repr(message))
                for needle in e.expect:
                    needle = needle.format(case=e.case_name, line=line, next=(line or 0) + 1, dir=folder)
                    self.assertIn(needle, message, e.name)
                if e.fix is not None:
                    self.assertIn(e.fix, message, e.name)
                self.assertFalse(os.path.exists(os.path.join(folder, "INJECTED")), e.name)
                if e.command == "run" and os.path.isdir(out):
                    check_output(self, out, e.run_output)
                elif e.run_output is not None:
                    self.fail(f"{e.name}: the run wrote no output folder")

    def test_a_run_killed_with_sigkill_leaves_readable_output(self):
        with tempfile.TemporaryDirectory() as folder:
            case = os.path.join(folder, "case.yaml")
            with open(case, "w") as f:
                f.write(base_text(STRIP_DYNAMIC))
            out = os.path.join(folder, "out")
            p = subprocess.Popen([EXE, "run", case, "-o", out, "--no-plot", "--set", "time.end=100",
                                  "--set", "output.every=3"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            try:
                deadline = time.monotonic() + 60
                probes = os.path.join(out, "probes.csv")
                while time.monotonic() < deadline:
                    if os.path.exists(probes) and os.path.getsize(probes) > 3000:
                        break
                    time.sleep(0.05)
                else:
                    self.fail("the run wrote no probes within 60 s")
                p.send_signal(signal.SIGKILL)
                self.assertEqual(p.wait(timeout=30), -signal.SIGKILL)
            finally:
                if p.poll() is None:
                    p.kill()
                    p.wait()
            check_output(self, out, 10, killed=True)


if __name__ == "__main__":
    unittest.main()
