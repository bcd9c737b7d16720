// Quasi-static solid cases with closed-form answers (../shared/reference/verification.md):
//
// uniaxial: unit cube, symmetry planes x = 0, y = 0, z = 0, face x = 1 pulled to stretch
//   lambda_1 = 1.5 in five load steps, lateral faces free. The deformation is homogeneous,
//   lambda_2 = lambda_3 from sigma_22 = 0, and
//     Neo-Hookean:  sigma_11 = mu J^{-5/3} (lambda_1^2 - lambda_2^2),  J = lambda_1 lambda_2^2,
//                   with mu J^{-5/3} (lambda_2^2 - I_1/3) + kappa (J - 1) = 0;
//     St. Venant-Kirchhoff: S_22 = 0, sigma_11 = lambda_1^2 S_11 / J.
//   A homogeneous field is exact in P1 (and the pressure constant, so the stabilization is
//   idle): the error is Newton's, far below the 1 % the issue asks.
//
// lame: a quarter of a thick cylinder (a = 1 cm, b = 2 cm) in plane strain (u_z = 0 on
//   both ends, symmetry on the cut planes) under inner pressure p = 1e-4 E, against
//     u(r) = p a^2 / (E (b^2 - a^2)) [(1 + nu)(1 - 2 nu) r + (1 + nu) b^2 / r],
//   for nu = 0.3 and nu = 0.49. At p = 1e-4 E the geometric nonlinearity is ~1e-4. The P1
//   error is O(h^2); at nu = 0.49 a locking element would be far off: the displacement-only
//   St. Venant-Kirchhoff element runs beside it and must be clearly worse.
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "mesh/structured_generator.hpp"
#include "physics/solid_kernel.hpp"
#include "run/solid_simulation.hpp"
#include "verify/cases.hpp"
#include "verify/solid_setup.hpp"

namespace tearflow::verify {

namespace {

using physics::SolidMaterial;
using physics::SolidModel;

constexpr double E = 1.2e6, rho = 1450.0; // the study's wall: 1.2 MPa, 1450 kg/m^3

/// lambda_2 of the Neo-Hookean bar from sigma_22 = 0, by bisection (sigma_22 increases
/// with lambda_2).
double neo_hookean_lateral_stretch(const SolidMaterial& m, double l1) {
  auto s22 = [&](double l2) {
    const double J = l1 * l2 * l2, I1 = l1 * l1 + 2.0 * l2 * l2;
    return m.mu * std::pow(J, -5.0 / 3.0) * (l2 * l2 - I1 / 3.0) + m.kappa * (J - 1.0);
  };
  double lo = 0.1, hi = 1.5;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (s22(mid) > 0.0 ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

struct UniaxialResult {
  double sigma_fe = 0.0, sigma_exact = 0.0, lateral_fe = 0.0, lateral_exact = 0.0;
  double worst_relative = 0.0; ///< max over elements of |sigma_11 - exact| / exact
};

UniaxialResult run_uniaxial(SolidModel model, int cells, bool progress) {
  constexpr double stretch = 1.5;
  io::SolidSpec spec;
  spec.material = SolidMaterial::from_young_poisson(model, E, 0.3, rho);
  spec.quasi_static = true;
  spec.conditions.fixed = {{"x0", 0b001, {}, 0.0},
                           {"y0", 0b010, {}, 0.0},
                           {"z0", 0b100, {}, 0.0},
                           {"x1", 0b001, {stretch - 1.0, 0.0, 0.0}, 1.0}};
  run::SolidSimulation sim(solid_case("verify-uniaxial", spec, 0.2, 5, 1.0, 5e5),
                           mesh::make_box({1.0, 1.0, 1.0}, {cells, cells, cells}));
  for (int s = 0; s < 5; ++s) {
    const auto r = sim.advance();
    if (progress)
      fmt::print(stderr, "uniaxial: step {} Newton {} KSP {}\n", s + 1, r.newton_iterations,
                 r.linear_iterations);
  }
  const std::vector<double> U = sim.gather(sim.solver().solution());
  const std::vector<double> D = sim.gather(sim.solver().displacement());
  const SolidMaterial& m = spec.material;
  UniaxialResult out;
  if (model == SolidModel::NeoHookean) {
    const double l2 = neo_hookean_lateral_stretch(m, stretch), J = stretch * l2 * l2;
    out.lateral_exact = l2;
    out.sigma_exact = m.mu * std::pow(J, -5.0 / 3.0) * (stretch * stretch - l2 * l2);
  } else { // S_22 = lambda (E11 + 2 E22) + 2 mu E22 = 0
    const double E11 = 0.5 * (stretch * stretch - 1.0);
    const double E22 = -m.lambda() * E11 / (2.0 * m.lambda() + 2.0 * m.mu);
    const double l2 = std::sqrt(1.0 + 2.0 * E22), J = stretch * l2 * l2;
    const double S11 = m.lambda() * (E11 + 2.0 * E22) + 2.0 * m.mu * E11;
    out.lateral_exact = l2;
    out.sigma_exact = stretch * stretch * S11 / J;
  }
  const mesh::Mesh& mesh = sim.mesh();
  double sigma_sum = 0.0;
  for (const Tet& t : mesh.tets) {
    std::array<Vec3, 4> X, u;
    double p = 0.0;
    for (int a = 0; a < 4; ++a) {
      X[a] = mesh.points[t[a]];
      u[a] = {D[4 * t[a]], D[4 * t[a] + 1], D[4 * t[a] + 2]};
      p += 0.25 * U[4 * t[a] + 3];
    }
    const Mat3 F = physics::deformation_gradient(fem::tet_geometry(X), u);
    const double s11 = physics::cauchy_stress(m, F, p)[0][0];
    sigma_sum += s11;
    out.worst_relative =
        std::max(out.worst_relative, std::abs(s11 - out.sigma_exact) / out.sigma_exact);
  }
  out.sigma_fe = sigma_sum / static_cast<double>(mesh.tets.size());
  // Lateral stretch from the mean displacement of face y1 (at y = 1 in the reference).
  for (const auto& f : sim.problem().measure_faces(sim.solver().displacement()))
    if (f.face == "y1")
      out.lateral_fe = 1.0 + f.displacement[1];
  return out;
}

struct LameResult {
  double inner = 0.0, outer = 0.0; ///< mean radial displacement on the faces [m]
  double inner_exact = 0.0, outer_exact = 0.0;
  double error = 0.0; ///< max relative error of the two
  int tets = 0, newton = 0;
};

LameResult run_lame(SolidModel model, double nu, int nr, bool progress) {
  constexpr double a = 0.01, b = 0.02, p = 1e-4 * E;
  io::SolidSpec spec;
  spec.material = SolidMaterial::from_young_poisson(model, E, nu, rho);
  spec.quasi_static = true;
  spec.conditions.fixed = {{"z0", 0b100, {}, 0.0},
                           {"z1", 0b100, {}, 0.0},
                           {"theta0", 0b010, {}, 0.0},  // plane y = 0
                           {"theta1", 0b001, {}, 0.0}}; // plane x = 0
  spec.conditions.loads = {{"inner", bc::Waveform::constant(p)}};
  mesh::AnnulusSpec geo;
  geo.inner_radius = a;
  geo.outer_radius = b;
  geo.angle = 0.5 * std::numbers::pi;
  // Cells about square in the r-theta plane at mid-radius; one layer through the slice.
  const int ntheta = static_cast<int>(std::ceil(nr * geo.angle * 0.5 * (a + b) / (b - a)));
  geo.length = (b - a) / nr;
  geo.cells = {nr, ntheta, 1};
  run::SolidSimulation sim(solid_case("verify-lame", spec, 1.0, 1, 1.0, p * a * (b - a) / nr),
                           mesh::make_annulus(geo));
  const auto r = sim.advance();
  if (progress)
    fmt::print(stderr, "lame nu = {}: Newton {} KSP {}\n", nu, r.newton_iterations,
               r.linear_iterations);
  auto exact = [&](double radius) {
    return p * a * a / (E * (b * b - a * a)) *
           ((1.0 + nu) * (1.0 - 2.0 * nu) * radius + (1.0 + nu) * b * b / radius);
  };
  // Area-weighted mean of u . e_r over the face, from the face's triangles.
  const std::vector<double> D = sim.gather(sim.solver().displacement());
  const mesh::Mesh& m = sim.mesh();
  auto mean_radial = [&](const std::string& name) {
    double sum = 0.0, area = 0.0;
    for (const Tri& t : m.face(name).triangles) {
      const Vec3 c = cross(m.points[t[1]] - m.points[t[0]], m.points[t[2]] - m.points[t[0]]);
      const double A = 0.5 * std::sqrt(dot(c, c));
      for (Index v : t) {
        const Vec3& x = m.points[v];
        const double rr = std::hypot(x[0], x[1]);
        sum += A / 3.0 * (D[4 * v] * x[0] + D[4 * v + 1] * x[1]) / rr;
      }
      area += A;
    }
    return sum / area;
  };
  LameResult out;
  out.inner = mean_radial("inner");
  out.outer = mean_radial("outer");
  out.inner_exact = exact(a);
  out.outer_exact = exact(b);
  out.error = std::max(std::abs(out.inner - out.inner_exact) / out.inner_exact,
                       std::abs(out.outer - out.outer_exact) / out.outer_exact);
  out.tets = m.num_tets();
  out.newton = r.newton_iterations;
  return out;
}

} // namespace

VerificationResult verify_uniaxial(const VerifyOptions& options) {
  const int cells = std::max(1, static_cast<int>(std::lround(3.0 / options.coarsening)));
  const UniaxialResult nh = run_uniaxial(SolidModel::NeoHookean, cells, options.progress);
  const UniaxialResult svk = run_uniaxial(SolidModel::StVenantKirchhoff, cells, options.progress);
  VerificationResult res;
  res.name = "uniaxial";
  // 1 % as the issue asks; the homogeneous state is exact in P1, so the expected error is
  // Newton's (relative residual 1e-10), and the elementwise worst case equals the mean.
  res.metrics.push_back({"neo_hookean_sigma11_relative_error", nh.worst_relative, 0.01,
                         "max over tets of |sigma_11 - closed form| / closed form at stretch "
                         "1.5 (Neo-Hookean, nu = 0.3); 1 %"});
  res.metrics.push_back({"neo_hookean_lateral_stretch_relative_error",
                         std::abs(nh.lateral_fe - nh.lateral_exact) / nh.lateral_exact, 0.01,
                         "|lambda_2 - closed form| / closed form; 1 %"});
  res.metrics.push_back({"svk_sigma11_relative_error", svk.worst_relative, 0.01,
                         "the same for St. Venant-Kirchhoff; 1 %"});
  res.details = {{"stretch", 1.5},
                 {"cells_per_edge", cells},
                 {"youngs_modulus_Pa", E},
                 {"poisson_ratio", 0.3},
                 {"neo_hookean",
                  {{"sigma11_Pa", nh.sigma_fe},
                   {"sigma11_exact_Pa", nh.sigma_exact},
                   {"lateral_stretch", nh.lateral_fe},
                   {"lateral_stretch_exact", nh.lateral_exact}}},
                 {"st_venant_kirchhoff",
                  {{"sigma11_Pa", svk.sigma_fe},
                   {"sigma11_exact_Pa", svk.sigma_exact},
                   {"lateral_stretch", svk.lateral_fe},
                   {"lateral_stretch_exact", svk.lateral_exact}}}};
  return res;
}

VerificationResult verify_lame(const VerifyOptions& options) {
  // Default: 8 cells through the wall (h = 1.25 mm, 13 around the quarter). The O(h^2)
  // error of P1 there is ~0.3 %: 2 % (the issue's) leaves room for the pressure
  // stabilization's O(h^2) consistency error at nu = 0.49. A coarsened mesh (CI's reduced
  // form) gets the tolerance scaled by the square of the coarsening.
  const int nr = std::max(2, static_cast<int>(std::lround(8.0 / options.coarsening)));
  const double scale = std::pow(8.0 / nr, 2);
  const double tolerance = 0.02 * scale;
  VerificationResult res;
  res.name = "lame";
  nlohmann::json details = {{"inner_radius_m", 0.01},
                            {"outer_radius_m", 0.02},
                            {"pressure_Pa", 1e-4 * E},
                            {"cells_through_wall", nr}};
  double stabilized_error = 0.0; // at nu = 0.49
  for (double nu : {0.3, 0.49}) {
    const LameResult r = run_lame(SolidModel::NeoHookean, nu, nr, options.progress);
    stabilized_error = r.error;
    const std::string tag = nu < 0.4 ? "nu_0.3" : "nu_0.49";
    res.metrics.push_back({"radial_displacement_relative_error_" + tag, r.error, tolerance,
                           fmt::format("max over inner and outer face of |mean u_r - Lame| / "
                                       "Lame, Neo-Hookean, nu = {}; 2 % x coarsening^2",
                                       nu)});
    details[tag] = {{"u_inner_m", r.inner}, {"u_inner_exact_m", r.inner_exact},
                    {"u_outer_m", r.outer}, {"u_outer_exact_m", r.outer_exact},
                    {"tets", r.tets},       {"newton_iterations", r.newton}};
  }
  // The contrast: the displacement-only St. Venant-Kirchhoff element at nu = 0.49 locks.
  // Its P1 error constant grows with lambda / mu (49 at nu = 0.49) until the displacement
  // saturates at the locked answer; the mixed form's does not depend on nu (its errors at
  // 0.3 and 0.49 agree). 0.25 asks the stabilized form to be at least 4 times closer: an
  // element that locked even partly would bring the ratio toward 1.
  const LameResult locked = run_lame(SolidModel::StVenantKirchhoff, 0.49, nr, options.progress);
  res.metrics.push_back({"locking_contrast_nu_0.49", stabilized_error / locked.error, 0.25,
                         "radial displacement error of the stabilized Neo-Hookean over that of "
                         "displacement-only St. Venant-Kirchhoff, nu = 0.49; < 0.25"});
  details["svk_displacement_only_nu_0.49_relative_error"] = locked.error;
  if (options.convergence) {
    // nu = 0.49 on three nested meshes (h halved): O(h^2) if nothing locks.
    nlohmann::json study = nlohmann::json::array();
    double worst_rate = 1e9, previous = 0.0;
    for (int n : {nr / 2, nr, 2 * nr}) {
      const LameResult r = run_lame(SolidModel::NeoHookean, 0.49, n, options.progress);
      nlohmann::json row = {{"cells_through_wall", n}, {"tets", r.tets}, {"error", r.error}};
      if (previous > 0.0) {
        const double rate = std::log2(previous / r.error);
        row["rate"] = rate;
        worst_rate = std::min(worst_rate, rate);
      }
      previous = r.error;
      study.push_back(row);
    }
    details["convergence_nu_0.49"] = study;
    res.metrics.push_back({"rate_shortfall_nu_0.49", 2.0 - worst_rate, 0.3,
                           "2 - (lowest observed rate of the radial displacement error, h "
                           "halved twice, nu = 0.49); P1 is second order in displacement"});
  }
  res.details = details;
  return res;
}

} // namespace tearflow::verify
