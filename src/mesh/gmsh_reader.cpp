// Gmsh .msh files through the Gmsh SDK, and the extraction of a Mesh from the in-memory Gmsh
// model that read_gmsh and make_pipe share.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <system_error>
#include <unordered_map>

#include <gmsh.h>

#include "core/error.hpp"
#include "mesh/gmsh_session.hpp"
#include "mesh/readers.hpp"

namespace tearflow::mesh {

namespace {

constexpr int kGmshTriangle = 2;    // 3-node triangle
constexpr int kGmshTetrahedron = 4; // 4-node tetrahedron

// Gmsh node tag -> 0-based index. Tags are usually dense (1..n), so a vector is the fast
// path; files with sparse tags (after deleting entities, merging, ...) use a hash map.
class NodeMap {
public:
  explicit NodeMap(const std::vector<std::size_t>& tags) {
    const std::size_t max_tag = tags.empty() ? 0 : *std::max_element(tags.begin(), tags.end());
    dense_ = max_tag <= 2 * tags.size() + 1024;
    if (dense_)
      table_.assign(max_tag + 1, -1);
    for (std::size_t i = 0; i < tags.size(); ++i) {
      if (dense_)
        table_[tags[i]] = static_cast<Index>(i);
      else
        sparse_.emplace(tags[i], static_cast<Index>(i));
    }
  }
  /// The index of `tag`, or -1 if the model has no such node.
  Index operator()(std::size_t tag) const {
    if (dense_)
      return tag < table_.size() ? table_[tag] : -1;
    const auto it = sparse_.find(tag);
    return it == sparse_.end() ? -1 : it->second;
  }

private:
  bool dense_ = true;
  std::vector<Index> table_;
  std::unordered_map<std::size_t, Index> sparse_;
};

// Only linear tets (3D) and linear triangles (2D) are supported; anything else (second
// order, hexahedra, prisms, quadrangles) would be silently dropped otherwise.
void check_element_types(const std::string& source) {
  for (int dim : {3, 2}) {
    std::vector<int> types;
    gmsh::model::mesh::getElementTypes(types, dim);
    const int expected = dim == 3 ? kGmshTetrahedron : kGmshTriangle;
    for (int type : types) {
      if (type == expected)
        continue;
      std::string name;
      int d = 0, order = 0, num_nodes = 0, num_primary = 0;
      std::vector<double> local;
      gmsh::model::mesh::getElementProperties(type, name, d, order, num_nodes, local, num_primary);
      input_error("{}: has {}D elements of type '{}' (Gmsh type {}, order {}); only linear "
                  "{} (Gmsh type {}) are supported",
                  source, dim, name, type, order, dim == 3 ? "tetrahedra" : "triangles", expected);
    }
  }
}

std::string physical_name(int dim, int tag, const char* fallback) {
  std::string name;
  gmsh::model::getPhysicalName(dim, tag, name);
  return name.empty() ? fallback + std::to_string(tag) : name;
}

// Appends the elements of `type` on entity `entity` to `out`, as node indices.
template <std::size_t N>
void append_elements(int type, int entity, const NodeMap& nodes, const std::string& source,
                     std::vector<std::array<Index, N>>& out) {
  // Fresh vectors: Gmsh 4.8 takes non-empty ones as preallocated for a multi-task call.
  std::vector<std::size_t> element_tags, node_tags;
  gmsh::model::mesh::getElementsByType(type, element_tags, node_tags, entity);
  if (node_tags.size() != N * element_tags.size())
    input_error("{}: entity {} has {} node tags for {} elements of type {}", source, entity,
                node_tags.size(), element_tags.size(), type);
  out.reserve(out.size() + element_tags.size());
  for (std::size_t e = 0; e < element_tags.size(); ++e) {
    std::array<Index, N> element{};
    for (std::size_t k = 0; k < N; ++k) {
      element[k] = nodes(node_tags[N * e + k]);
      if (element[k] < 0)
        input_error("{}: element {} refers to node {}, which is not in the mesh", source,
                    element_tags[e], node_tags[N * e + k]);
    }
    out.push_back(element);
  }
}

// Gmsh 4.8 does not check the node tags of elements read from an ASCII file: a negative tag
// (e.g. a corrupted "145" that became "1-5") indexes its node cache at -5 and crashes later.
// So in an ASCII file, the $Elements section must hold non-negative integers only.
void check_ascii_elements(const std::filesystem::path& file, const std::string& source) {
  std::ifstream in(file, std::ios::binary);
  std::string line;
  std::getline(in, line);
  if (line.rfind("$MeshFormat", 0) != 0)
    return; // let Gmsh judge other formats
  std::getline(in, line);
  std::istringstream format(line);
  double version = 0;
  int binary = 1;
  if (!(format >> version >> binary) || binary != 0)
    return;
  std::size_t number = 2;
  bool in_elements = false;
  while (std::getline(in, line)) {
    ++number;
    if (line.rfind("$Elements", 0) == 0)
      in_elements = true;
    else if (line.rfind("$EndElements", 0) == 0)
      in_elements = false;
    else if (in_elements) {
      const auto bad = std::find_if(line.begin(), line.end(), [](unsigned char c) {
        return !std::isdigit(c) && !std::isspace(c);
      });
      if (bad != line.end())
        input_error("{}: line {}: unexpected '{}' in $Elements, expected non-negative integers",
                    source, number, *bad);
    }
  }
}

} // namespace

Mesh mesh_from_gmsh_model(double length_scale, const std::string& source) {
  Mesh mesh;
  mesh.source = source;
  check_element_types(source);

  std::vector<std::size_t> node_tags;
  std::vector<double> coord, parametric;
  gmsh::model::mesh::getNodes(node_tags, coord, parametric, -1, -1, false, false);
  const NodeMap nodes(node_tags);
  mesh.points.resize(node_tags.size());
  for (std::size_t i = 0; i < node_tags.size(); ++i)
    for (int k = 0; k < 3; ++k)
      mesh.points[i][k] = length_scale * coord[3 * i + k];

  // Regions: 3D physical groups. An entity in two groups would duplicate its tets.
  gmsh::vectorpair groups;
  gmsh::model::getPhysicalGroups(groups, 3);
  std::map<int, int> region_of_volume; // volume entity -> region index
  for (const auto& [dim, tag] : groups) {
    mesh.regions.push_back(physical_name(dim, tag, "region"));
    std::vector<int> entities;
    gmsh::model::getEntitiesForPhysicalGroup(dim, tag, entities);
    for (int e : entities) {
      const auto [it, fresh] =
          region_of_volume.emplace(e, static_cast<int>(mesh.regions.size()) - 1);
      if (!fresh)
        input_error("{}: volume {} is in two 3D physical groups, '{}' and '{}'", source, e,
                    mesh.regions[it->second], mesh.regions.back());
    }
  }
  if (groups.empty())
    mesh.regions.push_back("fluid");

  gmsh::vectorpair volumes;
  gmsh::model::getEntities(volumes, 3);
  for (const auto& [dim, tag] : volumes) {
    const std::size_t before = mesh.tets.size();
    append_elements(kGmshTetrahedron, tag, nodes, source, mesh.tets);
    if (mesh.tets.size() == before)
      continue;
    int region = 0;
    if (!groups.empty()) {
      const auto it = region_of_volume.find(tag);
      if (it == region_of_volume.end())
        input_error("{}: the tets of volume {} are in no 3D physical group, but the file has "
                    "3D physical groups; put every volume in one",
                    source, tag);
      region = it->second;
    }
    mesh.tet_region.resize(mesh.tets.size(), region);
  }

  // Faces: 2D physical groups.
  gmsh::model::getPhysicalGroups(groups, 2);
  for (const auto& [dim, tag] : groups) {
    Face face{physical_name(dim, tag, "face"), {}};
    std::vector<int> entities;
    gmsh::model::getEntitiesForPhysicalGroup(dim, tag, entities);
    for (int e : entities)
      append_elements(kGmshTriangle, e, nodes, source, face.triangles);
    mesh.faces.push_back(std::move(face));
  }
  return mesh;
}

Mesh read_gmsh(const std::filesystem::path& file, double length_scale) {
  if (!(length_scale > 0) || !std::isfinite(length_scale))
    input_error("mesh file '{}': length scale {} must be positive", file.string(), length_scale);
  std::error_code ec;
  // Gmsh 4.8 ignores a missing file without any error, so check first.
  if (!std::filesystem::is_regular_file(file, ec))
    input_error("mesh file '{}' not found", file.string());
  const std::string source = "mesh file '" + file.string() + "'";
  check_ascii_elements(file, source);
  Mesh mesh;
  {
    GmshSession session;
    mesh = with_gmsh(source, [&] {
      gmsh::clear();
      gmsh::open(file.string());
      return mesh_from_gmsh_model(length_scale, source);
    });
  }
  if (mesh.tets.empty())
    input_error("{}: contains no tetrahedra (is it a volume mesh?)", source);
  drop_unused_nodes(mesh); // e.g. nodes of geometry points or of surface-only parts
  check_mesh(mesh);
  return mesh;
}

} // namespace tearflow::mesh
