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
#include "io/case_conditions.hpp"
#include "io/case_waveform.hpp"
#include "io/case_yaml.hpp"

namespace tearflow::io {

namespace {

namespace fs = std::filesystem;

// --- mesh --------------------------------------------------------------------------------

mesh::PipeSpec read_pipe(const YamlValue& v) {
  v.check_keys({"radius", "length", "element_size", "wall_thickness", "boundary_layers"});
  mesh::PipeSpec pipe;
  if (auto x = v.get("radius"))
    pipe.radius = x->positive();
  if (auto x = v.get("length"))
    pipe.length = x->positive();
  if (auto x = v.get("element_size"))
    pipe.element_size = x->positive();
  if (auto x = v.get("wall_thickness"))
    pipe.wall_thickness = x->non_negative();
  if (auto bl = v.get("boundary_layers")) {
    bl->check_keys({"count", "first", "growth", "wall_layers"});
    pipe.layers.count = bl->require("count", "the number of layers (>= 1)").integer(1);
    pipe.layers.first = bl->require("first", "the first layer's thickness in m").positive();
    if (auto x = bl->get("growth"))
      pipe.layers.growth = x->in_range(1.01, 3.0);
    if (auto x = bl->get("wall_layers"))
      pipe.layers.wall_layers = x->integer(1);
  }
  return pipe;
}

MeshSpec read_mesh_spec(const YamlValue& v, const fs::path& case_dir) {
  v.check_keys({"file", "wall_file", "units", "pipe", "region"});
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

  if (auto region = v.get("region"))
    spec.region = region->text();
  auto checked_path = [&](const YamlValue& node) {
    const fs::path path = resolve_path(case_dir, node.text());
    std::error_code ec;
    if (!fs::exists(path, ec))
      node.fail(fmt::format("mesh not found: {}", path.string()));
    if (fs::is_directory(path, ec)) {
      const fs::path volume = path / "mesh-complete.mesh.vtu";
      if (!fs::exists(volume, ec))
        node.fail(fmt::format("{} is not a SimVascular mesh-complete directory: {} is missing",
                              path.string(), volume.string()));
    } else if (path.extension() != ".msh") {
      node.fail(fmt::format("expected a Gmsh .msh file or a SimVascular mesh-complete "
                            "directory, got {}",
                            path.string()));
    }
    return path;
  };
  spec.file = checked_path(*file);
  if (auto wall = v.get("wall_file"))
    spec.wall_file = checked_path(*wall);
  return spec;
}

// --- sections of plain numbers -----------------------------------------------------------

FluidSpec read_fluid(const YamlValue& v) {
  v.check_keys({"density", "viscosity", "stabilization_time_scale", "viscous_correction",
                "grad_div_scale", "stabilization_metric"});
  FluidSpec fluid;
  if (auto x = v.get("density"))
    fluid.density = x->positive();
  if (auto x = v.get("viscosity"))
    fluid.viscosity = x->positive();
  physics::StabilizationSpec& stab = fluid.stabilization;
  if (auto x = v.get("stabilization_time_scale")) { // a time, `step` or `automatic`
    const std::string text = x->is_scalar() ? x->text() : "";
    stab.time_scale = text == "step" ? 0.0 : text == "automatic" ? -1.0 : x->positive();
  }
  if (auto x = v.get("viscous_correction"))
    stab.viscous_correction = x->choice({"true", "false"}) == "true";
  if (auto x = v.get("grad_div_scale"))
    stab.grad_div = x->non_negative();
  if (auto x = v.get("stabilization_metric"))
    stab.metric = x->choice({"symmetric", "reference_tet"}) == "symmetric"
                      ? physics::StabilizationSpec::Metric::symmetric
                      : physics::StabilizationSpec::Metric::reference_tet;
  return fluid;
}

/// How long to run, as the case file says it; resolved once the waveforms' period is known.
struct RunLength {
  std::optional<int> steps, cycles, max_cycles;
  std::optional<YamlValue> node; ///< the key that set cycles or periodicity, for messages
};

TimeSpec read_time(const YamlValue& v, RunLength& length) {
  v.check_keys(
      {"step", "steps", "end", "cycles", "periodicity", "period", "spectral_radius", "start"});
  TimeSpec time;
  time.step = v.require("step", "the time step in seconds, a number > 0").positive();
  std::vector<YamlValue> given;
  for (const char* key : {"steps", "end", "cycles", "periodicity"})
    if (auto x = v.get(key))
      given.push_back(*x);
  if (given.size() > 1)
    given[1].fail(fmt::format("give one of time.steps, time.end, time.cycles and "
                              "time.periodicity, not both {} and {}",
                              given[0].path(), given[1].path()));
  if (auto steps = v.get("steps"))
    length.steps = steps->integer(1);
  if (auto end = v.get("end")) {
    const double t_end = end->positive();
    const double n = std::round(t_end / time.step);
    if (n < 1.0)
      end->fail(
          fmt::format("time.end = {} s is shorter than half a time step ({} s)", t_end, time.step));
    if (n > INT_MAX)
      end->fail(fmt::format("time.end / time.step = {} steps is too many", n));
    length.steps = static_cast<int>(n);
    if (std::abs(n * time.step - t_end) > 1e-6 * time.step)
      spdlog::warn("{}: {} s is not a multiple of time.step = {} s; running {} steps, to t = {} s",
                   end->where(), t_end, time.step, n, n * time.step);
  }
  if (auto cycles = v.get("cycles")) {
    length.cycles = cycles->integer(1);
    length.node = *cycles;
  }
  if (auto p = v.get("periodicity")) {
    p->check_keys({"tolerance", "max_cycles", "measure"});
    time.periodicity_tolerance =
        p->require("tolerance", "the largest cycle-to-cycle change accepted as periodic, "
                                "relative, a number in (0, 1)")
            .in_range(0.0, 1.0);
    if (time.periodicity_tolerance <= 0.0)
      p->get("tolerance")->fail_expected("a number in (0, 1)");
    if (auto m = p->get("measure"))
      time.periodicity_measure = m->choice({"waveforms", "pressures_and_splits"}) == "waveforms"
                                     ? TimeSpec::Periodicity::waveforms
                                     : TimeSpec::Periodicity::pressures_and_splits;
    length.max_cycles = 10;
    if (auto m = p->get("max_cycles"))
      length.max_cycles = m->integer(2);
    length.node = *p;
  }
  if (auto x = v.get("period"))
    time.period = x->positive();
  if (auto x = v.get("spectral_radius"))
    time.spectral_radius = x->in_range(0.0, 1.0);
  if (auto x = v.get("start"))
    time.start_from_0d = x->choice({"periodic_0d", "rest"}) == "periodic_0d";
  return time;
}

/// The cardiac period: time.period if given, else the waveforms' common period; every
/// periodic waveform must have it. Then the run length in steps.
void resolve_period(Case& c, const YamlValue& time_node, const std::vector<GivenWaveform>& periodic,
                    const RunLength& length) {
  for (const GivenWaveform& given : periodic) {
    const bc::Waveform& w = given.waveform;
    if (c.time.period == 0.0) {
      c.time.period = w.period();
    } else if (std::abs(w.period() - c.time.period) > 1e-9 * c.time.period) {
      given.where.fail(
          fmt::format("the waveform's period is {} s but the case's period is {} s "
                      "({}); give every waveform over the same cardiac cycle",
                      w.period(), c.time.period,
                      time_node.has("period") ? "time.period" : "from an earlier waveform"));
    }
  }
  if (c.time.period > 0.0) {
    const double n = c.time.period / c.time.step;
    if (std::abs(n - std::round(n)) < 1e-6 * n)
      c.time.steps_per_cycle = static_cast<int>(std::round(n));
  }
  if (!length.cycles && !length.max_cycles) {
    c.time.steps = length.steps.value_or(c.time.steps);
    return;
  }
  if (c.time.period == 0.0)
    length.node->fail("cycles need a period: give time.period or a periodic waveform");
  if (c.time.steps_per_cycle == 0)
    length.node->fail(fmt::format("the period {} s is not a multiple of time.step = {} s",
                                  c.time.period, c.time.step));
  const long steps = static_cast<long>(length.cycles ? *length.cycles : *length.max_cycles) *
                     c.time.steps_per_cycle;
  if (steps > INT_MAX)
    length.node->fail(fmt::format("{} steps are too many", steps));
  c.time.steps = static_cast<int>(steps);
}

physics::NewtonSpec read_newton(const YamlValue& v) {
  v.check_keys({"max_iterations", "rtol", "atol", "continuity"});
  physics::NewtonSpec newton;
  if (auto x = v.get("max_iterations"))
    newton.max_iterations = x->integer(1);
  if (auto x = v.get("rtol"))
    newton.rtol = x->positive();
  if (auto x = v.get("atol"))
    newton.atol = x->positive();
  if (auto x = v.get("continuity"))
    newton.continuity = x->positive();
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
  root.check_keys({"name", "mesh", "fluid", "solid", "time", "boundary_conditions", "newton",
                   "petsc_options", "output"});
  const fs::path case_dir = fs::absolute(file).parent_path();

  Case c;
  c.file = fs::absolute(file).lexically_normal();
  c.name = read_name(root.get("name"), file);
  c.mesh = read_mesh_spec(root.require("mesh", "mesh.file (a mesh file or directory) or mesh.pipe"),
                          case_dir);
  if (auto fluid = root.get("fluid"))
    c.fluid = read_fluid(*fluid);
  const YamlValue time_node = root.require("time", "a mapping with at least time.step");
  RunLength length;
  c.time = read_time(time_node, length);
  if (auto solid = root.get("solid")) // with boundary_conditions: fluid-structure interaction
    c.solid = read_solid(*solid, case_dir);
  if (c.solid && !root.has("boundary_conditions")) { // solid-only: the solid's own conditions
    if (length.node)
      length.node->fail("time.cycles and time.periodicity apply to flow cases; give time.steps "
                        "or time.end");
    c.time.steps = length.steps.value_or(c.time.steps);
  } else {
    const YamlValue bcs_node =
        root.require("boundary_conditions", "a list of {face: ..., type: ...} mappings");
    std::vector<GivenWaveform> periodic;
    c.boundary_conditions = read_boundary_conditions(bcs_node, case_dir, periodic);
    resolve_period(c, time_node, periodic, length);
  }
  if (auto newton = root.get("newton"))
    c.newton = read_newton(*newton);
  if (auto petsc = root.get("petsc_options"))
    c.petsc_options = read_petsc_options(*petsc);
  c.output = read_output(root.get("output"), c.name);
  return c;
}

namespace {

/// A vessel's model spans millimetres to a metre: a mesh in cm or mm read as metres (an
/// aorta 30 m long) ended in a Newton failure without a hint; say which unit fits.
void check_scale(const Case& c, const mesh::Mesh& m, const std::string& source) {
  if (m.points.empty())
    return;
  Vec3 low = m.points.front(), high = m.points.front();
  for (const Vec3& x : m.points)
    for (int k = 0; k < 3; ++k) {
      low[k] = std::min(low[k], x[k]);
      high[k] = std::max(high[k], x[k]);
    }
  const Vec3 diagonal = high - low;
  const double span = std::sqrt(dot(diagonal, diagonal));
  if (span > 3.0 || span < 1e-3) {
    std::string hint;
    for (const auto& [unit, scale] : {std::pair{"m", 1.0}, {"cm", 1e-2}, {"mm", 1e-3}})
      if (const double d = span / c.mesh.length_scale * scale; hint.empty() && d > 0.01 && d < 1.0)
        hint = fmt::format("; its coordinates are probably in {} (mesh.units: {})", unit, unit);
    input_error("{}: the mesh{} spans {:.3g} m (its bounding box's diagonal, mesh units {} m): no "
                "blood vessel's model is that {}{}",
                source, m.source.empty() ? "" : " " + m.source, span, c.mesh.length_scale,
                span > 3.0 ? "large" : "small", hint);
  }
}

} // namespace

void check_case_against_mesh(const Case& c, const mesh::Mesh& m) {
  const std::string source = c.file.empty() ? fmt::format("case '{}'", c.name) : c.file.string();
  // A vessel's model spans millimetres to a metre: a mesh in cm or mm read as metres (an
  // aorta 30 m long) ended in a Newton failure without a hint; say which unit fits.
  check_scale(c, m, source);
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
  // An incompressible fluid cannot enter a closed rigid domain (Newton then failed at step
  // 1); a compliant one stores a cycle's net volume for ever, so only a zero-mean inflow.
  const bool open =
      std::any_of(c.boundary_conditions.begin(), c.boundary_conditions.end(),
                  [](const bc::BoundaryCondition& b) { return b.outlet() != nullptr; });
  for (size_t i = 0; i < c.boundary_conditions.size() && !open; ++i) {
    const bc::BoundaryCondition& b = c.boundary_conditions[i];
    if (b.inflow() && (!is_fsi(c) || std::abs(b.inflow()->flow.mean()) > 0.0))
      input_error("{}: boundary_conditions[{}]: flow enters through '{}' but no face lets it "
                  "out (no outlet condition{}): {}",
                  source, i, b.face,
                  unused.empty()
                      ? ""
                      : "; faces without a condition are walls: " + join_names(unused, "and"),
                  is_fsi(c) ? "the wall would store a cycle's net inflow every cycle"
                            : "an incompressible fluid cannot enter a closed rigid domain");
  }
  if (!unused.empty() && !is_fsi(c)) // in FSI they are the interface and the wall's faces
    spdlog::warn("{}: mesh faces without a boundary condition are no-slip walls: {}", source,
                 join_names(unused, "and"));
}

} // namespace tearflow::io
