// `tearflow mri`: synthesize an analytic 4D-flow scan, measure landmark flows in a scan, and
// compare a simulation with MRI (docs/mri.md). Each step prints its timing; `flow` writes
// mri.json with the corrections' reports beside the tables.
#include "mri/mri_command.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>

#include <unistd.h>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include "analysis/hemodynamics.hpp"
#include "bc/face_geometry.hpp"
#include "core/error.hpp"
#include "core/file_layout.hpp"
#include "core/units.hpp"
#include "io/case.hpp"
#include "mesh/orient_faces.hpp"
#include "mri/alignment.hpp"
#include "mri/compare.hpp"
#include "mri/corrected_scan.hpp"
#include "mri/corrections.hpp"
#include "mri/image_io.hpp"
#include "mri/plane_flow.hpp"
#include "mri/scan2d_command.hpp"
#include "mri/surface_alignment.hpp"
#include "mri/synthetic.hpp"
#include "mri/synthetic_run.hpp"
#include "run/flow_model.hpp"

namespace tearflow::mri {

namespace fs = std::filesystem;

namespace {

double quantity(const std::string& text, const std::string& option, bool velocity) {
  return units::quantity(text, option,
                         velocity ? units::Dimension::velocity : units::Dimension::length);
}

/// A linear + quadratic offset per component (monomials of corrections.hpp), |b| <~ a; of a
/// 2D scan what its encoding measures of it.
void inject_background(Flow4D& data, double a) {
  if (a == 0)
    return;
  using V = std::vector<double>;
  add_background(data, {V{0.2 * a, 0.3 * a, -0.2 * a, 0.1 * a, 0.2 * a, 0, -0.1 * a, 0, 0, 0},
                        V{-0.3 * a, 0, 0.2 * a, 0, 0, 0.15 * a, 0, 0, -0.1 * a, 0.05 * a},
                        V{0.1 * a, -0.1 * a, 0, 0.3 * a, 0, 0, 0.2 * a, 0, 0.1 * a, 0}});
  encode(data, data.encoding);
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

} // namespace

MriCommand::MriCommand(CLI::App& app) {
  command_ = app.add_subcommand("mri", "MRI (4D flow, 2D phase contrast, cine): synthesize, "
                                       "measure, compare (docs/mri.md)");
  command_->require_subcommand(1);

  synthesize_ = command_->add_subcommand(
      "synthesize", "a synthetic 4D-flow, 2D phase-contrast or cine scan (--scan-type) of a "
                    "run's VTU series, or of the analytic pulsatile (Womersley) pipe when no "
                    "run is given");
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
  synthesize_->add_option("--rotate", rotate_,
                          "grid rotated by this many degrees about (1,1,0); a run's 2D slices "
                          "tilted by it from their landmark planes");
  synthesize_->add_option("--background", background_,
                          "add a linear + quadratic phase offset of this size (default 0m/s)");
  synthesize_->add_option("--seed", seed_, "noise seed (default 1)");
  synthesize_
      ->add_option("--format", format_, "dicom (classic phase), dicom-rescaled, nifti or mha")
      ->check(CLI::IsMember({"dicom", "dicom-rescaled", "nifti", "mha"}));
  synthesize_
      ->add_option("--scan-type", scan_type_,
                   "4d (4D flow, default), pc (2D through-plane phase contrast) or cine (2D)")
      ->check(CLI::IsMember({"4d", "pc", "cine"}));
  synthesize_
      ->add_option("--at", at_, "2D scans of a run: at these landmark planes (default: every one)")
      ->delimiter(',');
  synthesize_->add_option("--thickness", thickness_, "2D slice thickness (default 6mm)");
  synthesize_->add_option("--case", case_file_,
                          "2D scans of a run: its case, so that --at may name mesh faces (a "
                          "slice across the vessel inside an outlet)");
  synthesize_->add_option("--landmarks", landmarks_,
                          "2D scans of a run: its landmarks (default RUN_DIR/geometry/"
                          "landmarks.json)");
  synthesize_->add_option("--fov", fov_, "2D field of view, square side (default 80mm)");

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
  scans_ = std::make_unique<Scan2dCommands>(*command_);
}

MriCommand::~MriCommand() = default;

int MriCommand::run() const {
  if (scans_->selected())
    return scans_->run();
  if (synthesize_->parsed())
    return synthesize();
  if (flow_->parsed())
    return flow();
  return compare();
}

namespace {

/// Rows e1, e2, n: a slice's in-plane axes and its normal n (unit).
Mat3 slice_axes(Vec3 n) {
  n = (1.0 / std::sqrt(dot(n, n))) * n;
  const Vec3 helper = std::abs(n[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  Vec3 e1 = cross(n, helper);
  e1 = (1.0 / std::sqrt(dot(e1, e1))) * e1;
  return {e1, cross(n, e1), n};
}

Encoding encoding_of(const std::string& scan_type) {
  return scan_type == "pc" ? Encoding::through_plane
                           : (scan_type == "cine" ? Encoding::magnitude : Encoding::velocity_3d);
}

} // namespace

int MriCommand::synthesize_slices_of_run() const {
  const auto t0 = std::chrono::steady_clock::now();
  if (format_ != "dicom" && format_ != "dicom-rescaled")
    input_error("mri synthesize --scan-type {}: 2D scans are written as DICOM (--format dicom "
                "or dicom-rescaled)",
                scan_type_);
  const fs::path landmarks_file =
      landmarks_.empty() ? RunFiles{run_dir_}.geometry().landmarks() : fs::path(landmarks_);
  const geometry::Landmarks landmarks = geometry::read_landmarks(landmarks_file);
  const double pixel = quantity(voxel_, "--voxel", false);
  const double thickness = quantity(thickness_, "--thickness", false);
  const double fov = quantity(fov_, "--fov", false);
  if (!(pixel > 0) || !(thickness > 0) || !(fov > pixel))
    input_error("mri synthesize: --voxel, --thickness and --fov must be positive, the field of "
                "view larger than a pixel");
  // Planes across the vessels inside named faces: the face's centroid moved inwards by half
  // the slice and 3 mm (a slab centred on the face would be half outside the fluid), its
  // normal downstream as a landmark's: the outward normal at an outlet, the inward one at an
  // inflow face. They replace landmarks of the same name (the model's inlet and outlet
  // landmarks lie on the faces).
  geometry::Landmarks planes = landmarks;
  if (!case_file_.empty()) {
    const io::Case c = io::load_case(case_file_);
    mesh::Mesh m = run::load_mesh(c);
    mesh::orient_faces_outward(m);
    for (const std::string& name : at_)
      if (m.has_face(name)) {
        std::erase_if(planes.planes, [&](const auto& l) { return l.name == name; });
        const bc::FaceGeometry f = bc::face_geometry(m, m.face(name));
        const Vec3 origin = f.centroid - (0.5 * thickness + 3e-3) * f.normal;
        const bool inflow = std::any_of(
            c.boundary_conditions.begin(), c.boundary_conditions.end(),
            [&](const bc::BoundaryCondition& b) { return b.face == name && b.inflow(); });
        planes.planes.push_back({name, origin, (inflow ? -1.0 : 1.0) * f.normal, "aorta", origin});
      }
  }
  for (const std::string& name : at_)
    if (std::none_of(planes.planes.begin(), planes.planes.end(),
                     [&](const geometry::Landmark& l) { return l.name == name; }))
      input_error("mri synthesize --at: no landmark plane '{}' in '{}'{}", name,
                  landmarks_file.string(),
                  case_file_.empty() ? " (give --case to name a mesh face)"
                                     : ", nor a face of the case's mesh");
  const fs::path out = output_;
  std::vector<std::string> written;
  std::vector<ImageGrid> grids;
  for (const geometry::Landmark& l : planes.planes) {
    if (!at_.empty() && std::find(at_.begin(), at_.end(), l.name) == at_.end())
      continue;
    // A station's TL and FL planes are one plane: one scan, in station<k>/.
    const int station = analysis::station_of(l);
    const std::string folder = station > 0 ? fmt::format("station{}", station) : l.name;
    if (std::find(written.begin(), written.end(), folder) != written.end())
      continue;
    // --rotate tilts the slice about its first in-plane axis: an oblique cut of the vessel.
    const Mat3 turn = rotation(slice_axes(l.normal)[0], rotate_);
    const Vec3 normal = l.normal[0] * turn[0] + l.normal[1] * turn[1] + l.normal[2] * turn[2];
    const int n = static_cast<int>(std::ceil(fov / pixel));
    grids.push_back(
        centred_grid(l.origin, slice_axes(normal), {n, n, 1}, {pixel, pixel, thickness}));
    written.push_back(folder);
  }
  RunScan scan;
  scan.run_dir = run_dir_;
  scan.frames = frames_;
  scan.encoding = encoding_of(scan_type_);
  scan.effects.venc = quantity(venc_, "--venc", true);
  scan.effects.snr = snr_;
  scan.effects.seed = seed_;
  std::vector<Flow4D> scans = mri::synthesize_run(scan, grids);
  const double background = quantity(background_, "--background", true);
  for (std::size_t i = 0; i < scans.size(); ++i) {
    inject_background(scans[i], background);
    write_scan(scans[i], out / written[i]);
  }
  // The planes scanned, for the seeds and directions of `mri inflow --landmarks`.
  geometry::write_landmarks(planes, GeometryFiles{out}.landmarks());
  fmt::print("mri synthesize '{}': {} scans ({}, {} mm pixels, {} mm slices, {} frames, SNR {}) "
             "in {:.2f} s: {} in '{}'\n",
             run_dir_, written.size(), encoding_name(encoding_of(scan_type_)), pixel * 1e3,
             thickness * 1e3, frames_, snr_, seconds_since(t0), fmt::join(written, ", "),
             out.string());
  return 0;
}

int MriCommand::synthesize_from_run() const {
  if (scan_type_ != "4d")
    return synthesize_slices_of_run();
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
  scan.encoding = encoding_of(scan_type_);
  Vec3 spacing{voxel, voxel, voxel};
  if (scan.encoding != Encoding::velocity_3d) { // one slice through the pipe's centre
    if (!size_.empty() && size[2] != 1)
      input_error("--size '{}': a 2D scan has one slice (NX,NY,1)", size_);
    size[2] = 1;
    spacing[2] = quantity(thickness_, "--thickness", false);
    if (!(spacing[2] > 0))
      input_error("mri synthesize --thickness '{}': a positive slice thickness is expected",
                  thickness_);
    if (format_ != "dicom" && format_ != "dicom-rescaled")
      input_error("mri synthesize --scan-type {}: 2D scans are written as DICOM (--format dicom "
                  "or dicom-rescaled)",
                  scan_type_);
  }
  if (!at_.empty())
    input_error("mri synthesize --at: landmark planes are a run's (give RUN_DIR)");
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
  scan.grid = centred_grid(scan.axis_point, rotation({1, 1, 0}, rotate_), size, spacing);
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
  CorrectionChoice choice;
  if (!venc_override_.empty())
    choice.venc = quantity(venc_override_, "--venc", true);
  choice.unwrap = !no_unwrap_;
  choice.background = !no_background_;
  choice.background_order = background_order_;
  Flow4D data = read_corrected(input, choice, report);
  data.require(Encoding::velocity_3d,
               fmt::format("'{}' (2D scans: `mri inflow` and `mri cine`)", input));
  return data;
}

int MriCommand::flow() const {
  nlohmann::json report;
  Flow4D data = load_corrected(input_, report);
  geometry::Landmarks landmarks = geometry::read_landmarks(landmarks_);
  const ScanPlacement placed = place_scan(data, align_, align_surface_, lumen_fraction_, report);
  if (!align_.empty() || !align_surface_.empty())
    landmarks = transformed(landmarks, placed.transform);
  if (placed.fit && !quiet_)
    fmt::print("surface alignment ({} start, {} iterations): RMS {:.3f} mm over {} of {} "
               "boundary points\n",
               placed.fit->start, placed.fit->iterations, placed.fit->transform.rms * 1e3,
               placed.fit->kept, placed.fit->points);
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
    std::size_t not_numbers = 0;
    for (const NonFiniteImage& i : data.non_finite)
      not_numbers += i.total();
    if (not_numbers > 0)
      fmt::print("the {} voxel value(s) that are not numbers (above) lie outside every "
                 "landmark's lumen section: no flow, area or velocity read them (mri.json: "
                 "non_finite)\n",
                 not_numbers);
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
