// The flow pictures (issue 30) on a CI-sized synthetic run (tests/pictures_support.hpp): a
// two-lumen channel, a true lumen (x = 0, r = 5 mm) and a false lumen beside it (x = 12 mm,
// r = 4 mm), each carrying Poiseuille flow along z with a time-varying amplitude, so that
// every streamline is a straight line along z and every plane's flow is known.
//
// Tolerances.
//   - A streamline starts at its seed, which lies on the seed plane; VTK keeps the output's
//     points in the input mesh's precision, so the first point is on the plane within the
//     rounding of a coordinate: a few float epsilons of the largest |x|.
//   - Inside the lumen: every point is located in a fluid tetrahedron (the tracer stops a
//     trace at the step that would leave the mesh and does not keep that point), and lies
//     within its own pipe's radius (plus the same rounding): the velocity has no transverse
//     part, so a trace cannot drift into the other lumen.
//   - A plane map's flow (its mean u.n times its area) is the plane integral of the same P1
//     field over the same section the analysis integrates (`flow_interpolated`), so the two
//     agree to rounding (1e-9 relative); against the exact Poiseuille flow both differ by the
//     P1 interpolation error <l^2> / (2 r^2) of tests/test_analysis.cpp's header.
#include <cfloat>
#include <cmath>
#include <fstream>
#include <iterator>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <vtkCellLocator.h>
#include <vtkDataArray.h>
#include <vtkGenericCell.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkUnstructuredGrid.h>

#include "analysis/flow_features.hpp"
#include "analysis/hemodynamics.hpp"
#include "analysis_support.hpp"
#include "cli_support.hpp"
#include "core/error.hpp"
#include "core/virtual_display.hpp"
#include "io/vtu_series.hpp"
#include "mesh/pipe_generator.hpp"
#include "pictures_support.hpp"
#include "report/flow_section.hpp"

namespace tearflow {
namespace {

using testing::drawn_fraction;
using testing::RunFolder;
using testing::SyntheticLumen;
using testing::SyntheticRun;
using testing::two_lumen_landmarks;
using testing::two_lumen_run;

constexpr double kLength = testing::kTwoLumenLength; // [m]

TEST(FlowFeatures, StreamlinesStartOnTheSeedPlaneAndStayInTheLumen) {
  const RunFolder f("flow-features-streamlines");
  // a(t) = 1 + sin(2 pi t / T) / 2 peaks at T / 4, a saved frame.
  const analysis::PictureFrame peak = analysis::cycle_frames(f.dir, f.landmarks).peak_systole;
  EXPECT_DOUBLE_EQ(peak.frame.time, f.run.period / 4);
  const auto fluid = analysis::read_flow_frame(peak.frame.file);
  const geometry::Landmark& seed = f.landmarks.plane("inlet");
  const auto lines = analysis::trace_streamlines(fluid, seed, {}, "test");
  ASSERT_GT(lines->GetNumberOfLines(), 20);

  const double tol = 8 * FLT_EPSILON * kLength; // see the header
  const SyntheticLumen& tl = f.run.lumina[0];
  auto locator = vtkSmartPointer<vtkCellLocator>::New();
  locator->SetDataSet(fluid);
  locator->BuildLocator();
  auto cell = vtkSmartPointer<vtkGenericCell>::New();
  double weights[4], pcoords[3];
  double lowest = kLength, highest = 0.0;
  vtkIdType n = 0;
  const vtkIdType* ids = nullptr;
  lines->GetLines()->InitTraversal();
  while (lines->GetLines()->GetNextCell(n, ids)) {
    ASSERT_GT(n, 0);
    double first[3];
    lines->GetPoint(ids[0], first);
    EXPECT_NEAR(first[2], seed.origin[2], tol) << "a streamline starts off the seed plane";
    for (vtkIdType k = 0; k < n; ++k) {
      double x[3];
      lines->GetPoint(ids[k], x);
      EXPECT_GE(locator->FindCell(x, 0.0, cell, pcoords, weights), 0)
          << "point (" << x[0] << ", " << x[1] << ", " << x[2] << ") outside the fluid";
      EXPECT_LE(std::hypot(x[0] - tl.x, x[1]), tl.radius + tol) << "left the true lumen";
      // Axial flow: a trace keeps its seed's x and y.
      EXPECT_NEAR(x[0], first[0], tol);
      EXPECT_NEAR(x[1], first[1], tol);
      lowest = std::min(lowest, x[2]);
      highest = std::max(highest, x[2]);
    }
  }
  // Traced both ways, to the ends of the channel (within a step of half a cell).
  EXPECT_LT(lowest, seed.origin[2] - 0.5 * (seed.origin[2]));
  EXPECT_GT(highest, kLength - f.edges.longest);
  vtkDataArray* speed = lines->GetPointData()->GetArray(analysis::kSpeedArray);
  ASSERT_NE(speed, nullptr);
  double range[2];
  speed->GetRange(range);
  EXPECT_LE(range[1], tl.u_peak * 1.5 + 1e-9); // a(T / 4) = 1.5
}

TEST(FlowFeatures, PlaneMapFlowMatchesTheAnalysis) {
  const RunFolder f("flow-features-planes");
  analysis::AnalyzeOptions options;
  options.run_dir = f.dir;
  const analysis::Analysis a = analysis::analyze_run(options);
  const analysis::PictureFrame peak = analysis::cycle_frames(f.dir, f.landmarks).peak_systole;
  ASSERT_DOUBLE_EQ(a.time[a.peak_systole], peak.frame.time);
  const auto fluid = analysis::read_flow_frame(peak.frame.file);
  const double l = f.edges.rms;
  for (std::size_t k = 0; k < f.landmarks.planes.size(); ++k) {
    const geometry::Landmark& landmark = f.landmarks.planes[k];
    const analysis::PlaneMap m = analysis::plane_map(fluid, landmark, 0.0, "test");
    const double mean = m.flow / m.area; // what the picture colours, times its area
    const analysis::SectionValues& v = a.series[k].samples[a.peak_systole];
    EXPECT_NEAR(mean * m.area, v.flow_interpolated, 1e-9 * std::abs(v.flow_interpolated))
        << landmark.name;
    EXPECT_NEAR(m.area, v.area, 1e-9 * v.area) << landmark.name;
    const std::size_t j = landmark.lumen == "FL" ? 1 : 0;
    const double r = f.run.lumina[j].radius;
    const double exact = f.run.flow(j, peak.frame.time);
    EXPECT_NEAR(m.flow, exact, exact * l * l / (2 * r * r)) << landmark.name;
    // The section is its own lumen's: every point within that pipe.
    for (vtkIdType i = 0; i < m.section->GetNumberOfPoints(); ++i) {
      double x[3];
      m.section->GetPoint(i, x);
      EXPECT_LE(std::hypot(x[0] - f.run.lumina[j].x, x[1]), r * (1 + 1e-9)) << landmark.name;
    }
    // The arrows: a grid inside the section; axial flow has no in-plane part.
    ASSERT_GT(m.vectors->GetNumberOfPoints(), 10) << landmark.name;
    vtkDataArray* w = m.vectors->GetPointData()->GetArray(analysis::kInPlaneArray);
    for (vtkIdType i = 0; i < w->GetNumberOfTuples(); ++i)
      EXPECT_LE(w->GetMaxNorm(), 1e-12) << landmark.name;
  }
}

TEST(FlowFeatures, MidDiastoleIsAfterTheFlowFalls) {
  {
    const RunFolder f("flow-features-no-diastole");
    // No diastole in a flow that never falls below a tenth of its peak (a = 1 +- 0.5).
    EXPECT_FALSE(analysis::cycle_frames(f.dir, f.landmarks).mid_diastole.has_value());
  }
  // A systole over the first half of the period, then rest: frames every 0.1 s, the peak at
  // 0.2 s, systole ends at 0.4 s (a = 0 < a tenth of the peak), the cycle at 0.8 s: mid-diastole
  // is the frame at 0.6 s.
  SyntheticRun run = two_lumen_run();
  run.amplitude = [](double t) { return std::max(0.0, std::sin(2 * M_PI * t / 0.8)); };
  const std::filesystem::path dir = testing::fresh_dir("flow-features-diastole");
  testing::write_synthetic_run(run, dir);
  const geometry::Landmarks landmarks = two_lumen_landmarks(run);
  const analysis::CycleFrames cycle = analysis::cycle_frames(dir, landmarks);
  EXPECT_DOUBLE_EQ(cycle.peak_systole.frame.time, 0.2);
  const auto& diastole = cycle.mid_diastole;
  ASSERT_TRUE(diastole.has_value());
  EXPECT_NEAR(diastole->frame.time, 0.6, 1e-12);
  EXPECT_EQ(diastole->event, "mid-diastole");
  // The frame nearest a time, and a time outside the run refused with the run's range.
  EXPECT_NEAR(analysis::frame_at(dir, 0.33).frame.time, 0.3, 1e-12);
  EXPECT_THROW(analysis::frame_at(dir, 0.9), InputError);
}

// Headless: DISPLAY removed, so the program starts its own X server (core/virtual_display).
TEST(FlowPictures, CommandRendersNonEmptyPicturesOnTheStatedScale) {
  const RunFolder f("flow-pictures-command");
  const std::filesystem::path out = report::flow_pictures_dir(f.dir); // the default
  const testing::Result r =
      testing::run_tearflow(fmt::format("pictures {} --speed-max 0.8 --animate", f.dir.string()),
                            "timeout 300 env -u DISPLAY"); // a hang becomes a failure
  ASSERT_EQ(r.code, 0) << r.output;
  const nlohmann::json record = testing::read_json(out / "pictures.json");
  EXPECT_EQ(record["seed_landmark"], "inlet");
  EXPECT_EQ(record["colour_scales"]["speed_m_per_s"], nlohmann::json({0.0, 0.8}));
  ASSERT_EQ(record["frames"].size(), 1u); // no diastole in this flow
  const nlohmann::json& peak = record["frames"][0];
  EXPECT_EQ(peak["event"], "peak systole");
  EXPECT_DOUBLE_EQ(peak["time_s"].get<double>(), f.run.period / 4);
  const std::filesystem::path dir = out / peak["folder"].get<std::string>();
  for (const char* vtp : {"streamlines.vtp", "plane_inlet.vtp", "plane_TL1.vtp", "plane_FL1.vtp",
                          "arrows_TL1.vtp", "plane_outlet.vtp"})
    EXPECT_TRUE(std::filesystem::is_regular_file(dir / vtp)) << vtp;
  std::size_t streamline_pictures = 0, plane_pictures = 0;
  for (const nlohmann::json& p : peak["pictures"]) {
    const std::string file = p["file"];
    const std::filesystem::path png = dir / file;
    ASSERT_TRUE(std::filesystem::is_regular_file(png)) << file;
    // The model fills a good part of the picture: far more than a caption and a bar.
    EXPECT_GT(drawn_fraction(png), 0.03) << file;
    const std::vector<double> range = p["scale_range"];
    if (file.rfind("streamlines_", 0) == 0) {
      ++streamline_pictures;
      EXPECT_EQ(p["scale_title"], "speed [m/s]");
      EXPECT_EQ(range, (std::vector<double>{0.0, 0.8})) << file;
    } else if (file.rfind("plane_", 0) == 0) {
      ++plane_pictures;
      EXPECT_EQ(p["scale_title"], "u.n [m/s]");
      EXPECT_EQ(range, (std::vector<double>{-0.8, 0.8})) << file;
    }
  }
  EXPECT_EQ(streamline_pictures, 2u); // anterior and left lateral: no tears, no flap view
  EXPECT_EQ(plane_pictures, 3u);      // inlet, station 1 (TL1 with FL1), outlet

  // The animation: one frame per saved frame of the cycle, as its acTL chunk says.
  const nlohmann::json& animation = record["animation"];
  EXPECT_EQ(animation["frames"], f.run.frames);
  EXPECT_EQ(testing::apng_frame_count(out / animation["file"].get<std::string>()),
            static_cast<unsigned>(f.run.frames));

  // The report's section: every picture embedded, once per run; runs side by side.
  const auto count = [](const std::string& html, const std::string& what) {
    std::size_t n = 0;
    for (std::size_t at = 0; (at = html.find(what, at)) != std::string::npos; ++at)
      ++n;
    return n;
  };
  const std::string one = report::flow_patterns_section({f.dir}, {"OR"});
  EXPECT_NE(one.find("<h2>Flow patterns</h2>"), std::string::npos);
  EXPECT_EQ(count(one, "src='data:image/png;base64,"), peak["pictures"].size() + 1); // + animation
  const std::string two =
      report::flow_patterns_section({f.dir, f.dir / "no-such-run"}, {"OR", "EN"});
  EXPECT_EQ(count(two, "src='data:image/png;base64,"), peak["pictures"].size() + 1);
  EXPECT_NE(two.find("EN: no pictures"), std::string::npos);
  EXPECT_TRUE(report::flow_patterns_section({f.dir / "no-such-run"}, {"EN"}).empty());
  // A picture listed but gone is said on the page, not skipped.
  const auto gone = out / "peak-systole" / "streamlines_left-lateral.png";
  const std::string kept = gone.string() + ".kept";
  std::filesystem::rename(gone, kept);
  const std::string without = report::flow_patterns_section({f.dir}, {"OR"});
  std::filesystem::rename(kept, gone);
  EXPECT_EQ(count(without, "src='data:image/png;base64,"), peak["pictures"].size());
  EXPECT_NE(without.find("missing: '" + gone.string() + "'"), std::string::npos);
  // This run has no mesh beside its landmarks: no model picture, and the record says why.
  EXPECT_TRUE(record["model"]["file"].is_null());
  EXPECT_NE(record["model"]["why"].get<std::string>().find("mesh.msh"), std::string::npos);

  // The comparison page's figures folder gets a copy of every picture it shows, the
  // animation's single frames left out.
  const auto figures = f.dir / "comparison_figures";
  const std::size_t copied =
      report::copy_flow_pictures({f.dir, f.dir / "no-such-run"}, {"OR rigid", "EN"}, figures);
  EXPECT_EQ(copied, peak["pictures"].size() + 1); // one frame pictured, and the animation
  EXPECT_TRUE(std::filesystem::exists(figures / "flow" / "OR_rigid" / "peak-systole" /
                                      "plane_station1.png"));
  EXPECT_FALSE(std::filesystem::exists(figures / "flow" / "OR_rigid" / "animation"));
}

// An FSI frame: a pipe with its wall region (fluid r < 5 mm, wall 5-6 mm), Poiseuille flow in
// the fluid, every node displaced radially by e r (the wall's motion and the fluid mesh's).
TEST(FlowPictures, FsiRunShowsTheWallsDisplacementOnItsScale) {
  const std::filesystem::path dir = testing::fresh_dir("flow-pictures-fsi");
  const double r = 0.005, length = 0.02, e = 0.02; // |d| up to e x 6 mm = 0.12 mm
  const mesh::Mesh pipe = mesh::make_pipe({r, length, 0.001, 0.001});
  ASSERT_EQ(pipe.regions.size(), 2u);
  std::vector<bool> in_fluid(pipe.points.size(), false);
  for (std::size_t t = 0; t < pipe.tets.size(); ++t)
    if (pipe.regions[static_cast<std::size_t>(pipe.tet_region[t])] == "fluid")
      for (Index n : pipe.tets[t])
        in_fluid[static_cast<std::size_t>(n)] = true;
  std::filesystem::create_directories(dir);
  io::VtuSeries series(pipe, dir, "flow");
  const int frames = 5;
  for (int i = 0; i < frames; ++i) {
    const double t = 0.8 * i / (frames - 1), a = 1.0 + 0.5 * std::sin(2 * M_PI * t / 0.8);
    io::PointField u{"velocity", 3, {}}, p{"pressure", 1, {}}, d{"displacement", 3, {}};
    for (std::size_t n = 0; n < pipe.points.size(); ++n) {
      const Vec3& x = pipe.points[n];
      const double rho2 = x[0] * x[0] + x[1] * x[1];
      const double w = in_fluid[n] ? std::max(0.0, 0.5 * a * (1 - rho2 / (r * r))) : 0.0;
      u.values.insert(u.values.end(), {0.0, 0.0, w});
      p.values.push_back(1e4 * a);
      d.values.insert(d.values.end(), {e * a / 1.5 * x[0], e * a / 1.5 * x[1], 0.0});
    }
    series.write(i, t, {u, p, d});
  }
  geometry::Landmarks landmarks;
  landmarks.planes = {{"inlet", {0, 0, 0.004}, {0, 0, 1}}, {"outlet", {0, 0, 0.016}, {0, 0, 1}}};
  std::filesystem::create_directories(dir / "geometry");
  geometry::write_landmarks(landmarks, dir / "geometry" / "landmarks.json");

  const testing::Result result = testing::run_tearflow(
      fmt::format("pictures {} --displacement-max-mm 0.3 --time 0.2", dir.string()),
      "timeout 300 env -u DISPLAY");
  ASSERT_EQ(result.code, 0) << result.output;
  const nlohmann::json record =
      testing::read_json(report::flow_pictures_dir(dir) / "pictures.json");
  const nlohmann::json& frame = record["frames"][0];
  EXPECT_EQ(frame["folder"], "t-0.2s");
  int walls = 0;
  for (const nlohmann::json& p : frame["pictures"]) {
    const std::string file = p["file"];
    if (file.rfind("wall_displacement_", 0) != 0)
      continue;
    ++walls;
    EXPECT_EQ(p["scale_title"], "displacement [mm]");
    EXPECT_EQ(p["scale_range"], nlohmann::json({0.0, 0.3}));
    EXPECT_GT(drawn_fraction(report::flow_pictures_dir(dir) / "t-0.2s" / file), 0.03) << file;
  }
  EXPECT_EQ(walls, 2); // anterior, left lateral
  // The sections are the deformed fluid's: at t = 0.2 s (a = 1.5) the lumen's radius is
  // r (1 + e), its area pi r^2 (1 + e)^2 (4 % above the rest area) less the chords' loss,
  // l^2 / (4 r^2) = 1 % at l = 1 mm (tests/test_analysis.cpp), taken twice for the spread of
  // the edges.
  const double area = frame["planes"]["inlet"]["area_m2"];
  const double deformed = M_PI * r * r * (1 + e) * (1 + e);
  EXPECT_LE(area, deformed * (1 + 1e-9));
  EXPECT_GE(area, deformed * (1 - 0.02));
}

// A moving wall: each lumen dilated about its own axis by e(t) = 0.04 sin(2 pi t / T), so that
// at peak systole (T / 4) its section is the end-diastolic one (t = 0, e = 0) scaled by 1.04.
// The displacement is linear about each axis, so the P1 section scales exactly: the areas'
// ratio is 1.04^2 to rounding. And a view asked for by direction replaces the standard ones.
TEST(FlowPictures, FlapAtPeakSystoleOverEndDiastoleAndViewsAskedFor) {
  RunFolder f("flow-pictures-flap", [](testing::SyntheticRun& run) {
    run.dilation = [](double t) { return 0.04 * std::sin(2 * M_PI * t / 0.8); };
  });
  const auto out = f.dir / "figures";
  const testing::Result r = testing::run_tearflow(
      fmt::format("pictures {} --view posterior:0,1,0 -o {}", f.dir.string(), out.string()));
  ASSERT_EQ(r.code, 0) << r.output;
  const nlohmann::json record = testing::read_json(out / "pictures.json");
  const nlohmann::json& peak = record["frames"][0];
  EXPECT_NEAR(peak["time_s"].get<double>(), 0.2, 1e-12);
  const nlohmann::json& flap = peak["flap_position"];
  EXPECT_NEAR(flap["end_diastole_time_s"].get<double>(), 0.0, 1e-12);
  for (const char* lumen : {"TL1", "FL1"}) {
    const nlohmann::json& a = flap["stations"]["station1"][lumen];
    EXPECT_NEAR(a["area_m2"].get<double>() / a["area_end_diastole_m2"].get<double>(), 1.04 * 1.04,
                1e-9)
        << lumen;
  }
  EXPECT_GT(testing::drawn_fraction(out / "peak-systole" / "flap_station1.png"), 0.003);
  std::vector<std::string> files;
  for (const nlohmann::json& p : peak["pictures"])
    files.push_back(p["file"]);
  EXPECT_NE(std::find(files.begin(), files.end(), "flap_station1.png"), files.end());
  EXPECT_NE(std::find(files.begin(), files.end(), "streamlines_posterior.png"), files.end());
  EXPECT_EQ(std::find(files.begin(), files.end(), "streamlines_anterior.png"), files.end());
}

TEST(FlowPictures, BadInputIsAClearError) {
  const RunFolder f("flow-pictures-bad");
  const std::string run = f.dir.string();
  struct Case {
    std::string args, says;
  };
  const std::vector<Case> cases = {
      {"pictures /nonexistent/run --no-png", "/nonexistent/run"},
      {fmt::format("pictures {} --seed AAx --no-png", run), "AAx"},
      {fmt::format("pictures {} --time 5 --no-png", run), "--time 5"},
      {fmt::format("pictures {} --model /nonexistent/model --no-png", run),
       "/nonexistent/model/landmarks.json"},
      {fmt::format("pictures {} --view superior --no-png", run), "--view superior"},
      {fmt::format("pictures {} --view up:0,0,0 --no-png", run), "NAME:X,Y,Z"}};
  for (const Case& c : cases) {
    const testing::Result r = testing::run_tearflow(c.args);
    EXPECT_NE(r.code, 0) << c.args;
    EXPECT_NE(r.output.find(c.says), std::string::npos) << c.args << ": " << r.output;
  }
  // No X display and no Xvfb to start one: said so, not a crash in VTK.
  const testing::Result r =
      testing::run_tearflow(fmt::format("pictures {} -o {}", run, (f.dir / "figures").string()),
                            "env -u DISPLAY TEARFLOW_XVFB=/nonexistent/Xvfb");
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.output.find("no Xvfb"), std::string::npos) << r.output;
}

TEST(VirtualDisplay, StartsItsOwnServerWithoutADisplay) {
  if (!std::filesystem::exists("/usr/bin/Xvfb"))
    GTEST_SKIP() << "no Xvfb on this machine";
  unsetenv("DISPLAY");
  const std::string display = ensure_display("test");
  ASSERT_FALSE(display.empty());
  EXPECT_EQ(display[0], ':');
  EXPECT_EQ(std::string(std::getenv("DISPLAY")), display);
  EXPECT_EQ(ensure_display("test"), display); // one server per process
}

} // namespace
} // namespace tearflow
