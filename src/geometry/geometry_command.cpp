#include "geometry/geometry_command.hpp"

#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/file_layout.hpp"
#include "core/units.hpp"
#include "geometry/boundary_layers.hpp"
#include "geometry/geometry_report.hpp"
#include "geometry/import.hpp"
#include "geometry/label_model.hpp"
#include "geometry/tbad_builder.hpp"
#include "geometry/voxelize.hpp"
#include "mesh/readers.hpp"

namespace tearflow::geometry {

namespace {
constexpr double mm = units::mm, mm2 = units::mm * units::mm;
} // namespace

/// Option values as typed (mm, mm^2, degrees); converted to a TbadSpec in `tbad_spec()`.
struct GeometryOptions {
  std::string output, variant = "OR";
  bool verbose = false;
  // tbad, in mm / mm^2 / degrees; NaN: keep the default (or the variant's value).
  double element_size = NAN, tear_element_size = NAN, wall_thickness = NAN, flap_length = NAN;
  double entry_area = NAN, exit_area = NAN, entry_position = NAN, exit_position = NAN;
  double tear_aspect = NAN, outlet_distance = NAN, inlet_extension = NAN;
  double ascending_length = NAN, ascending_bow = NAN, arch_radius = NAN, descending_bend = NAN;
  double aao_area = NAN, dao_dist_area = NAN, arch_distal_radius = NAN, flap_start_gap = NAN;
  double station_offset = NAN, bct_radius = NAN, lcc_radius = NAN, lsa_radius = NAN;
  double branch_length = NAN, taper_length = NAN, fl_end_depth = NAN;
  int lumen_elements = -1; // -1: keep the default
  std::vector<double> tl_areas, fl_areas;
  // import
  std::string mesh, wall_mesh, lumen, wall, landmarks, units = "mm";
  std::vector<std::string> renames;
  bool keep_surfaces = false;
  // report
  std::string dir, png;
  bool no_png = false;
  // labels (its SCAN is `dir`; also element_size, wall_thickness, entry/exit_area, renames,
  // landmarks, station_offset)
  int true_lumen = 1, false_lumen = 2, thrombus_label = -1;
  std::vector<std::string> tear_areas;
  // boundary layers (tbad, labels, layers; mm): count, first layer, growth, walls
  int layers = 0;
  double first_layer = NAN, layer_growth = NAN, layer_fraction = NAN;
  std::vector<std::string> layer_walls;
  // voxelize (its DIR is `dir`), in mm and degrees
  double voxel_spacing = 1.0;
  std::vector<double> rotate;
  bool thrombus = false;

  TbadSpec tbad_spec() const {
    TbadSpec s;
    apply_variant(s, variant);
    auto set = [](double& target, double value, double scale) {
      if (!std::isnan(value))
        target = value * scale;
    };
    set(s.element_size, element_size, mm);
    set(s.tear_element_size, tear_element_size, mm);
    if (lumen_elements >= 0)
      s.lumen_elements = lumen_elements;
    set(s.wall_thickness, wall_thickness, mm);
    set(s.flap_length, flap_length, mm);
    set(s.taper_length, taper_length, mm);
    set(s.fl_end_depth, fl_end_depth, mm);
    set(s.entry_tear.area, entry_area, mm2);
    set(s.exit_tear.area, exit_area, mm2);
    set(s.entry_tear.position, entry_position, mm);
    set(s.exit_tear.position, exit_position, mm);
    set(s.entry_tear.aspect, tear_aspect, 1);
    set(s.exit_tear.aspect, tear_aspect, 1);
    set(s.outlet_distance, outlet_distance, mm);
    set(s.inlet_extension, inlet_extension, mm);
    set(s.ascending_length, ascending_length, mm);
    set(s.ascending_bow, ascending_bow, mm);
    set(s.arch_radius, arch_radius, mm);
    set(s.descending_bend, descending_bend, M_PI / 180);
    set(s.aao_area, aao_area, mm2);
    set(s.dao_dist_area, dao_dist_area, mm2);
    set(s.arch_distal_radius, arch_distal_radius, mm);
    set(s.flap_start_gap, flap_start_gap, mm);
    set(s.station_offset, station_offset, mm);
    set(s.branches[0].radius, bct_radius, mm);
    set(s.branches[1].radius, lcc_radius, mm);
    set(s.branches[2].radius, lsa_radius, mm);
    for (BranchSpec& b : s.branches)
      set(b.length, branch_length, mm);
    for (auto [values, target, name] : {std::tuple{&tl_areas, &s.tl_areas, "--tl-areas"},
                                        {&fl_areas, &s.fl_areas, "--fl-areas"}}) {
      if (values->empty())
        continue;
      if (values->size() != 5)
        input_error("{}: expected 5 areas (stations 1 to 5), got {}", name, values->size());
      for (int k = 0; k < 5; ++k)
        (*target)[k] = (*values)[k] * mm2;
    }
    return s;
  }
};

namespace {

// NAME=VALUE (VALUE a finite number), for --tear-area and --face.
std::pair<std::string, std::string> name_value(const std::string& text, const char* option) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
    input_error("{} '{}': expected NAME=VALUE", option, text);
  return {text.substr(0, eq), text.substr(eq + 1)};
}

BoundaryLayerSpec layer_spec(const GeometryOptions& o) {
  BoundaryLayerSpec spec;
  spec.count = o.layers;
  if (std::isnan(o.first_layer))
    input_error("--layers {}: give the first layer's thickness with --first-layer (mm)", o.layers);
  spec.first = o.first_layer * mm;
  if (!std::isnan(o.layer_growth))
    spec.growth = o.layer_growth;
  if (!std::isnan(o.layer_fraction))
    spec.max_fraction = o.layer_fraction;
  return spec;
}

void print_layers(const BoundaryLayerReport& r, const BoundaryLayerSpec& spec) {
  fmt::print("boundary layers: {} of {:.3g} mm growing by {}: {} wall nodes, {} tets added; "
             "total {:.2f} mm; thinner at {} nodes where the lumen is thin, none at {}\n",
             spec.count, spec.first / mm, spec.growth, r.wall_nodes, r.tets_added, r.thickest / mm,
             r.thinned, r.ended);
}

/// --layers, --first-layer, --layer-growth, --layer-fraction on a model-building command.
void add_layer_options(CLI::App* sub, GeometryOptions& o) {
  sub->add_option("--layers", o.layers,
                  "prismatic boundary layers on the lumen's wall and the flap (0: none; "
                  "docs/geometry.md)");
  sub->add_option("--first-layer", o.first_layer, "the wall layer's thickness, mm");
  sub->add_option("--layer-growth", o.layer_growth,
                  "thickness ratio of neighbouring layers, inwards (1.2)");
  sub->add_option("--layer-fraction", o.layer_fraction,
                  "largest share of the lumen's local thickness the layers take (0.3)");
}

/// The model's mesh with the layers the options ask for (none: as it is), rewritten in DIR.
void layer_model(const GeometryOptions& o, const mesh::Mesh& built, const Landmarks& landmarks) {
  if (o.layers <= 0)
    return;
  const BoundaryLayerSpec spec = layer_spec(o);
  BoundaryLayerReport report;
  const mesh::Mesh layered = add_boundary_layers(built, "fluid", {"interface"}, spec, &report);
  print_layers(report, spec);
  write_geometry(layered, landmarks, o.output);
}

/// `geometry layers IN -o OUT`: a geometry directory's mesh (or a .msh file, in --units) with
/// boundary layers, written as OUT/mesh.msh with IN's landmarks.
int run_layers(const GeometryOptions& o) {
  const std::filesystem::path in = o.dir;
  const bool directory = std::filesystem::is_directory(in);
  const std::filesystem::path msh = directory ? GeometryFiles{in}.mesh() : in;
  const double scale = directory ? mm : units::length_scale(o.units, "--units");
  mesh::Mesh m = mesh::read_mesh(msh, scale);
  std::vector<std::string> walls = o.layer_walls;
  if (walls.empty())
    walls = {m.has_face("interface") ? "interface" : "wall"};
  const BoundaryLayerSpec spec = layer_spec(o);
  BoundaryLayerReport report;
  const mesh::Mesh layered = add_boundary_layers(m, "fluid", walls, spec, &report);
  print_layers(report, spec);
  if (directory && std::filesystem::is_regular_file(GeometryFiles{in}.landmarks())) {
    write_geometry(layered, read_landmarks(GeometryFiles{in}.landmarks()), o.output);
  } else {
    std::filesystem::create_directories(o.output);
    write_msh(layered, GeometryFiles{o.output}.mesh());
  }
  fmt::print("wrote {}\n", GeometryFiles{o.output}.mesh().string());
  return 0;
}

int run_labels(const GeometryOptions& o) {
  LabelModelOptions lo;
  lo.dissection.roles = {o.true_lumen, o.false_lumen, o.thrombus_label};
  if (!std::isnan(o.wall_thickness))
    lo.dissection.wall_thickness = o.wall_thickness * mm;
  if (!std::isnan(o.element_size))
    lo.element_size = o.element_size * mm;
  if (!std::isnan(o.station_offset))
    lo.station_offset = o.station_offset * mm;
  if (!std::isnan(o.entry_area))
    lo.tear_areas.push_back({"entry", o.entry_area * mm2});
  if (!std::isnan(o.exit_area))
    lo.tear_areas.push_back({"exit", o.exit_area * mm2});
  for (const std::string& t : o.tear_areas) {
    const auto [name, value] = name_value(t, "--tear-area");
    double area = NAN;
    std::size_t used = 0;
    try {
      area = std::stod(value, &used);
    } catch (const std::exception&) {
    }
    if (used != value.size() || !std::isfinite(area))
      input_error("--tear-area {}: '{}' is not a number of mm^2", name, value);
    lo.tear_areas.push_back({name, area * mm2});
  }
  for (const std::string& r : o.renames)
    lo.rename_faces.push_back(name_value(r, "--face"));
  lo.landmarks = o.landmarks;
  lo.verbose = o.verbose;
  // Checked before minutes of work, in the options' own units.
  for (auto [value, option] : {std::pair{lo.element_size, "--element-size"},
                               {lo.dissection.wall_thickness, "--wall-thickness"},
                               {lo.station_offset, "--station-offset"}})
    if (!(value > 0))
      input_error("{} {} mm: expected a positive length", option, value / mm);
  for (const auto& [name, area] : lo.tear_areas)
    if (!(area > 0))
      input_error("tear '{}': area {} mm^2, expected a positive number", name, area / mm2);
  const LabelModel m = geometry_from_labels(o.dir, lo, o.output);
  std::size_t fluid = 0;
  for (std::size_t t = 0; t < m.mesh.tets.size(); ++t)
    fluid += m.mesh.regions[m.mesh.tet_region[t]] == "fluid";
  fmt::print("labels: flap gap {:.2f} mm; caps:", m.flap_gap / mm);
  for (const LabelCap& c : m.caps)
    fmt::print(" {} {:.0f} mm^2", c.name, c.area / mm2);
  fmt::print("\ntears:");
  for (const LabelTear& t : m.tears)
    fmt::print(" {} {:.1f} mm^2{}", t.name, t.area / mm2,
               t.growth != 0 ? fmt::format(" (labels: {:.1f})", t.found_area / mm2) : "");
  fmt::print("\n{} nodes, {} fluid and {} wall tets; fields {:.1f} s, landmarks {:.1f} s, "
             "meshing {:.1f} s\nwrote {}, {} and {}\n",
             m.mesh.num_nodes(), fluid, m.mesh.tets.size() - fluid, m.seconds_fields,
             m.seconds_landmarks, m.seconds_mesh, GeometryFiles{o.output}.mesh().string(),
             GeometryFiles{o.output}.landmarks().string(),
             (std::filesystem::path(o.output) / "labels.json").string());
  layer_model(o, m.mesh, m.landmarks);
  return 0;
}

} // namespace

GeometryCommand::GeometryCommand(CLI::App& app) : options_(std::make_unique<GeometryOptions>()) {
  GeometryOptions& o = *options_;
  command_ = app.add_subcommand("geometry", "build, import or report a TBAD geometry");
  command_->require_subcommand(1);

  tbad_ = command_->add_subcommand(
      "tbad", "build and mesh the parametric type B dissection (lengths in mm, areas in mm^2)");
  tbad_->add_option("-o,--output", o.output, "output directory")->required();
  tbad_->add_option("--variant", o.variant, "reference study tear sizes: OR, EN or EX")
      ->check(CLI::IsMember({"OR", "EN", "EX"}));
  tbad_->add_option("--element-size", o.element_size,
                    "target element size, mm (default 3; 1.0 gives the study's 1.3 mm edges, "
                    "0.9 M fluid / 0.5 M wall tets)");
  tbad_->add_option("--tear-element-size", o.tear_element_size,
                    "element size at the tears, mm (default: 24 edges around each tear)");
  tbad_
      ->add_option("--lumen-elements", o.lumen_elements,
                   "elements across the true lumen's thickness in the dissected segment "
                   "(default 3; 0: uniform element size)")
      ->check(CLI::Range(0, 10));
  tbad_->add_option("--wall-thickness", o.wall_thickness, "wall and flap thickness h, mm (2)");
  tbad_->add_option("--flap-length", o.flap_length,
                    "dissection flap from its start to its distal taper, mm (200)");
  tbad_->add_option("--taper-length", o.taper_length,
                    "distal taper over which the flap re-attaches to the wall, mm (25)");
  tbad_->add_option("--fl-end-depth", o.fl_end_depth,
                    "false lumen depth at its distal end cap, mm (4)");
  tbad_->add_option("--entry-tear-area", o.entry_area, "mm^2 (overrides the variant's)");
  tbad_->add_option("--exit-tear-area", o.exit_area, "mm^2 (overrides the variant's)");
  tbad_->add_option("--entry-tear-position", o.entry_position,
                    "entry tear centre from the flap's proximal end, mm (15)");
  tbad_->add_option("--exit-tear-position", o.exit_position,
                    "exit tear centre from the start of the flap's distal taper, mm (default "
                    "0: just proximal to it, its axial semi-axis + max(2, h); 13.4 for 227 "
                    "mm^2)");
  tbad_->add_option("--tear-aspect", o.tear_aspect, "tear length over width (1.8)");
  tbad_->add_option("--outlet-distance", o.outlet_distance,
                    "outlet distal to the false lumen's end, mm (21.6)");
  tbad_->add_option("--inlet-extension", o.inlet_extension, "straight inlet extension, mm (20)");
  tbad_->add_option("--ascending-length", o.ascending_length, "ascending aorta, mm (50)");
  tbad_->add_option("--ascending-bow", o.ascending_bow,
                    "out-of-plane offset of the ascending aorta, mm (8)");
  tbad_->add_option("--arch-radius", o.arch_radius, "tightest arch radius of curvature, mm (25)");
  tbad_->add_option("--descending-bend", o.descending_bend,
                    "bend of the descending aorta, degrees (6.9)");
  tbad_->add_option("--aao-area", o.aao_area, "ascending aorta lumen area, mm^2 (492.6)");
  tbad_->add_option("--dao-dist-area", o.dao_dist_area,
                    "lumen area distal to the dissection, mm^2 (365.5)");
  tbad_->add_option("--arch-distal-radius", o.arch_distal_radius,
                    "lumen radius at the LSA, mm (11)");
  tbad_->add_option("--flap-start-gap", o.flap_start_gap,
                    "flap start distal to the LSA's wall, mm (6)");
  tbad_->add_option("--station-offset", o.station_offset,
                    "TL1/FL1 (TL5/FL5) distal (proximal) to the entry (exit) tear, mm (24)");
  tbad_->add_option("--tl-areas", o.tl_areas, "true lumen areas at stations 1..5, mm^2")
      ->expected(5)
      ->delimiter(',');
  tbad_->add_option("--fl-areas", o.fl_areas, "false lumen areas at stations 1..5, mm^2")
      ->expected(5)
      ->delimiter(',');
  tbad_->add_option("--bct-radius", o.bct_radius, "mm (6)");
  tbad_->add_option("--lcc-radius", o.lcc_radius, "mm (3.5)");
  tbad_->add_option("--lsa-radius", o.lsa_radius, "mm (4.5)");
  tbad_->add_option("--branch-length", o.branch_length,
                    "branch length from the aortic centreline, mm (45)");
  add_layer_options(tbad_, o);
  tbad_->add_flag("-v,--verbose", o.verbose, "show Gmsh's progress");

  import_ =
      command_->add_subcommand("import", "check a user's model and write the geometry layout");
  import_->add_option("-o,--output", o.output, "output directory")->required();
  import_->add_option("--mesh", o.mesh, "finished mesh: .msh or SimVascular mesh-complete dir");
  import_->add_option("--wall-mesh", o.wall_mesh,
                      "separate wall mesh sharing the fluid's wall nodes (SimVascular FSI)");
  import_->add_option("--face", o.renames, "rename a face: OLD=NEW (repeatable)");
  import_->add_option("--lumen", o.lumen,
                      "lumen faces: a directory of STL/VTP files, one per face (inlet, ..., "
                      "interface), or one file");
  import_->add_option("--wall", o.wall,
                      "wall faces: a directory of STL/VTP files (outer_wall, wall_<cap> rings)");
  import_->add_option("--landmarks", o.landmarks, "landmarks JSON")->required();
  import_->add_option("--units", o.units, "length unit of the inputs: m, cm or mm (mm)");
  import_->add_option("--element-size", o.element_size, "element size for surfaces, mm (3)");
  import_->add_flag("--keep-surfaces", o.keep_surfaces,
                    "keep the surfaces' triangles as the mesh's boundary (no remeshing)");
  import_->add_flag("-v,--verbose", o.verbose, "show Gmsh's progress");

  report_ = command_->add_subcommand("report", "measure a geometry directory, render a picture");
  report_->add_option("dir", o.dir, "geometry directory (mesh.msh, landmarks.json)")->required();
  report_->add_option("--png", o.png, "picture file (default DIR/geometry.png)");
  report_->add_flag("--no-png", o.no_png, "no picture");

  // A number option given as nan or inf would read as "not given" (NaN keeps the default)
  // or run away: every FLOAT option must be finite (issue 28: --element-size nan meshed at
  // the default 3 mm without a word).
  const CLI::Validator finite(
      [](std::string& text) -> std::string {
        double v = 0;
        try {
          v = std::stod(text);
        } catch (const std::exception&) {
          return {}; // CLI11's own conversion reports it
        }
        return std::isfinite(v) ? std::string{} : "a finite number is expected, got '" + text + "'";
      },
      "FINITE");
  for (CLI::App* sub : {tbad_, import_})
    for (CLI::Option* option : sub->get_options())
      if (option->get_type_name() == "FLOAT")
        option->check(finite);

  // The header keeps no pointer to these two: run() finds them by name.
  CLI::App* labels = command_->add_subcommand(
      "labels", "build a dissection model from a segmented scan (label map): flap, tears, wall, "
                "caps, landmarks and mesh");
  labels->add_option("scan", o.dir, "label map: .nii.gz, .nii, .mha, .mhd, .nrrd or .nhdr")
      ->required();
  labels->add_option("-o,--output", o.output, "output directory")->required();
  labels->add_option("--true-lumen", o.true_lumen, "label of the true lumen (1)");
  labels->add_option("--false-lumen", o.false_lumen, "label of the false lumen (2)");
  labels->add_option("--thrombus", o.thrombus_label,
                     "label of thrombus in the false lumen (none); meshed as wall");
  labels->add_option("--wall-thickness", o.wall_thickness, "wall and flap thickness h, mm (2)");
  labels->add_option("--element-size", o.element_size, "target element size, mm (3)");
  labels->add_option("--entry-tear-area", o.entry_area, "resize the entry tear, mm^2");
  labels->add_option("--exit-tear-area", o.exit_area, "resize the exit tear, mm^2");
  labels->add_option("--tear-area", o.tear_areas,
                     "resize a tear: NAME=mm^2 (entry, exit, tear_2, ...; repeatable)");
  labels->add_option("--face", o.renames, "rename a cap: OLD=NEW (repeatable)");
  labels->add_option("--landmarks", o.landmarks,
                     "landmarks JSON to use instead of the ones placed on the centreline");
  labels->add_option("--station-offset", o.station_offset,
                     "TL1/FL1 (TL5/FL5) distal (proximal) to the entry (exit) tear, mm (24)");
  add_layer_options(labels, o);
  labels->add_flag("-v,--verbose", o.verbose, "show the stages");
  for (CLI::Option* option : labels->get_options())
    if (option->get_type_name() == "FLOAT")
      option->check(finite);

  CLI::App* layers = command_->add_subcommand(
      "layers", "add prismatic boundary layers on the lumen's wall to a model's mesh");
  layers->add_option("in", o.dir, "geometry directory (mesh.msh, landmarks.json) or a .msh file")
      ->required();
  layers->add_option("-o,--output", o.output, "output directory")->required();
  layers->add_option("--layers", o.layers, "number of layers")
      ->required()
      ->check(CLI::PositiveNumber);
  layers->add_option("--first-layer", o.first_layer, "the wall layer's thickness, mm")->required();
  layers->add_option("--growth", o.layer_growth, "thickness ratio of neighbouring layers (1.2)");
  layers->add_option("--max-fraction", o.layer_fraction,
                     "largest share of the lumen's local thickness the layers take (0.3)");
  layers
      ->add_option("--walls", o.layer_walls,
                   "faces to grow layers on (interface if the mesh has it, else wall)")
      ->delimiter(',');
  layers->add_option("--units", o.units, "length unit of a .msh file: m, cm or mm (mm)");
  for (CLI::Option* option : layers->get_options())
    if (option->get_type_name() == "FLOAT")
      option->check(finite);

  CLI::App* voxelize = command_->add_subcommand(
      "voxelize", "write a geometry as a label map: true lumen 1, false lumen 2, thrombus 3; "
                  "flap, wall and outside 0 (the round trip of `geometry labels`)");
  voxelize->add_option("dir", o.dir, "geometry directory (mesh.msh, landmarks.json)")->required();
  voxelize
      ->add_option("-o,--output", o.output,
                   "label map: .nii.gz, .nii, .mha, .mhd or .nrrd (coordinates in mm, LPS)")
      ->required();
  voxelize->add_option("--spacing", o.voxel_spacing, "isotropic voxel size, mm (1)")->check(finite);
  voxelize
      ->add_option("--rotate", o.rotate,
                   "image axes rotated about x, then y, then z: ax,ay,az in degrees (oblique "
                   "scan)")
      ->expected(3)
      ->delimiter(',')
      ->check(finite);
  voxelize->add_flag("--thrombus", o.thrombus,
                     "label the false lumen past the exit tear as thrombus (3)");
}

GeometryCommand::~GeometryCommand() = default;

bool GeometryCommand::selected() const {
  return command_->parsed();
}

int GeometryCommand::run() const {
  const GeometryOptions& o = *options_;
  if (tbad_->parsed()) {
    const TbadSpec spec = o.tbad_spec();
    // Long work is announced with its size before it starts. Measured (fluid + wall tets):
    // 0.24 M at 2.25 mm, 1.52 M at 1.0 mm: about h^-2.3 above 1 mm, where the tears' and
    // the true lumen's own sizes still hold part of the mesh, and h^-3 below (all uniform).
    if (const double h = spec.element_size / mm; h < 1.5) {
      const double tets = 1.52e6 * (h >= 1.0 ? std::pow(h, -2.3) : std::pow(h, -3.0));
      fmt::print("geometry tbad: element size {} mm gives about {:.2g} M tets (estimate); "
                 "meshing {}\n",
                 h, tets / 1e6, tets > 5e6 ? "takes tens of minutes or more" : "takes minutes");
      std::fflush(stdout);
    }
    const TbadBuild b = build_tbad(spec, o.output, o.verbose);
    std::size_t fluid = 0;
    for (std::size_t t = 0; t < b.mesh.tets.size(); ++t)
      fluid += b.mesh.regions[b.mesh.tet_region[t]] == "fluid";
    fmt::print("tbad ({} tears {:.0f} / {:.0f} mm^2, element size {} mm): {} nodes, {} fluid and "
               "{} wall tets; CAD {:.1f} s, meshing {:.1f} s\nwrote {} and {}\n",
               o.variant, spec.entry_tear.area / mm2, spec.exit_tear.area / mm2,
               spec.element_size / mm, b.mesh.num_nodes(), fluid, b.mesh.tets.size() - fluid,
               b.cad_seconds, b.mesh_seconds, GeometryFiles{o.output}.mesh().string(),
               GeometryFiles{o.output}.landmarks().string());
    layer_model(o, b.mesh, b.landmarks);
    return 0;
  }
  if (import_->parsed()) {
    ImportOptions io;
    io.mesh = o.mesh;
    io.wall_mesh = o.wall_mesh;
    for (const std::string& r : o.renames) {
      const auto eq = r.find('=');
      if (eq == std::string::npos || eq == 0 || eq + 1 == r.size())
        input_error("--face '{}': expected OLD=NEW", r);
      io.rename_faces.push_back({r.substr(0, eq), r.substr(eq + 1)});
    }
    io.lumen = o.lumen;
    io.wall = o.wall;
    io.landmarks = o.landmarks;
    io.length_scale = units::length_scale(o.units, "--units");
    if (!std::isnan(o.element_size))
      io.element_size = o.element_size * mm;
    io.verbose = o.verbose;
    io.remesh_surfaces = !o.keep_surfaces;
    import_geometry(io, o.output);
    fmt::print("wrote {} and {}\n", GeometryFiles{o.output}.mesh().string(),
               GeometryFiles{o.output}.landmarks().string());
    return 0;
  }
  if (command_->get_subcommand("labels")->parsed())
    return run_labels(o);
  if (command_->get_subcommand("layers")->parsed())
    return run_layers(o);
  if (const CLI::App* voxelize = command_->get_subcommand("voxelize"); voxelize->parsed()) {
    VoxelizeOptions vo;
    vo.spacing = o.voxel_spacing * mm;
    if (!o.rotate.empty())
      vo.rotation = {o.rotate[0], o.rotate[1], o.rotate[2]};
    vo.thrombus = o.thrombus;
    const VoxelizeResult r = voxelize_geometry(o.dir, vo, o.output);
    fmt::print("{} x {} x {} voxels of {} mm; label: voxels, volume\n", r.size[0], r.size[1],
               r.size[2], o.voxel_spacing);
    fmt::print("  {} true lumen: {}, {:.2f} mL\n  {} false lumen: {}, {:.2f} mL\n", vo.true_lumen,
               r.tl_voxels, r.tl_volume / units::mL, vo.false_lumen, r.fl_voxels,
               r.fl_volume / units::mL);
    if (vo.thrombus)
      fmt::print("  {} thrombus: {}, {:.2f} mL\n", vo.thrombus_label, r.thrombus_voxels,
                 r.thrombus_volume / units::mL);
    if (r.pocket_voxels > 0)
      fmt::print("({} voxels in pockets cut off from both lumens took their neighbours' label)\n",
                 r.pocket_voxels);
    fmt::print("wrote {}\n", o.output);
    return 0;
  }
  const std::filesystem::path dir = o.dir;
  std::filesystem::path png = o.png.empty() ? dir / "geometry.png" : std::filesystem::path(o.png);
  // Without an X display the picture starts a virtual one (core/virtual_display.hpp).
  if (o.no_png)
    png.clear();
  report_geometry(dir, png);
  return 0;
}

} // namespace tearflow::geometry
