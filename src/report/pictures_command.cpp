#include "report/pictures_command.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <vtkAbstractCellLocator.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkUnstructuredGrid.h>

#include "analysis/flow_features.hpp"
#include "core/error.hpp"
#include "core/file_layout.hpp"
#include "core/units.hpp"
#include "geometry/fsi_mesh.hpp"
#include "geometry/geometry_report.hpp"
#include "io/durable_file.hpp"
#include "io/vtu_series.hpp"
#include "report/cycle_animation.hpp"
#include "report/flow_pictures.hpp"
#include "report/paraview_state.hpp"
#include "report/scan_pictures.hpp"

namespace tearflow::report {

namespace {

using nlohmann::json;
namespace fs = std::filesystem;

constexpr const char* kParaviewState = "flow.pvsm";

/// A folder name for a frame: "peak-systole", "mid-diastole", "t-0.25s".
std::string folder_of(const analysis::PictureFrame& f) {
  if (f.event == "peak systole")
    return "peak-systole";
  if (f.event == "mid-diastole")
    return "mid-diastole";
  return fmt::format("t-{}s", f.frame.time);
}

/// The landmark streamlines start from: the option's, else inlet, else AAo, else the first.
const geometry::Landmark& seed_landmark(const geometry::Landmarks& landmarks,
                                        const std::string& name) {
  if (!name.empty()) {
    std::string known;
    for (const geometry::Landmark& l : landmarks.planes) {
      if (l.name == name)
        return l;
      known += " " + l.name;
    }
    input_error("pictures: --seed {}: no such landmark; the planes are:{}", name, known);
  }
  for (const char* preferred : {"inlet", "AAo"})
    for (const geometry::Landmark& l : landmarks.planes)
      if (l.name == preferred)
        return l;
  if (landmarks.planes.empty())
    input_error("pictures: the landmarks hold no plane to seed streamlines on");
  return landmarks.planes.front();
}

/// The in-plane (secondary) flow is a fraction of the through-plane one: its arrows (an
/// arrow of 1.5 grid steps) are scaled on a quarter of the speed scale, stated on the picture.
double in_plane_arrow_speed(const PicturesOptions& o) {
  return o.speed_max / 4;
}

/// The views asked for (`--view`): standard ones by name, or NAME:X,Y,Z a camera from the
/// direction (X, Y, Z) (model axes; up the head's direction, +z, as far as it is not the
/// viewing one); none asked: the standard ones.
std::vector<View> chosen_views(const std::vector<View>& standard,
                               const std::vector<std::string>& asked) {
  if (asked.empty())
    return standard;
  std::vector<View> views;
  for (const std::string& spec : asked) {
    const std::size_t colon = spec.find(':');
    if (colon == std::string::npos) {
      const auto v = std::find_if(standard.begin(), standard.end(),
                                  [&](const View& x) { return x.name == spec; });
      if (v == standard.end()) {
        std::string known;
        for (const View& x : standard)
          known += " " + x.name;
        input_error("pictures: --view {}: no such view; the standard ones here are:{} (or "
                    "NAME:X,Y,Z for a camera from the direction X, Y, Z)",
                    spec, known);
      }
      views.push_back(*v);
      continue;
    }
    Vec3 from{};
    char end = 0;
    const std::string name = spec.substr(0, colon);
    if (name.empty() || name.find_first_of("/\\ ") != std::string::npos ||
        std::sscanf(spec.c_str() + colon + 1, "%lf,%lf,%lf%c", &from[0], &from[1], &from[2],
                    &end) != 3 ||
        !(dot(from, from) > 0) || !std::isfinite(dot(from, from)))
      input_error("pictures: --view {}: expected NAME:X,Y,Z (a file-name-safe name, and a "
                  "non-zero direction from the model toward the camera, e.g. posterior:0,1,0)",
                  spec);
    from = (1.0 / std::sqrt(dot(from, from))) * from;
    Vec3 up = Vec3{0, 0, 1} - from[2] * from;
    if (dot(up, up) < 1e-6)
      up = Vec3{0, 1, 0} - from[1] * from;
    views.push_back({name, from, (1.0 / std::sqrt(dot(up, up))) * up});
  }
  return views;
}

/// A picture's entry in pictures.json: its file and the scale its scalar bar shows.
json picture_json(const Picture& p) {
  json j = {{"file", p.file.filename().string()},
            {"scale_title", p.scale_title},
            {"scale_range", {p.scale_min, p.scale_max}}};
  if (p.plane) // where each pixel lies (flow_pictures.hpp, PlaneView)
    j["plane_view"] = {{"centre_m", p.plane->centre},
                       {"right", p.plane->right},
                       {"up", p.plane->up},
                       {"half_height_m", p.plane->half_height},
                       {"map_pixels", {p.model_width, p.model_height}}};
  return j;
}

/// The planes of one picture: a paired station's TL and FL together, others alone; each with
/// the view the run's sections set, shared by the scan's picture of the same plane.
struct PlaneGroup {
  std::string name; ///< "station1", "AAo"
  std::vector<std::string> landmarks;
  std::optional<PlaneView> view;
};

/// Which landmarks share a picture, in the landmarks' order.
std::vector<PlaneGroup> plane_groups(const geometry::Landmarks& landmarks) {
  std::vector<PlaneGroup> groups;
  for (const geometry::Landmark& l : landmarks.planes) {
    const int k = analysis::station_of(l);
    const std::string name = k > 0 ? fmt::format("station{}", k) : l.name;
    auto g = std::find_if(groups.begin(), groups.end(),
                          [&](const PlaneGroup& x) { return x.name == name; });
    if (g == groups.end())
      g = groups.insert(groups.end(), PlaneGroup{name, {}, std::nullopt});
    g->landmarks.push_back(l.name);
  }
  return groups;
}

/// One field's plane maps of a frame: a VTP pair per landmark (`prefix` ahead of each file
/// name) and a PNG per group. The run's maps (`scan` false) set each group's view and the
/// arrows' spacing per landmark; the scan's use them, and a landmark whose section the scan's
/// lumen does not hold is listed under "not_in_scan" (with the reason) instead of failing the
/// whole picture.
json plane_maps(vtkUnstructuredGrid* fluid, const geometry::Landmarks& landmarks,
                const std::string& frame, const std::string& caption_head, const PicturesOptions& o,
                const fs::path& dir, const std::string& prefix, bool scan,
                std::vector<PlaneGroup>& groups, std::map<std::string, double>& spacing,
                json& pictures) {
  std::map<std::string, analysis::PlaneMap> maps;
  json out = json::object();
  const auto locator = analysis::fluid_locator(fluid); // one for all the planes
  for (const geometry::Landmark& l : landmarks.planes) {
    try {
      maps[l.name] = analysis::plane_map(fluid, l, scan ? spacing.at(l.name) : 0.0, frame, locator);
    } catch (const InputError& e) {
      if (!scan)
        throw;
      out["not_in_scan"][l.name] = e.what();
      continue;
    }
    const analysis::PlaneMap& m = maps[l.name];
    spacing[l.name] = m.vector_spacing;
    analysis::write_vtp(m.section, dir / (prefix + "plane_" + l.name + ".vtp"));
    analysis::write_vtp(m.vectors, dir / (prefix + "arrows_" + l.name + ".vtp"));
    out[l.name] = {{"section", prefix + "plane_" + l.name + ".vtp"},
                   {"arrows", prefix + "arrows_" + l.name + ".vtp"},
                   {"lumen", l.lumen},
                   {"area_m2", m.area},
                   {"flow_m3_per_s", m.flow},
                   {"mean_through_plane_velocity_m_per_s", m.flow / m.area},
                   {"arrow_spacing_m", m.vector_spacing}};
  }
  if (!o.png)
    return out;
  const ColourScale scale = through_plane_scale(o.speed_max);
  const double arrow_speed = in_plane_arrow_speed(o);
  for (PlaneGroup& g : groups) {
    std::vector<const analysis::PlaneMap*> drawn;
    for (const std::string& name : g.landmarks)
      if (maps.count(name))
        drawn.push_back(&maps.at(name));
    if (drawn.empty())
      continue;
    if (!g.view)
      g.view = plane_view(drawn, kPlaneMapSize);
    const Picture p =
        render_plane_map(drawn, scale, arrow_speed,
                         fmt::format("{}{}; arrows: 1.5 grid steps = {} m/s in plane", caption_head,
                                     g.name, arrow_speed),
                         dir / (prefix + "plane_" + g.name + ".png"), kPlaneMapSize, g.view);
    pictures.push_back(picture_json(p));
  }
  return out;
}

/// A moving wall's flap at each paired station: the TLk and FLk sections' rims at the frame
/// pictured (`fluid`, peak systole) over those at end diastole (the cycle's first frame, as
/// `analyze` takes it), thick over thin, in the plane maps' views: flap_station<k>.png.
json flap_position(vtkUnstructuredGrid* fluid, const analysis::PictureFrame& f,
                   const analysis::FlowFrame& end_diastole, const geometry::Landmarks& landmarks,
                   const std::vector<PlaneGroup>& groups, const fs::path& dir, json& pictures) {
  const auto before = analysis::read_flow_frame(end_diastole.file);
  json out = {{"end_diastole_time_s", end_diastole.time}, {"stations", json::object()}};
  for (const PlaneGroup& g : groups) {
    if (g.landmarks.size() < 2 || !g.view) // a paired station, drawn in the plane maps
      continue;
    std::vector<vtkSmartPointer<vtkPolyData>> sections; // kept alive for the outlines
    std::vector<Outline> outlines;
    json station = json::object();
    for (const std::string& name : g.landmarks) {
      const geometry::Landmark& l = landmarks.plane(name);
      const auto late = analysis::lumen_section(before, l, end_diastole.file.string());
      const auto now = analysis::lumen_section(fluid, l, f.frame.file.string());
      sections.insert(sections.end(), {late, now});
      outlines.push_back({late, lumen_colour(l.lumen, true), 2.0});
      outlines.push_back({now, lumen_colour(l.lumen), 3.0});
      station[name] = {{"area_m2", analysis::area_and_flow(now).first},
                       {"area_end_diastole_m2", analysis::area_and_flow(late).first}};
    }
    const Picture p = render_outlines(
        outlines,
        fmt::format("{}, the flap; thick: {} (t = {} s); thin: end diastole (t = {} s)", g.name,
                    f.event, f.frame.time, end_diastole.time),
        dir / ("flap_" + g.name + ".png"), *g.view);
    pictures.push_back(picture_json(p));
    out["stations"][g.name] = station;
  }
  return out;
}

/// The ParaView state's scene (paraview_state.hpp): the run's series and the first frame's
/// files (`entry`, its record in pictures.json), named from the state's folder `out`, and its
/// lumen `fluid`, which the cameras frame.
StateScene state_scene(const RunFiles& run, const fs::path& out, const json& entry,
                       vtkUnstructuredGrid* fluid, const std::vector<View>& views,
                       const PicturesOptions& o) {
  StateScene s;
  s.flow_pvd = fs::relative(run.flow_pvd(), out).generic_string();
  if (vtkDataArray* region = fluid->GetCellData()->GetArray(io::kRegionArray);
      region != nullptr && region->GetNumberOfTuples() > 0)
    s.fluid_region = static_cast<long>(region->GetTuple1(0)); // the fluid's cells only
  s.displaced = fluid->GetPointData()->GetArray("displacement") != nullptr;
  s.time = entry["time_s"];
  const fs::path folder = entry["folder"].get<std::string>();
  s.streamlines = (folder / entry["streamlines"]["file"].get<std::string>()).generic_string();
  for (const auto& [name, plane] : entry["planes"].items())
    s.planes.push_back({name, (folder / plane["section"].get<std::string>()).generic_string(),
                        (folder / plane["arrows"].get<std::string>()).generic_string(),
                        plane["arrow_spacing_m"]});
  s.speed_max = o.speed_max;
  s.arrow_speed = in_plane_arrow_speed(o);
  fluid->GetBounds(s.bounds.data());
  s.views = views;
  return s;
}

/// The scan's pictures of the run frame of `event` (none when the scan has no such frame):
/// streamlines from the run's `seeds` (when given) in the run's camera (`bounds` its lumen's),
/// and the plane maps in the run's views and arrow spacing; files prefixed "mri_".
json scan_frame(const ScanPictures& scan, const std::string& event, vtkPolyData* seeds,
                const double* bounds, const geometry::Landmarks& landmarks,
                const std::vector<View>& views, const PicturesOptions& o, const fs::path& dir,
                std::vector<PlaneGroup>& groups, std::map<std::string, double>& spacing) {
  const std::optional<std::size_t> k = scan.frame_of(event);
  if (!k)
    return {{"event", event}, {"frame", nullptr}, {"why", "the scan's flow has no such frame"}};
  const double t = scan.time_of(*k);
  const std::string name = fmt::format("scan frame {} ({} s after the trigger)", *k, t);
  const auto field = scan.field(*k);
  json pictures = json::array();
  json entry = {{"event", event}, {"frame", *k}, {"time_after_trigger_s", t}};
  if (seeds != nullptr) {
    analysis::StreamlineOptions so;
    const auto lines = analysis::trace_streamlines(field, seeds, so);
    analysis::write_vtp(lines, dir / "mri_streamlines.vtp");
    entry["streamlines"] = {{"file", "mri_streamlines.vtp"},
                            {"seeds", seeds->GetNumberOfPoints()},
                            {"lines", lines->GetNumberOfLines()},
                            {"points", lines->GetNumberOfPoints()}};
    if (o.png)
      for (const Picture& p :
           render_streamlines(lines, boundary_surface(field), views, speed_scale(o.speed_max),
                              fmt::format("4D-flow MRI: streamlines, {}, {}", event, name), dir,
                              "mri_streamlines", {}, bounds))
        pictures.push_back(picture_json(p));
  }
  entry["planes"] = plane_maps(field, landmarks, name, fmt::format("4D-flow MRI, {}, ", event), o,
                               dir, "mri_", true, groups, spacing, pictures);
  entry["pictures"] = pictures;
  if (!o.quiet)
    fmt::print("  scan: {}, {} pictures\n", name, pictures.size());
  return entry;
}

/// The model's picture (geometry/render.cpp: faces, tears and landmark planes named) when
/// the landmarks' folder holds its mesh: model.png in `out`; else the record says why.
json model_picture(const fs::path& model_dir, const geometry::Landmarks& landmarks,
                   const PicturesOptions& o, const fs::path& out) {
  const GeometryFiles model{model_dir};
  if (!o.png)
    return {{"file", nullptr}, {"why", "--no-png"}};
  if (!fs::exists(model.mesh())) {
    if (!o.quiet)
      fmt::print("no model picture: '{}' does not exist\n", model.mesh().string());
    return {{"file", nullptr}, {"why", fmt::format("no mesh '{}'", model.mesh().string())}};
  }
  // The geometry folders' meshes are in mm (docs/geometry.md).
  geometry::render_geometry(geometry::read_fsi_mesh(model.mesh(), units::mm), landmarks,
                            out / "model.png");
  return {{"file", "model.png"}, {"mesh", model.mesh().string()}};
}

} // namespace

int make_pictures(const PicturesOptions& o) {
  const RunFiles run{o.run_dir};
  if (!fs::is_directory(o.run_dir))
    input_error("pictures: run folder '{}' does not exist", o.run_dir);
  if (!fs::exists(run.flow_pvd()))
    input_error("pictures: '{}' does not exist (is '{}' a run's output directory?)",
                run.flow_pvd().string(), o.run_dir);
  if (!(o.speed_max > 0))
    input_error("pictures: --speed-max must be > 0 m/s (got {})", o.speed_max);
  const fs::path landmarks_file = !o.landmarks.empty()   ? fs::path(o.landmarks)
                                  : !o.model_dir.empty() ? GeometryFiles{o.model_dir}.landmarks()
                                                         : run.geometry().landmarks();
  if (!fs::exists(landmarks_file))
    input_error("pictures: landmarks '{}' do not exist (give the model's folder with --model "
                "or the file with --landmarks)",
                landmarks_file.string());
  const geometry::Landmarks landmarks = geometry::read_landmarks(landmarks_file);
  const geometry::Landmark& seed = seed_landmark(landmarks, o.seed);
  const fs::path out =
      o.output.empty() ? run.analysis_dir() / "figures" / "flow" : fs::path(o.output);

  // The frames: the one asked for, else peak systole for everything and mid-diastole for the
  // plane maps.
  std::vector<analysis::PictureFrame> frames;
  std::optional<analysis::CycleFrames> cycle;
  if (o.time < 0 || o.animate)
    cycle = analysis::cycle_frames(o.run_dir, landmarks);
  if (o.time >= 0) {
    frames.push_back(analysis::frame_at(o.run_dir, o.time));
  } else {
    frames.push_back(cycle->peak_systole);
    if (cycle->mid_diastole)
      frames.push_back(*cycle->mid_diastole);
  }
  const std::vector<View> views = chosen_views(standard_views(landmarks), o.views);
  json record = {{"run", o.run_dir},
                 {"landmarks", landmarks_file.string()},
                 {"seed_landmark", seed.name},
                 {"colour_scales",
                  {{"speed_m_per_s", {0.0, o.speed_max}},
                   {"through_plane_velocity_m_per_s", {-o.speed_max, o.speed_max}},
                   {"displacement_mm", {0.0, o.displacement_max / units::mm}},
                   {"in_plane_arrow_of_1.5_grid_steps_m_per_s", in_plane_arrow_speed(o)}}},
                 {"frames", json::array()}};
  fs::create_directories(out);
  record["model"] = model_picture(landmarks_file.parent_path(), landmarks, o, out);
  std::optional<ScanPictures> scan;
  if (!o.scan.scan.empty()) {
    if (o.time >= 0)
      input_error("pictures: --mri pictures the scan at the cycle's events (peak systole, "
                  "mid-diastole); leave out --time");
    scan.emplace(o.scan, o.run_dir, landmarks);
    record["scan"] = scan->record();
  }
  std::vector<PlaneGroup> groups = plane_groups(landmarks);
  TracedFrame traced;                     // the first frame's streamlines,
  vtkSmartPointer<vtkPolyData> run_seeds; // their seeds
  double run_bounds[6] = {};              // and the box their cameras frame
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const analysis::PictureFrame& f = frames[i];
    const fs::path dir = out / folder_of(f);
    fs::create_directories(dir);
    const auto fluid = analysis::read_flow_frame(f.frame.file);
    json pictures = json::array();
    json entry = {{"event", f.event},
                  {"time_s", f.frame.time},
                  {"frame", f.frame.file.string()},
                  {"folder", folder_of(f)}};
    // The box the streamline cameras frame (the run's, and the scan's beside it).
    double bounds[6];
    fluid->GetBounds(bounds);
    vtkSmartPointer<vtkPolyData> seeds;
    if (i == 0) { // streamlines and the wall at the first frame (peak systole, or the asked)
      analysis::StreamlineOptions so;
      so.seed_spacing = o.seed_spacing;
      seeds = analysis::seed_points(fluid, seed, so, f.frame.file.string());
      const auto lines = analysis::trace_streamlines(fluid, seeds, so);
      traced = {f.frame.file, lines};
      run_seeds = seeds;
      std::copy(bounds, bounds + 6, run_bounds);
      analysis::write_vtp(lines, dir / "streamlines.vtp");
      entry["streamlines"] = {{"file", "streamlines.vtp"},
                              {"seed_landmark", seed.name},
                              {"lines", lines->GetNumberOfLines()},
                              {"points", lines->GetNumberOfPoints()}};
      if (o.png) {
        const std::string caption =
            fmt::format("streamlines from {}, {} (t = {} s)", seed.name, f.event, f.frame.time);
        for (const Picture& p :
             render_streamlines(lines, boundary_surface(fluid), views, speed_scale(o.speed_max),
                                caption, dir, "streamlines", {}, bounds))
          pictures.push_back(picture_json(p));
      }
      // (read only for a picture: the wall has no VTP of its own)
      if (const auto wall =
              o.png ? analysis::read_wall(f.frame.file) : vtkSmartPointer<vtkUnstructuredGrid>()) {
        const std::string caption =
            fmt::format("wall displacement, {} (t = {} s)", f.event, f.frame.time);
        for (const Picture& p :
             render_wall_displacement(boundary_surface(wall), views,
                                      {"displacement [mm]", 0.0, o.displacement_max / units::mm},
                                      caption, dir, "wall_displacement"))
          pictures.push_back(picture_json(p));
      }
    }
    std::map<std::string, double> spacing;
    entry["planes"] = plane_maps(fluid, landmarks, f.frame.file.string(),
                                 fmt::format("{} (t = {} s), ", f.event, f.frame.time), o, dir, "",
                                 false, groups, spacing, pictures);
    // A moving wall's flap against end diastole (its first frame is end diastole itself).
    if (i == 0 && o.png && cycle && fluid->GetPointData()->GetArray("displacement") != nullptr &&
        cycle->frames.front().file != f.frame.file)
      entry["flap_position"] =
          flap_position(fluid, f, cycle->frames.front(), landmarks, groups, dir, pictures);
    entry["pictures"] = pictures;
    if (i == 0) { // the first frame in ParaView, beside the pictures
      io::write_file_atomically(out / kParaviewState,
                                paraview_state(state_scene(run, out, entry, fluid, views, o)));
      record["paraview_state"] = kParaviewState;
    }
    if (scan)
      entry["scan"] =
          scan_frame(*scan, f.event, seeds, bounds, landmarks, views, o, dir, groups, spacing);
    record["frames"].push_back(entry);
    if (!o.quiet)
      fmt::print("{} (t = {} s): {} pictures in '{}'\n", f.event, f.frame.time, pictures.size(),
                 dir.string());
  }
  if (o.animate && o.png) {
    record["animation"] = animate_run(*cycle, seed, animation_view(views), o, traced, out);
    if (scan)
      record["scan_animation"] =
          animate_scan(*scan, run_seeds, run_bounds, animation_view(views), o, out);
  }
  io::write_file_atomically(out / "pictures.json", record.dump(2) + "\n");
  if (!o.quiet)
    fmt::print("wrote '{}'\n", (out / "pictures.json").string());
  return 0;
}

PicturesCommand::PicturesCommand(CLI::App& app) {
  command_ = app.add_subcommand("pictures", "flow-pattern figures of a run: streamlines, plane "
                                            "maps, wall displacement (docs/analysis.md)");
  command_->add_option("run_dir", options_.run_dir, "output directory of `tearflow run`")
      ->required();
  command_->add_option("--model", options_.model_dir,
                       "the model's geometry folder (its landmarks.json; default "
                       "RUN_DIR/geometry)");
  command_->add_option("--landmarks", options_.landmarks, "landmarks JSON (overrides --model)");
  command_
      ->add_option("--time", options_.time,
                   "picture the saved frame nearest this time [s] (default: peak systole, and "
                   "mid-diastole for the plane maps)")
      ->check(CLI::NonNegativeNumber);
  command_->add_option("--seed", options_.seed,
                       "landmark whose plane seeds the streamlines (default inlet, else AAo)");
  command_->add_option("--speed-max", options_.speed_max,
                       "top of the speed colour scale [m/s]; the through-plane scale is +-it "
                       "(default 1.5)");
  command_
      ->add_option("--displacement-max-mm", displacement_max_mm_,
                   "top of the wall displacement colour scale [mm] (default 2)")
      ->check(CLI::PositiveNumber);
  command_
      ->add_option("--seed-spacing-mm", seed_spacing_mm_,
                   "spacing of the seed grid [mm] (default: the seed section's equivalent "
                   "diameter / 10)")
      ->check(CLI::PositiveNumber);
  command_->add_option("-o,--output", options_.output,
                       "output directory (default RUN_DIR/analysis/figures/flow)");
  command_->add_flag("--no-png", no_png_, "the VTP files and pictures.json only, no rendering");
  command_->add_flag("--animate", options_.animate,
                     "also the streamlines of every frame of the cycle (and of the --mri "
                     "scan's) as an animated PNG");
  command_->add_option("--view", options_.views,
                       "a view of the streamline and wall pictures (repeatable): anterior, "
                       "left-lateral, flap, or NAME:X,Y,Z, a camera from the direction X,Y,Z "
                       "(default: the standard ones)");
  command_->add_option("--mri", options_.scan.scan,
                       "a 4D-flow scan (DICOM folder or volume folder, as `mri flow` reads it): "
                       "the same streamlines and plane maps from it, beside the run's");
  command_->add_option("--mri-align", options_.scan.align,
                       "paired model / MRI points (JSON) placing the scan (default: the scan is "
                       "in the model's coordinates)");
  command_
      ->add_option("--mri-venc", options_.scan.venc,
                   "the scan's velocity encoding [m/s], overriding (or supplying) the files' "
                   "(needed for the temporal unwrapping when they have none)")
      ->check(CLI::PositiveNumber);
  command_->add_flag("--mri-align-surface", options_.scan.align_surface,
                     "place the scan by fitting its lumen surface to the run's mesh (ICP, "
                     "started from --mri-align when given)");
  command_
      ->add_option("--mri-lumen-fraction", options_.scan.lumen_fraction,
                   "the scan's lumen: time-mean magnitude >= this x its 99th percentile "
                   "(default 0.6)")
      ->check(CLI::Range(0.05, 0.95));
  command_->add_flag("-q,--quiet", options_.quiet, "no summary lines");
}

int PicturesCommand::run() const {
  PicturesOptions o = options_;
  o.displacement_max = displacement_max_mm_ * units::mm;
  o.seed_spacing = seed_spacing_mm_ * units::mm;
  o.png = !no_png_;
  return make_pictures(o);
}

} // namespace tearflow::report
