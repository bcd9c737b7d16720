// The reduced-order model on the built-in dissection (issue 26): the model directory's
// measurement, calibration on stored 3D results of the coarse demo (4.5 mm, rigid and FSI,
// tests/data/rom: the analysis tables of OR, EN and EX and their cases), the held-out variants
// predicted from OR alone against their stored 3D results, the sweep, and bad input.
// The model is built here by `geometry tbad` (the same mesh the demo ran on: the builder is
// deterministic), about 20 s.
#include <cmath>
#include <fstream>
#include <map>
#include <regex>
#include <stdexcept>

#include <gtest/gtest.h>

#include "cli_support.hpp"
#include "core/file_layout.hpp"
#include "core/units.hpp"
#include "geometry/fsi_mesh.hpp"
#include "geometry/sections.hpp"
#include "io/case.hpp"
#include "rom/calibration.hpp"
#include "rom/dissection_geometry.hpp"
#include "rom/dissection_network.hpp"

using namespace tearflow;
using namespace tearflow::testing;
namespace fs = std::filesystem;

namespace {

const fs::path kData = test_data / "rom";

/// A stored case (`kind`: rigid or fsi) with the model's mesh in place of MODEL.
fs::path stored_case(const std::string& variant, const fs::path& model, const fs::path& dir,
                     const std::string& kind = "rigid", const fs::path& data = kData) {
  std::ifstream in(data / (variant + "-" + kind + ".yaml"));
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text = std::regex_replace(text, std::regex("MODEL/"), model.string() + "/");
  const fs::path out = dir / (variant + "-" + kind + ".yaml");
  std::ofstream(out) << text;
  return out;
}

/// FR_FL and peak-systolic dP per station of a stored 3D run (peak systole: the frame of the
/// largest inflow, as `analyze` marks it).
struct Stations {
  std::vector<double> fr, dp;
};

Stations stored_stations(const std::string& variant, const rom::DissectionGeometry& g,
                         const fs::path& case_file, const std::string& kind = "rigid",
                         const fs::path& data = kData) {
  const rom::CalibrationRun run =
      rom::read_calibration_run(data / (variant + "-" + kind), io::load_case(case_file), g, 0.0);
  const std::vector<double>& q = run.flow.at("inlet");
  const size_t peak = std::max_element(q.begin(), q.end()) - q.begin();
  auto mean = [&](const std::vector<double>& v) {
    double s = 0;
    for (size_t k = 1; k < v.size(); ++k)
      s += 0.5 * (v[k] + v[k - 1]) * (run.time[k] - run.time[k - 1]);
    return s;
  };
  Stations s;
  for (int k = 1; k <= 5; ++k) {
    const std::string tl = "TL" + std::to_string(k), fl = "FL" + std::to_string(k);
    s.fr.push_back(100.0 * mean(run.flow.at(fl)) / (mean(run.flow.at(fl)) + mean(run.flow.at(tl))));
    s.dp.push_back((run.pressure.at(tl)[peak] - run.pressure.at(fl)[peak]) / units::mmHg);
  }
  return s;
}

void print_station(const Stations& rom, const Stations& d3, int k, const std::string& what) {
  std::printf("%s station %d: FR_FL %.1f (3D %.1f) %%, dP %.1f (3D %.1f) mmHg\n", what.c_str(),
              k + 1, rom.fr[k], d3.fr[k], rom.dp[k], d3.dp[k]);
}

/// The criterion at station k: FR_FL within 5 points, peak-systolic dP within 3 mmHg or
/// 20 %; `fr_points` above 5 holds a documented miss of FR_FL to its measured error.
void expect_within_criterion(const Stations& rom, const Stations& d3, int k,
                             const std::string& what, double fr_points = 5.0) {
  print_station(rom, d3, k, what);
  EXPECT_NEAR(rom.fr[k], d3.fr[k], fr_points)
      << what << " station " << k + 1 << (fr_points > 5.0 ? " (a documented miss)" : "");
  EXPECT_NEAR(rom.dp[k], d3.dp[k], std::max(3.0, 0.2 * std::abs(d3.dp[k])))
      << what << " station " << k + 1;
}

Stations predicted_stations(const fs::path& metrics) {
  const nlohmann::json m = read_json(metrics);
  Stations s;
  for (int k = 1; k <= 5; ++k) {
    const nlohmann::json& st = m["stations"][std::to_string(k)];
    s.fr.push_back(st["FR_FL_percent"].get<double>());
    s.dp.push_back(st["dP_TL_minus_FL_peak_systole_mmHg"].get<double>());
  }
  return s;
}

/// `rom predict` of a held-out variant (EN: the entry at 62 mm^2, EX: the exit at 61, EN120 and
/// EX120: the entry or the exit at 120) with its case into `out`; its stations.
Stations predict_variant(const fs::path& model, const std::string& variant,
                         const fs::path& case_file, const fs::path& out) {
  const std::map<std::string, std::string> areas{{"EN", " --entry-tear-area 62"},
                                                 {"EX", " --exit-tear-area 61"},
                                                 {"EN120", " --entry-tear-area 120"},
                                                 {"EX120", " --exit-tear-area 120"}};
  const auto it = areas.find(variant);
  if (it == areas.end()) {
    ADD_FAILURE() << "no tear areas for variant " << variant;
    return {};
  }
  const std::string& area = it->second;
  const Result p = run_tearflow("rom predict -q " + model.string() + " --case " +
                                case_file.string() + area + " -o " + out.string());
  EXPECT_EQ(p.code, 0) << p.output;
  return predicted_stations(out / "analysis" / "metrics.json");
}

} // namespace

TEST(RomModel, FlapWidthIsTheChordThatDividesTheSection) {
  // A straight chord at distance d from the centre of a circle of radius r is 2 sqrt(r^2 - d^2)
  // long and cuts off the fraction (theta - sin theta) / (2 pi), theta = 2 acos(d / r): the
  // width from that fraction must give the chord back (bisection to 1e-12, on either side).
  const double r = 0.012;
  for (const double d : {0.0, 0.2 * r, 0.5 * r, 0.8 * r, 0.97 * r}) {
    const double theta = 2.0 * std::acos(d / r);
    const double f = (theta - std::sin(theta)) / (2.0 * M_PI);
    const double chord = 2.0 * std::sqrt(r * r - d * d);
    EXPECT_NEAR(rom::flap_width(r, f), chord, 1e-9 * r) << "d = " << d;
    EXPECT_NEAR(rom::flap_width(r, 1.0 - f), chord, 1e-9 * r) << "d = " << d;
  }
  EXPECT_NEAR(rom::flap_width(r, 0.0), 0.0, 1e-9 * r);
}

TEST(RomModel, EndToEndOnTheBuiltModel) {
  const fs::path dir = fresh_dir("rom");
  const fs::path model = dir / "OR";
  const Result built =
      run_tearflow("geometry tbad --element-size 4.5 --variant OR -o " + model.string());
  ASSERT_EQ(built.code, 0) << built.output;

  // --- the measurement ----------------------------------------------------------------------
  const rom::DissectionGeometry g = rom::model_geometry(model, false);
  // The built wall and flap are 2 mm thick; 2 V / (A_outer + A_interface) is exact for a
  // shell of uniform thickness up to its curvature (h / 2R ~ 8 % at the TL's 12 mm radius,
  // half of it cancelling between the two faces) and the meshing: 5 %.
  EXPECT_NEAR(g.wall_thickness, 2e-3, 0.05 * 2e-3);
  const mesh::Mesh mesh = geometry::read_fsi_mesh(GeometryFiles{model}.mesh(), 1e-3);
  const geometry::Landmarks lm = geometry::read_landmarks(GeometryFiles{model}.landmarks());
  // The entry tear is cut by DAo_prox (the built model's rule) and lies ~24 mm above FL1;
  // the exit tear lies between TL5 and DAo_dist.
  const auto& entry = g.tears.at(0);
  EXPECT_EQ(entry.name, "entry");
  EXPECT_EQ(entry.tl_node, "DAo_prox");
  EXPECT_EQ(entry.fl_node, "FL_entry");
  EXPECT_EQ(g.tears.at(1).tl_node, "TL_exit");
  // The entry's junction area is the true lumen's beside the tear, not DAo_prox's section,
  // which also cuts the false lumen's blind end above the tear (732 mm^2): its distal rim is
  // TL1's lumen (234 mm^2), its proximal rim wider where the flap's top edge nears (~320): the
  // mean lies between TL1's area and 1.5 times it (278 mm^2 measured at 4.5, 3 and 2 mm). An
  // inserted TL node (the exit's) is its own channel.
  const double tl1 = g.nodes[g.node("TL1")].area;
  EXPECT_GT(entry.channel_area, tl1);
  EXPECT_LT(entry.channel_area, 1.5 * tl1);
  EXPECT_DOUBLE_EQ(g.tears.at(1).channel_area, g.nodes[g.node("TL_exit")].area);
  // The exit's nodes are measured at its rims, where the flap has moved from station 5's
  // 57 mm^2 TL to lumina of about half the section each: together with the tear's own strip
  // of the section (the flap's thickness times the tear's width) they make the undivided
  // section through the tear's centre, within 5 % (the rims' sections differ by 2-3 % from
  // the centre's at 4.5 mm).
  {
    const rom::GeometryNode &tl = g.nodes[g.node("TL_exit")], &fl = g.nodes[g.node("FL_exit")];
    const geometry::TearLandmark& exit = lm.tear("exit");
    const geometry::Section centre = geometry::cut_region(
        mesh, geometry::region_index(mesh, "fluid"), exit.centroid, lm.plane("TL5").normal);
    const int piece = centre.piece_containing(exit.centroid);
    ASSERT_GE(piece, 0);
    const double strip = g.wall_thickness * 2.0 * exit.across;
    std::printf("exit rims: TL %.0f, FL %.0f mm^2 (station 5's TL %.0f); centre %.0f mm^2\n",
                tl.area * 1e6, fl.area * 1e6, g.nodes[g.node("TL5")].area * 1e6,
                centre.areas[piece] * 1e6);
    EXPECT_NEAR((tl.area + fl.area + strip) / centre.areas[piece], 1.0, 0.05);
    EXPECT_GT(tl.area, 2.0 * g.nodes[g.node("TL5")].area);
  }
  // Every station node's area is its landmark's section (geometry/sections.hpp).
  for (const char* name : {"AAo", "TL3", "FL3", "DAo_dist"})
    EXPECT_DOUBLE_EQ(g.nodes[g.node(name)].area, geometry::landmark_area(mesh, lm.plane(name)))
        << name;
  // The segments' volumes add up to the fluid's: the sampled sections (five per segment, the
  // branches as cylinders of their caps' area) miss the ostia, the flap's tapered ends and the
  // blind ends of the false lumen beyond its tears, each a few % of the volume, partly
  // cancelling (0.995 measured at 4.5 mm): within 5 %.
  double segments = 0.0, fluid = 0.0;
  for (const rom::GeometrySegment& s : g.segments)
    segments += s.volume;
  const int f = geometry::region_index(mesh, "fluid");
  for (Index t = 0; t < mesh.num_tets(); ++t)
    if (mesh.tet_region[t] == f) {
      const Tet& k = mesh.tets[t];
      fluid += mesh::signed_volume(mesh.points[k[0]], mesh.points[k[1]], mesh.points[k[2]],
                                   mesh.points[k[3]]);
    }
  EXPECT_NEAR(segments / fluid, 1.0, 0.05) << segments << " vs " << fluid;
  std::printf("wall thickness %.3f mm, segment volumes / fluid volume %.3f\n",
              g.wall_thickness * 1e3, segments / fluid);
  // The arch's centreline is longer than its chord (AAo to DAo_prox) and shorter than a
  // detour of three chords.
  double arch = 0.0;
  for (const rom::GeometrySegment& s : g.segments)
    if (s.lumen == "aorta" && s.from != "inlet" && s.to != "outlet" && s.from != "DAo_dist")
      arch += s.length;
  const double chord = std::sqrt(dot(lm.plane("DAo_prox").origin - lm.plane("AAo").origin,
                                     lm.plane("DAo_prox").origin - lm.plane("AAo").origin));
  std::printf("arch %.1f mm, chord %.1f mm\n", arch * 1e3, chord * 1e3);
  EXPECT_GT(arch, 1.2 * chord);
  EXPECT_LT(arch, 3.0 * chord);

  // --- calibrated on OR alone, the model reproduces OR --------------------------------------
  const fs::path or_case = stored_case("OR", model, dir);

  // --- the network's junctions --------------------------------------------------------------
  // The entry divides the aorta's flow and the exit rejoins it (rom/dissection_network.hpp):
  // at both the TL's channel beside the tear is the node's area, and the segment onward carries
  // the head of the flow that arrives there in the channel (the aorta's at the entry, the TL's
  // own at the exit); each tear's loss takes it in series with the channel.
  {
    const rom::RomCoefficients k;
    const rom::RomInputs in = rom::rom_inputs(io::load_case(or_case), g);
    const rom::LumpedNetwork net = rom::build_network(g, in, k);
    auto edge = [&](const std::string& name) -> const rom::NetworkEdge& {
      for (const rom::NetworkEdge& e : net.edges())
        if (e.name == name)
          return e;
      throw std::runtime_error("no edge " + name);
    };
    auto index = [&](const std::string& name) { return &edge(name) - net.edges().data(); };
    const double a_entry = g.tears.at(0).channel_area, a_exit = g.tears.at(1).channel_area;
    EXPECT_DOUBLE_EQ(edge("arch_LSA-DAo_prox").area_to, a_entry);
    EXPECT_DOUBLE_EQ(edge("DAo_prox-TL1").area_from, a_entry);
    EXPECT_EQ(edge("DAo_prox-TL1").regain_edge, index("arch_LSA-DAo_prox"));
    EXPECT_DOUBLE_EQ(edge("TL5-TL_exit").area_to, a_exit);
    EXPECT_DOUBLE_EQ(edge("TL_exit-DAo_dist").area_from, a_exit);
    EXPECT_EQ(edge("TL_exit-DAo_dist").regain_edge, index("TL5-TL_exit"));
    EXPECT_DOUBLE_EQ(edge("TL_exit-DAo_dist").regain, 0.5 * in.density / (a_exit * a_exit));
    for (const rom::GeometryTear& t : g.tears) {
      const double expected = k.tear_loss * 0.5 * in.density *
                              (1.0 / (t.area * t.area) + 1.0 / std::pow(t.channel_area, 2));
      EXPECT_NEAR(edge("tear_" + t.name).loss, expected, 1e-12 * expected) << t.name;
    }
  }

  Result r = run_tearflow("rom calibrate " + model.string() + " --run " +
                          (kData / "OR-rigid").string() + " --case " + or_case.string());
  ASSERT_EQ(r.code, 0) << r.output;
  r = run_tearflow("rom predict -q " + model.string() + " --case " + or_case.string() + " -o " +
                   (dir / "or").string());
  ASSERT_EQ(r.code, 0) << r.output;
  const Stations or3d = stored_stations("OR", g, or_case);
  const Stations or0d = predicted_stations(dir / "or" / "analysis" / "metrics.json");
  for (int k = 0; k < 5; ++k) {
    // The fit's own residual: its weighted rms is ~1 (1 mmHg, 0.5 point).
    EXPECT_NEAR(or0d.fr[k], or3d.fr[k], 1.0) << "station " << k + 1;
    EXPECT_NEAR(or0d.dp[k], or3d.dp[k], 2.0) << "station " << k + 1;
  }

  // --- calibrated on OR alone, the held-out EX (the criterion) and EN ---------------
  // On these 4.5 mm runs (three elements across the true lumen, whose losses are mostly the
  // scheme's there: docs/study.md) FR_FL of both held-out variants meets the criterion with
  // both walls (at worst 2.7 points, rigid EX), and the FSI EX meets it whole (dP 3.8 mmHg off
  // at station 5, 4.6 allowed). dP misses it in the others: rigid EX at stations 4-5 (4.8 and
  // 8.7 mmHg off), rigid EN at station 4 (3.1), FSI EN at stations 3-4 (4.2, 4.2). Those are
  // held to 10 mmHg (rigid EX) and 5 mmHg (their measured errors and the fit's ~1 mmHg
  // residual), so that a regression shows; HeldOutVariantsWithTheTrueLumenResolved checks the
  // criterion where the true lumen is resolved.
  auto held_out = [&](const std::string& kind) {
    for (const std::string variant : {"EN", "EX"}) {
      const fs::path c = stored_case(variant, model, dir, kind);
      const Stations d3 = stored_stations(variant, g, c, kind);
      const Stations d0 = predict_variant(model, variant, c, dir / (kind + "-" + variant));
      const std::string what = kind + " " + variant;
      const double documented = what == "fsi EX" ? 0.0 : what == "rigid EX" ? 10.0 : 5.0;
      for (int k = 0; k < 5; ++k) {
        print_station(d0, d3, k, what);
        EXPECT_NEAR(d0.fr[k], d3.fr[k], 5.0) << what << " station " << k + 1;
        EXPECT_NEAR(d0.dp[k], d3.dp[k], std::max({3.0, 0.2 * std::abs(d3.dp[k]), documented}))
            << what << " station " << k + 1;
      }
      std::fflush(stdout);
    }
  };
  held_out("rigid");
  r = run_tearflow("rom calibrate " + model.string() + " --run " + (kData / "OR-fsi").string() +
                   " --case " + stored_case("OR", model, dir, "fsi").string());
  ASSERT_EQ(r.code, 0) << r.output;
  held_out("fsi");

  // The prediction is a run's folder to `report`: its page has the headline table.
  r = run_tearflow("report -q " + (dir / "rigid-EX").string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir / "rigid-EX" / "analysis" / "report.html"));

  // --- the sweep ----------------------------------------------------------------------------
  r = run_tearflow("rom sweep " + model.string() + " --case " + or_case.string() +
                   " --entry 60:228 --exit 60:228 --steps 3 --mark OR=228:227 --mark EN=62:227 "
                   "-o " +
                   (dir / "sweep").string());
  ASSERT_EQ(r.code, 0) << r.output;
  std::ifstream csv(dir / "sweep" / "sweep.csv");
  std::string header, line;
  std::getline(csv, header);
  EXPECT_NE(header.find("FR_FL1_percent,dP1_peak_systole_mmHg,dP1_end_diastole_mmHg"),
            std::string::npos);
  std::vector<std::vector<double>> rows;
  while (std::getline(csv, line)) {
    std::vector<double> v;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');)
      v.push_back(std::stod(cell));
    rows.push_back(v);
  }
  ASSERT_EQ(rows.size(), 9u);
  // A larger entry tear at a fixed exit sends more flow into the FL, and lowers dP at
  // station 1 (the pressure falls less across the entry).
  for (int j = 0; j < 3; ++j) {
    EXPECT_LT(rows[j][2], rows[3 + j][2]);
    EXPECT_LT(rows[3 + j][2], rows[6 + j][2]);
    EXPECT_GT(rows[j][3], rows[6 + j][3]);
  }
  std::ifstream html_in(dir / "sweep" / "sweep.html");
  const std::string html((std::istreambuf_iterator<char>(html_in)),
                         std::istreambuf_iterator<char>());
  size_t maps = 0;
  for (size_t p = html.find("<svg"); p != std::string::npos; p = html.find("<svg", p + 1))
    ++maps;
  EXPECT_EQ(maps, 5u);
  EXPECT_NE(html.find(">EN</text>"), std::string::npos);

  // --- bad input ----------------------------------------------------------------------------
  auto fails_with = [&](const std::string& args, const std::string& expected) {
    const Result bad = run_tearflow(args);
    EXPECT_NE(bad.code, 0) << args;
    EXPECT_NE(bad.output.find(expected), std::string::npos) << args << "\n" << bad.output;
  };
  fails_with("rom predict " + model.string() + " --case " + or_case.string() +
                 " --tear-area middle=40",
             "no tear 'middle' (its tears: entry, exit)");
  fails_with("rom sweep " + model.string() + " --case " + or_case.string() +
                 " --entry 300:30 --exit 30:300",
             "--entry '300:30': MAX must exceed MIN");
  fails_with("rom sweep " + model.string() + " --case " + or_case.string() +
                 " --entry 30:300 --exit 30:300 --mark EN",
             "--mark 'EN': expected NAME=ENTRY:EXIT");
  fails_with("rom calibrate " + model.string() + " --run " + dir.string() + " --case " +
                 or_case.string(),
             "analysis/inlet.csv: cannot read");
  fails_with("rom calibrate " + model.string() + " --run " + (kData / "OR-rigid").string() +
                 " --case " + or_case.string() + " --fit flap",
             "nothing to fit"); // the flap is not seen by rigid runs
  fails_with("rom calibrate " + model.string() + " --run " + (kData / "OR-rigid").string() +
                 " --case " + or_case.string() + " --fit flaps",
             "--fit");
  fails_with("rom predict " + (dir / "nowhere").string() + " --case " + or_case.string(),
             "mesh.msh: cannot read");
  fs::remove_all(dir);
}

TEST(RomModel, HeldOutVariantsWithTheTrueLumenResolved) {
  // The accuracy test on the rigid study at 3 mm with six elements across the true
  // lumen (results/tbad-3mm-n6-rigid; the built mesh is the runs' own, byte for byte), the
  // sizing at which the lumina's losses have the network's form (docs/rom.md): calibrated on
  // OR alone, the held-out EN and EX; calibrated on OR and one small-tear variant (that tear's
  // size exponent fitted), the other. Measured: OR + EX -> EN 4.5 points and OR + EN -> EX
  // 1.7 points, dP within the criterion. From OR alone, EN's dP and EX's FR_FL are within the
  // criterion (EX 1.2 points); two misses: EN's FR_FL 5.3 points off (50.4 against 55.6 %;
  // OR alone cannot tell how the entry's coefficient changes with its size) and EX's dP at
  // station 4, 4.0 mmHg off (-13.5 against -17.5) where the criterion allows 3.5. They are
  // held to their measured errors and the fit's residual (rms ~0.7 mmHg or 0.35 point): 6
  // points and 5 mmHg, so that a regression shows, and stay in docs/rom.md's table as not met.
  // Between the study's sizes (EN120, EX120: the entry or the exit at 120 mm^2, runs made
  // after the network was settled) OR alone meets the criterion: 2.9 and 0.4 points. Last,
  // the same with the wall: FSI OR alone -> FSI EN and EX, and each from OR and the other.
  const fs::path dir = fresh_dir("rom-3mm-n6");
  const fs::path model = dir / "OR";
  const fs::path data = kData / "3mm-n6";
  const Result built = run_tearflow("geometry tbad --element-size 3 --lumen-elements 6 "
                                    "--variant OR -o " +
                                    model.string());
  ASSERT_EQ(built.code, 0) << built.output;
  const rom::DissectionGeometry g = rom::model_geometry(model, false);
  const fs::path or_case = stored_case("OR", model, dir, "rigid", data);
  const fs::path en_case = stored_case("EN", model, dir, "rigid", data);
  const fs::path ex_case = stored_case("EX", model, dir, "rigid", data);
  const fs::path en120_case = stored_case("EN120", model, dir, "rigid", data);
  const fs::path ex120_case = stored_case("EX120", model, dir, "rigid", data);
  auto calibrate = [&](const std::vector<std::string>& variants, const std::string& kind) {
    std::string args = "rom calibrate " + model.string();
    for (const std::string& v : variants)
      args += " --run " + (data / (v + "-" + kind)).string() + " --case " +
              (dir / (v + "-" + kind + ".yaml")).string();
    for (const std::string& v : variants)
      args += " --run-model " + (v == "OR" ? model : data / (v + "-model")).string();
    fs::remove(model / "rom" / "calibration.json");
    const Result r = run_tearflow(args);
    ASSERT_EQ(r.code, 0) << r.output;
  };
  // The held-out `variant` predicted with the calibration in place, against its 3D stations.
  auto predict_within_criterion = [&](const std::string& variant, const fs::path& case_file,
                                      const Stations& d3, const std::string& out,
                                      const std::string& what, double fr_points = 5.0) {
    const Stations rom = predict_variant(model, variant, case_file, dir / out);
    for (int k = 0; k < 5; ++k)
      expect_within_criterion(rom, d3, k, what, fr_points);
  };
  const Stations en3d = stored_stations("EN", g, en_case, "rigid", data);
  const Stations ex3d = stored_stations("EX", g, ex_case, "rigid", data);
  const Stations en120_3d = stored_stations("EN120", g, en120_case, "rigid", data);
  const Stations ex120_3d = stored_stations("EX120", g, ex120_case, "rigid", data);

  ASSERT_NO_FATAL_FAILURE(calibrate({"OR"}, "rigid"));
  const Stations en = predict_variant(model, "EN", en_case, dir / "en"),
                 ex = predict_variant(model, "EX", ex_case, dir / "ex");
  for (int k = 0; k < 5; ++k) {
    expect_within_criterion(en, en3d, k, "OR -> EN", 6.0);
    if (k != 3) {
      expect_within_criterion(ex, ex3d, k, "OR -> EX");
    } else {
      print_station(ex, ex3d, k, "OR -> EX");
      EXPECT_NEAR(ex.fr[k], ex3d.fr[k], 5.0);
      EXPECT_NEAR(ex.dp[k], ex3d.dp[k], 5.0) << "OR -> EX station 4 (a documented miss)";
    }
  }

  const Stations en120 = predict_variant(model, "EN120", en120_case, dir / "en120"),
                 ex120 = predict_variant(model, "EX120", ex120_case, dir / "ex120");
  for (int k = 0; k < 5; ++k) {
    expect_within_criterion(en120, en120_3d, k, "OR -> EN120");
    expect_within_criterion(ex120, ex120_3d, k, "OR -> EX120");
  }

  ASSERT_NO_FATAL_FAILURE(calibrate({"OR", "EX"}, "rigid"));
  // The fit's bounds hold: alpha >= 1 (Poiseuille's is the least) and the exit's size exponent
  // within (-1, 1) (docs/rom.md, "Calibration").
  const nlohmann::json fit = read_json(model / "rom" / "calibration.json")["rigid"]["coefficients"];
  EXPECT_GE(fit["viscous_factor"].get<double>(), 1.0);
  EXPECT_LT(std::abs(fit["tear_size_exponents"]["exit"].get<double>()), 1.0);
  predict_within_criterion("EN", en_case, en3d, "en-two-sizes", "OR + EX -> EN");

  ASSERT_NO_FATAL_FAILURE(calibrate({"OR", "EN"}, "rigid"));
  predict_within_criterion("EX", ex_case, ex3d, "ex-two-sizes", "OR + EN -> EX");

  // With the wall (results/tbad-3mm-n6-fsi, the same meshes), calibrated on the FSI OR alone
  // (the fit kept before EN ran): the held-out FSI EN's dP within the criterion at every
  // station; its FR_FL 5.8 points off (51.1 against 57.0 %), the rigid runs' miss again (fitted
  // to each run alone the entry's K_t is 2.16 at 228 mm^2 and 1.51 at 62 mm^2, the rigid runs'
  // ratio), held to 6.5 points: the measured error and the fit's residual, as above.
  const fs::path en_fsi_case = stored_case("EN", model, dir, "fsi", data);
  stored_case("OR", model, dir, "fsi", data); // dir/OR-fsi.yaml, which `calibrate` reads
  const Stations en_fsi3d = stored_stations("EN", g, en_fsi_case, "fsi", data);
  ASSERT_NO_FATAL_FAILURE(calibrate({"OR"}, "fsi"));
  predict_within_criterion("EN", en_fsi_case, en_fsi3d, "en-fsi", "FSI OR -> EN", 6.5);
  // FSI EX (run after the fit was kept, as EN), held out from the same fit: within the
  // criterion, FR_FL 1.7 points (58.7 against 60.4 %), dP within 2.9 mmHg (station 5, where
  // 4.6 are allowed).
  const fs::path ex_fsi_case = stored_case("EX", model, dir, "fsi", data);
  const Stations ex_fsi3d = stored_stations("EX", g, ex_fsi_case, "fsi", data);
  predict_within_criterion("EX", ex_fsi_case, ex_fsi3d, "ex-fsi", "FSI OR -> EX");
  // Calibrated on FSI OR and the other small-tear variant, as the rigid runs above: both
  // within the criterion (OR + EX -> EN 3.3 points, OR + EN -> EX 0.1 points; dP within 2.6
  // and 3.4 mmHg, the latter at station 5 where 4.6 are allowed).
  ASSERT_NO_FATAL_FAILURE(calibrate({"OR", "EX"}, "fsi"));
  predict_within_criterion("EN", en_fsi_case, en_fsi3d, "en-fsi-two-sizes", "FSI OR + EX -> EN");
  ASSERT_NO_FATAL_FAILURE(calibrate({"OR", "EN"}, "fsi"));
  predict_within_criterion("EX", ex_fsi_case, ex_fsi3d, "ex-fsi-two-sizes", "FSI OR + EN -> EX");
  fs::remove_all(dir);
}
