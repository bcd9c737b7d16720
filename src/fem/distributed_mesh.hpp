#pragma once
// The mesh as one MPI rank sees it. Every rank holds the whole (replicated) input mesh, which
// keeps readers simple and is affordable up to a few million tets; the nodes are
// partitioned by PETSc's graph partitioner and renumbered so that each rank owns a
// contiguous range of global node numbers, in reverse Cuthill-McKee order within it (a
// tet's nodes get close numbers: cache-friendly assembly); local tets are ordered by their
// lowest node. Each rank assembles the tets and face triangles
// whose first node it owns, so it needs the values of some nodes owned by others: its
// ghosts. Local node numbers: [0, n_owned) owned, [n_owned, n_local) ghosts.
#include <string>
#include <vector>

#include <petscvec.h>

#include "core/types.hpp"
#include "mesh/mesh.hpp"

namespace tearflow::fem {

struct LocalFace {
  std::string name;
  std::vector<Tri> triangles;     ///< this rank's share of the face, local node numbers
  std::vector<Index> owned_nodes; ///< every owned local node lying on the face
};

class DistributedMesh {
public:
  /// Collective. Throws a collective InputError when the ranks' copies of `mesh` differ.
  DistributedMesh(const mesh::Mesh& mesh, MPI_Comm comm);

  MPI_Comm comm() const { return comm_; }
  Index num_owned() const { return n_owned_; }
  Index num_local() const { return static_cast<Index>(local_to_global_.size()); }
  Index num_global() const { return n_global_; }
  Index owned_begin() const { return owned_begin_; }

  Index global_index(Index local) const { return local_to_global_[local]; }
  Index original_index(Index local) const { return local_to_original_[local]; }
  /// For every node of the input mesh, its global (partitioned) number. Same on all ranks.
  const std::vector<Index>& original_to_global() const { return original_to_global_; }

  const std::vector<Vec3>& points() const { return x_; } ///< local node coordinates [m]
  const std::vector<Tet>& tets() const { return tets_; } ///< local tets, local node numbers
  const std::vector<int>& tet_region() const { return tet_region_; }
  const std::vector<LocalFace>& faces() const { return faces_; }
  const LocalFace& face(const std::string& name) const;

  /// Per owned node: number of distinct nodes it shares a tet with (itself included) that
  /// are owned by this rank (diag) and by others (offdiag). Exact matrix preallocation.
  const std::vector<PetscInt>& diag_node_counts() const { return d_nnz_; }
  const std::vector<PetscInt>& offdiag_node_counts() const { return o_nnz_; }

private:
  MPI_Comm comm_;
  Index n_owned_ = 0, n_global_ = 0, owned_begin_ = 0;
  std::vector<Index> local_to_global_, local_to_original_, original_to_global_;
  std::vector<Vec3> x_;
  std::vector<Tet> tets_;
  std::vector<int> tet_region_;
  std::vector<LocalFace> faces_;
  std::vector<PetscInt> d_nnz_, o_nnz_;
};

/// A node-block vector (`block` unknowns per node) whole on every rank, in the input mesh's
/// node order (collective): what checkpoints and frames hold.
std::vector<double> gather_nodes(const DistributedMesh& mesh, Vec v, int block);
/// Sets this rank's owned entries of `v` from such a whole vector.
void scatter_nodes(const DistributedMesh& mesh, const std::vector<double>& all, Vec v, int block);

/// Node-to-node adjacency of a tet mesh in CSR form (each row sorted, self excluded).
struct NodeGraph {
  std::vector<Index> offsets, neighbours;
};
NodeGraph node_graph(const mesh::Mesh& mesh);

} // namespace tearflow::fem
