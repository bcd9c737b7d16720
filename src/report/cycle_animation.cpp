#include "report/cycle_animation.hpp"

#include <algorithm>
#include <functional>

#include <fmt/format.h>
#include <vtkUnstructuredGrid.h>

#include "report/apng.hpp"

namespace tearflow::report {

namespace {

using nlohmann::json;
namespace fs = std::filesystem;

/// Renders `times.size()` frames, `render(i, dir)` writing frame i's PNG into `dir` (the
/// animation/ folder) and returning its path, and joins them into
/// `out`/<stem>_<view>_animation.png: the cycle in about 4 s however many frames there are (20-500
/// ms each), so that a run's animation and its scan's play side by side at one pace.
json join_frames(const std::vector<double>& times,
                 const std::function<fs::path(std::size_t, const fs::path&)>& render,
                 const std::string& stem, const View& view, const PicturesOptions& o,
                 const fs::path& out) {
  const fs::path dir = out / "animation";
  fs::create_directories(dir);
  std::vector<fs::path> pngs;
  for (std::size_t i = 0; i < times.size(); ++i)
    pngs.push_back(render(i, dir));
  const int delay_ms = std::clamp(static_cast<int>(4000 / pngs.size()), 20, 500);
  const fs::path file = out / (stem + "_" + view.name + "_animation.png");
  write_apng(pngs, delay_ms, file);
  if (!o.quiet)
    fmt::print("animation of {} frames: '{}'\n", pngs.size(), file.string());
  return {{"file", file.filename().string()},
          {"view", view.name},
          {"frames", pngs.size()},
          {"frame_delay_ms", delay_ms},
          {"frame_times_s", times}};
}

} // namespace

const View& animation_view(const std::vector<View>& views) {
  return views.back().name == "flap" ? views.back() : views.front();
}

json animate_run(const analysis::CycleFrames& cycle, const geometry::Landmark& seed,
                 const View& view, const PicturesOptions& o, const TracedFrame& traced,
                 const fs::path& out) {
  analysis::StreamlineOptions so;
  so.seed_spacing = o.seed_spacing;
  std::vector<double> times;
  for (const analysis::FlowFrame& f : cycle.frames)
    times.push_back(f.time);
  const auto render = [&](std::size_t i, const fs::path& dir) {
    const analysis::FlowFrame& f = cycle.frames[i];
    const auto fluid = analysis::read_flow_frame(f.file);
    const auto lines = f.file == traced.file
                           ? traced.lines
                           : analysis::trace_streamlines(fluid, seed, so, f.file.string());
    const std::string stem = fmt::format("streamlines_{:03d}", i);
    render_streamlines(lines, boundary_surface(fluid), {view}, speed_scale(o.speed_max),
                       fmt::format("streamlines from {}, t = {} s", seed.name, f.time), dir, stem);
    return dir / (stem + "_" + view.name + ".png");
  };
  return join_frames(times, render, "streamlines", view, o, out);
}

json animate_scan(const ScanPictures& scan, vtkPolyData* seeds, const double* bounds,
                  const View& view, const PicturesOptions& o, const fs::path& out) {
  const analysis::StreamlineOptions so; // as scan_frame's: the seeds are given
  std::vector<double> times;
  for (std::size_t k = 0; k < scan.frames(); ++k)
    times.push_back(scan.time_of(k));
  const auto render = [&](std::size_t k, const fs::path& dir) {
    const auto field = scan.field(k);
    const auto lines = analysis::trace_streamlines(field, seeds, so);
    const std::string stem = fmt::format("mri_streamlines_{:03d}", k);
    render_streamlines(lines, boundary_surface(field), {view}, speed_scale(o.speed_max),
                       fmt::format("4D-flow MRI: streamlines, scan frame {} ({} s after the "
                                   "trigger)",
                                   k, scan.time_of(k)),
                       dir, stem, {}, bounds);
    return dir / (stem + "_" + view.name + ".png");
  };
  return join_frames(times, render, "mri_streamlines", view, o, out);
}

} // namespace tearflow::report
