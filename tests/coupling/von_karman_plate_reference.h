#pragma once
// Independent reference model: nonlinear flutter of a clamped, in-plane immovable rectangular plate in supersonic
// flow (von Kármán plate + first-order piston theory), Ritz/Galerkin in space, explicit RK4 in time. SI units.
//
// Plate x in [0,a] (flow along +x), y in [0,b]; w > 0 towards the air (upper side), cavity below;
// D = E h^3/(12(1-nu^2)) [N m], A_m = E h/(1-nu^2) [N/m]. Edges: w = w_n = 0 and u = v = 0. Per unit area:
//   rho_s h w_tt + D lap^2 w - (N_x w_xx + 2 N_xy w_xy + N_y w_yy) = f,
//   f = p_c - p = -dip p_inf [t < dip_end] - (rho U^2/beta)(w_x + g_D w_t/U)  [Pa],
//   beta = sqrt(M^2-1), g_D = (M^2-2)/(M^2-1), U = M sqrt(gamma p_inf/rho).
// Membrane (quasi-static: no in-plane inertia): eps_x = u_x + w_x^2/2, eps_y = v_y + w_y^2/2,
// gamma = u_y + v_x + w_x w_y, (N_x, N_y, N_xy) = A_m (eps_x + nu eps_y, eps_y + nu eps_x, (1-nu)/2 gamma).
//
// w = sum q_mn phi_m(x/a) phi_n(y/b) with clamped-clamped beam modes; u, v = sum c_ij sin(i pi x/a) sin(j pi y/b),
// i, j <= inplane; tensor Gauss-Legendre quadrature. The in-plane problem is condensed once: with s_p = q_j q_k
// (j <= k) the membrane energy minimised over (u, v) is exactly U_m = 1/2 s^T G s, G = F - H^T K_uv^-1 H, and the
// membrane force N(q) = dU_m/dq is cubic in q. Model::membrane_force_direct computes the same force point by
// point (w_x, w_y -> in-plane solve -> N_x, N_y, N_xy -> integrals); the two agree to round-off (tested).
// Modal equations: M q'' + C q' + (K + A) q + N(q) = f_dip [t < dip_end], with M = rho_s h int Phi Phi,
// C = (rho U^2/beta)(g_D/U) int Phi Phi, A = (rho U^2/beta) int Phi_i dPhi_j/dx, f_dip = -dip p_inf int Phi.
// Eigen is a system header in the project build; standalone (-I, -Werror) GCC 12 reports false
// -Wmaybe-uninitialized positives inside Eigen.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <Eigen/Dense>
#pragma GCC diagnostic pop

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>
#include <vector>

namespace shellflow::testing::von_karman {

/// Physical and numerical parameters (SI units).
struct Params {
  double a = 0.5, b = 0.5, h = 1.35e-3;                              ///< plate size and thickness [m]
  double E = 77.28e9, nu = 0.33, rho_s = 2710.0;                     ///< [Pa], [-], [kg/m^3]
  double rho_air = 0.339, p_inf = 28000.0, gamma = 1.4, mach = 4.0;  ///< air on the +w side
  double dip = 1e-3, dip_end = 4e-3;  ///< cavity pressure p_inf (1 - dip) for t < dip_end [-], [s]
  double init_w = 0.0;                ///< initial shape: mode (1,1) scaled to this centre deflection [m]
  int modes_x = 8;                    ///< streamwise modes m = 1..modes_x
  int modes_y = 3;                    ///< spanwise modes: n = 1,3,5,.. (span_symmetric) or n = 1..modes_y
  bool span_symmetric = true;         ///< keep only modes symmetric about y = b/2 (odd n)
  bool x_symmetric = false;           ///< keep only modes symmetric about x = a/2 (odd m; static runs without flow)
  int inplane = 16;                   ///< sine modes per direction for u and v
  int quad = 0;                       ///< Gauss points per direction (0: automatic)
  bool nonlinear = true;              ///< include the von Kármán membrane force
  bool aero_damping = true;           ///< include the piston-theory term g_D w_t / U
  double dt = 1e-4;                   ///< RK4 time step [s]
};

inline constexpr double pi = std::numbers::pi;
inline double bending_stiffness(const Params& s) { return s.E * s.h * s.h * s.h / (12.0 * (1.0 - s.nu * s.nu)); }
inline double speed(const Params& s) { return s.mach * std::sqrt(s.gamma * s.p_inf / s.rho_air); }  ///< U [m/s]
/// Piston-theory stiffness coefficient rho U^2/beta [Pa].
inline double dynamic_pressure(const Params& s) {
  const double u = speed(s);
  return s.rho_air * u * u / std::sqrt(s.mach * s.mach - 1.0);
}
/// Non-dimensional dynamic pressure lambda = (rho U^2/beta) a^3/D.
inline double lambda(const Params& s) { return dynamic_pressure(s) * s.a * s.a * s.a / bending_stiffness(s); }
/// Viscous coefficient of piston theory (rho U^2/beta) g_D/U [Pa s/m] (0 if aero_damping is off).
inline double damping_coefficient(const Params& s) {
  const double m2 = s.mach * s.mach;
  return s.aero_damping ? dynamic_pressure(s) * (m2 - 2.0) / (m2 - 1.0) / speed(s) : 0.0;
}

/// Gauss-Legendre nodes and weights on [0,1].
std::pair<std::vector<double>, std::vector<double>> gauss_legendre(int n);

/// Clamped-clamped Euler-Bernoulli beam mode on [0,1]: cos(beta) cosh(beta) = 1,
/// phi = cosh(bx) - cos(bx) - sigma (sinh(bx) - sin(bx)), written without large exponentials:
/// phi = e^{-bx} + r (e^{b(x-1)} - e^{-b(x+1)}) - cos(bx) + sigma sin(bx). Normalised: int_0^1 phi^2 = 1.
struct BeamMode {
  double beta = 0.0, sigma = 0.0, r = 0.0;
  explicit BeamMode(int m);
  /// {phi, phi', phi''} at xi in [0,1] (derivatives with respect to xi).
  std::array<double, 3> operator()(double xi) const;
};

/// The Galerkin model: constant matrices, the condensed membrane form G and the mode shapes.
class Model {
 public:
  using Mat = Eigen::MatrixXd;
  using Vec = Eigen::VectorXd;

  explicit Model(const Params& s);

  const Params& params() const { return s_; }
  int size() const { return static_cast<int>(index_.size()); }
  const std::vector<std::pair<int, int>>& modes() const { return index_; }  ///< (m, n) of each q
  Mat mass() const { return s_.rho_s * s_.h * shape_m_; }                   ///< M [kg]
  const Mat& stiffness() const { return K_; }                               ///< K [N/m]
  const Mat& shape_x() const { return shape_x_; }  ///< int Phi_i dPhi_j/dx [m]; A = (rho U^2/beta) shape_x
  const Mat& shape_m() const { return shape_m_; }  ///< int Phi_i Phi_j [m^2]; C = damping_coefficient * shape_m
  const Vec& load() const { return load_; }        ///< int Phi_i [m^2]: generalized force per unit pressure (+w)

  /// Phi_i(xi a, eta b), so that w(xi a, eta b) = shape_at(xi, eta) . q.
  Vec shape_at(double xi, double eta) const;
  /// Initial modal state of Params::init_w: mode (1,1) with centre deflection init_w.
  Vec initial_q() const;

  /// Membrane energy U_m = 1/2 s^T G s [J].
  double membrane_energy(const Vec& q) const;
  /// Membrane generalized force N(q) = dU_m/dq = sum_p (G s)_p ds_p/dq [N] (zero if !nonlinear).
  Vec membrane_force(const Vec& q) const;
  /// dN/dq = J^T G J + sum_p (G s)_p d^2 s_p/dq^2 with J = ds/dq [N/m].
  Mat membrane_jacobian(const Vec& q) const;
  /// The same force by the point-wise pipeline: w_x, w_y at the points -> K_uv c = -B(L, e0) -> N_x, N_y, N_xy
  /// [N/m] at the points -> F_i = int (N_x w_x Phi_i,x + N_y w_y Phi_i,y + N_xy (w_x Phi_i,y + w_y Phi_i,x)).
  Vec membrane_force_direct(const Vec& q) const;

 private:
  Vec products(const Vec& q) const;

  Params s_;
  std::vector<std::pair<int, int>> index_, pairs_;
  std::vector<BeamMode> beams_;
  Vec wts_, load_;
  Mat phi_, phix_, phiy_, K_, shape_x_, shape_m_, lx_, ly_, lg_, G_;
  Eigen::LLT<Mat> kuv_;
  double am_ = 0.0;  ///< membrane stiffness E h/(1-nu^2) [N/m]
};

/// Leading eigenvalue of M q'' + C q' + (K + A) q = 0.
struct Eigenvalue {
  double growth_rate = 0.0;   ///< max Re(s) [1/s]
  double frequency_hz = 0.0;  ///< |Im(s)|/(2 pi) of that eigenvalue [Hz]
};
/// For `model` (any Mach) at the Mach, damping flag of `s`.
Eigenvalue linear_eigenvalue(const Model& model, const Params& s);
Eigenvalue linear_eigenvalue(Params s);

/// Flutter Mach number of the linear system (scan upward from M = 1.5 in steps of 0.25, then bisection).
/// Undamped (aero_damping = false): the first coalescence, i.e. complex eigenvalues of M^-1 (K + A).
/// Damped: the first Mach with a growing eigenvalue, Re(s) > 0.
double flutter_mach(Params s, bool aero_damping);

/// Explicit RK4 for M q'' = f_dip(t) - C q' - (K + A) q - N(q) from q = q0 (default: Model::initial_q()),
/// q' = 0. `observe(t, q)` is called after every step and returns false to stop.
template <class Observer>
void integrate(const Model& model, double t_end, Observer&& observe, Eigen::VectorXd q0 = {}) {
  const Params& s = model.params();
  const int n = model.size();
  const Eigen::MatrixXd minv = model.mass().inverse();
  const Eigen::MatrixXd kt = minv * (model.stiffness() + dynamic_pressure(s) * model.shape_x());
  const Eigen::MatrixXd ct = minv * (damping_coefficient(s) * model.shape_m());
  const Eigen::VectorXd fdip = minv * (-s.dip * s.p_inf * model.load());
  // RK4 is stable for |s dt| < 2.8 on the imaginary axis; keep the highest in-vacuo mode well inside.
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> modes(model.stiffness(), model.mass(),
                                                                        Eigen::EigenvaluesOnly);
  if (std::sqrt(modes.eigenvalues().maxCoeff()) * s.dt > 2.0)
    throw std::invalid_argument("von_karman::integrate: dt too large for RK4");
  bool dip_on = true;
  auto accel = [&](const Eigen::VectorXd& q, const Eigen::VectorXd& v) -> Eigen::VectorXd {
    Eigen::VectorXd acc = -kt * q - ct * v;
    if (s.nonlinear) acc -= minv * model.membrane_force(q);
    if (dip_on) acc += fdip;
    return acc;
  };
  Eigen::VectorXd q = q0.size() == n ? q0 : model.initial_q(), v = Eigen::VectorXd::Zero(n);
  double t = 0.0;
  while (t < t_end - 1e-12 * s.dt) {
    // The forcing is piecewise constant: a step never straddles the end of the dip (it is cut there).
    dip_on = s.dip_end - t > 1e-9 * s.dt;
    const double dt = (dip_on && t + s.dt > s.dip_end) ? s.dip_end - t : s.dt;
    const Eigen::VectorXd k1 = accel(q, v), l1 = v;
    const Eigen::VectorXd k2 = accel(q + 0.5 * dt * l1, v + 0.5 * dt * k1), l2 = v + 0.5 * dt * k1;
    const Eigen::VectorXd k3 = accel(q + 0.5 * dt * l2, v + 0.5 * dt * k2), l3 = v + 0.5 * dt * k2;
    const Eigen::VectorXd k4 = accel(q + dt * l3, v + dt * k3), l4 = v + dt * k3;
    q += dt / 6.0 * (l1 + 2.0 * l2 + 2.0 * l3 + l4);
    v += dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    t += dt;
    if (!observe(t, q)) return;
  }
}

/// Time history of w at the probe (xi a, eta b), every `record_every` steps.
struct History {
  std::vector<double> t, w;  ///< [s], [m]
};
History simulate(const Params& s, double t_end, double xi, double eta, int record_every = 1);

/// Response quantities of a probe signal.
struct Response {
  double growth_rate = 0.0;          ///< fitted d ln(amplitude)/dt [1/s]
  double frequency_hz = 0.0;         ///< 1/(mean cycle length) [Hz]
  double lco_amplitude = 0.0;        ///< half peak-to-peak at the probe, mean of the last 3 cycles [m]
  double plate_max_amplitude = 0.0;  ///< max over the plate of half peak-to-peak over two further cycles [m]
  double time = 0.0;                 ///< time at which the limit cycle was declared converged [s]
  int cycles = 0;                    ///< complete cycles seen
  bool converged = false;            ///< 3 successive cycle amplitudes each changed by < rel_change
};

/// Splits a signal into cycles between upward zero crossings (crossing times linearly interpolated); a cycle's
/// amplitude is (max - min)/2, the extrema refined by a parabola through the three samples around them.
class CycleTracker {
 public:
  /// Feeds one sample; true when a cycle has just been completed.
  bool add(double t, double w);
  std::vector<double> starts, ends, amplitudes;  ///< per completed cycle [s], [s], [m]

 private:
  double w0_ = 0.0, w1_ = 0.0, t1_ = 0.0, t0_ = 0.0, hi_ = -1e300, lo_ = 1e300;
  long n_ = 0;
  bool started_ = false;
};

/// Growth rate (least-squares slope of ln(cycle amplitude) against cycle mid-time) and frequency of the cycles
/// starting at or after t_from.
Response fit_growth(const History& h, double t_from);

/// Integrates until the limit cycle at the probe has converged (3 successive cycle amplitudes each within
/// `rel_change` of the previous one) or t_max, then two more cycles for the maximum over the plate (41 x 41 grid; 41 x
/// 21 on y <= b/2 with span symmetry). Not converged: amplitude and frequency of the last cycle.
Response lco_response(const Params& s, double t_max, double xi = 0.7, double eta = 0.5, double rel_change = 1e-3);

/// The limit cycle at the probe (xi, eta) = (0.7, 0.5) for a given Mach number, other parameters from `s`.
Response lco_at_mach(double mach, Params s = {}, double t_max = 3.0);

/// Static large deflection under a uniform pressure p (+w, no flow): solves K q + N(q) = p int Phi by Newton
/// with `steps` load increments. Returns the centre deflection w(a/2, b/2) [m].
double static_center_deflection(const Params& s, double pressure, int steps = 10);

}  // namespace shellflow::testing::von_karman
