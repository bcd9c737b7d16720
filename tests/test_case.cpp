// Case files: a complete case loads into SI values, defaults fill what is left out, and
// every kind of bad input is an InputError naming the file, line and key path.
// Inputs live in tests/data/cases/; bad_*.yaml each hold one mistake.
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <memory>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <spdlog/sinks/ringbuffer_sink.h>
#include <spdlog/spdlog.h>

#include "core/error.hpp"
#include "core/units.hpp"
#include "io/case.hpp"
#include "io/case_yaml.hpp"

using namespace tearflow;
using testing::HasSubstr;
namespace fs = std::filesystem;

namespace {

const fs::path kCases = fs::path(TEARFLOW_SOURCE_DIR) / "tests" / "data" / "cases";
const fs::path kShared = (fs::path(TEARFLOW_SOURCE_DIR) / ".." / "shared").lexically_normal();

/// The message of the InputError that load_case throws for `file` ("" if none).
std::string load_error(const fs::path& file) {
  try {
    io::load_case(file);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

} // namespace

// --- valid cases -------------------------------------------------------------------------

TEST(LoadCase, FullCaseInSiUnits) {
  const io::Case c = io::load_case(kCases / "full.yaml");
  EXPECT_EQ(c.name, "full-case");
  EXPECT_EQ(c.file, (kCases / "full.yaml").lexically_normal());

  // Mesh path taken from the case file's folder; `units: mm`.
  EXPECT_EQ(c.mesh.file, kShared / "meshes" / "pipe-rcr");
  EXPECT_DOUBLE_EQ(c.mesh.length_scale, 1e-3);
  EXPECT_FALSE(c.mesh.pipe.has_value());

  EXPECT_DOUBLE_EQ(c.fluid.density, 1050.0);
  EXPECT_DOUBLE_EQ(c.fluid.viscosity, 0.0035);
  EXPECT_DOUBLE_EQ(c.fluid.stabilization.time_scale, 0.005);
  EXPECT_FALSE(c.fluid.stabilization.viscous_correction);
  EXPECT_DOUBLE_EQ(c.fluid.stabilization.grad_div, 0.5);
  EXPECT_EQ(c.fluid.stabilization.metric, physics::StabilizationSpec::Metric::reference_tet);

  EXPECT_DOUBLE_EQ(c.time.step, 0.005);
  EXPECT_EQ(c.time.steps, 200); // end 1.0 s / step 5 ms
  EXPECT_DOUBLE_EQ(c.time.spectral_radius, 0.4);

  ASSERT_EQ(c.boundary_conditions.size(), 4u);
  const bc::BoundaryCondition& wall = c.boundary_conditions[0];
  EXPECT_EQ(wall.face, "lumen_wall");
  EXPECT_TRUE(std::holds_alternative<bc::NoSlip>(wall.kind));

  // Inflow from inflow.csv in mL/s -> m^3/s; the spline passes through the samples.
  EXPECT_EQ(c.boundary_conditions[1].face, "lumen_inlet");
  ASSERT_TRUE(c.boundary_conditions[1].inflow());
  const bc::Inflow& inlet = *c.boundary_conditions[1].inflow();
  EXPECT_EQ(inlet.profile, bc::ProfileShape::Womersley);
  EXPECT_EQ(inlet.womersley_modes, 8);
  EXPECT_FALSE(inlet.flow.is_constant());
  EXPECT_DOUBLE_EQ(inlet.flow.period(), 1.0);
  EXPECT_NEAR(inlet.flow(0.0), 10e-6, 1e-15);
  EXPECT_NEAR(inlet.flow(0.2), 300e-6, 1e-15);
  EXPECT_NEAR(inlet.flow(1.2), 300e-6, 1e-15); // one period later

  // Constant pressure in mmHg -> Pa.
  ASSERT_TRUE(c.boundary_conditions[2].outlet());
  const bc::Outlet& outlet = *c.boundary_conditions[2].outlet();
  const auto* pressure = std::get_if<bc::PressureOutlet>(&outlet.law);
  ASSERT_TRUE(pressure);
  EXPECT_TRUE(pressure->pressure.is_constant());
  EXPECT_NEAR(pressure->pressure(0.3), 80.0 * units::mmHg, 1e-9);
  EXPECT_DOUBLE_EQ(outlet.backflow_beta, 0.3);

  ASSERT_TRUE(c.boundary_conditions[3].outlet());
  const bc::Outlet& branch = *c.boundary_conditions[3].outlet();
  const auto* resistance = std::get_if<bc::ResistanceOutlet>(&branch.law);
  ASSERT_TRUE(resistance);
  EXPECT_DOUBLE_EQ(resistance->resistance, 1.2e7);
  EXPECT_DOUBLE_EQ(branch.backflow_beta, 0.0);

  EXPECT_EQ(c.newton.max_iterations, 6);
  EXPECT_DOUBLE_EQ(c.newton.rtol, 1e-5);
  EXPECT_DOUBLE_EQ(c.newton.atol, 1e-9);
  EXPECT_DOUBLE_EQ(c.newton.continuity, 2e-4);

  EXPECT_EQ(c.petsc_options, "-fluid_ksp_type gmres -fluid_pc_type bjacobi -fluid_ksp_monitor");

  // Output directory relative to the working directory, stored absolute.
  EXPECT_EQ(c.output.directory, fs::absolute("out/full").lexically_normal());
  EXPECT_EQ(c.output.every, 5);
  EXPECT_EQ(c.output.checkpoint_every, 50);
}

TEST(LoadCase, DefaultsFillTheRest) {
  const io::Case c = io::load_case(kCases / "minimal.yaml");
  const io::Case defaults;
  EXPECT_EQ(c.name, "minimal"); // the file's stem
  EXPECT_TRUE(c.mesh.file.empty());
  ASSERT_TRUE(c.mesh.pipe.has_value());
  EXPECT_DOUBLE_EQ(c.mesh.pipe->radius, mesh::PipeSpec{}.radius);
  EXPECT_DOUBLE_EQ(c.mesh.pipe->length, mesh::PipeSpec{}.length);
  EXPECT_DOUBLE_EQ(c.mesh.pipe->element_size, mesh::PipeSpec{}.element_size);
  EXPECT_DOUBLE_EQ(c.mesh.length_scale, 1.0);
  EXPECT_DOUBLE_EQ(c.fluid.density, defaults.fluid.density);
  EXPECT_DOUBLE_EQ(c.fluid.viscosity, defaults.fluid.viscosity);
  EXPECT_EQ(c.fluid.stabilization.time_scale, -1.0); // automatic
  EXPECT_EQ(c.fluid.stabilization.effective_time_scale(0.01), 0.005);
  EXPECT_EQ(c.fluid.stabilization.viscous_correction, true);
  EXPECT_EQ(c.fluid.stabilization.grad_div, 0.125);
  EXPECT_EQ(c.fluid.stabilization.metric, physics::StabilizationSpec::Metric::symmetric);
  EXPECT_EQ(c.newton.continuity, 1e-3);
  EXPECT_DOUBLE_EQ(c.time.step, 0.01);
  EXPECT_EQ(c.time.steps, defaults.time.steps);
  EXPECT_DOUBLE_EQ(c.time.spectral_radius, defaults.time.spectral_radius);

  ASSERT_EQ(c.boundary_conditions.size(), 1u);
  ASSERT_TRUE(c.boundary_conditions[0].inflow());
  const bc::Inflow& inlet = *c.boundary_conditions[0].inflow();
  EXPECT_TRUE(inlet.flow.is_constant());
  EXPECT_DOUBLE_EQ(inlet.flow(0.0), 2.0e-6); // m3/s by default
  EXPECT_EQ(inlet.profile, bc::ProfileShape::Parabolic);

  EXPECT_EQ(c.newton.max_iterations, defaults.newton.max_iterations);
  EXPECT_EQ(c.petsc_options, "");
  EXPECT_EQ(c.output.directory, fs::absolute("results/minimal").lexically_normal());
  EXPECT_EQ(c.output.every, defaults.output.every);
  EXPECT_EQ(c.output.checkpoint_every, defaults.output.checkpoint_every);
}

TEST(LoadCase, PipeWithBoundaryLayers) {
  const io::Case c = io::load_case(kCases / "pipe_layers.yaml");
  ASSERT_TRUE(c.mesh.pipe.has_value());
  const mesh::BoundaryLayers& bl = c.mesh.pipe->layers;
  EXPECT_EQ(bl.count, 4);
  EXPECT_DOUBLE_EQ(bl.first, 2.0e-4);
  EXPECT_DOUBLE_EQ(bl.growth, 1.4);
  EXPECT_EQ(bl.wall_layers, mesh::BoundaryLayers{}.wall_layers);
  EXPECT_EQ(mesh::PipeSpec{}.layers.count, 0); // none unless asked for
}

TEST(LoadCase, InlineSamplesAndSimVascularFlow) {
  const io::Case c = io::load_case(kCases / "samples.yaml");
  ASSERT_EQ(c.boundary_conditions.size(), 3u);
  ASSERT_TRUE(c.mesh.pipe.has_value());
  EXPECT_DOUBLE_EQ(c.mesh.pipe->radius, 0.005);
  EXPECT_EQ(c.time.steps, 3);

  // SimVascular .flow in cm^3/s, negative into the domain; sign -1 makes it positive.
  ASSERT_TRUE(c.boundary_conditions[0].inflow());
  const bc::Inflow& inlet = *c.boundary_conditions[0].inflow();
  EXPECT_EQ(inlet.profile, bc::ProfileShape::Plug);
  EXPECT_DOUBLE_EQ(inlet.flow.period(), 1.0);
  EXPECT_NEAR(inlet.flow(0.0625), 4.782786e-6, 1e-12);

  // Inline samples in ms and mmHg with an explicit period.
  ASSERT_TRUE(c.boundary_conditions[1].outlet());
  const auto* outlet = std::get_if<bc::PressureOutlet>(&c.boundary_conditions[1].outlet()->law);
  ASSERT_TRUE(outlet);
  EXPECT_DOUBLE_EQ(outlet->pressure.period(), 1.0);
  EXPECT_NEAR(outlet->pressure(0.2), 120.0 * units::mmHg, 1e-9);
  EXPECT_NEAR(outlet->pressure(1.2), 120.0 * units::mmHg, 1e-9);
  // The cardiac period comes from the waveforms; 1 s is 1000 steps of 1 ms.
  EXPECT_DOUBLE_EQ(c.time.period, 1.0);
  EXPECT_EQ(c.time.steps_per_cycle, 1000);

  EXPECT_EQ(c.petsc_options, "-fluid_ksp_type fgmres -fluid_pc_type asm");
}

TEST(LoadCase, WindkesselOutletAndPeriodicityStop) {
  const io::Case c = io::load_case(kCases / "rcr_cycles.yaml");
  ASSERT_TRUE(c.boundary_conditions[1].outlet());
  const auto* outlet = std::get_if<bc::RcrOutlet>(&c.boundary_conditions[1].outlet()->law);
  ASSERT_TRUE(outlet);
  EXPECT_DOUBLE_EQ(outlet->rcr.proximal_resistance, 1.21e7);
  EXPECT_DOUBLE_EQ(outlet->rcr.capacitance, 1.5e-10);
  EXPECT_DOUBLE_EQ(outlet->rcr.distal_resistance, 1.212e8);
  EXPECT_NEAR(outlet->rcr.reference_pressure, 5.0 * units::mmHg, 1e-9);
  ASSERT_TRUE(outlet->initial_distal_pressure.has_value());
  EXPECT_NEAR(*outlet->initial_distal_pressure, 80.0 * units::mmHg, 1e-9);
  // Period from the .flow file; at most 6 cycles of 100 steps.
  EXPECT_DOUBLE_EQ(c.time.period, 1.0);
  EXPECT_EQ(c.time.steps_per_cycle, 100);
  EXPECT_EQ(c.time.steps, 600);
  EXPECT_DOUBLE_EQ(c.time.periodicity_tolerance, 0.01);
  EXPECT_FALSE(c.time.start_from_0d);
}

TEST(LoadCase, RcOutlet) {
  const io::Case c = io::load_case(kCases / "rc_outlet.yaml");
  ASSERT_TRUE(c.boundary_conditions[1].outlet());
  const bc::Outlet& outlet = *c.boundary_conditions[1].outlet();
  const auto* rc = std::get_if<bc::RcOutlet>(&outlet.law);
  ASSERT_TRUE(rc);
  EXPECT_DOUBLE_EQ(rc->resistance, 1.333e8); // resistances and capacitances stay SI
  EXPECT_DOUBLE_EQ(rc->capacitance, 1.5e-10);
  EXPECT_NEAR(rc->reference_pressure, 5.0 * units::mmHg, 1e-9);
  ASSERT_TRUE(rc->initial_pressure.has_value());
  EXPECT_NEAR(*rc->initial_pressure, 80.0 * units::mmHg, 1e-9);
  EXPECT_DOUBLE_EQ(outlet.backflow_beta, 0.5);
  EXPECT_EQ(c.time.steps, 200);
}

// --- invalid cases -----------------------------------------------------------------------

TEST(LoadCase, MissingFileIsNamed) {
  const std::string message = load_error(kCases / "no_such_case.yaml");
  EXPECT_THAT(message, HasSubstr("no_such_case.yaml"));
  EXPECT_THAT(message, HasSubstr("not found"));
}

struct BadCase {
  const char* file; ///< in tests/data/cases
  int line;         ///< where the message must point
  const char* key;  ///< key path named in the message ("" for none)
  const char* says; ///< and what it must say
};

std::ostream& operator<<(std::ostream& os, const BadCase& b) {
  return os << b.file;
}

class BadCaseFile : public testing::TestWithParam<BadCase> {};

TEST_P(BadCaseFile, NamesFileLineAndKey) {
  const BadCase& bad = GetParam();
  const std::string message = load_error(kCases / bad.file);
  ASSERT_FALSE(message.empty()) << bad.file << " loaded without error";
  const std::string where = *bad.key ? fmt::format("{}:{}: {}", bad.file, bad.line, bad.key)
                                     : fmt::format("{}:{}", bad.file, bad.line);
  EXPECT_THAT(message, HasSubstr(where));
  EXPECT_THAT(message, HasSubstr(bad.says));
}

TEST(LoadCase, MissingMeshNamesThePath) {
  const std::string message = load_error(kCases / "bad_mesh_missing_file.yaml");
  EXPECT_THAT(message, HasSubstr((kCases / "meshes" / "no_such_mesh.msh").string()));
}

// clang-format off
INSTANTIATE_TEST_SUITE_P(LoadCase, BadCaseFile, testing::Values(
  BadCase{"bad_empty.yaml", 1, "", "the case file is empty"},
  BadCase{"bad_flow_magnitude.yaml", 9, "boundary_conditions[0].flow",
          "a peak of 300 m^3/s (3e+05 L/s) is no blood flow; the values are probably in mL/s: "
          "add `units: mL/s`"},
  BadCase{"bad_flow_magnitude_units.yaml", 10, "boundary_conditions[0].flow",
          "a peak of 0.3 m^3/s (300 L/s) is no blood flow; check the values against the units "
          "given"},
  BadCase{"bad_malformed.yaml", 4, "", "malformed YAML"},
  BadCase{"bad_unknown_key.yaml", 8, "fluid.viscocity",
          "unknown key 'viscocity' (did you mean 'viscosity'?); allowed keys in fluid: density, "
          "viscosity, stabilization_time_scale, viscous_correction, grad_div_scale, "
          "stabilization_metric"},
  BadCase{"bad_unknown_top_key.yaml", 10, "outputs", "did you mean 'output'?"},
  BadCase{"bad_duplicate_key.yaml", 9, "fluid.density", "given twice (first on line 7)"},
  BadCase{"bad_density_type.yaml", 7, "fluid.density", "expected a number > 0, got 'heavy'"},
  BadCase{"bad_quoted_number.yaml", 7, "fluid.viscosity",
          "expected a number > 0, got '0.004' (quoted, so a string; remove the quotes)"},
  BadCase{"bad_density_negative.yaml", 7, "fluid.density", "expected a number > 0, got '-1060'"},
  BadCase{"bad_spectral_radius.yaml", 6, "time.spectral_radius",
          "expected a number in [0, 1], got '1.5'"},
  BadCase{"bad_steps_fraction.yaml", 6, "time.steps", "expected an integer >= 1, got '2.5'"},
  BadCase{"bad_steps_and_end.yaml", 7, "time.end", "not both"},
  BadCase{"bad_missing_step.yaml", 4, "time.step", "required key 'step' is missing"},
  BadCase{"bad_missing_bcs.yaml", 2, "boundary_conditions",
          "required key 'boundary_conditions' is missing"},
  BadCase{"bad_bcs_not_list.yaml", 6, "boundary_conditions", "expected a list"},
  BadCase{"bad_empty_bcs.yaml", 6, "boundary_conditions", "at least one boundary condition"},
  BadCase{"bad_bc_missing_face.yaml", 10, "boundary_conditions[1].face",
          "required key 'face' is missing"},
  BadCase{"bad_bc_type.yaml", 11, "boundary_conditions[1].type",
          "unknown value 'no-slip' (did you mean 'no_slip'?)"},
  BadCase{"bad_key_for_type.yaml", 12, "boundary_conditions[1].backflow_beta",
          "does not apply here (type: no_slip)"},
  BadCase{"bad_profile.yaml", 10, "boundary_conditions[0].profile", "did you mean 'parabolic'?"},
  BadCase{"bad_womersley_constant.yaml", 10, "boundary_conditions[0].profile",
          "needs a periodic flow"},
  BadCase{"bad_womersley_modes.yaml", 11, "boundary_conditions[0].womersley_modes",
          "expected an integer from 1 to 256, got '1000000'"},
  BadCase{"bad_resistance_zero.yaml", 14, "boundary_conditions[2].resistance",
          "expected a number > 0, got '0'"},
  BadCase{"bad_duplicate_face.yaml", 12, "boundary_conditions[2].face",
          "face 'inlet' already has a boundary condition (boundary_conditions[0].face, line 7)"},
  BadCase{"bad_flow_units.yaml", 10, "boundary_conditions[0].units", "unknown flow unit 'mL/min'"},
  BadCase{"bad_waveform_missing.yaml", 9, "boundary_conditions[0].flow.file", "no_such_inflow.csv"},
  BadCase{"bad_samples_length.yaml", 11, "boundary_conditions[0].flow.values",
          "2 values for 3 times"},
  BadCase{"bad_mesh_both.yaml", 4, "mesh.pipe", "either mesh.file or mesh.pipe, not both"},
  BadCase{"bad_mesh_neither.yaml", 2, "mesh", "expected mesh.file"},
  BadCase{"bad_pipe_layers.yaml", 4, "mesh.pipe.boundary_layers.growth",
          "expected a number in [1.01, 3], got '5'"},
  BadCase{"bad_mesh_missing_file.yaml", 3, "mesh.file", "not found: "},
  BadCase{"bad_mesh_units.yaml", 4, "mesh.units",
          "unknown value 'inch'; expected one of m, cm or mm"},
  BadCase{"bad_petsc_nested.yaml", 11, "petsc_options.fluid", "expected a string, got a mapping"},
  BadCase{"bad_period.yaml", 15, "boundary_conditions[1].pressure",
          "the waveform's period is 0.6 s but the case's period is 1 s"},
  BadCase{"bad_period_mismatch.yaml", 12, "boundary_conditions[0].flow",
          "the waveform's period is 1 s but the case's period is 0.8 s (time.period)"},
  BadCase{"bad_rcr_capacitance.yaml", 14, "boundary_conditions[1].capacitance",
          "expected a number > 0, got '-1.0e-9'"},
  BadCase{"bad_rcr_capacitance_zero.yaml", 14, "boundary_conditions[1].capacitance",
          "expected a number > 0, got '0.0'"},
  BadCase{"bad_rcr_distal_zero.yaml", 15, "boundary_conditions[1].distal_resistance",
          "expected a number > 0, got '0'"},
  BadCase{"bad_rcr_proximal_negative.yaml", 13, "boundary_conditions[1].proximal_resistance",
          "expected a number >= 0, got '-1.0e7'"},
  BadCase{"bad_rcr_missing_c.yaml", 11, "boundary_conditions[1]",
          "required key 'capacitance' is missing"},
  BadCase{"bad_rcr_key.yaml", 13, "boundary_conditions[1].resistance",
          "key 'resistance' does not apply here (type: rcr)"},
  BadCase{"bad_rc_key.yaml", 13, "boundary_conditions[1].proximal_resistance",
          "key 'proximal_resistance' does not apply here (type: rc)"},
  BadCase{"bad_rc_missing_c.yaml", 11, "boundary_conditions[1]",
          "required key 'capacitance' is missing"},
  BadCase{"bad_cycles_step.yaml", 7, "time.cycles",
          "the period 1 s is not a multiple of time.step = 0.003 s"},
  BadCase{"bad_cycles_and_steps.yaml", 8, "time.cycles", "not both time.steps and time.cycles"}),
  [](const testing::TestParamInfo<BadCase>& info) {
    std::string name = fs::path(info.param.file).stem().string();
    std::replace_if(name.begin(), name.end(), [](char ch) { return !std::isalnum(ch); }, '_');
    return name;
  });
// clang-format on

TEST(CaseYaml, NearestNameSuggestsOnlyTypos) {
  const std::vector<std::string> keys{"density", "viscosity"};
  EXPECT_EQ(nearest_name("viscocity", keys), "viscosity");
  EXPECT_EQ(nearest_name("Density", keys), "density");
  EXPECT_EQ(nearest_name("desnity", keys), "density"); // swapped letters
  EXPECT_EQ(nearest_name("temperature", keys), "");
}

// --- the case against its mesh -----------------------------------------------------------

namespace {

mesh::Mesh three_face_mesh() {
  mesh::Mesh m;
  m.source = "test-pipe";
  for (const char* name : {"inlet", "outlet", "wall"})
    m.faces.push_back({name, {}});
  return m;
}

io::Case case_with_faces(std::initializer_list<const char*> faces) {
  io::Case c;
  c.file = "pipe.yaml";
  for (const char* face : faces) {
    c.boundary_conditions.push_back({face, bc::NoSlip{}});
  }
  return c;
}

/// Runs f with the default logger writing to a buffer; returns the lines logged.
template <typename F> std::vector<std::string> logged(F f) {
  auto sink = std::make_shared<spdlog::sinks::ringbuffer_sink_mt>(16);
  auto previous = spdlog::default_logger();
  spdlog::set_default_logger(std::make_shared<spdlog::logger>("test", sink));
  f();
  spdlog::set_default_logger(previous);
  return sink->last_formatted();
}

} // namespace

TEST(CheckCaseAgainstMesh, AcceptsMatchingFaces) {
  const auto lines = logged([] {
    io::check_case_against_mesh(case_with_faces({"inlet", "outlet", "wall"}), three_face_mesh());
  });
  EXPECT_TRUE(lines.empty());
}

TEST(CheckCaseAgainstMesh, UnknownFaceListsTheMeshFaces) {
  try {
    io::check_case_against_mesh(case_with_faces({"wall", "inlt"}), three_face_mesh());
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("pipe.yaml: boundary_conditions[1].face"));
    EXPECT_THAT(e.what(), HasSubstr("no face 'inlt' (did you mean 'inlet'?)"));
    EXPECT_THAT(e.what(), HasSubstr("inlet, outlet and wall"));
  }
}

TEST(CheckCaseAgainstMesh, AnImplausibleScaleNamesTheUnitThatFits) {
  // An aorta of 30 cm in a file in cm, read as metres (the probe's case); and a 2 cm pipe in
  // mm given as metres' thousandths twice over.
  mesh::Mesh m = three_face_mesh();
  m.points = {{0, 0, 0}, {30, 0, 0}, {0, 2.5, 0}, {0, 0, 2.5}};
  try {
    io::check_case_against_mesh(case_with_faces({"inlet", "outlet", "wall"}), m);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("the mesh test-pipe spans 30.2 m"));
    EXPECT_THAT(e.what(), HasSubstr("probably in cm (mesh.units: cm)"));
  }
  io::Case in_mm = case_with_faces({"inlet", "outlet", "wall"});
  in_mm.mesh.length_scale = 1e-3;
  for (Vec3& x : m.points)
    x = 1e-6 * x; // 30 um: the coordinates were in metres already
  try {
    io::check_case_against_mesh(in_mm, m);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("is that small; its coordinates are probably in m"));
  }
  for (Vec3& x : m.points)
    x = 1e3 * x; // 3 cm: fine
  EXPECT_NO_THROW(io::check_case_against_mesh(in_mm, m));
}

TEST(CheckCaseAgainstMesh, InflowIntoAClosedDomainIsRefused) {
  // The probe's case: the outlet left without a condition, so a wall; it only warned.
  io::Case c = case_with_faces({"inlet", "wall"});
  c.boundary_conditions[0].kind = bc::Inflow{bc::Waveform::constant(1e-6)};
  try {
    io::check_case_against_mesh(c, three_face_mesh());
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("pipe.yaml: boundary_conditions[0]: flow enters through "
                                    "'inlet' but no face lets it out"));
    EXPECT_THAT(e.what(), HasSubstr("faces without a condition are walls: outlet"));
  }
  c.boundary_conditions.push_back({"outlet", bc::Outlet{bc::ResistanceOutlet{1e8, 0.0}}});
  EXPECT_NO_THROW(io::check_case_against_mesh(c, three_face_mesh()));
}

TEST(CheckCaseAgainstMesh, FaceGivenTwice) {
  try {
    io::check_case_against_mesh(case_with_faces({"inlet", "wall", "inlet"}), three_face_mesh());
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("boundary_conditions[2].face: face 'inlet' already has"));
  }
}

TEST(CheckCaseAgainstMesh, WarnsAboutFacesWithoutCondition) {
  const auto lines = logged([] {
    io::check_case_against_mesh(case_with_faces({"inlet", "outlet"}), three_face_mesh());
  });
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_THAT(lines[0], HasSubstr("no-slip walls: wall"));
}
