// Case files: YAML in, a validated Case in SI units out. One reader per section; each
// checks its keys (unknown keys are errors) and values (type and range) through YamlValue,
// whose messages name the file, line and key path. docs/case-file.md documents every key.
#include "io/case.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <map>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "core/error.hpp"
#include "core/units.hpp"
#include "io/case_waveform.hpp"
#include "io/case_yaml.hpp"

namespace tearflow::io {

namespace {

namespace fs = std::filesystem;

// --- mesh --------------------------------------------------------------------------------

mesh::PipeSpec read_pipe(const YamlValue& v) {
  v.check_keys({"radius", "length", "element_size"});
  mesh::PipeSpec pipe;
  if (auto x = v.get("radius"))
    pipe.radius = x->positive();
  if (auto x = v.get("length"))
    pipe.length = x->positive();
  if (auto x = v.get("element_size"))
    pipe.element_size = x->positive();
  return pipe;
}

MeshSpec read_mesh_spec(const YamlValue& v, const fs::path& case_dir) {
  v.check_keys({"file", "units", "pipe"});
  const auto file = v.get("file");
  const auto pipe = v.get("pipe");
  if (file && pipe)
    pipe->fail("give either mesh.file or mesh.pipe, not both");
  if (!file && !pipe)
    v.fail("expected mesh.file (a Gmsh .msh file or a SimVascular mesh-complete directory) "
           "or mesh.pipe (the built-in pipe)");

  MeshSpec spec;
  if (pipe) {
    if (auto units = v.get("units"))
      units->fail("mesh.units applies to mesh.file only; mesh.pipe dimensions are in metres");
    spec.pipe = read_pipe(*pipe);
    return spec;
  }
  if (auto units = v.get("units"))
    spec.length_scale = units::length_scale(units->choice({"m", "cm", "mm"}), units->where());

  spec.file = resolve_path(case_dir, file->text());
  std::error_code ec;
  if (!fs::exists(spec.file, ec))
    file->fail(fmt::format("mesh not found: {}", spec.file.string()));
  if (fs::is_directory(spec.file, ec)) {
    const fs::path volume = spec.file / "mesh-complete.mesh.vtu";
    if (!fs::exists(volume, ec))
      file->fail(fmt::format("{} is not a SimVascular mesh-complete directory: {} is missing",
                             spec.file.string(), volume.string()));
  } else if (spec.file.extension() != ".msh") {
    file->fail(fmt::format("expected a Gmsh .msh file or a SimVascular mesh-complete "
                           "directory, got {}",
                           spec.file.string()));
  }
  return spec;
}

// --- sections of plain numbers -----------------------------------------------------------

FluidSpec read_fluid(const YamlValue& v) {
  v.check_keys({"density", "viscosity"});
  FluidSpec fluid;
  if (auto x = v.get("density"))
    fluid.density = x->positive();
  if (auto x = v.get("viscosity"))
    fluid.viscosity = x->positive();
  return fluid;
}

TimeSpec read_time(const YamlValue& v) {
  v.check_keys({"step", "steps", "end", "spectral_radius"});
  TimeSpec time;
  time.step = v.require("step", "the time step in seconds, a number > 0").positive();
  const auto steps = v.get("steps");
  const auto end = v.get("end");
  if (steps && end)
    end->fail("give either time.steps or time.end, not both");
  if (steps)
    time.steps = steps->integer(1);
  if (end) {
    const double t_end = end->positive();
    const double n = std::round(t_end / time.step);
    if (n < 1.0)
      end->fail(
          fmt::format("time.end = {} s is shorter than half a time step ({} s)", t_end, time.step));
    if (n > INT_MAX)
      end->fail(fmt::format("time.end / time.step = {} steps is too many", n));
    time.steps = static_cast<int>(n);
    if (std::abs(n * time.step - t_end) > 1e-6 * time.step)
      spdlog::warn("{}: {} s is not a multiple of time.step = {} s; running {} steps, to t = {} s",
                   end->where(), t_end, time.step, time.steps, n * time.step);
  }
  if (auto x = v.get("spectral_radius"))
    time.spectral_radius = x->in_range(0.0, 1.0);
  return time;
}

NewtonSpec read_newton(const YamlValue& v) {
  v.check_keys({"max_iterations", "rtol", "atol"});
  NewtonSpec newton;
  if (auto x = v.get("max_iterations"))
    newton.max_iterations = x->integer(1);
  if (auto x = v.get("rtol"))
    newton.rtol = x->positive();
  if (auto x = v.get("atol"))
    newton.atol = x->positive();
  return newton;
}

/// A string as is, a list of strings joined by spaces, or a mapping {option: value} written
/// as "-option value" (a leading '-' added when missing; an empty value gives "-option").
std::string read_petsc_options(const YamlValue& v) {
  if (v.is_null())
    return "";
  if (v.is_scalar())
    return v.text();
  std::vector<std::string> words;
  if (v.is_list()) {
    for (const YamlValue& item : v.items())
      words.push_back(item.text());
  } else if (v.is_map()) {
    for (const auto& [key, value] : v.entries()) {
      words.push_back(key.starts_with('-') ? key : "-" + key);
      if (!value.is_null())
        words.push_back(value.text());
    }
  } else {
    v.fail_expected("a string, a list of strings or a mapping {option: value}");
  }
  return fmt::format("{}", fmt::join(words, " "));
}

OutputSpec read_output(const std::optional<YamlValue>& v, const std::string& name) {
  OutputSpec output;
  fs::path directory = fs::path("results") / name;
  if (v) {
    v->check_keys({"directory", "every", "checkpoint_every"});
    if (auto x = v->get("directory"))
      directory = x->text();
    if (auto x = v->get("every"))
      output.every = x->integer(0);
    if (auto x = v->get("checkpoint_every"))
      output.checkpoint_every = x->integer(0);
  }
  output.directory = fs::absolute(directory).lexically_normal();
  return output;
}

// --- boundary conditions -----------------------------------------------------------------

BcType read_bc_type(const YamlValue& v) {
  const std::string type = v.choice({"no_slip", "inflow", "pressure", "resistance"});
  if (type == "inflow")
    return BcType::Inflow;
  if (type == "pressure")
    return BcType::Pressure;
  if (type == "resistance")
    return BcType::Resistance;
  return BcType::NoSlip;
}

InflowProfile read_profile(const YamlValue& v) {
  const std::string profile = v.choice({"parabolic", "plug", "womersley"});
  if (profile == "plug")
    return InflowProfile::Plug;
  if (profile == "womersley")
    return InflowProfile::Womersley;
  return InflowProfile::Parabolic;
}

BoundaryCondition read_bc(const YamlValue& v, const fs::path& case_dir) {
  if (!v.is_map())
    v.fail_expected("a mapping with face, type and the type's keys");
  // First against every key any condition takes (to catch typos), then against the type's.
  v.check_keys({"face", "type", "flow", "units", "profile", "womersley_modes", "pressure",
                "resistance", "backflow_beta"});
  BoundaryCondition bc;
  const YamlValue face = v.require("face", "the name of a mesh face");
  bc.face = face.text();
  if (bc.face.empty())
    face.fail_expected("the name of a mesh face");
  const YamlValue type = v.require("type", "no_slip, inflow, pressure or resistance");
  bc.type = read_bc_type(type);
  const std::string reason = fmt::format("type: {}", type.text());

  switch (bc.type) {
  case BcType::NoSlip:
    v.check_keys(
        {"face", "type"},
        {"flow", "units", "profile", "womersley_modes", "pressure", "resistance", "backflow_beta"},
        reason);
    break;
  case BcType::Inflow: {
    v.check_keys({"face", "type", "flow", "units", "profile", "womersley_modes"},
                 {"pressure", "resistance", "backflow_beta"}, reason);
    const YamlValue flow =
        v.require("flow", "the volume flow into the domain: a number (m3/s unless units "
                          "says otherwise) or a mapping with file or times/values");
    bc.flow = read_case_waveform(flow, v.get("units"), kFlow, case_dir);
    if (auto p = v.get("profile")) {
      bc.profile = read_profile(*p);
      if (bc.profile == InflowProfile::Womersley && bc.flow.is_constant())
        p->fail("profile womersley needs a periodic flow (file or times/values); use "
                "parabolic for a constant flow");
    }
    if (auto m = v.get("womersley_modes")) {
      if (bc.profile != InflowProfile::Womersley)
        m->fail("womersley_modes applies to profile: womersley only");
      bc.womersley_modes = m->integer(1);
    }
    break;
  }
  case BcType::Pressure:
    v.check_keys({"face", "type", "pressure", "units", "backflow_beta"},
                 {"flow", "profile", "womersley_modes", "resistance"}, reason);
    if (auto p = v.get("pressure"))
      bc.pressure = read_case_waveform(*p, v.get("units"), kPressure, case_dir);
    else if (auto u = v.get("units"))
      u->fail("units applies to pressure, which is not given (it defaults to 0)");
    break;
  case BcType::Resistance:
    v.check_keys({"face", "type", "resistance", "backflow_beta"},
                 {"flow", "units", "profile", "womersley_modes", "pressure"}, reason);
    bc.resistance =
        v.require("resistance", "the outlet resistance in Pa s/m^3, a number > 0").positive();
    break;
  }
  if (auto beta = v.get("backflow_beta"))
    bc.backflow_beta = beta->non_negative();
  return bc;
}

std::vector<BoundaryCondition> read_bcs(const YamlValue& v, const fs::path& case_dir) {
  const std::vector<YamlValue> items = v.items();
  if (items.empty())
    v.fail("expected at least one boundary condition");
  std::vector<BoundaryCondition> bcs;
  std::map<std::string, YamlValue> first_use; // face -> its `face` key
  for (const YamlValue& item : items) {
    bcs.push_back(read_bc(item, case_dir));
    const YamlValue face = *item.get("face");
    if (auto [it, inserted] = first_use.emplace(bcs.back().face, face); !inserted)
      face.fail(fmt::format("face '{}' already has a boundary condition ({}, line {}); give "
                            "each face once",
                            bcs.back().face, it->second.path(), it->second.line()));
  }
  return bcs;
}

std::string read_name(const std::optional<YamlValue>& v, const fs::path& file) {
  if (!v)
    return file.stem().string();
  const std::string name = v->text();
  if (name.empty() || name.find_first_of("/\\") != std::string::npos)
    v->fail_expected("a non-empty name without '/' (it names the output folder)");
  return name;
}

} // namespace

Case load_case(const fs::path& file) {
  const YamlValue root(file.string(), parse_yaml_file(file));
  if (root.is_null())
    root.fail("the case file is empty; expected at least mesh, time and boundary_conditions");
  root.check_keys({"name", "mesh", "fluid", "time", "boundary_conditions", "newton",
                   "petsc_options", "output"});
  const fs::path case_dir = fs::absolute(file).parent_path();

  Case c;
  c.file = fs::absolute(file).lexically_normal();
  c.name = read_name(root.get("name"), file);
  c.mesh = read_mesh_spec(root.require("mesh", "mesh.file (a mesh file or directory) or mesh.pipe"),
                          case_dir);
  if (auto fluid = root.get("fluid"))
    c.fluid = read_fluid(*fluid);
  c.time = read_time(root.require("time", "a mapping with at least time.step"));
  c.boundary_conditions = read_bcs(
      root.require("boundary_conditions", "a list of {face: ..., type: ...} mappings"), case_dir);
  if (auto newton = root.get("newton"))
    c.newton = read_newton(*newton);
  if (auto petsc = root.get("petsc_options"))
    c.petsc_options = read_petsc_options(*petsc);
  c.output = read_output(root.get("output"), c.name);
  return c;
}

void check_case_against_mesh(const Case& c, const mesh::Mesh& m) {
  const std::string source = c.file.empty() ? fmt::format("case '{}'", c.name) : c.file.string();
  std::vector<std::string> face_names;
  for (const mesh::Face& f : m.faces)
    face_names.push_back(f.name);

  std::map<std::string, size_t> used; // face -> index of its condition
  for (size_t i = 0; i < c.boundary_conditions.size(); ++i) {
    const std::string& face = c.boundary_conditions[i].face;
    if (auto [it, inserted] = used.emplace(face, i); !inserted)
      input_error("{}: boundary_conditions[{}].face: face '{}' already has a boundary "
                  "condition (boundary_conditions[{}])",
                  source, i, face, it->second);
    if (std::find(face_names.begin(), face_names.end(), face) == face_names.end()) {
      const std::string best = nearest_name(face, face_names);
      input_error("{}: boundary_conditions[{}].face: the mesh{} has no face '{}'{}; its faces "
                  "are {}",
                  source, i, m.source.empty() ? "" : " " + m.source, face,
                  best.empty() ? "" : fmt::format(" (did you mean '{}'?)", best),
                  join_names(face_names, "and"));
    }
  }
  std::vector<std::string> unused;
  for (const std::string& name : face_names)
    if (!used.contains(name))
      unused.push_back(name);
  if (!unused.empty())
    spdlog::warn("{}: mesh faces without a boundary condition are no-slip walls: {}", source,
                 join_names(unused, "and"));
}

} // namespace tearflow::io
