// Measured data through the analysis, the deformed fluid of a fluid-structure frame, and the
// report pages rendered in headless Chromium (issue 7).
#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "analysis/hemodynamics.hpp"
#include "analysis_support.hpp"
#include "cli_support.hpp"
#include "core/units.hpp"

namespace tearflow {
namespace {

using testing::read_json;

using testing::SyntheticLumen;
using testing::SyntheticRun;

/// The two-lumen channel of test_analysis.cpp, analysed: TL1 / FL1 at z = 1 mm, TL2 / FL2 at
/// z = 2 mm.
SyntheticRun two_lumen_run() {
  SyntheticRun run;
  run.lumina = {SyntheticLumen{0.0, 0.005, 0.6, 1.2e4}, SyntheticLumen{0.012, 0.004, 0.3, 1.1e4}};
  run.length = 0.003;
  return run;
}

std::filesystem::path analysed_two_lumen_run(const std::string& name) {
  const SyntheticRun run = two_lumen_run();
  const std::filesystem::path dir = testing::fresh_dir(name);
  testing::write_synthetic_run(run, dir);
  geometry::Landmarks landmarks;
  landmarks.planes = {
      testing::plane_at(run, "TL1", 0.001, 0, "TL"), testing::plane_at(run, "FL1", 0.001, 1, "FL"),
      testing::plane_at(run, "TL2", 0.002, 0, "TL"), testing::plane_at(run, "FL2", 0.002, 1, "FL")};
  std::filesystem::create_directories(dir / "geometry");
  geometry::write_landmarks(landmarks, dir / "geometry" / "landmarks.json");
  const testing::Result r = testing::run_tearflow("analyze -q " + dir.string());
  EXPECT_EQ(r.code, 0) << r.output;
  return dir;
}

/// Measurement tables of the same channel from its exact answers: flow and pressure at
/// `frames` samples over the period, the (constant) areas at 3 other instants.
std::filesystem::path measured_two_lumen(const std::string& name, int frames,
                                         double flow_scale = 1.0) {
  const SyntheticRun run = two_lumen_run();
  const std::filesystem::path dir = testing::fresh_dir(name);
  std::filesystem::create_directories(dir);
  std::ofstream flow(dir / "flow.csv"), pressure(dir / "pressure.csv"), area(dir / "area.csv");
  flow << "time_s,TL1_mL_per_s,FL1_mL_per_s,TL2_mL_per_s,FL2_mL_per_s\n";
  pressure << "time_s,TL1_mmHg,FL1_mmHg,TL2_Pa,FL2_Pa\n";
  for (int i = 0; i < frames; ++i) {
    const double t = run.period * i / (frames - 1);
    const double q0 = flow_scale * run.flow(0, t) / units::mL,
                 q1 = flow_scale * run.flow(1, t) / units::mL;
    flow << fmt::format("{:.12g},{:.12g},{:.12g},{:.12g},{:.12g}\n", t, q0, q1, q0, q1);
    pressure << fmt::format("{:.12g},{:.12g},{:.12g},{:.12g},{:.12g}\n", t,
                            run.pressure(0, 0.001, t) / units::mmHg,
                            run.pressure(1, 0.001, t) / units::mmHg, run.pressure(0, 0.002, t),
                            run.pressure(1, 0.002, t));
  }
  const double a0 = M_PI * 25.0, a1 = M_PI * 16.0; // mm^2 of r = 5 and 4 mm
  area << "time_s,TL1_mm2,FL1_mm2\n";
  for (double t : {0.1, 0.4, 0.7})
    area << fmt::format("{},{:.12g},{:.12g}\n", t, a0, a1);
  return dir;
}

TEST(MeasuredData, TablesGiveTheSameQuantitiesAsASimulation) {
  const SyntheticRun run = two_lumen_run();
  const int frames = 21;
  const std::filesystem::path dir = measured_two_lumen("measured-two-lumen", frames);
  const testing::Result r = testing::run_tearflow("analyze " + dir.string());
  ASSERT_EQ(r.code, 0) << r.output;
  const nlohmann::json m = read_json(dir / "analysis" / "metrics.json");
  EXPECT_EQ(m["source"], "measured");
  EXPECT_EQ(m["frame_count"], frames);
  // The tables hold the exact values at their samples; what the analysis adds is the
  // trapezoidal cycle mean (the same for both lumina, which follow one a(t), so FR_FL is
  // exact), the peak-systolic frame (t = T / 4 is sample 5 of 21) and unit conversions:
  // rounding only (12 printed digits).
  const double q_tl = run.flow(0, 0), q_fl = run.flow(1, 0);
  const double t_peak = run.period / 4;
  EXPECT_NEAR(m["peak_systole_time_s"].get<double>(), t_peak, 1e-12);
  for (const auto& [k, z] : {std::pair{"1", 0.001}, {"2", 0.002}}) {
    const nlohmann::json& s = m["stations"][k];
    EXPECT_NEAR(s["FR_FL_percent"].get<double>(), 100 * q_fl / (q_fl + q_tl), 1e-8) << k;
    const double dp = run.pressure(0, z, t_peak) - run.pressure(1, z, t_peak);
    EXPECT_NEAR(s["dP_TL_minus_FL_peak_systole_Pa"].get<double>(), dp, 1e-8 * std::abs(dp)) << k;
  }
  // Areas: given for station 1 only (constant, so holding and interpolating are exact);
  // station 2 has none, which the metrics say with null rather than a number.
  EXPECT_NEAR(m["landmarks"]["TL1"]["A_0_mm2"].get<double>(), M_PI * 25.0, 1e-9);
  EXPECT_NEAR(m["landmarks"]["FL1"]["A_mean_mm2"].get<double>(), M_PI * 16.0, 1e-9);
  EXPECT_TRUE(m["landmarks"]["TL2"]["A_0_mm2"].is_null());
  EXPECT_TRUE(m["landmarks"]["TL2"]["max_through_plane_velocity_m_per_s"].is_null());
}

TEST(MeasuredData, BadTablesNameTheFileAndColumn) {
  const std::filesystem::path dir = testing::fresh_dir("measured-bad");
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "flow.csv") << "time_s,TL1_L_per_min\n0,1\n0.5,2\n";
  testing::Result r = testing::run_tearflow("analyze " + dir.string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("flow.csv' line 1, column 2 'TL1_L_per_min': expected "
                          "<landmark>_mL_per_s or <landmark>_m3_per_s"),
            std::string::npos)
      << r.output;

  std::ofstream(dir / "flow.csv") << "time_s,TL1_mL_per_s\n0,1\n0.5,2\n0.5,3\n";
  r = testing::run_tearflow("analyze " + dir.string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("line 4: time 0.5 s does not increase"), std::string::npos) << r.output;

  std::filesystem::remove(dir / "flow.csv");
  r = testing::run_tearflow("analyze " + dir.string());
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("holds neither a run's output (flow.pvd) nor a measurement table"),
            std::string::npos)
      << r.output;
}

TEST(Analysis, FluidStructureFrameIsCutInItsDeformedFluid) {
  // A tube with a wall region, every node moved radially by d = eps (x, y, 0): the lumen of
  // radius r becomes one of radius (1 + eps) r. Only the fluid region may be cut (the wall's
  // annulus shares the interface nodes and would join the section), and in its deformed
  // position.
  const double r = 0.005, eps = 0.05, h = r / 8;
  const mesh::Mesh tube = mesh::make_pipe({r, 0.004, h, 0.002});
  const std::filesystem::path dir = testing::fresh_dir("analysis-fsi-frame");
  std::filesystem::create_directories(dir / "geometry");
  io::VtuSeries series(tube, dir, "flow");
  io::PointField u{"velocity", 3, {}}, p{"pressure", 1, {}}, d{"displacement", 3, {}};
  const double u_peak = 0.4;
  for (const Vec3& x : tube.points) {
    const double rho2 = x[0] * x[0] + x[1] * x[1];
    u.values.insert(u.values.end(), {0.0, 0.0, rho2 < r * r ? u_peak * (1 - rho2 / (r * r)) : 0});
    p.values.push_back(1000.0);
    d.values.insert(d.values.end(), {eps * x[0], eps * x[1], 0.0});
  }
  series.write(0, 0.0, {u, p, d});
  series.write(1, 0.1, {u, p, d});
  geometry::Landmarks landmarks;
  landmarks.planes = {{"AAo", {0, 0, 0.002}, {0, 0, 1}, "aorta", std::nullopt}};
  geometry::write_landmarks(landmarks, dir / "geometry" / "landmarks.json");
  const testing::Result res = testing::run_tearflow("analyze -q --frames all " + dir.string());
  ASSERT_EQ(res.code, 0) << res.output;
  const nlohmann::json l = read_json(dir / "analysis" / "metrics.json")["landmarks"]["AAo"];
  // The section is the polygon of chords of the deformed circle: its area falls short of
  // pi R^2 by at most l^2 / (4 R^2) relative (test_analysis.cpp), l <~ 1.5 h the edge length.
  const double R = (1 + eps) * r, l2 = 2.25 * h * h;
  const double area = M_PI * R * R / (units::mm * units::mm);
  EXPECT_NEAR(l["A_0_mm2"].get<double>(), area, area * l2 / (4 * r * r));
  // Flow: the velocity moves with the nodes, so Q = (1 + eps)^2 pi r^2 u_peak / 2, within the
  // P1 error l^2 / (2 r^2) of test_analysis.cpp.
  const double q = (1 + eps) * (1 + eps) * M_PI * r * r * u_peak / 2;
  EXPECT_NEAR(l["mean_flow_m3_per_s"].get<double>(), q, q * l2 / (2 * r * r));
  // The wall displacement at the station: eps r on the rim (cut points on chords, which are
  // within l^2 / (8 r^2) of the circle).
  EXPECT_NEAR(l["max_wall_displacement_mm"].get<double>(), eps * r / units::mm,
              eps * r / units::mm * l2 / (8 * r * r));
}

TEST(Report, PagesRenderInHeadlessChromiumWithEveryFigure) {
  const std::filesystem::path run = analysed_two_lumen_run("report-run");
  const std::filesystem::path measured = measured_two_lumen("report-measured", 21);
  ASSERT_EQ(testing::run_tearflow("analyze -q " + measured.string()).code, 0);
  const std::filesystem::path page = testing::fresh_dir("report-compare.html");
  // --png renders each page in Chromium and exits non-zero on any script error.
  const testing::Result r = testing::run_tearflow(
      fmt::format("report {} {} -o {} --png", run.string(), measured.string(), page.string()));
  ASSERT_EQ(r.code, 0) << r.output;
  for (const std::filesystem::path& html :
       {run / "analysis" / "report.html", measured / "analysis" / "report.html", page}) {
    ASSERT_TRUE(std::filesystem::exists(html)) << html;
    std::ifstream in(html);
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    EXPECT_EQ(text.find("src=\"http"), std::string::npos) << "the page must be self-contained";
  }
  // The comparison page: both runs, and the measured one's difference from the simulation.
  std::ifstream in(page);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(text.find("tearflow-test-report-measured &minus; tearflow-test-report-run"),
            std::string::npos);
  // Figures of a two-lumen run: flow TL, flow FL, dP(t), normalised pressure is absent (no
  // inlet), area change of the lumina, maximum area: 5, each a PNG.
  std::filesystem::path figures = page;
  figures.replace_extension("");
  figures += "_figures";
  int pngs = 0;
  for (const auto& entry : std::filesystem::directory_iterator(figures)) {
    std::ifstream png(entry.path(), std::ios::binary);
    char signature[8] = {};
    png.read(signature, 8);
    EXPECT_EQ(std::string(signature + 1, 3), "PNG") << entry.path();
    EXPECT_GT(std::filesystem::file_size(entry.path()), 2000u) << entry.path();
    ++pngs;
  }
  EXPECT_EQ(pngs, 5) << r.output;
}

TEST(Report, MriComparisonSectionShowsTheStatisticsAndEveryFigure) {
  // A "scan" reading 10 % more flow than the run, so that the differences are not zero.
  const std::filesystem::path run = analysed_two_lumen_run("report-mri-run");
  const std::filesystem::path measured = measured_two_lumen("report-mri-measured", 21, 1.1);
  const std::filesystem::path compare = testing::fresh_dir("report-mri-compare");
  testing::Result r = testing::run_tearflow(
      fmt::format("mri compare -q {} {} -o {}", run.string(), measured.string(), compare.string()));
  ASSERT_EQ(r.code, 0) << r.output;
  ASSERT_EQ(testing::run_tearflow("analyze -q " + measured.string()).code, 0);
  const std::filesystem::path page = testing::fresh_dir("report-mri.html");
  r = testing::run_tearflow(fmt::format("report {} {} -o {} --mri {} --png", run.string(),
                                        measured.string(), page.string(), compare.string()));
  ASSERT_EQ(r.code, 0) << r.output;
  std::ifstream in(page);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(text.find("Simulation against 4D-flow MRI"), std::string::npos);
  // The pooled Bland-Altman row, recomputed here from flow_comparison.csv's differences.
  std::ifstream csv(compare / "flow_comparison.csv");
  std::string line;
  std::getline(csv, line);
  std::vector<double> d;
  while (std::getline(csv, line)) {
    std::vector<std::string> cells;
    std::stringstream s(line);
    for (std::string c; std::getline(s, c, ',');)
      cells.push_back(c);
    ASSERT_EQ(cells.size(), 6u) << line;
    d.push_back(std::stod(cells[4]));
  }
  ASSERT_EQ(d.size(), 4u * 21u); // 4 landmarks x 21 frames
  double bias = 0, ss = 0;
  for (double x : d)
    bias += x / d.size();
  for (double x : d)
    ss += (x - bias) * (x - bias);
  const double sd = std::sqrt(ss / (d.size() - 1));
  // The MRI reads 10 % more: the bias is positive and the spread is not zero.
  EXPECT_GT(bias, 0.0);
  EXPECT_GT(sd, 0.0);
  EXPECT_NE(text.find(fmt::format("<td>all ({} pairs)</td>", d.size())), std::string::npos);
  EXPECT_NE(text.find(fmt::format("<td>{:.2f} &plusmn; {:.2f}</td><td>{:.2f} to {:.2f}</td>", bias,
                                  sd, bias - 1.96 * sd, bias + 1.96 * sd)),
            std::string::npos)
      << "pooled bias " << bias << " SD " << sd;
  // Every landmark's row carries compare.json's limits of agreement and r; the FL flow ratio
  // of each station is in its table.
  const nlohmann::json c = read_json(compare / "compare.json");
  for (const char* landmark : {"TL1", "FL1", "TL2", "FL2"}) {
    const nlohmann::json& l = c["landmarks"][landmark];
    const nlohmann::json& loa = l["limits_of_agreement_mL_per_s"];
    EXPECT_NE(
        text.find(fmt::format("<td>{:.2f} to {:.2f}</td><td>{:.4f}</td>", loa[0].get<double>(),
                              loa[1].get<double>(), l["correlation"].get<double>())),
        std::string::npos)
        << landmark;
  }
  for (const char* k : {"1", "2"}) {
    const nlohmann::json& f = c["fl_flow_ratio_percent"][k];
    EXPECT_NE(text.find(fmt::format("<tr><td>{}</td><td>{:.1f}</td><td>{:.1f}</td>", k,
                                    f["simulation"].get<double>(), f["mri"].get<double>())),
              std::string::npos)
        << k;
  }
  // Figures: the page's 5 (test above), the Bland-Altman plot and one waveform per landmark.
  std::filesystem::path figures = page;
  figures.replace_extension("");
  figures += "_figures";
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(figures)) {
    EXPECT_GT(std::filesystem::file_size(entry.path()), 2000u) << entry.path();
    names.push_back(entry.path().stem().string());
  }
  EXPECT_EQ(names.size(), 10u) << r.output;
  for (const char* name :
       {"mri_bland_altman", "mri_flow_TL1", "mri_flow_FL1", "mri_flow_TL2", "mri_flow_FL2"})
    EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << name;

  // A folder that `mri compare` did not write: the missing file is named, exit 2.
  r = testing::run_tearflow(fmt::format("report {} --mri {}", run.string(), measured.string()));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("compare.json' does not exist"), std::string::npos) << r.output;
}

} // namespace
} // namespace tearflow
