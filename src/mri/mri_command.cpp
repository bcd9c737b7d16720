// `tearflow mri`: synthesize an analytic 4D-flow scan, measure landmark flows in a scan, and
// compare a simulation with MRI (docs/mri.md). Each step prints its timing; `flow` writes
// mri.json with the corrections' reports beside the tables.
#include "mri/mri_command.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <optional>
#include <regex>

#include <unistd.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "analysis/hemodynamics.hpp"
#include "core/error.hpp"
#include "core/file_layout.hpp"
#include "core/units.hpp"
#include "mri/alignment.hpp"
#include "mri/compare.hpp"
#include "mri/corrections.hpp"
#include "mri/image_io.hpp"
#include "mri/plane_flow.hpp"
#include "mri/surface_alignment.hpp"
#include "mri/synthetic.hpp"
#include "mri/synthetic_run.hpp"

namespace tearflow::mri {

namespace fs = std::filesystem;

namespace {

/// "1.5mm", "0.2 cm", "2e-3m" -> metres; "1.5m/s", "150cm/s" -> m/s. InputError naming the
/// option otherwise.
double quantity(const std::string& text, const std::string& option, bool velocity) {
  static const std::regex re(R"(\s*([-+0-9.eE]+)\s*([a-zA-Z/]*)\s*)");
  std::smatch m;
  if (!std::regex_match(text, m, re))
    input_error("{} '{}': a number with a unit is expected (e.g. {})", option, text,
                velocity ? "1.5m/s" : "1.5mm");
  double value = 0;
  try {
    value = std::stod(m[1]);
  } catch (...) {
    input_error("{} '{}': not a number", option, text);
  }
  std::string unit = m[2];
  if (velocity) {
    if (unit.size() < 2 || unit.substr(unit.size() - 2) != "/s")
      input_error("{} '{}': a velocity in m/s, cm/s or mm/s is expected", option, text);
    unit = unit.substr(0, unit.size() - 2);
  }
  return value * units::length_scale(unit, option);
}

/// A linear + quadratic offset per component (monomials of corrections.hpp), |b| <~ a.
void inject_background(Flow4D& data, double a) {
  if (a == 0)
    return;
  using V = std::vector<double>;
  add_background(data, {V{0.2 * a, 0.3 * a, -0.2 * a, 0.1 * a, 0.2 * a, 0, -0.1 * a, 0, 0, 0},
                        V{-0.3 * a, 0, 0.2 * a, 0, 0, 0.15 * a, 0, 0, -0.1 * a, 0.05 * a},
                        V{0.1 * a, -0.1 * a, 0, 0.3 * a, 0, 0, 0.2 * a, 0, 0.1 * a, 0}});
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

} // namespace

MriCommand::MriCommand(CLI::App& app) {
  command_ = app.add_subcommand("mri", "4D-flow MRI: synthesize, measure flows, compare "
                                       "(docs/mri.md)");
  command_->require_subcommand(1);

  synthesize_ = command_->add_subcommand(
      "synthesize", "a synthetic 4D-flow scan of a run's VTU series, or of the analytic "
                    "pulsatile (Womersley) pipe when no run is given");
  synthesize_->add_option("run_dir", run_dir_, "output folder of `tearflow run` (flow.pvd)");
  synthesize_->add_option("-o,--output", output_, "output folder")->required();
  synthesize_->add_option("--voxel", voxel_, "isotropic voxel size (default 1.5mm)");
  synthesize_->add_option("--frames", frames_, "cardiac frames (default 20)")
      ->check(CLI::Range(1, 200));
  synthesize_->add_option("--venc", venc_, "velocity encoding (default 1m/s)");
  synthesize_->add_option("--snr", snr_, "magnitude SNR in the lumen; 0: no noise (default)")
      ->check(CLI::Range(0.0, 1e6));
  synthesize_->add_option("--radius", radius_, "pipe radius (default 10mm)");
  synthesize_->add_option("--tissue", tissue_, "static tissue out to this radius (default 2x)");
  synthesize_->add_option("--size", size_, "voxels NX,NY,NZ (default: 5 radii across, 12 slices)");
  synthesize_->add_option("--rotate", rotate_, "grid rotated by this many degrees about (1,1,0)");
  synthesize_->add_option("--background", background_,
                          "add a linear + quadratic phase offset of this size (default 0m/s)");
  synthesize_->add_option("--seed", seed_, "noise seed (default 1)");
  synthesize_
      ->add_option("--format", format_, "dicom (classic phase), dicom-rescaled, nifti or mha")
      ->check(CLI::IsMember({"dicom", "dicom-rescaled", "nifti", "mha"}));

  flow_ = command_->add_subcommand("flow", "landmark flow, area and peak velocity of a scan "
                                           "(DICOM folder or NIfTI/MetaImage volumes)");
  flow_->add_option("input", input_, "DICOM folder or volume folder")->required();
  flow_->add_option("--landmarks", landmarks_, "landmarks JSON (docs/geometry.md)")->required();
  flow_->add_option("-o,--output", output_, "output folder for the tables")->required();
  flow_->add_option("--venc", venc_override_, "velocity encoding, overriding the files'");
  flow_->add_option("--align", align_,
                    "paired model / MRI points (JSON): move the landmarks by their rigid fit");
  flow_->add_option("--align-surface", align_surface_,
                    "run folder or .vtu mesh: move the landmarks by the rigid fit (ICP) of the "
                    "MRI lumen's surface to the mesh's (started from --align when given)");
  flow_->add_flag("--no-background", no_background_, "no background phase-offset correction");
  flow_
      ->add_option("--background-order", background_order_,
                   "background polynomial order 0, 1 or 2 (default 2)")
      ->check(CLI::Range(0, 2));
  flow_->add_flag("--no-unwrap", no_unwrap_, "no temporal phase unwrapping");
  flow_
      ->add_option("--lumen-fraction", lumen_fraction_,
                   "lumen: magnitude >= this x the lumen point's (default 0.6)")
      ->check(CLI::Range(0.05, 1.0));
  flow_->add_flag("-q,--quiet", quiet_, "no summary lines");

  compare_ = command_->add_subcommand("compare", "simulation against MRI flows at the landmarks");
  compare_->add_option("simulation", simulation_, "run folder or measured-table folder")
      ->required();
  compare_->add_option("mri", measured_, "folder of MRI tables (`tearflow mri flow`)")->required();
  compare_->add_option("-o,--output", output_, "output folder")->required();
  compare_->add_option("--scan", scan_,
                       "the MRI scan itself (DICOM or volume folder): adds voxel-wise speed "
                       "and angle differences in the lumen (the simulation must be a run)");
  compare_->add_option("--venc", venc_override_, "velocity encoding of --scan, if not in it");
  compare_->add_flag("-q,--quiet", quiet_, "no summary lines");
}

int MriCommand::run() const {
  if (synthesize_->parsed())
    return synthesize();
  if (flow_->parsed())
    return flow();
  return compare();
}

int MriCommand::synthesize_from_run() const {
  const auto t0 = std::chrono::steady_clock::now();
  RunScan scan;
  scan.run_dir = run_dir_;
  scan.voxel = quantity(voxel_, "--voxel", false);
  scan.frames = frames_;
  scan.direction = rotation({1, 1, 0}, rotate_);
  scan.effects.venc = quantity(venc_, "--venc", true);
  scan.effects.snr = snr_;
  scan.effects.seed = seed_;
  if (!(scan.voxel > 0) || !(scan.effects.venc > 0))
    input_error("mri synthesize: --voxel and --venc must be positive");
  if (!size_.empty() || !tissue_.empty())
    input_error("mri synthesize RUN_DIR: --size and --tissue are for the analytic pipe (the "
                "grid covers the run's fluid plus 5 mm)");
  Flow4D data = mri::synthesize_run(scan);
  inject_background(data, quantity(background_, "--background", true));
  const double t_synth = seconds_since(t0);
  const fs::path out = output_;
  const auto t1 = std::chrono::steady_clock::now();
  write_scan(data, out / "images");
  const fs::path landmarks = RunFiles{run_dir_}.geometry().landmarks();
  if (fs::exists(landmarks))
    fs::copy_file(landmarks, GeometryFiles{out}.landmarks(), fs::copy_options::overwrite_existing);
  fmt::print("mri synthesize '{}': {} x {} x {} voxels of {} mm, {} frames, venc {} m/s, SNR "
             "{}\nsynthesis {:.2f} s, writing ({}) {:.2f} s; images{} in '{}'\n",
             run_dir_, data.grid.size[0], data.grid.size[1], data.grid.size[2], scan.voxel * 1e3,
             scan.frames, scan.effects.venc, scan.effects.snr, t_synth, format_, seconds_since(t1),
             fs::exists(landmarks) ? " and landmarks.json" : "", out.string());
  return 0;
}

void MriCommand::write_scan(const Flow4D& data, const fs::path& dir) const {
  if (format_ == "dicom" || format_ == "dicom-rescaled")
    write_dicom(data, dir,
                {format_ == "dicom" ? PhaseConvention::classic : PhaseConvention::rescaled, true});
  else
    write_volumes(data, dir, format_ == "nifti" ? ".nii.gz" : ".mha");
}

int MriCommand::synthesize() const {
  if (!run_dir_.empty())
    return synthesize_from_run();
  const auto t0 = std::chrono::steady_clock::now();
  PipeScan scan;
  const double radius = quantity(radius_, "--radius", false);
  const double voxel = quantity(voxel_, "--voxel", false);
  scan.flow = pulsatile_pipe_flow(radius);
  scan.venc = quantity(venc_, "--venc", true);
  scan.snr = snr_;
  scan.frames = frames_;
  scan.seed = seed_;
  scan.tissue_radius = tissue_.empty() ? 2 * radius : quantity(tissue_, "--tissue", false);
  scan.axis_point = {0.0, 0.0, 0.0};
  scan.axis = {0, 0, 1};
  std::array<int, 3> size{};
  if (size_.empty()) {
    const int n = static_cast<int>(std::ceil(5 * radius / voxel)) + 1;
    size = {n, n, 12};
  } else if (std::sscanf(size_.c_str(), "%d,%d,%d", &size[0], &size[1], &size[2]) != 3 ||
             size[0] < 1 || size[1] < 1 || size[2] < 1) {
    input_error("--size '{}': three positive voxel counts NX,NY,NZ are expected", size_);
  }
  if (!(voxel > 0) || !(radius > 0) || !(scan.venc > 0))
    input_error("mri synthesize: --voxel, --radius and --venc must be positive");
  // The scan is held in memory (4 float images over the voxels and frames) before it is
  // written: refused before allocating when that exceeds half of this machine's memory.
  const double bytes = 4.0 * sizeof(float) * size[0] * size[1] * size[2] * std::max(frames_, 1);
  const double machine = static_cast<double>(::sysconf(_SC_PHYS_PAGES)) *
                         static_cast<double>(::sysconf(_SC_PAGE_SIZE));
  if (machine > 0 && bytes > 0.5 * machine)
    input_error("mri synthesize: --size {} x {} x {} voxels x {} frames needs about {:.1f} GB in "
                "memory, more than half of this machine's {:.1f} GB; give fewer voxels or frames",
                size[0], size[1], size[2], frames_, bytes / 1e9, machine / 1e9);
  if (bytes > 1e9)
    fmt::print("mri synthesize: about {:.1f} GB of images in memory\n", bytes / 1e9);
  scan.grid =
      centred_grid(scan.axis_point, rotation({1, 1, 0}, rotate_), size, {voxel, voxel, voxel});
  Flow4D data = synthesize_pipe(scan);
  inject_background(data, quantity(background_, "--background", true));
  const double t_synth = seconds_since(t0);
  const fs::path out = output_;
  const auto t1 = std::chrono::steady_clock::now();
  write_scan(data, out / "images");
  const double t_write = seconds_since(t1);

  // Landmarks: two planes across the pipe, 3 mm either side of its centre.
  geometry::Landmarks landmarks;
  for (const auto& [name, dz] : {std::pair{"inlet", -3e-3}, std::pair{"outlet", 3e-3}}) {
    geometry::Landmark l;
    l.name = name;
    l.origin = scan.axis_point + dz * scan.axis;
    l.normal = scan.axis;
    l.point = l.origin;
    landmarks.planes.push_back(l);
  }
  geometry::write_landmarks(landmarks, GeometryFiles{out}.landmarks());
  // The exact flow (each frame's window mean) in the measured layout.
  fs::create_directories(out / "exact");
  std::ofstream exact(out / "exact" / "flow.csv");
  exact << "time_s,inlet_mL_per_s,outlet_mL_per_s\n";
  for (int k = 0; k < scan.frames; ++k) {
    const double q = exact_frame_flow(scan, k) / units::mL;
    exact << fmt::format("{:.6g},{:.8g},{:.8g}\n", data.frames[k].time, q, q);
  }
  fmt::print("mri synthesize: {} x {} x {} voxels of {} mm, {} frames, venc {} m/s, SNR {}; "
             "pipe radius {} mm, alpha {:.1f}\n",
             size[0], size[1], size[2], voxel * 1e3, scan.frames, scan.venc, scan.snr, radius * 1e3,
             scan.flow.womersley_number());
  fmt::print("synthesis {:.2f} s, writing ({}) {:.2f} s; images, landmarks.json and "
             "exact/flow.csv in '{}'\n",
             t_synth, format_, t_write, out.string());
  return 0;
}

Flow4D MriCommand::load_corrected(const std::string& input, nlohmann::json& report) const {
  auto t0 = std::chrono::steady_clock::now();
  ReadOptions ro;
  if (!venc_override_.empty())
    ro.venc = quantity(venc_override_, "--venc", true);
  Flow4D data = read_flow_data(input, ro);
  report["read_s"] = seconds_since(t0);
  report["grid"] = {
      {"size", data.grid.size},
      {"spacing_mm",
       {data.grid.spacing[0] * 1e3, data.grid.spacing[1] * 1e3, data.grid.spacing[2] * 1e3}},
      {"frames", data.frames.size()},
      {"venc_m_per_s", data.venc}};
  t0 = std::chrono::steady_clock::now();
  if (no_unwrap_) {
    report["unwrap"] = "off";
  } else if (!(data.venc > 0)) {
    report["unwrap"] = "skipped: the data has no venc (give --venc)";
  } else {
    report["unwrap"] = unwrap_temporal(data).to_json();
  }
  report["unwrap_s"] = seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  if (no_background_) {
    report["background"] = "off";
  } else {
    BackgroundOptions bo;
    bo.order = background_order_;
    report["background"] = correct_background(data, bo).to_json();
  }
  report["background_s"] = seconds_since(t0);
  return data;
}

int MriCommand::flow() const {
  nlohmann::json report;
  Flow4D data = load_corrected(input_, report);
  geometry::Landmarks landmarks = geometry::read_landmarks(landmarks_);
  if (!align_surface_.empty()) {
    const auto t0 = std::chrono::steady_clock::now();
    std::optional<RigidTransform> start;
    if (!align_.empty())
      start = read_alignment(align_);
    const double voxel =
        std::min({data.grid.spacing[0], data.grid.spacing[1], data.grid.spacing[2]});
    const SurfaceFit fit = fit_surface(read_model_surface(align_surface_),
                                       lumen_boundary_points(data, lumen_fraction_), voxel, start);
    landmarks = transformed(landmarks, fit.transform);
    report["alignment"] = fit.to_json();
    report["alignment_s"] = seconds_since(t0);
    if (!quiet_)
      fmt::print("surface alignment ({} start, {} iterations): RMS {:.3f} mm over {} of {} "
                 "boundary points\n",
                 fit.start, fit.iterations, fit.transform.rms * 1e3, fit.kept, fit.points);
  } else if (!align_.empty()) {
    const RigidTransform t = read_alignment(align_);
    landmarks = transformed(landmarks, t);
    report["alignment"] = t.to_json();
  }
  auto t0 = std::chrono::steady_clock::now();
  PlaneOptions po;
  po.lumen_fraction = lumen_fraction_;
  const std::vector<PlaneSeries> planes = measure_planes(data, landmarks, po);
  report["planes_s"] = seconds_since(t0);
  write_measured_tables(data, planes, output_);
  {
    std::ofstream out(fs::path(output_) / "mri.json");
    out << report.dump(2) << '\n';
  }
  if (!quiet_) {
    fmt::print("mri flow '{}': {} x {} x {} voxels, {} frames, venc {} m/s\n", input_,
               data.grid.size[0], data.grid.size[1], data.grid.size[2], data.frames.size(),
               data.venc);
    fmt::print("read {:.2f} s, unwrap {:.2f} s, background {:.2f} s, planes {:.2f} s\n",
               report["read_s"].get<double>(), report["unwrap_s"].get<double>(),
               report["background_s"].get<double>(), report["planes_s"].get<double>());
    fmt::print("{:<10} {:>14} {:>14} {:>12}\n", "landmark", "Qmean [mL/s]", "Qpeak [mL/s]",
               "A [mm2]");
    for (const PlaneSeries& s : planes) {
      double mean = 0, peak = -1e300, area = 0;
      for (std::size_t k = 0; k < s.flow.size(); ++k) {
        mean += s.flow[k] / s.flow.size();
        peak = std::max(peak, s.flow[k]);
        area += s.area[k] / s.flow.size();
      }
      fmt::print("{:<10} {:>14.3f} {:>14.3f} {:>12.1f}\n", s.name, mean / units::mL,
                 peak / units::mL, area * 1e6);
    }
    fmt::print("flow.csv, area.csv, velocity.csv and mri.json in '{}'\n", output_);
  }
  return 0;
}

int MriCommand::compare() const {
  analysis::AnalyzeOptions so, mo;
  so.run_dir = simulation_;
  mo.run_dir = measured_;
  Comparison c = compare_flows(analysis::analyze_run(so), analysis::analyze_run(mo));
  if (!scan_.empty()) {
    nlohmann::json report;
    const Flow4D measured = load_corrected(scan_, report);
    RunScan rs;
    rs.run_dir = simulation_;
    rs.grid = measured.grid;
    rs.frames = static_cast<int>(measured.frames.size());
    rs.effects.venc = measured.venc > 0 ? measured.venc : 1.0;
    rs.effects.wrap = false;
    c.voxels = compare_voxels(synthesize_run(rs), measured);
  }
  write_comparison(c, output_);
  if (!quiet_) {
    fmt::print("{:<10} {:>12} {:>12} {:>16} {:>8}\n", "landmark", "Qsim [mL/s]", "Qmri [mL/s]",
               "diff mean+-SD", "r");
    for (const WaveformComparison& w : c.landmarks)
      fmt::print("{:<10} {:>12.3f} {:>12.3f} {:>8.3f} +- {:<5.3f} {:>8.4f}\n", w.landmark,
                 w.mean_sim / units::mL, w.mean_mri / units::mL, w.bias / units::mL,
                 w.sd / units::mL, w.correlation);
    fmt::print("compare.json and flow_comparison.csv in '{}'\n", output_);
  }
  return 0;
}

} // namespace tearflow::mri
