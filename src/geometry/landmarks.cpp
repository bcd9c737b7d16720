#include "geometry/landmarks.hpp"

#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/units.hpp"
#include "geometry/tbad_model.hpp"

namespace tearflow::geometry {

namespace {

using nlohmann::json;

constexpr const char* kFormat = "tearflow-landmarks";
constexpr int kVersion = 1;

json vec(const Vec3& v, double scale) {
  return json::array({v[0] / scale, v[1] / scale, v[2] / scale});
}

Vec3 read_vec(const json& j, const std::string& where, double scale) {
  if (!j.is_array() || j.size() != 3 || !j[0].is_number() || !j[1].is_number() || !j[2].is_number())
    input_error("{}: expected three numbers [x, y, z], got {}", where, j.dump());
  return {j[0].get<double>() * scale, j[1].get<double>() * scale, j[2].get<double>() * scale};
}

Vec3 read_direction(const json& j, const std::string& where) {
  const Vec3 v = read_vec(j, where, 1.0);
  const double n = std::sqrt(dot(v, v));
  if (!(n > 0) || !std::isfinite(n))
    input_error("{}: a direction of zero length", where);
  return (1.0 / n) * v;
}

const json& key(const json& j, const char* name, const std::string& where) {
  if (!j.is_object() || !j.contains(name))
    input_error("{}: missing key '{}'", where, name);
  return j.at(name);
}

} // namespace

const Landmark& Landmarks::plane(const std::string& name) const {
  std::string known;
  for (const Landmark& l : planes) {
    if (l.name == name)
      return l;
    known += " " + l.name;
  }
  input_error("landmarks: no plane '{}'; the planes are:{}", name, known);
}

const TearLandmark& Landmarks::tear(const std::string& name) const {
  for (const TearLandmark& t : tears)
    if (t.name == name)
      return t;
  input_error("landmarks: no tear '{}'", name);
}

const std::vector<std::string>& area_landmark_names() {
  static const std::vector<std::string> names{"AAo", "TL1", "TL2", "TL3", "TL4", "TL5",
                                              "FL1", "FL2", "FL3", "FL4", "FL5", "DAo_dist"};
  return names;
}

Landmarks tbad_landmarks(const TbadModel& model) {
  Landmarks out;
  for (const Station& st : model.stations()) {
    const Frame f = model.frame(st.s);
    const bool paired = st.name.size() == 1 && std::isdigit(static_cast<unsigned char>(st.name[0]));
    if (!paired) {
      out.planes.push_back({st.name, f.origin, f.tangent, "aorta", f.origin});
      continue;
    }
    out.planes.push_back({"TL" + st.name, f.origin, f.tangent, "TL", model.true_lumen_point(st.s)});
    out.planes.push_back(
        {"FL" + st.name, f.origin, f.tangent, "FL", model.false_lumen_point(st.s)});
  }
  for (const TearGeometry& t : model.tears())
    out.tears.push_back({t.name, t.centre, t.normal, t.axis, t.area(), t.axial, t.across});
  return out;
}

void write_landmarks(const Landmarks& landmarks, const std::filesystem::path& file,
                     const std::string& length_unit) {
  const double scale = units::length_scale(length_unit, "landmarks length unit");
  json planes = json::array(), tears = json::array();
  for (const Landmark& l : landmarks.planes) {
    json p{{"name", l.name},
           {"origin", vec(l.origin, scale)},
           {"normal", vec(l.normal, 1.0)},
           {"lumen", l.lumen}};
    if (l.point)
      p["point"] = vec(*l.point, scale);
    planes.push_back(p);
  }
  for (const TearLandmark& t : landmarks.tears)
    tears.push_back({{"name", t.name},
                     {"centroid", vec(t.centroid, scale)},
                     {"normal", vec(t.normal, 1.0)},
                     {"axis", vec(t.axis, 1.0)},
                     {"area", t.area / (scale * scale)},
                     {"semi_axes", json::array({t.axial / scale, t.across / scale})}});
  const json j{{"format", kFormat},
               {"version", kVersion},
               {"length_unit", length_unit},
               {"planes", planes},
               {"tears", tears}};
  std::ofstream out(file);
  out << j.dump(2) << "\n";
  if (!out)
    input_error("could not write landmarks file '{}'", file.string());
}

Landmarks read_landmarks(const std::filesystem::path& file) {
  const std::string src = "landmarks file '" + file.string() + "'";
  std::ifstream in(file);
  if (!in)
    input_error("{}: cannot open it", src);
  json j;
  try {
    j = json::parse(in);
  } catch (const json::exception& e) {
    input_error("{}: not valid JSON: {}", src, e.what());
  }
  if (!j.is_object() || j.value("format", "") != kFormat)
    input_error("{}: expected \"format\": \"{}\" at the top level", src, kFormat);
  if (j.value("version", 0) != kVersion)
    input_error("{}: version {} is not supported (expected {})", src, j.value("version", 0),
                kVersion);
  const json& unit = key(j, "length_unit", src);
  if (!unit.is_string())
    input_error("{}: length_unit must be a string (m, cm or mm)", src);
  const double scale = units::length_scale(unit.get<std::string>(), src + ": length_unit");
  Landmarks out;
  const json& planes = key(j, "planes", src);
  if (!planes.is_array() || planes.empty())
    input_error("{}: 'planes' must be a non-empty list", src);
  for (std::size_t i = 0; i < planes.size(); ++i) {
    const json& p = planes[i];
    const std::string where = fmt::format("{}: planes[{}]", src, i);
    const json& name = key(p, "name", where);
    if (!name.is_string() || name.get<std::string>().empty())
      input_error("{}: 'name' must be a non-empty string", where);
    Landmark l;
    l.name = name.get<std::string>();
    const std::string at = fmt::format("{}: plane '{}'", src, l.name);
    l.origin = read_vec(key(p, "origin", at), at + ": origin", scale);
    l.normal = read_direction(key(p, "normal", at), at + ": normal");
    l.lumen = p.value("lumen", "aorta");
    if (l.lumen != "aorta" && l.lumen != "TL" && l.lumen != "FL")
      input_error("{}: lumen '{}', expected aorta, TL or FL", at, l.lumen);
    if (p.contains("point"))
      l.point = read_vec(p.at("point"), at + ": point", scale);
    else if (l.lumen != "aorta")
      input_error("{}: a {} plane needs a 'point' inside its lumen", at, l.lumen);
    for (const Landmark& other : out.planes)
      if (other.name == l.name)
        input_error("{}: plane name '{}' is used twice", src, l.name);
    out.planes.push_back(l);
  }
  if (j.contains("tears")) {
    const json& tears = j.at("tears");
    if (!tears.is_array())
      input_error("{}: 'tears' must be a list", src);
    for (std::size_t i = 0; i < tears.size(); ++i) {
      const json& t = tears[i];
      const std::string where = fmt::format("{}: tears[{}]", src, i);
      TearLandmark tl;
      tl.name = key(t, "name", where).get<std::string>();
      tl.centroid = read_vec(key(t, "centroid", where), where + ": centroid", scale);
      tl.normal = read_direction(key(t, "normal", where), where + ": normal");
      const json& area = key(t, "area", where);
      if (!area.is_number() || !(area.get<double>() > 0))
        input_error("{}: 'area' must be a positive number", where);
      tl.area = area.get<double>() * scale * scale;
      if (t.contains("axis"))
        tl.axis = read_direction(t.at("axis"), where + ": axis");
      if (t.contains("semi_axes")) {
        const json& a = t.at("semi_axes");
        if (!a.is_array() || a.size() != 2 || !a[0].is_number() || !a[1].is_number())
          input_error("{}: 'semi_axes' must be [axial, across]", where);
        tl.axial = a[0].get<double>() * scale;
        tl.across = a[1].get<double>() * scale;
      }
      out.tears.push_back(tl);
    }
  }
  return out;
}

} // namespace tearflow::geometry
