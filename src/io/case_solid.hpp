#pragma once
// The `solid:` section of a case file: material, density, integration mode and the solid's
// boundary conditions by face name (docs/case-file.md). A case with a solid section and no
// top-level boundary_conditions is a solid-only case.
#include <filesystem>
#include <string>

#include "bc/solid_conditions.hpp"
#include "io/case_yaml.hpp"
#include "mesh/mesh.hpp"
#include "physics/solid_material.hpp"

namespace tearflow::io {

struct SolidSpec {
  physics::SolidMaterial material; ///< validated moduli and density, SI
  bool quasi_static = false;       ///< no inertia: each step is an equilibrium under load
  bc::SolidConditions conditions;
};

/// Reads and validates `solid:`; errors name the file, line and key.
SolidSpec read_solid(const YamlValue& v, const std::filesystem::path& case_dir);

/// Every face the solid's conditions name exists in the mesh (InputError listing the mesh's
/// faces otherwise), and no face has two conditions.
void check_solid_against_mesh(const SolidSpec& s, const mesh::Mesh& m, const std::string& source);

} // namespace tearflow::io
