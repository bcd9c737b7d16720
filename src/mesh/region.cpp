#include "mesh/region.hpp"

#include <algorithm>
#include <map>

#include "core/error.hpp"

namespace tearflow::mesh {

int region_index(const Mesh& mesh, const std::string& name) {
  const auto it = std::find(mesh.regions.begin(), mesh.regions.end(), name);
  if (it == mesh.regions.end()) {
    std::string known;
    for (const std::string& r : mesh.regions)
      known += " '" + r + "'";
    input_error("{}: no volume region '{}'; its regions are{}", mesh.source, name, known);
  }
  return static_cast<int>(it - mesh.regions.begin());
}

Mesh extract_region(const Mesh& mesh, const std::string& name) {
  const int r = region_index(mesh, name);
  Mesh out;
  out.points = mesh.points;
  out.regions = {name};
  out.source = mesh.source + " (region " + name + ")";
  // Count how often each triangle (sorted nodes) appears among the region's tet faces: once
  // means it bounds the region.
  std::map<Tri, int> faces;
  constexpr int kFaceNodes[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  for (size_t t = 0; t < mesh.tets.size(); ++t) {
    if (mesh.tet_region[t] != r)
      continue;
    out.tets.push_back(mesh.tets[t]);
    out.tet_region.push_back(0);
    for (const auto& f : kFaceNodes) {
      Tri s{mesh.tets[t][f[0]], mesh.tets[t][f[1]], mesh.tets[t][f[2]]};
      std::sort(s.begin(), s.end());
      ++faces[s];
    }
  }
  for (const Face& f : mesh.faces) {
    Face kept{f.name, {}};
    for (const Tri& t : f.triangles) {
      Tri s = t;
      std::sort(s.begin(), s.end());
      if (const auto hit = faces.find(s); hit != faces.end() && hit->second == 1)
        kept.triangles.push_back(t);
    }
    if (!kept.triangles.empty())
      out.faces.push_back(std::move(kept));
  }
  drop_unused_nodes(out);
  return out;
}

} // namespace tearflow::mesh
