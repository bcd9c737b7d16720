// Stage 1 of outlet tuning: the 0D fit of the Windkessel totals to the reference study's
// targets (../shared/reference/tbad-study.md, OR, EN, EX).
#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include "bc/aortic_inflow.hpp"
#include "core/error.hpp"
#include "core/units.hpp"
#include "tuning/targets.hpp"
#include "tuning/windkessel_fit.hpp"

using namespace tearflow;

namespace {

struct StudyTargets {
  const char* model;
  double sys, dias, map;        // mmHg
  double bct, lcc, lsa, outlet; // % of outflow
};
const StudyTargets kStudy[] = {{"OR", 126.4, 60.0, 86.1, 15.0, 3.1, 5.4, 76.5},
                               {"EN", 137.7, 69.9, 96.2, 11.4, 2.8, 5.7, 80.1},
                               {"EX", 142.1, 73.5, 98.9, 10.9, 3.1, 4.6, 81.4}};

bc::Waveform study_inflow() {
  return bc::typical_aortic_inflow(74.1e-6, 300e-6, 1.0);
}

std::vector<tuning::OutletFraction> fractions(const StudyTargets& s) {
  // The study's splits sum to 100 within rounding; normalise them.
  const double sum = s.bct + s.lcc + s.lsa + s.outlet;
  return {
      {"BCT", s.bct / sum}, {"LCC", s.lcc / sum}, {"LSA", s.lsa / sum}, {"outlet", s.outlet / sum}};
}

tuning::InletPressures pressures(const StudyTargets& s) {
  return {s.sys * units::mmHg, s.dias * units::mmHg, s.map * units::mmHg};
}

} // namespace

TEST(Tuning, TypicalAorticInflowHasTheStudysStrokeVolume) {
  const bc::Waveform q = study_inflow();
  EXPECT_NEAR(q.mean() * 1.0, 74.1e-6, 0.005 * 74.1e-6); // spline vs half sine: < 0.5 %
  EXPECT_NEAR(q(0.194), 300e-6, 0.01 * 300e-6);
}

TEST(Tuning, ZeroDStageMeetsTheStudysTargets) {
  for (const StudyTargets& s : kStudy) {
    const auto outlets = fractions(s);
    const tuning::FitResult fit =
        tuning::fit_windkessel_totals(pressures(s), study_inflow(), outlets);
    // Acceptance: the three pressures within 1 %.
    EXPECT_LT(fit.max_relative_error, 0.01) << s.model;
    // The splits of the fitted 0D model within 0.5 % points of the targets.
    const bc::PeriodicState st =
        bc::WindkesselNetwork(tuning::distribute(fit.totals, outlets)).periodic(study_inflow());
    double total = 0.0;
    for (size_t i = 0; i < outlets.size(); ++i)
      total += st.mean_branch_flow(i);
    const double sum = s.bct + s.lcc + s.lsa + s.outlet;
    const double target[] = {s.bct, s.lcc, s.lsa, s.outlet};
    for (size_t i = 0; i < outlets.size(); ++i)
      EXPECT_NEAR(100.0 * st.mean_branch_flow(i) / total, 100.0 * target[i] / sum, 0.5)
          << s.model << " " << outlets[i].face;
    std::printf("%s: R_T %.1f MPa s/m^3 (study %s), C_T %.3g m^3/Pa, k_d %.3f, %d evaluations\n",
                s.model, fit.totals.resistance / 1e6,
                s.model[1] == 'R'   ? "150"
                : s.model[1] == 'N' ? "161"
                                    : "170",
                fit.totals.capacitance, fit.totals.distal_share, fit.evaluations);
  }
}

TEST(Tuning, ResultDoesNotDependOnTheStartingGuess) {
  const StudyTargets& s = kStudy[0];
  const auto outlets = fractions(s);
  const tuning::FitResult a = tuning::fit_windkessel_totals(pressures(s), study_inflow(), outlets);
  const tuning::FitResult b =
      tuning::fit_windkessel_totals(pressures(s), study_inflow(), outlets, 0.0, {4e8, 1e-9, 0.5});
  // Three equations in three unknowns with one solution: both starts must find it. The
  // pressures match to the fit's tolerance, so the parameters agree to ~1e-4.
  EXPECT_LT(b.max_relative_error, 0.01);
  EXPECT_NEAR(b.totals.resistance, a.totals.resistance, 1e-3 * a.totals.resistance);
  EXPECT_NEAR(b.totals.capacitance, a.totals.capacitance, 1e-3 * a.totals.capacitance);
  EXPECT_NEAR(b.totals.distal_share, a.totals.distal_share, 1e-3);
}

TEST(Tuning, TargetsNoWindkesselCanMeetAreRejected) {
  const StudyTargets& s = kStudy[0];
  tuning::InletPressures bad = pressures(s);
  bad.diastolic = bad.mean + 1.0; // P_dias above MAP
  try {
    tuning::fit_windkessel_totals(bad, study_inflow(), fractions(s));
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("0 < P_dias < MAP < P_sys"), std::string::npos);
  }
}

TEST(Tuning, TargetsFile) {
  const std::filesystem::path dir =
      std::filesystem::path(TEARFLOW_SOURCE_DIR) / "tests/data/tuning";
  const tuning::TuningTargets t = tuning::load_targets(dir / "or.yaml");
  EXPECT_NEAR(t.pressure.systolic, 126.4 * units::mmHg, 1e-9);
  ASSERT_EQ(t.splits.size(), 4u);
  EXPECT_EQ(t.splits[3].face, "outlet");
  EXPECT_NEAR(t.splits[3].fraction, 76.5 / 100.0, 1e-12); // these sum to exactly 100
  EXPECT_NEAR(t.pressure_tolerance, 0.046, 1e-12);
  EXPECT_EQ(t.max_iterations, 2);

  auto message = [&](const char* file) {
    try {
      tuning::load_targets(dir / file);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("bad_splits.yaml").find("bad_splits.yaml:3: splits: the splits sum to 93.50 %"),
            std::string::npos)
      << message("bad_splits.yaml");
  EXPECT_NE(message("bad_pressures.yaml").find("expected diastolic < mean < systolic"),
            std::string::npos)
      << message("bad_pressures.yaml");
}
