#include "report/paraview_state.hpp"

#include <cmath>
#include <utility>

#include <fmt/format.h>

#include "analysis/flow_features.hpp"
#include "report/report.hpp"

namespace tearflow::report {

namespace {

// The lumen's colour (flow_pictures.cpp); the scalar bars' titles are the pictures' own.
const std::vector<double> kLumenColour{0.75, 0.6, 0.55};
constexpr double kLumenOpacity = 0.12;
// VTK's and ParaView's default view angle [deg], which the pictures' cameras keep.
constexpr double kViewAngle = 30.0;

Vec3 unit(const Vec3& v) {
  return (1.0 / std::sqrt(dot(v, v))) * v;
}

/// One property of a proxy: values (`elements`), or other proxies of the state (`proxies`),
/// an input being a proxy's first output port.
struct Property {
  std::string name;
  std::vector<std::string> elements = {};
  std::vector<int> proxies = {};
  bool input = false;
};

Property text(std::string name, std::string value) {
  return {std::move(name), {std::move(value)}};
}

Property numbers(std::string name, const std::vector<double>& values) {
  Property p{std::move(name)};
  for (const double v : values)
    p.elements.push_back(fmt::format("{}", v)); // shortest text that reads back the same
  return p;
}

Property proxies(std::string name, std::vector<int> ids) {
  return {std::move(name), {}, std::move(ids)};
}

Property input(int id) {
  return {"Input", {}, {id}, true};
}

/// An array selection as ParaView stores it: its association (0 points, 1 cells) and name.
Property array(std::string name, int association, const std::string& array) {
  return {std::move(name), {"", "", "", std::to_string(association), array}};
}
constexpr int kPoints = 0, kCells = 1;

/// The state being written: proxies in order, then the collections that name them (the
/// pipeline browser's names, the layouts' tab titles).
class StateXml {
public:
  /// Appends a proxy; returns its id, the file's own (ParaView gives the proxies new ones).
  int proxy(const std::string& group, const std::string& type,
            const std::vector<Property>& properties) {
    const int id = next_id_++;
    proxies_ += fmt::format("    <Proxy group=\"{}\" type=\"{}\" id=\"{}\" servers=\"{}\">\n",
                            group, type, id, servers(group));
    for (const Property& p : properties) {
      const std::size_t n = p.elements.size() + p.proxies.size();
      proxies_ +=
          fmt::format("      <Property name=\"{}\" id=\"{}.{}\" number_of_elements=\"{}\">\n",
                      p.name, id, p.name, n);
      for (std::size_t i = 0; i < p.elements.size(); ++i)
        proxies_ += fmt::format("        <Element index=\"{}\" value=\"{}\"/>\n", i,
                                escape_html(p.elements[i]));
      for (const int other : p.proxies)
        proxies_ += p.input
                        ? fmt::format("        <Proxy value=\"{}\" output_port=\"0\"/>\n", other)
                        : fmt::format("        <Proxy value=\"{}\"/>\n", other);
      proxies_ += "      </Property>\n";
    }
    proxies_ += "    </Proxy>\n";
    return id;
  }

  /// A layout (a tab in ParaView's window) holding one view.
  int layout(int view) {
    const int id = next_id_++;
    proxies_ +=
        fmt::format("    <Proxy group=\"misc\" type=\"ViewLayout\" id=\"{}\" servers=\"20\">\n"
                    "      <Layout number_of_elements=\"1\">\n"
                    "        <Item direction=\"0\" fraction=\"0.5\" view=\"{}\"/>\n"
                    "      </Layout>\n"
                    "    </Proxy>\n",
                    id, view);
    return id;
  }

  void name(const std::string& collection, int id, const std::string& name) {
    for (auto& [c, items] : collections_)
      if (c == collection) {
        items.emplace_back(id, name);
        return;
      }
    collections_.push_back({collection, {{id, name}}});
  }

  std::string text() const {
    std::string out = "<?xml version=\"1.0\"?>\n"
                      "<ParaView>\n"
                      "  <ServerManagerState version=\"5.11.0\">\n" +
                      proxies_;
    for (const auto& [collection, items] : collections_) {
      out += fmt::format("    <ProxyCollection name=\"{}\">\n", collection);
      for (const auto& [id, name] : items)
        out += fmt::format("      <Item id=\"{}\" name=\"{}\"/>\n", id, escape_html(name));
      out += "    </ProxyCollection>\n";
    }
    return out + "  </ServerManagerState>\n</ParaView>\n";
  }

private:
  /// Where ParaView keeps a proxy of `group` (1 data server, 16 client, 21 client and render
  /// server), as its own state files say.
  static int servers(const std::string& group) {
    if (group == "sources" || group == "filters")
      return 1;
    if (group == "animation" || group == "misc")
      return 16;
    return 21;
  }

  std::string proxies_;
  std::vector<std::pair<std::string, std::vector<std::pair<int, std::string>>>> collections_;
  int next_id_ = 1;
};

/// A source or filter, under `name` in the pipeline browser.
int pipeline(StateXml& x, const std::string& group, const std::string& type,
             const std::vector<Property>& properties, const std::string& name) {
  const int id = x.proxy(group, type, properties);
  x.name("sources", id, name);
  return id;
}

int vtp_reader(StateXml& x, const std::string& file) {
  const std::string name = file.substr(file.find_last_of('/') + 1);
  return pipeline(x, "sources", "XMLPolyDataReader", {text("FileName", file)}, name);
}

/// A colour map fixed to its range: ParaView must not rescale it to the data (the pictures'
/// scales are the same for every run and frame, so that they compare).
int colour_map(StateXml& x, const std::string& array, const std::vector<double>& rgb_points,
               int colour_space) {
  const int id = x.proxy(
      "lookup_tables", "PVLookupTable",
      {numbers("RGBPoints", rgb_points), numbers("ColorSpace", {static_cast<double>(colour_space)}),
       numbers("HSVWrap", {0}), numbers("AutomaticRescaleRangeMode", {-1}), // "Never"
       numbers("ScalarRangeInitialized", {1})});
  // ParaView finds an array's colour map by this name: colouring anything else by the same
  // array reuses it.
  x.name("lookup_tables", id, array + ".PVLookupTable");
  return id;
}

/// A scalar bar in a corner of a view (ParaView places it to fit its labels there).
int scalar_bar(StateXml& x, int lookup_table, const std::string& title, int corner) {
  const int id = x.proxy("representations", "ScalarBarWidgetRepresentation",
                         {proxies("LookupTable", {lookup_table}), text("Title", title),
                          text("ComponentTitle", ""), numbers("WindowLocation", {double(corner)}),
                          numbers("TitleColor", {0, 0, 0}), numbers("LabelColor", {0, 0, 0}),
                          text("RangeLabelFormat", "%.2g"), numbers("Visibility", {1})});
  x.name("scalar_bars", id, title);
  return id;
}
constexpr int kLowerRight = 2, kUpperRight = 5; // ParaView's WindowLocation values

int representation(StateXml& x, int source, const std::vector<Property>& properties) {
  std::vector<Property> all = {input(source)};
  all.insert(all.end(), properties.begin(), properties.end());
  const int id = x.proxy("representations", "GeometryRepresentation", all);
  x.name("representations", id, fmt::format("representation{}", id));
  return id;
}

std::vector<double> components(const Vec3& v) {
  return {v[0], v[1], v[2]};
}

} // namespace

Camera picture_camera(const View& view, const std::array<double, 6>& bounds) {
  const Vec3 centre{0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]),
                    0.5 * (bounds[4] + bounds[5])};
  const Vec3 diagonal{bounds[1] - bounds[0], bounds[3] - bounds[2], bounds[5] - bounds[4]};
  double radius = 0.5 * std::sqrt(dot(diagonal, diagonal));
  if (radius == 0.0)
    radius = 1.0; // as VTK does for an empty box
  const double distance = radius / std::sin(0.5 * kViewAngle * M_PI / 180.0);
  return {centre + distance * unit(view.from), centre, unit(view.up), radius};
}

std::string paraview_state(const StateScene& s) {
  StateXml x;
  // The series and the lumen: the fluid's cells (an FSI run's wall left out), moved by the
  // mesh's displacement when it moves, and their boundary, as the pictures draw it.
  const int flow = pipeline(x, "sources", "PVDReader", {text("FileName", s.flow_pvd)},
                            s.flow_pvd.substr(s.flow_pvd.find_last_of('/') + 1));
  int fluid = flow;
  if (s.fluid_region) {
    const double r = static_cast<double>(*s.fluid_region);
    fluid = pipeline(x, "filters", "Threshold",
                     {input(fluid), array("SelectInputScalars", kCells, "region"),
                      numbers("LowerThreshold", {r}), numbers("UpperThreshold", {r})},
                     "fluid");
  }
  if (s.displaced)
    fluid = pipeline(x, "filters", "WarpVector",
                     {input(fluid), array("SelectInputVectors", kPoints, "displacement")},
                     "moved fluid");
  const int lumen = pipeline(x, "filters", "DataSetSurfaceFilter", {input(fluid)}, "lumen");

  // The pictured frame's files; the arrows as glyphs scaled as in the plane maps (an arrow of
  // 1.5 grid steps at arrow_speed).
  const int lines = vtp_reader(x, s.streamlines);
  std::vector<std::pair<int, int>> planes; // section, arrows
  for (const StatePlane& p : s.planes) {
    const int section = vtp_reader(x, p.section);
    const int grid = vtp_reader(x, p.arrows);
    const int arrow = x.proxy("sources", "ArrowSource", {});
    const int arrows = pipeline(x, "filters", "Glyph",
                                {input(grid), proxies("Source", {arrow}),
                                 array("OrientationArray", kPoints, analysis::kInPlaneArray),
                                 array("ScaleArray", kPoints, analysis::kInPlaneArray),
                                 numbers("ScaleFactor", {1.5 * p.arrow_spacing / s.arrow_speed}),
                                 numbers("GlyphMode", {0})}, // every point
                                "arrows " + p.name);
    // The glyph's choice of shapes lists its source under this name.
    x.name(fmt::format("pq_helper_proxies.{}", arrows), arrow, "Source");
    planes.emplace_back(section, arrows);
  }

  // The pictures' colour maps: speed blue to red through the rainbow (hue 0.667 to 0, as
  // flow_pictures.cpp's table), u.n blue - white - red in RGB.
  const double v = s.speed_max;
  const int speed = colour_map(x, analysis::kSpeedArray, {0, 0, 0, 1, v, 1, 0, 0}, 1 /* HSV */);
  const int through_plane = colour_map(x, analysis::kThroughPlaneArray,
                                       {-v, 0, 0, 1, 0, 1, 1, 1, v, 1, 0, 0}, 0 /* RGB */);

  // One view per standard view, each in a layout of its own: a representation belongs to one
  // view, so every view has its own.
  std::vector<int> views;
  for (const View& view : s.views) {
    std::vector<int> shown = {
        representation(x, lumen,
                       {numbers("DiffuseColor", kLumenColour),
                        numbers("AmbientColor", kLumenColour),
                        numbers("Opacity", {kLumenOpacity})}),
        representation(x, lines,
                       {array("ColorArrayName", kPoints, analysis::kSpeedArray),
                        proxies("LookupTable", {speed}), numbers("LineWidth", {2})})};
    for (const auto& [section, arrows] : planes) {
      shown.push_back(
          representation(x, section,
                         {array("ColorArrayName", kPoints, analysis::kThroughPlaneArray),
                          proxies("LookupTable", {through_plane})}));
      shown.push_back(representation(
          x, arrows, {numbers("DiffuseColor", {0, 0, 0}), numbers("AmbientColor", {0, 0, 0})}));
    }
    shown.push_back(scalar_bar(x, speed, kSpeedTitle, kLowerRight));
    shown.push_back(scalar_bar(x, through_plane, kThroughPlaneTitle, kUpperRight));
    const Camera c = picture_camera(view, s.bounds);
    const int id = x.proxy(
        "views", "RenderView",
        {proxies("Representations", shown), numbers("UseColorPaletteForBackground", {0}),
         numbers("Background", {1, 1, 1}), numbers("CameraPosition", components(c.position)),
         numbers("CameraFocalPoint", components(c.focal_point)),
         numbers("CameraViewUp", components(c.up)),
         numbers("CameraParallelScale", {c.parallel_scale}),
         numbers("CenterOfRotation", components(c.focal_point)), numbers("ViewTime", {s.time})});
    x.name("views", id, view.name);
    x.name("layouts", x.layout(id), view.name);
    views.push_back(id);
  }

  // The clock at the pictured frame, stepping through the series' own times; ParaView's
  // session has one time keeper and one animation scene, which these update.
  const int time_keeper =
      x.proxy("misc", "TimeKeeper",
              {numbers("Time", {s.time}), proxies("TimeSources", {flow}), proxies("Views", views)});
  x.name("timekeeper", time_keeper, "TimeKeeper1");
  const int cue = x.proxy("animation", "TimeAnimationCue",
                          {proxies("AnimatedProxy", {time_keeper}),
                           text("AnimatedPropertyName", "Time"), numbers("UseAnimationTime", {1})});
  const int scene = x.proxy("animation", "AnimationScene",
                            {numbers("AnimationTime", {s.time}), proxies("Cues", {cue}),
                             proxies("TimeKeeper", {time_keeper}), proxies("ViewModules", views),
                             numbers("PlayMode", {2})}); // "Snap To TimeSteps"
  x.name("animation", scene, "AnimationScene1");
  x.name("animation", cue, "TimeAnimationCue1");
  return x.text();
}

} // namespace tearflow::report
