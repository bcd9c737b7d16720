// Parametric TBAD without meshing: the layout against its own definition, the checks on bad
// parameters, and the landmarks file.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "geometry/landmarks.hpp"
#include "geometry/tbad_model.hpp"
#include "geometry/tbad_spec.hpp"

namespace tearflow::geometry {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
constexpr double pi = std::numbers::pi;

std::string error_of(const TbadSpec& s) {
  try {
    TbadModel m(s);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(GeometryModel, CircularSegmentAreaLimits) {
  const double r = 0.01;
  EXPECT_NEAR(circular_segment_area(r, 0), 0.5 * pi * r * r, 1e-15);
  EXPECT_NEAR(circular_segment_area(r, -r), pi * r * r, 1e-15);
  EXPECT_NEAR(circular_segment_area(r, r), 0, 1e-15);
  // A thin segment: area ~ (4/3) sqrt(2 r) t^(3/2) for height t.
  const double t = 1e-5;
  EXPECT_NEAR(circular_segment_area(r, r - t), 4.0 / 3.0 * std::sqrt(2 * r) * std::pow(t, 1.5),
              1e-3 * std::pow(t, 1.5));
}

// The profile solved at the stations must give back the requested lumen areas when the
// flap (a chord band of thickness h) is laid across a circle of the solved radius.
TEST(GeometryModel, StationProfileReproducesLumenAreas) {
  const TbadSpec spec;
  const TbadModel m(spec);
  const double h = spec.wall_thickness;
  for (int k = 1; k <= 5; ++k) {
    const double s = m.paired_station(k), r = m.radius(s), e = m.flap_offset(s);
    EXPECT_NEAR(circular_segment_area(r, e + h / 2), spec.tl_areas[k - 1], 1e-9) << "TL" << k;
    EXPECT_NEAR(circular_segment_area(r, h / 2 - e), spec.fl_areas[k - 1], 1e-9) << "FL" << k;
  }
  // The true lumen narrows distally, so the flap moves towards it.
  EXPECT_GT(m.flap_offset(m.paired_station(5)), m.flap_offset(m.paired_station(1)));
}

TEST(GeometryModel, LayoutFollowsTheStudy) {
  const TbadSpec spec;
  const TbadModel m(spec);
  const auto& tears = m.tears();
  // The domain ends outlet_distance (21.6 mm) distal to the false lumen's end, which is
  // taper_length (25 mm) distal to the taper's start, 13.4 mm from the default exit tear's
  // centre: 60 mm from the tear's centre along the centreline (the study's domain ends 35 mm
  // distal to it; DAo_dist, one lumen, must lie past the FL's end). The last 30 mm above
  // the tear and all beyond it are straight, so the chord equals the arclength there.
  EXPECT_NEAR(m.length() - m.flap_end(), 21.6e-3, 1e-12);
  EXPECT_NEAR(m.flap_end() - m.taper_start(), 25e-3, 1e-12);
  const Vec3 d = m.frame(m.length()).origin - tears[1].centre;
  const Vec3 t = m.frame(m.length()).tangent;
  EXPECT_NEAR(dot(d, t), 60e-3, 0.05e-3); // 13.40 + 25 + 21.6 mm, rounded to 0.1 mm
  // Entry tear just distal to the LSA, exit tear near the flap's distal end.
  EXPECT_GT(m.flap_start(), m.arch_start());
  EXPECT_LT(m.flap_start(), m.arch_start() + m.arch_length());
  EXPECT_NEAR(tears[0].area(), 228e-6, 1e-12);
  EXPECT_NEAR(tears[1].area(), 227e-6, 1e-12);
  // The centreline is 3D: the ascending aorta leaves the arch plane x = 0 by ascending_bow.
  EXPECT_NEAR(m.frame(0).origin[0], -spec.ascending_bow, 1e-9);
  EXPECT_NEAR(m.frame(m.arch_start() + 0.5 * m.arch_length()).origin[0], 0, 1e-5);
  // Frames are orthonormal and right-handed everywhere.
  for (double s = 0; s < m.length(); s += 5e-3) {
    const Frame f = m.frame(s);
    EXPECT_NEAR(dot(f.tangent, f.tangent), 1, 1e-12);
    EXPECT_NEAR(dot(f.normal, f.tangent), 0, 1e-12);
    EXPECT_NEAR(dot(cross(f.across, f.normal), f.tangent), 1, 1e-12);
  }
  // Arch radius: the tightest bend is the requested one (sampled at 0.1 mm: 1 % is the
  // finite-difference error of the sampled tangent at that step, with margin).
  EXPECT_NEAR(m.min_curvature_radius(0, m.length()), spec.arch_radius, 0.01 * spec.arch_radius);
}

// The distal re-attachment (docs/geometry.md, "The flap's distal taper"). The default exit
// tear sits just proximal to the taper, one ligament of max(2 mm, h) of flat flap from it;
// the flap is flat across the tear and over the taper moves to the false lumen's side until
// the FL is fl_end_depth deep at its end cap, where the TL has DAo_dist's area. All the
// descending flow leaves the FL through the tear and passes the TL distal to it, so the TL
// must never be narrower there than beside the tear, and there no narrower than the tear
// (the tear, not the model, is the constriction). Exact relations of the layout: tolerances
// are rounding (1e-9 m), the bisections (1e-9 m, 1e-12 m^2) and the centreline's
// Simpson-integrated sampling (1e-6 m).
TEST(GeometryModel, FlapTapersToTheWallDistalToTheExitTear) {
  for (const char* variant : {"OR", "EN", "EX"}) {
    TbadSpec spec;
    apply_variant(spec, variant);
    const TbadModel m(spec);
    const double h = spec.wall_thickness;
    const TearGeometry& exit = m.tears()[1];
    const double margin = std::max(2e-3, h);
    EXPECT_NEAR(m.spec().exit_tear.position, exit.axial + margin, 1e-9) << variant;
    EXPECT_NEAR(m.flap_end() - m.taper_start(), spec.taper_length, 1e-12) << variant;
    // Distal edge of the tear to the taper's start, along the (straight) centreline there.
    const Frame ft = m.frame(m.taper_start());
    EXPECT_NEAR(dot(ft.origin - (exit.centre + exit.axial * exit.axis), ft.tangent), margin, 1e-6)
        << variant;
    // Flat across the tear (the hole is cut and measured in a flat flap), at the centre.
    const double s_exit = m.taper_start() - m.spec().exit_tear.position;
    for (double s = s_exit - exit.axial; s <= m.taper_start(); s += 0.5e-3)
      EXPECT_NEAR(m.flap_offset(s), 0, 1e-9) << variant << " at " << s;
    // The FL closes to fl_end_depth at its end cap; the TL there has DAo_dist's area.
    const double r_end = m.radius(m.flap_end()), e_end = m.flap_offset(m.flap_end());
    EXPECT_NEAR(r_end + e_end - 0.5 * h, spec.fl_end_depth, 1e-9) << variant;
    EXPECT_NEAR(circular_segment_area(r_end, e_end + 0.5 * h), spec.dao_dist_area, 1e-12)
        << variant;
    // The TL from the tear to the FL's end: never narrower than beside the tear's distal rim,
    // which is wider than the tear; the flap moves monotonically to the FL's side.
    const double s_rim = s_exit + exit.axial;
    auto tl_area = [&](double s) {
      return circular_segment_area(m.radius(s), m.flap_offset(s) + 0.5 * h);
    };
    EXPECT_GT(tl_area(s_rim), spec.exit_tear.area) << variant;
    double previous = tl_area(s_rim), e_prev = m.flap_offset(s_rim);
    for (double s = s_rim; s <= m.flap_end(); s += 0.5e-3) {
      EXPECT_GE(tl_area(s), previous - 1e-12) << variant << " at " << s;
      EXPECT_LE(m.flap_offset(s), e_prev + 1e-12) << variant << " at " << s;
      previous = tl_area(s);
      e_prev = m.flap_offset(s);
    }
    // Past the end cap the undivided lumen narrows to DAo_dist's radius, no further.
    const double r_dist = std::sqrt(spec.dao_dist_area / pi);
    for (double s = m.flap_end(); s <= m.length(); s += 0.5e-3)
      EXPECT_GE(m.radius(s), r_dist - 1e-9) << variant << " at " << s;
    if (std::string(variant) == "OR")
      for (double s = m.paired_station(5); s <= m.flap_end() + 2e-3; s += 2e-3)
        fmt::print("OR d = {:5.1f} mm from TL5: R {:.2f} mm, flap offset {:+.2f} mm, TL {:.1f} "
                   "mm^2, FL depth {:.2f} mm\n",
                   (s - m.paired_station(5)) * 1e3, m.radius(s) * 1e3, m.flap_offset(s) * 1e3,
                   tl_area(s) * 1e6, (m.radius(s) + m.flap_offset(s) - 0.5 * h) * 1e3);
  }
  // An explicit position is kept (from the taper's start); a negative one is an error.
  TbadSpec spec;
  spec.exit_tear.position = 15e-3;
  const TbadModel m(spec);
  EXPECT_DOUBLE_EQ(m.spec().exit_tear.position, 15e-3);
  const Vec3 d = m.frame(m.taper_start()).origin - m.tears()[1].centre;
  EXPECT_NEAR(dot(d, m.frame(m.taper_start()).tangent), 15e-3, 1e-6);
  spec.exit_tear.position = -1e-3;
  EXPECT_THAT(error_of(spec), HasSubstr("exit tear position is -1 mm, expected >= 0"));
  spec = TbadSpec{};
  spec.fl_end_depth = 15e-3;
  EXPECT_THAT(error_of(spec), HasSubstr("false lumen end depth 15 mm must be less than"));
  spec = TbadSpec{};
  spec.taper_length = 0;
  EXPECT_THAT(error_of(spec), HasSubstr("flap taper length is 0 mm, expected a positive number"));
}

TEST(GeometryModel, VariantsSetTearAreas) {
  TbadSpec s;
  apply_variant(s, "EN");
  EXPECT_DOUBLE_EQ(s.entry_tear.area, 62e-6);
  EXPECT_DOUBLE_EQ(s.exit_tear.area, 227e-6);
  apply_variant(s, "EX");
  EXPECT_DOUBLE_EQ(s.entry_tear.area, 228e-6);
  EXPECT_DOUBLE_EQ(s.exit_tear.area, 61e-6);
  EXPECT_THROW(apply_variant(s, "XX"), InputError);
}

TEST(GeometryModel, TearLargerThanTheFlapIsAnError) {
  TbadSpec s;
  // 800 mm^2: the flap is at the vessel's centre at the exit tear, as wide as the lumen.
  s.exit_tear.area = 800e-6;
  const std::string e = error_of(s);
  EXPECT_THAT(e, HasSubstr("exit tear area 800.0 mm^2 is larger than the flap can hold"));
  EXPECT_THAT(e, HasSubstr("the largest exit tear that fits is"));
  // The largest area it names does fit.
  const auto at = e.find("fits is ");
  ASSERT_NE(at, std::string::npos);
  s.exit_tear.area = 0.999 * std::stod(e.substr(at + 8)) * 1e-6;
  EXPECT_NO_THROW(TbadModel{s});
}

TEST(GeometryModel, BadDimensionsAreErrors) {
  TbadSpec s;
  s.wall_thickness = -2e-3;
  EXPECT_THAT(error_of(s), HasSubstr("wall thickness (h) is -2 mm, expected a positive number"));
  s = TbadSpec{};
  s.tl_areas[2] = 0;
  EXPECT_THAT(error_of(s), HasSubstr("TL3 area is 0 mm^2"));
  s = TbadSpec{};
  s.arch_radius = 12e-3; // tighter than the aorta itself
  EXPECT_THAT(error_of(s), HasSubstr("increase the arch radius"));
  s = TbadSpec{};
  s.flap_length = 60e-3;
  EXPECT_THAT(error_of(s), HasSubstr("lengthen the flap"));
  s = TbadSpec{};
  s.entry_tear.aspect = 0.5;
  EXPECT_THAT(error_of(s), HasSubstr("entry tear aspect is 0.5"));
}

TEST(GeometryModel, LandmarksRoundTripInMillimetres) {
  const TbadModel m{TbadSpec{}};
  const Landmarks l = tbad_landmarks(m);
  // inlet, AAo, DAo_prox, TL1..5, FL1..5, DAo_dist, outlet.
  EXPECT_EQ(l.planes.size(), 15u);
  for (const std::string& name : area_landmark_names())
    EXPECT_NO_THROW(l.plane(name)) << name;
  const fs::path file = fs::temp_directory_path() / "tearflow-test-landmarks.json";
  write_landmarks(l, file, "mm");
  const Landmarks back = read_landmarks(file);
  fs::remove(file);
  ASSERT_EQ(back.planes.size(), l.planes.size());
  for (std::size_t i = 0; i < l.planes.size(); ++i) {
    EXPECT_EQ(back.planes[i].name, l.planes[i].name);
    EXPECT_EQ(back.planes[i].lumen, l.planes[i].lumen);
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(back.planes[i].origin[k], l.planes[i].origin[k], 1e-12);
  }
  ASSERT_EQ(back.tears.size(), 2u);
  EXPECT_NEAR(back.tear("entry").area, 228e-6, 1e-15);
  // TL and FL points lie on their plane, on opposite sides of the flap.
  const Landmark &tl = back.plane("TL3"), &fl = back.plane("FL3");
  EXPECT_NEAR(dot(*tl.point - tl.origin, tl.normal), 0, 1e-9);
  EXPECT_LT(dot(*fl.point - fl.origin, m.frame(m.paired_station(3)).normal), 0);
  EXPECT_GT(dot(*tl.point - tl.origin, m.frame(m.paired_station(3)).normal), 0);
}

TEST(GeometryModel, BadLandmarksFilesAreErrors) {
  const fs::path file = fs::temp_directory_path() / "tearflow-test-bad-landmarks.json";
  auto error_for = [&](const std::string& text) {
    std::ofstream(file) << text;
    try {
      read_landmarks(file);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  const std::string head = R"({"format": "tearflow-landmarks", "version": 1, )";
  EXPECT_THAT(error_for("{"), HasSubstr("not valid JSON"));
  EXPECT_THAT(error_for(head + R"("length_unit": "in", "planes": []})"),
              HasSubstr("unknown length unit 'in'"));
  EXPECT_THAT(error_for(head + R"("length_unit": "mm", "planes": [{"name": "TL1",
      "origin": [0, 0, 0], "normal": [0, 0, 1], "lumen": "TL"}]})"),
              HasSubstr("a TL plane needs a 'point'"));
  EXPECT_THAT(error_for(head + R"("length_unit": "mm", "planes": [{"name": "A",
      "origin": [0, 0, 0], "normal": [0, 0, 0]}]})"),
              HasSubstr("plane 'A': normal: a direction of zero length"));
  fs::remove(file);
}

} // namespace
} // namespace tearflow::geometry
