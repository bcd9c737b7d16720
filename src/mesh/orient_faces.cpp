#include "mesh/orient_faces.hpp"

#include <algorithm>
#include <unordered_map>

#include "core/error.hpp"

namespace tearflow::mesh {

namespace {
std::uint64_t key(Tri t) {
  std::sort(t.begin(), t.end());
  // 21 bits per node index covers 2 M nodes; beyond that fall back to a mixed hash key.
  return (static_cast<std::uint64_t>(t[0]) * 2654435761ULL) ^
         (static_cast<std::uint64_t>(t[1]) << 21) ^ (static_cast<std::uint64_t>(t[2]) << 42);
}
} // namespace

void orient_faces_outward(Mesh& mesh) {
  // Only the tet faces that some named face uses are entered, so the map stays small.
  struct Entry {
    Tri sorted;
    Index opposite;
  };
  std::unordered_multimap<std::uint64_t, Entry> wanted;
  for (const Face& f : mesh.faces)
    for (Tri t : f.triangles) {
      std::sort(t.begin(), t.end());
      wanted.emplace(key(t), Entry{t, -1});
    }
  static constexpr int face_of[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  for (const Tet& tet : mesh.tets)
    for (int k = 0; k < 4; ++k) {
      Tri t{tet[face_of[k][0]], tet[face_of[k][1]], tet[face_of[k][2]]};
      std::sort(t.begin(), t.end());
      auto [lo, hi] = wanted.equal_range(key(t));
      for (auto it = lo; it != hi; ++it)
        if (it->second.sorted == t)
          it->second.opposite = tet[k];
    }
  for (Face& f : mesh.faces)
    for (Tri& t : f.triangles) {
      Tri s = t;
      std::sort(s.begin(), s.end());
      Index opposite = -1;
      auto [lo, hi] = wanted.equal_range(key(s));
      for (auto it = lo; it != hi; ++it)
        if (it->second.sorted == s)
          opposite = it->second.opposite;
      if (opposite < 0)
        input_error("{}: a triangle of face '{}' (nodes {} {} {}) bounds no tetrahedron",
                    mesh.source, f.name, t[0], t[1], t[2]);
      const Vec3& a = mesh.points[t[0]];
      const Vec3 n = cross(mesh.points[t[1]] - a, mesh.points[t[2]] - a);
      if (dot(n, mesh.points[opposite] - a) > 0.0)
        std::swap(t[1], t[2]);
    }
}

} // namespace tearflow::mesh
