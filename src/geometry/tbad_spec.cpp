#include "geometry/tbad_spec.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.hpp"

namespace tearflow::geometry {

void apply_variant(TbadSpec& spec, std::string_view variant) {
  // Tear areas of the reference study's printed models [m^2].
  if (variant == "OR") {
    spec.entry_tear.area = 228e-6;
    spec.exit_tear.area = 227e-6;
  } else if (variant == "EN") {
    spec.entry_tear.area = 62e-6;
    spec.exit_tear.area = 227e-6;
  } else if (variant == "EX") {
    spec.entry_tear.area = 228e-6;
    spec.exit_tear.area = 61e-6;
  } else {
    input_error("tbad: unknown variant '{}' (expected OR, EN or EX)", variant);
  }
}

double resolved_exit_tear_position(const TbadSpec& spec) {
  const TearSpec& t = spec.exit_tear;
  if (t.position > 0)
    return t.position;
  const double axial = std::sqrt(t.area * t.aspect / std::numbers::pi); // as TearGeometry::axial
  return axial + std::max(2e-3, spec.wall_thickness);
}

namespace {

void positive(double value, const char* name, double to_unit = 1e3, const char* unit = "mm") {
  if (!(value > 0) || !std::isfinite(value))
    input_error("tbad: {} is {} {}, expected a positive number", name, value * to_unit, unit);
}

} // namespace

void validate(const TbadSpec& s) {
  positive(s.inlet_extension, "inlet extension");
  positive(s.ascending_length, "ascending aorta length");
  positive(s.arch_radius, "arch radius");
  positive(s.arch_distal_radius, "arch distal radius");
  positive(s.flap_start_gap, "flap start gap");
  positive(s.flap_length, "flap length");
  positive(s.taper_length, "flap taper length");
  positive(s.fl_end_depth, "false lumen end depth");
  positive(s.wall_thickness, "wall thickness (h)");
  positive(s.station_offset, "station offset");
  positive(s.outlet_distance, "outlet distance");
  positive(s.element_size, "element size");
  positive(s.aao_area, "AAo area", 1e6, "mm^2");
  positive(s.dao_dist_area, "DAo_dist area", 1e6, "mm^2");
  if (!(s.ascending_bow >= 0) || !std::isfinite(s.ascending_bow))
    input_error("tbad: ascending bow is {} mm, expected >= 0", s.ascending_bow * 1e3);
  if (!(std::abs(s.descending_bend) < 0.5))
    input_error("tbad: descending bend is {} rad, expected between -0.5 and 0.5",
                s.descending_bend);
  if (!(s.tear_element_size >= 0) || !std::isfinite(s.tear_element_size))
    input_error("tbad: tear element size is {} mm, expected >= 0 (0: automatic)",
                s.tear_element_size * 1e3);
  if (s.lumen_elements < 0 || s.lumen_elements > 10)
    input_error("tbad: lumen elements is {}, expected 0 (off) to 10 elements across the true lumen",
                s.lumen_elements);
  for (int k = 0; k < 5; ++k) {
    positive(s.tl_areas[k], fmt::format("TL{} area", k + 1).c_str(), 1e6, "mm^2");
    positive(s.fl_areas[k], fmt::format("FL{} area", k + 1).c_str(), 1e6, "mm^2");
  }
  for (const auto* tear : {&s.entry_tear, &s.exit_tear}) {
    const char* which = tear == &s.entry_tear ? "entry" : "exit";
    positive(tear->area, fmt::format("{} tear area", which).c_str(), 1e6, "mm^2");
    if (tear == &s.entry_tear)
      positive(tear->position, "entry tear position");
    else if (!(tear->position >= 0) || !std::isfinite(tear->position))
      input_error(
          "tbad: exit tear position is {} mm, expected >= 0 (0: just proximal to the flap's taper)",
          tear->position * 1e3);
    if (!(tear->aspect >= 1 && tear->aspect <= 4))
      input_error("tbad: {} tear aspect is {}, expected 1 to 4 (axial over circumferential)", which,
                  tear->aspect);
  }
  for (const BranchSpec& b : s.branches) {
    positive(b.radius, fmt::format("{} radius", b.name).c_str());
    positive(b.length, fmt::format("{} length", b.name).c_str());
    if (!(b.arch_position > 0.05 && b.arch_position < 0.95))
      input_error("tbad: {} arch position is {}, expected between 0.05 and 0.95", b.name,
                  b.arch_position);
  }
  for (int i = 0; i + 1 < 3; ++i)
    if (!(s.branches[i].arch_position < s.branches[i + 1].arch_position))
      input_error("tbad: branch arch positions must increase BCT < LCC < LSA, got {} {} {}",
                  s.branches[0].arch_position, s.branches[1].arch_position,
                  s.branches[2].arch_position);
  // Tets per element_size^3 is about 5 (see mesh/pipe_generator.cpp); a 0.5 m aorta of
  // 500 mm^2 with its wall at 0.4 mm would already be 25 M tets.
  if (s.element_size < 0.4e-3)
    input_error("tbad: element size {} mm is below 0.4 mm (tens of millions of tetrahedra)",
                s.element_size * 1e3);
}

} // namespace tearflow::geometry
