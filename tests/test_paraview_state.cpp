// The ParaView state of the flow pictures (issue 30; src/report/paraview_state.*), on the
// pictures' CI-sized two-lumen run (tests/pictures_support.hpp).
//
// In CI (no ParaView): the state is well-formed XML whose every proxy reference resolves,
// whose file names, taken from the state's folder, are the run's files, whose colour maps are
// the pictures' fixed scales and whose cameras look along the pictures' standard views.
// Under `ctest -L paraview` (ParaviewLoad, not in CI): ParaView's own pvbatch loads it, the
// sources hold data, the series has flow.pvd's times, and each view renders a picture. It
// needs pvbatch with the module paraview.simple (Debian: packages paraview and
// python3-paraview; the latter conflicts with python3-vtk9, which libvtk9-dev needs, so it
// may be unpacked aside and found through PYTHONPATH, docs/analysis.md); skipped without.
//
// Tolerances. Cameras: the state's numbers are written in shortest round-trip form, so a
// direction read back is the computed unit vector to rounding (1e-12). The focal point is the
// lumen's box centre; the pipes' boundary nodes lie on their circles, so the box is the
// channel's own within a chord's sag, well under 0.1 mm at 1 mm elements.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <vtkSmartPointer.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLDataParser.h>

#include "analysis/landmark_sections.hpp"
#include "cli_support.hpp"
#include "core/virtual_display.hpp"
#include "pictures_support.hpp"
#include "report/flow_section.hpp"
#include "report/paraview_state.hpp"

namespace tearflow {
namespace {

namespace fs = std::filesystem;
using testing::RunFolder;

/// A state file read back: its proxies by id, and the names the collections give them.
struct State {
  vtkSmartPointer<vtkXMLDataParser> parser;
  std::map<int, vtkXMLDataElement*> proxies;
  std::map<std::string, std::vector<std::pair<int, std::string>>> collections;

  /// A property's values as text (empty when the proxy does not set it).
  std::vector<std::string> values(int id, const std::string& property) const {
    std::vector<std::string> out;
    vtkXMLDataElement* p =
        proxies.at(id)->FindNestedElementWithNameAndAttribute("Property", "name", property.c_str());
    for (int i = 0; p != nullptr && i < p->GetNumberOfNestedElements(); ++i)
      if (std::string(p->GetNestedElement(i)->GetName()) == "Element") {
        const char* v = p->GetNestedElement(i)->GetAttribute("value"); // null when ""
        out.push_back(v != nullptr ? v : "");
      }
    return out;
  }
  std::vector<double> numbers(int id, const std::string& property) const {
    std::vector<double> out;
    for (const std::string& v : values(id, property))
      out.push_back(std::stod(v));
    return out;
  }
  /// The id a collection gives `name`, -1 when none.
  int named(const std::string& collection, const std::string& name) const {
    if (collections.count(collection))
      for (const auto& [id, n] : collections.at(collection))
        if (n == name)
          return id;
    return -1;
  }
  std::vector<int> of(const std::string& group, const std::string& type) const {
    std::vector<int> ids;
    for (const auto& [id, e] : proxies)
      if (group == e->GetAttribute("group") && type == e->GetAttribute("type"))
        ids.push_back(id);
    return ids;
  }
};

/// Parses `xml`; a failure to parse fails the test. Every proxy a property or collection
/// refers to must be in the file.
State read_state(const std::string& xml) {
  State s;
  s.parser = vtkSmartPointer<vtkXMLDataParser>::New();
  std::istringstream in(xml);
  s.parser->SetStream(&in);
  EXPECT_EQ(s.parser->Parse(), 1) << "not well-formed XML";
  vtkXMLDataElement* root = s.parser->GetRootElement();
  if (root == nullptr)
    return s;
  EXPECT_STREQ(root->GetName(), "ParaView");
  vtkXMLDataElement* state = root->FindNestedElementWithName("ServerManagerState");
  EXPECT_NE(state, nullptr);
  if (state == nullptr)
    return s;
  std::vector<int> referenced;
  for (int i = 0; i < state->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* e = state->GetNestedElement(i);
    int id = 0;
    e->GetScalarAttribute("id", id);
    if (std::string(e->GetName()) == "Proxy") {
      EXPECT_EQ(s.proxies.count(id), 0u) << "two proxies with id " << id;
      s.proxies[id] = e;
      for (int j = 0; j < e->GetNumberOfNestedElements(); ++j) {
        vtkXMLDataElement* p = e->GetNestedElement(j);
        for (int k = 0; k < p->GetNumberOfNestedElements(); ++k) {
          int other = 0;
          if (p->GetNestedElement(k)->GetScalarAttribute(
                  std::string(p->GetName()) == "Layout" ? "view" : "value", other) &&
              std::string(p->GetNestedElement(k)->GetName()) != "Element")
            referenced.push_back(other);
        }
      }
    } else if (std::string(e->GetName()) == "ProxyCollection") {
      for (int j = 0; j < e->GetNumberOfNestedElements(); ++j) {
        vtkXMLDataElement* item = e->GetNestedElement(j);
        item->GetScalarAttribute("id", id);
        s.collections[e->GetAttribute("name")].emplace_back(id, item->GetAttribute("name"));
        referenced.push_back(id);
      }
    }
  }
  for (const int id : referenced)
    EXPECT_EQ(s.proxies.count(id), 1u) << "proxy " << id << " is referred to but not in the state";
  return s;
}

Vec3 unit(const Vec3& v) {
  return (1.0 / std::sqrt(dot(v, v))) * v;
}

/// The view named `name`, in a layout of its name, looks from `from` with `up` upward.
void expect_camera(const State& s, const std::string& name, const Vec3& from, const Vec3& up) {
  const int view = s.named("views", name);
  ASSERT_GE(view, 0) << "no view " << name;
  EXPECT_GE(s.named("layouts", name), 0) << "no layout " << name;
  const std::vector<double> p = s.numbers(view, "CameraPosition"),
                            f = s.numbers(view, "CameraFocalPoint"),
                            u = s.numbers(view, "CameraViewUp");
  ASSERT_EQ(p.size(), 3u);
  ASSERT_EQ(f.size(), 3u);
  ASSERT_EQ(u.size(), 3u);
  const Vec3 looking_from = unit(Vec3{p[0] - f[0], p[1] - f[1], p[2] - f[2]});
  const Vec3 expected_from = unit(from), expected_up = unit(up);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(looking_from[k], expected_from[k], 1e-12) << name;
    EXPECT_NEAR(u[k], expected_up[k], 1e-12) << name;
  }
}

/// The colour map of `array` spans [lo, hi] (its first and last control points) and stays so.
void expect_scale(const State& s, const std::string& array, double lo, double hi) {
  const int lut = s.named("lookup_tables", array + ".PVLookupTable");
  ASSERT_GE(lut, 0) << "no colour map for " << array;
  const std::vector<double> points = s.numbers(lut, "RGBPoints"); // (x, r, g, b) each
  ASSERT_GE(points.size(), 8u);
  EXPECT_EQ(points.front(), lo) << array;
  EXPECT_EQ(points[points.size() - 4], hi) << array;
  EXPECT_EQ(s.numbers(lut, "AutomaticRescaleRangeMode"), std::vector<double>{-1}) << array;
}

/// The representation of `source` in `view` colours by `array` through its colour map.
void expect_coloured(const State& s, int view, int source, const std::string& array) {
  const int lut = s.named("lookup_tables", array + ".PVLookupTable");
  int found = 0;
  vtkXMLDataElement* reps = s.proxies.at(view)->FindNestedElementWithNameAndAttribute(
      "Property", "name", "Representations");
  ASSERT_NE(reps, nullptr);
  for (int i = 0; i < reps->GetNumberOfNestedElements(); ++i) {
    int rep = 0;
    reps->GetNestedElement(i)->GetScalarAttribute("value", rep);
    vtkXMLDataElement* in =
        s.proxies.at(rep)->FindNestedElementWithNameAndAttribute("Property", "name", "Input");
    int input = -1;
    if (in != nullptr && in->GetNumberOfNestedElements() == 1)
      in->GetNestedElement(0)->GetScalarAttribute("value", input);
    if (input != source)
      continue;
    ++found;
    const std::vector<std::string> colour = s.values(rep, "ColorArrayName");
    ASSERT_EQ(colour.size(), 5u);
    EXPECT_EQ(colour[4], array);
    vtkXMLDataElement* table =
        s.proxies.at(rep)->FindNestedElementWithNameAndAttribute("Property", "name", "LookupTable");
    ASSERT_NE(table, nullptr);
    int id = 0;
    table->GetNestedElement(0)->GetScalarAttribute("value", id);
    EXPECT_EQ(id, lut);
  }
  EXPECT_EQ(found, 1) << "source " << source << " shown " << found << " times in view " << view;
}

TEST(ParaviewState, IsWellFormedWithThePicturesScalesAndViews) {
  geometry::Landmarks landmarks;
  landmarks.tears.push_back({"entry", {0.01, 0, 0.02}, {0.6, 0.0, 0.8}, {0, 0, 1}});
  report::StateScene scene;
  scene.flow_pvd = "../../../flow.pvd";
  scene.fluid_region = 0;
  scene.displaced = true;
  scene.time = 0.25;
  scene.streamlines = "peak-systole/streamlines.vtp";
  // A landmark's name is the user's: the XML must carry any character.
  scene.planes = {{"AAo", "peak-systole/plane_AAo.vtp", "peak-systole/arrows_AAo.vtp", 0.002},
                  {"a&b\"<c>", "peak-systole/plane_a&b\"<c>.vtp", "x", 0.001}};
  scene.speed_max = 1.2;
  scene.arrow_speed = 0.3;
  scene.bounds = {-0.01, 0.03, -0.02, 0.02, 0.0, 0.2};
  scene.views = report::standard_views(landmarks);
  ASSERT_EQ(scene.views.size(), 3u);
  const State s = read_state(report::paraview_state(scene));

  expect_scale(s, "speed", 0.0, 1.2);
  expect_scale(s, "through_plane_velocity", -1.2, 1.2);
  expect_camera(s, "anterior", {0, -1, 0}, {0, 0, 1});
  expect_camera(s, "left-lateral", {1, 0, 0}, {0, 0, 1});
  // The flap's view: along the tear's normal, up the head's direction off that normal.
  expect_camera(s, "flap", {0.6, 0.0, 0.8}, {-0.48, 0.0, 0.36});
  // Each camera frames the lumen's box as VTK's ResetCamera does for the pictures.
  const int anterior = s.named("views", "anterior");
  const std::vector<double> focal = s.numbers(anterior, "CameraFocalPoint");
  ASSERT_EQ(focal.size(), 3u);
  EXPECT_NEAR(focal[0], 0.01, 1e-15);
  EXPECT_NEAR(focal[1], 0.0, 1e-15);
  EXPECT_NEAR(focal[2], 0.1, 1e-15);
  const double radius = 0.5 * std::sqrt(0.04 * 0.04 + 0.04 * 0.04 + 0.2 * 0.2);
  EXPECT_NEAR(s.numbers(anterior, "CameraPosition")[1], -radius / std::sin(M_PI / 12), 1e-12);

  // The pipeline: the series' fluid cells, moved, then their boundary; the files as given.
  const int flow = s.named("sources", "flow.pvd");
  ASSERT_GE(flow, 0);
  EXPECT_EQ(s.values(flow, "FileName"), std::vector<std::string>{"../../../flow.pvd"});
  const std::vector<int> threshold = s.of("filters", "Threshold");
  ASSERT_EQ(threshold.size(), 1u);
  EXPECT_EQ(s.values(threshold[0], "SelectInputScalars"),
            (std::vector<std::string>{"", "", "", "1", "region"}));
  const std::vector<int> warp = s.of("filters", "WarpVector");
  ASSERT_EQ(warp.size(), 1u);
  EXPECT_EQ(s.values(warp[0], "SelectInputVectors"),
            (std::vector<std::string>{"", "", "", "0", "displacement"}));
  const int odd = s.named("sources", "plane_a&b\"<c>.vtp");
  ASSERT_GE(odd, 0);
  EXPECT_EQ(s.values(odd, "FileName"), std::vector<std::string>{"peak-systole/plane_a&b\"<c>.vtp"});
  // Arrows: an arrow of 1.5 grid steps at arrow_speed.
  const int glyph = s.named("sources", "arrows AAo");
  ASSERT_GE(glyph, 0);
  EXPECT_EQ(s.numbers(glyph, "ScaleFactor"), std::vector<double>{1.5 * 0.002 / 0.3});
  // Coloured as the pictures: streamlines by speed, sections by u.n, in every view.
  const int lines = s.named("sources", "streamlines.vtp");
  const int section = s.named("sources", "plane_AAo.vtp");
  for (const char* view : {"anterior", "left-lateral", "flap"}) {
    expect_coloured(s, s.named("views", view), lines, "speed");
    expect_coloured(s, s.named("views", view), section, "through_plane_velocity");
  }
  // The clock at the pictured frame.
  const std::vector<int> keeper = s.of("misc", "TimeKeeper");
  ASSERT_EQ(keeper.size(), 1u);
  EXPECT_EQ(s.numbers(keeper[0], "Time"), std::vector<double>{0.25});
}

/// The state `tearflow pictures` wrote for `f`, its folder and pictures.json.
struct Written {
  fs::path folder;
  nlohmann::json record;
  std::string xml;
};
Written pictures_state(const RunFolder& f) {
  const testing::Result r =
      testing::run_tearflow(fmt::format("pictures {} --speed-max 0.8 --no-png", f.dir.string()));
  EXPECT_EQ(r.code, 0) << r.output;
  Written w{report::flow_pictures_dir(f.dir), {}, {}};
  w.record = testing::read_json(w.folder / "pictures.json");
  EXPECT_EQ(w.record["paraview_state"], "flow.pvsm");
  std::ifstream in(w.folder / "flow.pvsm");
  w.xml.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return w;
}

TEST(ParaviewState, PicturesWriteTheStateOfTheirFiles) {
  const RunFolder f("paraview-state-pictures");
  const Written w = pictures_state(f);
  const State s = read_state(w.xml);
  // Every file named, from the state's folder, is there, and they are the run's series and
  // the pictured frame's files.
  std::set<fs::path> files;
  for (const auto& [id, proxy] : s.proxies)
    for (const std::string& name : s.values(id, "FileName")) {
      EXPECT_FALSE(fs::path(name).is_absolute()) << name;
      const fs::path file = w.folder / name;
      EXPECT_TRUE(fs::is_regular_file(file)) << name;
      files.insert(fs::weakly_canonical(file));
    }
  const fs::path frame = w.folder / w.record["frames"][0]["folder"].get<std::string>();
  std::set<fs::path> expected = {fs::weakly_canonical(f.dir / "flow.pvd"),
                                 fs::weakly_canonical(frame / "streamlines.vtp")};
  for (const geometry::Landmark& l : f.landmarks.planes) {
    expected.insert(fs::weakly_canonical(frame / ("plane_" + l.name + ".vtp")));
    expected.insert(fs::weakly_canonical(frame / ("arrows_" + l.name + ".vtp")));
  }
  EXPECT_EQ(files, expected);

  expect_scale(s, "speed", 0.0, 0.8);
  expect_scale(s, "through_plane_velocity", -0.8, 0.8);
  // No tears in these landmarks: no flap view.
  expect_camera(s, "anterior", {0, -1, 0}, {0, 0, 1});
  expect_camera(s, "left-lateral", {1, 0, 0}, {0, 0, 1});
  EXPECT_EQ(s.named("views", "flap"), -1);
  // Framing the channel: x from -r_TL to x_FL + r_FL, |y| < r_TL, z along its length.
  const std::vector<double> focal = s.numbers(s.named("views", "anterior"), "CameraFocalPoint");
  const double x0 = -f.run.lumina[0].radius, x1 = f.run.lumina[1].x + f.run.lumina[1].radius;
  EXPECT_NEAR(focal[0], 0.5 * (x0 + x1), 1e-4);
  EXPECT_NEAR(focal[1], 0.0, 1e-4);
  EXPECT_NEAR(focal[2], 0.5 * f.run.length, 1e-9);
  const std::vector<int> keeper = s.of("misc", "TimeKeeper");
  ASSERT_EQ(keeper.size(), 1u);
  EXPECT_EQ(s.numbers(keeper[0], "Time"),
            std::vector<double>{w.record["frames"][0]["time_s"].get<double>()});
}

// What pvbatch reports of a loaded state (argv: state, results JSON, "folder" to load with
// the state's folder as the data directory, "cwd" to load as `paraview --state` started in
// that folder, then screenshots' stem).
constexpr const char* kLoadScript = R"py(
import json, os, sys
try:
    from paraview.simple import *
except ImportError as e:
    json.dump({'no_paraview_simple': str(e)}, open(sys.argv[2], 'w'))
    sys.exit(0)
state, results, mode, stem = sys.argv[1:5]
if mode == 'folder':
    LoadState(state, data_directory=os.path.dirname(state))
else:
    os.chdir(os.path.dirname(state))
    LoadState(state)
keeper = GetTimeKeeper()
out = {'time': keeper.Time, 'time_steps': list(keeper.TimestepValues), 'sources': {},
       'views': [], 'layouts': sorted(name for name, _ in GetLayouts().keys())}
for (name, _), source in GetSources().items():
    source.UpdatePipeline(keeper.Time)
    out['sources'][name] = {'points': source.GetDataInformation().GetNumberOfPoints(),
                            'time_steps': list(getattr(source, 'TimestepValues', None) or [])}
for i, view in enumerate(GetRenderViews()):
    png = '%s_%d.png' % (stem, i)
    SaveScreenshot(png, view, ImageResolution=[600, 700])
    out['views'].append(png)
json.dump(out, open(results, 'w'))
)py";

TEST(ParaviewLoad, PvbatchLoadsTheStateAndRendersItsViews) {
  const char* named = std::getenv("TEARFLOW_PVBATCH");
  const std::string pvbatch = named != nullptr ? named : "pvbatch";
  if (testing::run_command("command -v " + pvbatch).code != 0)
    GTEST_SKIP() << "no " << pvbatch << " (ParaView) on this machine";
  const RunFolder f("paraview-load");
  const Written w = pictures_state(f);
  const fs::path script = f.dir / "load_state.py";
  std::ofstream(script) << kLoadScript;
  ensure_display("pvbatch"); // Debian's ParaView renders through X even off-screen
  const std::vector<double> times = [&] {
    std::vector<double> t;
    for (const analysis::FlowFrame& frame : analysis::read_pvd(f.dir / "flow.pvd"))
      t.push_back(frame.time);
    return t;
  }();
  const nlohmann::json& peak = w.record["frames"][0];
  for (const char* mode : {"folder", "cwd"}) {
    SCOPED_TRACE(mode);
    const fs::path results = f.dir / fmt::format("loaded_{}.json", mode);
    const testing::Result r = testing::run_command(
        fmt::format("cd / && timeout 300 {} {} {} {} {} {}", pvbatch, script.string(),
                    (w.folder / "flow.pvsm").string(), results.string(), mode,
                    (f.dir / fmt::format("view_{}", mode)).string()));
    ASSERT_EQ(r.code, 0) << r.output;
    ASSERT_TRUE(fs::exists(results)) << r.output;
    const nlohmann::json loaded = testing::read_json(results);
    if (loaded.contains("no_paraview_simple"))
      GTEST_SKIP() << "pvbatch has no paraview.simple (" << loaded["no_paraview_simple"]
                   << "): install python3-paraview, or unpack it and set PYTHONPATH";
    // ParaView reports unreadable files on its error stream but carries on: none here.
    EXPECT_EQ(r.output.find("ERR|"), std::string::npos) << r.output;
    const nlohmann::json& sources = loaded["sources"];
    EXPECT_EQ(sources["flow.pvd"]["time_steps"].get<std::vector<double>>(), times);
    EXPECT_EQ(loaded["time_steps"].get<std::vector<double>>(), times);
    EXPECT_EQ(loaded["time"].get<double>(), peak["time_s"].get<double>());
    EXPECT_EQ(sources["streamlines.vtp"]["points"], peak["streamlines"]["points"]);
    EXPECT_GT(sources["streamlines.vtp"]["points"].get<long>(), 0);
    EXPECT_GT(sources["lumen"]["points"].get<long>(), 0);
    for (const geometry::Landmark& l : f.landmarks.planes) {
      EXPECT_GT(sources["plane_" + l.name + ".vtp"]["points"].get<long>(), 0) << l.name;
      EXPECT_GT(sources["arrows " + l.name]["points"].get<long>(), 0) << l.name;
    }
    EXPECT_EQ(loaded["layouts"], nlohmann::json({"anterior", "left-lateral"}));
    ASSERT_EQ(loaded["views"].size(), 2u);
    for (const std::string png : loaded["views"]) {
      ASSERT_TRUE(fs::is_regular_file(png)) << png;
      // The lumen, streamlines and scalar bars fill a good part of the picture.
      EXPECT_GT(testing::drawn_fraction(png), 0.03) << png;
    }
  }
}

} // namespace
} // namespace tearflow
