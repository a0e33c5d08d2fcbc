// The flow's error per wavelength on the wavy wall (tests/support/wavy_wall.h): one CSV row per
// mesh density, for the scheme options given. bench/fluid/wavy_wall.py runs the tables of
// docs/fluid.md and plots them.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <string>
#include <vector>

#include "support/wavy_wall.h"

int main(int argc, char** argv) {
  CLI::App app{"Wavy-wall error per wavelength of the Euler flow (CSV on stdout)"};
  shellflow::support::WavyWallSetup s;
  std::vector<double> cells{4, 8, 16};
  bool header = false;
  std::string wall_csv;
  app.add_option("--wall-csv", wall_csv, "write the wall pressure of the last mesh here (x, p - p_inf, theory)");
  app.add_option("--mach", s.mach, "free-stream Mach number")->capture_default_str();
  app.add_option("--cells", cells, "cells per lambda_x / M_r (several: one row each)")->capture_default_str();
  app.add_flag("--unstructured", s.unstructured, "Gmsh tetrahedra instead of the Kuhn slab");
  app.add_flag("--moving-mesh", s.moving_mesh, "the wall deflects in the mesh (else transpiration)");
  app.add_option("--wave-speed", s.wave_speed, "V / c of a travelling deflection wave")->capture_default_str();
  app.add_option("--q-dif", s.options.q_dif, "artificial viscosity coefficient")->capture_default_str();
  app.add_option("--consistent-mass", s.options.consistent_mass_iterations, "Jacobi sweeps (0: lumped)")
      ->capture_default_str();
  std::string walls = "weak";
  app.add_option("--slip-walls", walls, "weak (the wall's flux) or strong (nodal projection)")
      ->check(CLI::IsMember({"weak", "strong"}))
      ->capture_default_str();
  app.add_option("--cfl", s.cfl, "CFL number")->capture_default_str();
  app.add_flag("--header", header, "print the CSV header first");
  CLI11_PARSE(app, argc, argv);
  s.options.weak_slip_walls = walls == "weak";
  if (header)
    std::printf(
        "mach,wave_speed,mesh,motion,slip_walls,q_dif,consistent_mass,cfl,cells_per_wavelength,tets,steps,"
        "seconds,amplitude_ratio,phase_deg,loss_per_wavelength,drift_deg_per_wavelength\n");
  for (const double c : cells) {
    s.cells_per_wavelength = c;
    const auto r = shellflow::support::run_wavy_wall(s);
    std::printf("%g,%g,%s,%s,%s,%g,%d,%g,%g,%ld,%ld,%.2f,%.6f,%.4f,%.6f,%.4f\n", s.mach, s.wave_speed,
                s.unstructured ? "unstructured" : "slab", s.moving_mesh ? "mesh" : "transpiration", walls.c_str(),
                s.options.q_dif, s.options.consistent_mass_iterations, s.cfl, c, long(r.cells), r.steps, r.seconds,
                r.amplitude_ratio, r.phase_deg, r.loss_per_wavelength, r.drift_per_wavelength);
    std::fflush(stdout);
    if (!wall_csv.empty()) {
      std::FILE* f = std::fopen(wall_csv.c_str(), "w");
      if (!f) return 1;
      std::fprintf(f, "x,p,theory\n");
      for (const auto& w : r.wall) std::fprintf(f, "%.9g,%.9g,%.9g\n", w[0], w[1], w[2]);
      std::fclose(f);
    }
  }
}
