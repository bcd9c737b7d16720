// The `solid:` section of a case file. Units are SI (Pa, kg/m^3, m, s); pressures may be
// waveforms with `units`, as for the fluid's outlets.
#include "io/case_solid.hpp"

#include <algorithm>
#include <map>

#include <fmt/format.h>

#include "core/error.hpp"
#include "io/case_waveform.hpp"

namespace tearflow::io {

namespace {

namespace fs = std::filesystem;

physics::SolidMaterial read_material(const YamlValue& v) {
  const auto model = v.get("model") ? v.get("model")->choice({"neo_hookean", "st_venant_kirchhoff"})
                                    : std::string("neo_hookean");
  const physics::SolidModel m = model == "st_venant_kirchhoff"
                                    ? physics::SolidModel::StVenantKirchhoff
                                    : physics::SolidModel::NeoHookean;
  const double density = v.require("density", "the reference density in kg/m^3, > 0").positive();
  const auto E = v.get("youngs_modulus"), nu = v.get("poisson_ratio");
  const auto mu = v.get("shear_modulus"), kappa = v.get("bulk_modulus");
  // Moduli come in pairs; the material's own checks give the range messages.
  auto checked = [&](const YamlValue& where, auto make) {
    try {
      return make();
    } catch (const InputError& e) {
      where.fail(e.what());
    }
  };
  physics::SolidMaterial out;
  if ((E || nu) && (mu || kappa))
    (mu ? *mu : *kappa)
        .fail("give youngs_modulus and poisson_ratio, or shear_modulus and bulk_modulus, not both");
  if (E || nu) {
    const YamlValue e = v.require("youngs_modulus", "Young's modulus in Pa (with poisson_ratio)");
    const YamlValue n = v.require("poisson_ratio", "Poisson's ratio in (-1, 0.5)");
    const double E_value = e.number(), nu_value = n.number();
    out = checked(E_value > 0.0 ? n : e, [&] {
      return physics::SolidMaterial::from_young_poisson(m, E_value, nu_value, density);
    });
  } else if (mu || kappa) {
    const YamlValue s = v.require("shear_modulus", "the shear modulus in Pa (with bulk_modulus)");
    const YamlValue k = v.require("bulk_modulus", "the bulk modulus in Pa (with shear_modulus)");
    const double mu_value = s.number(), kappa_value = k.number();
    out = checked(mu_value > 0.0 ? k : s, [&] {
      return physics::SolidMaterial::from_shear_bulk(m, mu_value, kappa_value, density);
    });
  } else {
    v.fail("expected youngs_modulus and poisson_ratio, or shear_modulus and bulk_modulus");
  }
  if (auto a = v.get("stabilization"))
    out.stabilization = a->positive();
  return out;
}

std::uint8_t read_components(const YamlValue& v) {
  std::uint8_t mask = 0;
  for (const YamlValue& item : v.items()) {
    const std::string c = item.choice({"x", "y", "z"});
    mask |= static_cast<std::uint8_t>(1u << (c[0] - 'x'));
  }
  if (mask == 0)
    v.fail_expected("a non-empty list of components x, y, z");
  return mask;
}

struct SolidBc {
  std::string face;
  YamlValue face_node;
};

} // namespace

SolidSpec read_solid(const YamlValue& v, const fs::path& case_dir) {
  v.check_keys({"model", "density", "youngs_modulus", "poisson_ratio", "shear_modulus",
                "bulk_modulus", "stabilization", "quasi_static", "boundary_conditions"});
  SolidSpec s;
  s.material = read_material(v);
  if (auto q = v.get("quasi_static"))
    s.quasi_static = q->choice({"true", "false"}) == "true";
  const YamlValue list =
      v.require("boundary_conditions", "a list of {face: ..., type: fixed|pressure|robin}");
  std::map<std::string, YamlValue> first_use;
  for (const YamlValue& item : list.items()) {
    if (!item.is_map())
      item.fail_expected("a mapping with face, type and the type's keys");
    item.check_keys({"face", "type", "components", "displacement", "ramp", "pressure", "units",
                     "stiffness", "damping"});
    const YamlValue face = item.require("face", "the name of a mesh face");
    const std::string name = face.text();
    if (name.empty())
      face.fail_expected("the name of a mesh face");
    if (auto [it, inserted] = first_use.emplace(name, face); !inserted)
      face.fail(fmt::format("face '{}' already has a boundary condition ({}, line {}); give "
                            "each face once",
                            name, it->second.path(), it->second.line()));
    const YamlValue type = item.require("type", "fixed, pressure or robin");
    const std::string t = type.choice({"fixed", "pressure", "robin"});
    const std::string reason = fmt::format("type: {}", t);
    if (t == "fixed") {
      item.check_keys({"face", "type", "components", "displacement", "ramp"},
                      {"pressure", "units", "stiffness", "damping"}, reason);
      bc::FixedFace f;
      f.face = name;
      if (auto c = item.get("components"))
        f.components = read_components(*c);
      if (auto d = item.get("displacement")) {
        const std::vector<double> g = d->numbers();
        if (g.size() != 3)
          d->fail_expected("three numbers [x, y, z] in m");
        f.displacement = {g[0], g[1], g[2]};
      }
      if (auto r = item.get("ramp"))
        f.ramp = r->non_negative();
      s.conditions.fixed.push_back(f);
    } else if (t == "pressure") {
      item.check_keys({"face", "type", "pressure", "units"},
                      {"components", "displacement", "ramp", "stiffness", "damping"}, reason);
      const YamlValue p = item.require("pressure", "the pressure in Pa (or units), or a waveform");
      s.conditions.loads.push_back(
          {name, read_case_waveform(p, item.get("units"), kPressure, case_dir)});
    } else {
      item.check_keys({"face", "type", "stiffness", "damping", "pressure"},
                      {"components", "displacement", "ramp", "units"}, reason);
      bc::RobinSupport r;
      r.face = name;
      r.stiffness = item.require("stiffness", "k_s in Pa/m, a number >= 0").non_negative();
      if (auto c = item.get("damping"))
        r.damping = c->non_negative();
      if (auto p = item.get("pressure"))
        r.pressure = p->number();
      s.conditions.supports.push_back(r);
    }
  }
  if (first_use.empty())
    list.fail("expected at least one boundary condition");
  return s;
}

void check_solid_against_mesh(const SolidSpec& s, const mesh::Mesh& m, const std::string& source) {
  std::vector<std::string> names;
  for (const mesh::Face& f : m.faces)
    names.push_back(f.name);
  auto check = [&](const std::string& face, const char* what) {
    if (std::find(names.begin(), names.end(), face) != names.end())
      return;
    const std::string best = nearest_name(face, names);
    input_error("{}: solid.boundary_conditions: {} on face '{}', but the mesh{} has no such "
                "face{}; its faces are {}",
                source, what, face, m.source.empty() ? "" : " " + m.source,
                best.empty() ? "" : fmt::format(" (did you mean '{}'?)", best),
                join_names(names, "and"));
  };
  for (const auto& f : s.conditions.fixed)
    check(f.face, "fixed");
  for (const auto& p : s.conditions.loads)
    check(p.face, "pressure");
  for (const auto& r : s.conditions.supports)
    check(r.face, "robin");
}

} // namespace tearflow::io
