#include "verify/verification.hpp"

#include "verify/cases.hpp"

namespace tearflow::verify {

bool VerificationResult::passed() const {
  for (const Metric& m : metrics)
    if (!m.passed())
      return false;
  return !metrics.empty();
}

nlohmann::json VerificationResult::to_json() const {
  nlohmann::json j;
  j["case"] = name;
  j["passed"] = passed();
  for (const Metric& m : metrics)
    j["metrics"][m.name] = {{"value", m.value},
                            {"tolerance", m.tolerance},
                            {"passed", m.passed()},
                            {"meaning", m.meaning}};
  j["details"] = details;
  return j;
}

const std::map<std::string, VerificationCase>& verification_cases() {
  static const std::map<std::string, VerificationCase> cases = {
      {"poiseuille",
       {"steady flow in a rigid pipe against the parabolic profile and the "
        "Hagen-Poiseuille pressure drop; --convergence adds the L2 rate",
        verify_poiseuille}},
      {"womersley",
       {"pulsatile flow in a rigid pipe (Womersley number ~12) against the "
        "analytic Womersley profile over one cycle",
        verify_womersley}},
      {"rcr",
       {"rigid pipe closed by an RCR Windkessel: periodic outlet pressure against the RCR "
        "ODE's exact periodic solution",
        verify_rcr}},
      {"rc",
       {"rigid pipe closed by a two-element (RC) Windkessel: periodic outlet pressure against "
        "the RC ODE's exact periodic solution",
        verify_rc}},
      {"splits",
       {"three-outlet junction with RCR outlets: flow split of the 3D run against the 0D "
        "model of the outlets",
        verify_splits}},
      {"tuning",
       {"two-stage Windkessel tuning on a three-outlet junction: targets from a known "
        "parameter set are met by the tuned outlets",
        verify_tuning}},
      {"uniaxial",
       {"Neo-Hookean and St. Venant-Kirchhoff unit cube stretched to 1.5: Cauchy stress "
        "against the closed form",
        verify_uniaxial}},
      {"lame",
       {"thick cylinder under inner pressure, plane strain, nu = 0.3 and 0.49: radial "
        "displacement against Lame (no locking; St. Venant-Kirchhoff locks for contrast)",
        verify_lame}},
      {"robin",
       {"column on the spring-dashpot tissue support under a step load: settled "
        "displacement (also with the support's ambient pressure p_0), and faster settling "
        "with damping",
        verify_robin}},
      {"energy",
       {"free axial oscillation of a bar over 10 periods: energy conserved with rho_inf = 1, "
        "lost as the scheme predicts with rho_inf = 0.5",
        verify_energy}},
      {"inflation",
       {"compliant tube (FSI) under a slowly rising pressure: radius against thick-wall Lame",
        verify_inflation}},
      {"pulse",
       {"pressure pulse in a compliant tube (FSI): wave speed against the thick-wall estimate and "
        "the tube's linear continuum",
        verify_pulse}},
  };
  return cases;
}

} // namespace tearflow::verify
