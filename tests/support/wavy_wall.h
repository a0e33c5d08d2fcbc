#pragma once
// The wavy-wall measurement of the flow's error per wavelength (docs/fluid.md "Accuracy per
// wavelength"; design note accuracy.md): steady supersonic flow over a wall with a small
// sinusoidal deflection, or a deflection wave travelling downstream at speed V, against linear
// supersonic theory,
//   p - p_inf = rho (U - V)^2 A k cos(k (x - V t) - k beta_r y) / beta_r,  beta_r = sqrt(M_r^2 - 1),
// M_r = (U - V) / c. Non-dimensional: rho = 1, c = 1, U = M, wavelength lambda_x = 1, slope
// A k = 1e-3. The mesh is sized in cells per lambda_n = lambda_x / M_r (the wavelength normal
// to the wave fronts). The wall's motion enters either as a transpiration velocity on the flat
// wall (the scheme alone) or as a mesh that deflects with the wall (the ALE terms too).
//
// What it measures: the wall pressure's amplitude ratio and phase (a least-squares fit of one
// harmonic over two wavelengths, away from the inflow corner and before the wave reflected
// by the top boundary returns), and the loss and phase drift per wavelength travelled along
// the Mach lines (the same fit at heights up to two normal wavelengths of travel).
#include <fmt/format.h>
#include <unistd.h>

#include <Eigen/Dense>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "shellflow/fluid/fluid_model.h"
#include "shellflow/fluid/ordering.h"
#include "shellflow/mesh/gmsh_io.h"
#include "support/box_mesh.h"

namespace shellflow::support {

struct WavyWallSetup {
  double mach = 2.3;
  double cells_per_wavelength = 8.0;  ///< cells per lambda_n = lambda_x / M_r
  bool unstructured = false;          ///< Gmsh tetrahedra in a box 3 cells wide; else the Kuhn slab
  bool moving_mesh = false;           ///< the wall deflects in the mesh; else transpiration
  double wave_speed = 0.0;            ///< V / c: a travelling deflection wave; 0: steady wavy wall
  fluid::FluidOptions options;        ///< gas, q_dif, mass, ...
  double cfl = 0.5;
};

struct WavyWallResult {
  double amplitude_ratio = 0.0;             ///< wall pressure amplitude / linear theory
  double phase_deg = 0.0;                   ///< wall pressure phase lag behind linear theory, degrees
  double loss_per_wavelength = 0.0;         ///< amplitude lost per lambda_n travelled (fraction)
  double drift_per_wavelength = 0.0;        ///< phase lag gained per lambda_n travelled, degrees
  std::vector<std::array<double, 3>> wall;  ///< (x, p - p_inf, linear theory) at the wall nodes of the window
  Index cells = 0;
  long steps = 0;
  double seconds = 0.0;
};

namespace wavy_wall_detail {

constexpr double two_pi = 2.0 * std::numbers::pi;

struct Geometry {
  double mach_r, beta_r, h, y_top, height, length, width;
};

inline Geometry geometry(const WavyWallSetup& s) {
  Geometry g;
  g.mach_r = s.mach - s.wave_speed;
  g.beta_r = std::sqrt(g.mach_r * g.mach_r - 1.0);
  g.h = 1.0 / (g.mach_r * s.cells_per_wavelength);
  // Heights that a signal reaches after travelling two normal wavelengths along the Mach
  // lines (y M_r^2 / beta_r wavelengths at height y); the wall window x in [1, 3]; the top
  // boundary far enough that its reflection reaches neither window.
  g.y_top = 2.0 * g.beta_r / (g.mach_r * g.mach_r);
  g.height = g.y_top + 1.6 / g.beta_r + 0.1;
  g.length = g.beta_r * g.y_top + 3.2;
  g.width = s.unstructured ? 3.0 * g.h : g.h;
  return g;
}

inline std::string group_of(const Vec3& c, const Geometry& g) {
  const double tol = 1e-9;
  if (std::abs(c.x()) < tol) return "inflow";
  if (std::abs(c.x() - g.length) < tol) return "outflow";
  if (std::abs(c.y()) < tol) return "wall";
  if (std::abs(c.y() - g.height) < tol) return "top";
  return "symmetry";
}

inline mesh::Mesh unstructured_mesh(const Geometry& g) {
  const auto dir = std::filesystem::temp_directory_path() / fmt::format("shellflow_wavy_wall_{}", ::getpid());
  std::filesystem::create_directories(dir);
  const auto geo = dir / "wavy_wall_box.geo";
  {
    std::ofstream out(geo);
    out << fmt::format(
        "SetFactory(\"OpenCASCADE\");\nBox(1) = {{0, 0, 0, {}, {}, {}}};\ne = 1e-6;\n"
        "Physical Surface(\"inflow\") = Surface In BoundingBox{{-e, -e, -e, e, {h} + e, {w} + e}};\n"
        "Physical Surface(\"outflow\") = Surface In BoundingBox{{{l} - e, -e, -e, {l} + e, {h} + e, {w} + e}};\n"
        "Physical Surface(\"wall\") = Surface In BoundingBox{{-e, -e, -e, {l} + e, e, {w} + e}};\n"
        "Physical Surface(\"top\") = Surface In BoundingBox{{-e, {h} - e, -e, {l} + e, {h} + e, {w} + e}};\n"
        "s0[] = Surface In BoundingBox{{-e, -e, -e, {l} + e, {h} + e, e}};\n"
        "s1[] = Surface In BoundingBox{{-e, -e, {w} - e, {l} + e, {h} + e, {w} + e}};\n"
        "Physical Surface(\"symmetry\") = {{s0[], s1[]}};\nPhysical Volume(\"fluid\") = Volume{{:}};\n"
        "MeshSize{{ PointsOf{{ Volume{{:}}; }} }} = {s};\n",
        g.length, g.height, g.width, fmt::arg("l", g.length), fmt::arg("h", g.height), fmt::arg("w", g.width),
        fmt::arg("s", g.h));
  }
  mesh::MeshingOptions options;
  mesh::Mesh m = mesh::generate_mesh(geo, options, "wavy_wall");
  std::filesystem::remove_all(dir);
  return m;
}

/// Least-squares p = c0 + a cos(phi) + b sin(phi) over the samples: amplitude and phase lag
/// (radians) of the harmonic, p ~ amplitude cos(phi - lag).
inline std::pair<double, double> fit_harmonic(const std::vector<double>& phi, const std::vector<double>& p) {
  Eigen::MatrixXd a(Eigen::Index(phi.size()), 3);
  Eigen::VectorXd b(Eigen::Index(phi.size()));
  for (std::size_t i = 0; i < phi.size(); ++i) {
    a.row(Eigen::Index(i)) << 1.0, std::cos(phi[i]), std::sin(phi[i]);
    b(Eigen::Index(i)) = p[i];
  }
  const Eigen::Vector3d c = a.colPivHouseholderQr().solve(b);
  return {std::hypot(c(1), c(2)), std::atan2(c(2), c(1))};
}

}  // namespace wavy_wall_detail

/// Runs the flow until the start-up transient has left the box and measures the wave pattern.
inline WavyWallResult run_wavy_wall(const WavyWallSetup& s) {
  using namespace wavy_wall_detail;
  using fluid::BoundaryCondition;
  using fluid::BoundaryKind;
  const auto start = std::chrono::steady_clock::now();
  const Geometry g = geometry(s);
  const double slope = 1e-3, amplitude = slope / two_pi, u = s.mach, v = s.wave_speed;
  mesh::Mesh m = s.unstructured
                     ? unstructured_mesh(g)
                     : box_mesh({int(std::ceil(g.length / g.h)), int(std::ceil(g.height / g.h)), 1},
                                Vec3(g.length, g.height, g.width), [&](const Vec3& c) { return group_of(c, g); });
  fluid::renumber_for_locality(m);
  const double gamma = s.options.gas.gamma;
  const fluid::Primitive inf{1.0, Vec3(u, 0, 0), 1.0 / gamma};
  // Deflection y_w = A r(x) sin(k (x - V t)), r a smooth ramp over the first half wavelength.
  const auto ramp = [](double x) { return x >= 0.5 ? 1.0 : std::pow(std::sin(std::numbers::pi * x), 2); };
  const auto ramp_slope = [](double x) { return x >= 0.5 ? 0.0 : std::numbers::pi * std::sin(two_pi * x); };
  const auto deflection = [&](double x, double t) { return amplitude * ramp(x) * std::sin(two_pi * (x - v * t)); };
  const auto deflection_rate = [&](double x, double t) {
    return -amplitude * ramp(x) * two_pi * v * std::cos(two_pi * (x - v * t));
  };
  const auto deflection_slope = [&](double x, double t) {
    return amplitude *
           (ramp_slope(x) * std::sin(two_pi * (x - v * t)) + ramp(x) * two_pi * std::cos(two_pi * (x - v * t)));
  };
  const std::vector<Vec3> X(m.nodes);
  fluid::WallVelocity wall = [&](Index a, const Vec3&, double t) {
    const double x = X[std::size_t(a)].x();
    // Transpiration: the linearised kinematic condition dy_w/dt + U dy_w/dx on the flat wall;
    // a deflecting mesh: the wall's own velocity (the normals turn with it).
    return Vec3(0, s.moving_mesh ? deflection_rate(x, t) : deflection_rate(x, t) + u * deflection_slope(x, t), 0);
  };
  std::vector<BoundaryCondition> bcs{{"inflow", BoundaryKind::supersonic_inflow, inf},
                                     {"outflow", BoundaryKind::supersonic_outflow},
                                     {"wall", BoundaryKind::slip_wall, {}, wall},
                                     {"top", BoundaryKind::far_field, inf},
                                     {"symmetry", BoundaryKind::symmetry}};
  fluid::FluidModel model(std::move(m), s.options, std::move(bcs));
  model.set_state([&](const Vec3&) { return inf; });
  const auto place = [&](double t, std::vector<Vec3>& x) {
    for (std::size_t a = 0; a < X.size(); ++a)
      x[a] = X[a] + Vec3(0, deflection(X[a].x(), t) * (1.0 - X[a].y() / g.height), 0);
  };
  std::vector<Vec3> x(X.size());
  // The start-up transient leaves the box at the slowest downstream signal speed U - c.
  const double t_end = g.length / (u - 1.0) + g.length / u;
  WavyWallResult r;
  while (model.time() < t_end * (1 - 1e-14)) {
    const double dt = std::min(model.stable_dt(s.cfl), t_end - model.time());
    if (s.moving_mesh) {
      place(model.time() + dt, x);
      model.step(dt, x);
    } else {
      model.step(dt);
    }
    ++r.steps;
  }
  // Fits at the wall and at heights along the Mach lines, phi = k (x - V t - beta_r y).
  const double t = model.time();
  const double p_exact = (u - v) * (u - v) * slope / g.beta_r;
  const auto fit_at = [&](double y) {
    std::vector<double> phi, p;
    const double x0 = 1.0 + g.beta_r * y, band = 0.51 * g.h;
    for (std::size_t a = 0; a < X.size(); ++a) {
      const Vec3& xa = X[a];
      if (std::abs(xa.y() - y) > band || xa.x() < x0 || xa.x() > x0 + 2.0) continue;
      phi.push_back(two_pi * (xa.x() - v * t - g.beta_r * xa.y()));
      p.push_back(model.pressure(Index(a)));
    }
    return fit_harmonic(phi, p);
  };
  const auto [wall_amplitude, wall_lag] = fit_at(0.0);
  for (std::size_t a = 0; a < X.size(); ++a)
    if (X[a].y() == 0.0 && X[a].z() == 0.0)
      r.wall.push_back(
          {X[a].x(), model.pressure(Index(a)) - 1.0 / gamma, p_exact * std::cos(two_pi * (X[a].x() - v * t))});
  r.amplitude_ratio = wall_amplitude / p_exact;
  r.phase_deg = wall_lag * 180.0 / std::numbers::pi;
  // Loss and drift per wavelength travelled: log amplitude and lag against the wavelengths
  // n = y M_r^2 / beta_r travelled, from 0.2 to 1 of y_top (straight-line fits).
  constexpr int levels = 5;
  Eigen::MatrixXd a(levels, 2);
  Eigen::VectorXd log_amp(levels), lag(levels);
  for (int j = 0; j < levels; ++j) {
    const double y = g.y_top * (0.2 + 0.8 * j / (levels - 1));
    const auto [amp, phase] = fit_at(y);
    a.row(j) << 1.0, y * g.mach_r * g.mach_r / g.beta_r;
    log_amp(j) = std::log(amp);
    lag(j) = phase;
  }
  const auto qr = a.colPivHouseholderQr();
  r.loss_per_wavelength = 1.0 - std::exp(qr.solve(log_amp)(1));
  r.drift_per_wavelength = qr.solve(lag)(1) * 180.0 / std::numbers::pi;
  r.cells = model.mesh().num_cells();
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace shellflow::support
