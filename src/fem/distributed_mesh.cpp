#include "fem/distributed_mesh.hpp"

#include <algorithm>
#include <numeric>

#include <petscmat.h>

#include "core/error.hpp"
#include "fem/petsc.hpp"

namespace tearflow::fem {

NodeGraph node_graph(const mesh::Mesh& mesh) {
  const Index n = mesh.num_nodes();
  // node -> tets (CSR), then the union of their vertices per node, deduplicated by marker.
  std::vector<Index> count(n + 1, 0);
  for (const Tet& t : mesh.tets)
    for (Index v : t)
      ++count[v + 1];
  std::partial_sum(count.begin(), count.end(), count.begin());
  std::vector<Index> node_tets(count.back());
  std::vector<Index> fill(count.begin(), count.end() - 1);
  for (Index e = 0; e < mesh.num_tets(); ++e)
    for (Index v : mesh.tets[e])
      node_tets[fill[v]++] = e;

  NodeGraph g;
  g.offsets.assign(n + 1, 0);
  g.neighbours.reserve(static_cast<size_t>(n) * 14);
  std::vector<Index> marker(n, -1);
  for (Index v = 0; v < n; ++v) {
    marker[v] = v;
    const size_t row_begin = g.neighbours.size();
    for (Index k = count[v]; k < count[v + 1]; ++k)
      for (Index w : mesh.tets[node_tets[k]])
        if (marker[w] != v) {
          marker[w] = v;
          g.neighbours.push_back(w);
        }
    std::sort(g.neighbours.begin() + static_cast<std::ptrdiff_t>(row_begin), g.neighbours.end());
    g.offsets[v + 1] = static_cast<Index>(g.neighbours.size());
  }
  return g;
}

namespace {

/// Every rank reads or builds the whole mesh itself (see the header), and the partition and
/// the assembly take for granted that the copies are one mesh. They are not when the ranks
/// were given different cases, a mesh file changed while they read it, or a mesher is not
/// deterministic (as Gmsh's HXT is; pipe_generator.cpp and tbad_builder.cpp avoid it for that
/// reason): the partition then crashed, or the run would assemble parts of two meshes.
void check_ranks_hold_one_mesh(const mesh::Mesh& m, MPI_Comm comm) {
  if (mpi_size(comm) == 1)
    return;
  const std::uint64_t mine = mesh::digest(m);
  // One reduction: the least of (d, ~d) over the ranks is (lowest, ~highest).
  const std::uint64_t both[2] = {mine, ~mine};
  std::uint64_t least[2] = {0, 0};
  MPI_Allreduce(both, least, 2, MPI_UINT64_T, MPI_MIN, comm);
  if (least[0] != ~least[1])
    collective_input_error(
        "the {} MPI ranks hold different meshes (rank 0's: {}; digests differ, e.g. {:016x} and "
        "{:016x}). Each rank reads or builds the mesh itself, and all must get the same one: "
        "were the ranks given different cases, or was the mesh file changed while they read "
        "it? Give every rank the same case and a complete mesh file.",
        mpi_size(comm), m.source, least[0], ~least[1]);
}

/// Rank of every node, from PETSc's graph partitioner (PT-Scotch in Debian's build, chosen
/// with -mat_partitioning_type). Each rank hands PETSc one contiguous block of graph rows.
std::vector<int> partition_nodes(const NodeGraph& g, MPI_Comm comm) {
  const Index n = static_cast<Index>(g.offsets.size()) - 1;
  const int size = mpi_size(comm), rank = mpi_rank(comm);
  if (size == 1)
    return std::vector<int>(n, 0);

  const Index begin = static_cast<Index>(static_cast<long long>(n) * rank / size);
  const Index end = static_cast<Index>(static_cast<long long>(n) * (rank + 1) / size);
  PetscInt *ia = nullptr, *ja = nullptr; // ownership passes to the MPIAdj matrix
  const Index nnz = g.offsets[end] - g.offsets[begin];
  TF_PETSC(PetscMalloc1(end - begin + 1, &ia));
  TF_PETSC(PetscMalloc1(nnz, &ja));
  for (Index i = begin; i <= end; ++i)
    ia[i - begin] = g.offsets[i] - g.offsets[begin];
  std::copy(g.neighbours.begin() + g.offsets[begin], g.neighbours.begin() + g.offsets[end], ja);

  OwnedMat adj;
  TF_PETSC(MatCreateMPIAdj(comm, end - begin, n, ia, ja, nullptr, adj.out()));
  MatPartitioning part;
  TF_PETSC(MatPartitioningCreate(comm, &part));
  TF_PETSC(MatPartitioningSetAdjacency(part, adj));
  TF_PETSC(MatPartitioningSetFromOptions(part));
  OwnedIS local_part, all_part;
  TF_PETSC(MatPartitioningApply(part, local_part.out()));
  TF_PETSC(MatPartitioningDestroy(&part));
  TF_PETSC(ISAllGather(local_part, all_part.out()));
  const PetscInt* p = nullptr;
  TF_PETSC(ISGetIndices(all_part, &p));
  std::vector<int> owner(p, p + n);
  TF_PETSC(ISRestoreIndices(all_part, &p));
  return owner;
}

/// Breadth-first order of the component of `start` (neighbours by increasing degree, then
/// number), appended to `order`; marks the nodes visited.
void breadth_first(const NodeGraph& g, Index start, std::vector<char>& visited,
                   std::vector<Index>& order) {
  auto degree = [&](Index v) { return g.offsets[v + 1] - g.offsets[v]; };
  std::vector<Index> next;
  visited[start] = 1;
  order.push_back(start);
  for (size_t head = order.size() - 1; head < order.size(); ++head) {
    const Index v = order[head];
    next.clear();
    for (Index k = g.offsets[v]; k < g.offsets[v + 1]; ++k)
      if (const Index w = g.neighbours[k]; !visited[w]) {
        visited[w] = 1;
        next.push_back(w);
      }
    std::sort(next.begin(), next.end(), [&](Index a, Index b) {
      return degree(a) != degree(b) ? degree(a) < degree(b) : a < b;
    });
    order.insert(order.end(), next.begin(), next.end());
  }
}

/// Reverse Cuthill-McKee order of the nodes (George & Liu, Computer Solution of Large
/// Sparse Positive Definite Systems, 1981): per connected component, breadth-first from a
/// pseudo-peripheral node (the last node reached from a lowest-degree node, twice over),
/// reversed. Nodes of one tet get close numbers, so element loops, matrix insertion and the
/// solver's sweeps touch memory that is already in cache. Deterministic: every rank
/// computes the same order from the replicated graph.
std::vector<Index> reverse_cuthill_mckee(const NodeGraph& g) {
  const Index n = static_cast<Index>(g.offsets.size()) - 1;
  std::vector<Index> by_degree(n);
  std::iota(by_degree.begin(), by_degree.end(), 0);
  std::stable_sort(by_degree.begin(), by_degree.end(), [&](Index a, Index b) {
    return g.offsets[a + 1] - g.offsets[a] < g.offsets[b + 1] - g.offsets[b];
  });
  std::vector<char> visited(n, 0), probe(n, 0);
  std::vector<Index> order, sweep;
  order.reserve(n);
  for (Index s : by_degree) {
    if (visited[s])
      continue;
    Index start = s;
    for (int pass = 0; pass < 2; ++pass) { // towards a pseudo-peripheral node
      sweep.clear();
      breadth_first(g, start, probe, sweep);
      for (Index v : sweep)
        probe[v] = 0;
      start = sweep.back();
    }
    breadth_first(g, start, visited, order);
  }
  std::reverse(order.begin(), order.end());
  return order;
}

} // namespace

DistributedMesh::DistributedMesh(const mesh::Mesh& mesh, MPI_Comm comm) : comm_(comm) {
  check_ranks_hold_one_mesh(mesh, comm);
  const int rank = mpi_rank(comm), size = mpi_size(comm);
  const Index n = mesh.num_nodes();
  n_global_ = n;
  const NodeGraph graph = node_graph(mesh);
  const std::vector<int> owner = partition_nodes(graph, comm);

  // Renumber: nodes of rank 0 first, then rank 1, ...; reverse Cuthill-McKee order within a
  // rank (outputs and checkpoints keep the input order through original_index).
  std::vector<Index> first(size + 1, 0);
  for (Index v = 0; v < n; ++v)
    ++first[owner[v] + 1];
  std::partial_sum(first.begin(), first.end(), first.begin());
  owned_begin_ = first[rank];
  n_owned_ = first[rank + 1] - first[rank];
  original_to_global_.resize(n);
  {
    std::vector<Index> next(first.begin(), first.end() - 1);
    for (Index v : reverse_cuthill_mckee(graph))
      original_to_global_[v] = next[owner[v]]++;
  }

  // Local nodes: owned ones in global order, then ghosts in global order.
  std::vector<Index> global_to_local(n, -1);
  local_to_original_.assign(n_owned_, 0);
  for (Index v = 0; v < n; ++v)
    if (owner[v] == rank)
      local_to_original_[original_to_global_[v] - owned_begin_] = v;
  for (Index l = 0; l < n_owned_; ++l)
    global_to_local[local_to_original_[l]] = l;

  std::vector<Index> my_tets;
  for (Index e = 0; e < mesh.num_tets(); ++e)
    if (owner[mesh.tets[e][0]] == rank)
      my_tets.push_back(e);
  // Tets in the order of their lowest node: consecutive tets share nodes (cache reuse).
  auto lowest = [&](Index e) {
    const Tet& t = mesh.tets[e];
    return std::min({original_to_global_[t[0]], original_to_global_[t[1]],
                     original_to_global_[t[2]], original_to_global_[t[3]]});
  };
  std::stable_sort(my_tets.begin(), my_tets.end(),
                   [&](Index a, Index b) { return lowest(a) < lowest(b); });
  std::vector<Index> ghosts; // original numbers
  auto note_ghost = [&](Index v) {
    if (global_to_local[v] == -1) {
      global_to_local[v] = -2; // seen
      ghosts.push_back(v);
    }
  };
  for (Index e : my_tets)
    for (Index v : mesh.tets[e])
      note_ghost(v);
  for (const mesh::Face& f : mesh.faces)
    for (const Tri& t : f.triangles)
      if (owner[t[0]] == rank)
        for (Index v : t)
          note_ghost(v);
  std::sort(ghosts.begin(), ghosts.end(),
            [&](Index a, Index b) { return original_to_global_[a] < original_to_global_[b]; });
  for (Index v : ghosts) {
    global_to_local[v] = static_cast<Index>(local_to_original_.size());
    local_to_original_.push_back(v);
  }
  local_to_global_.resize(local_to_original_.size());
  x_.resize(local_to_original_.size());
  for (size_t l = 0; l < local_to_original_.size(); ++l) {
    local_to_global_[l] = original_to_global_[local_to_original_[l]];
    x_[l] = mesh.points[local_to_original_[l]];
  }

  tets_.reserve(my_tets.size());
  tet_region_.reserve(my_tets.size());
  for (Index e : my_tets) {
    const Tet& t = mesh.tets[e];
    tets_.push_back({global_to_local[t[0]], global_to_local[t[1]], global_to_local[t[2]],
                     global_to_local[t[3]]});
    tet_region_.push_back(mesh.tet_region.empty() ? 0 : mesh.tet_region[e]);
  }
  for (const mesh::Face& f : mesh.faces) {
    LocalFace lf;
    lf.name = f.name;
    std::vector<char> seen(n_owned_, 0);
    for (const Tri& t : f.triangles) {
      if (owner[t[0]] == rank)
        lf.triangles.push_back(
            {global_to_local[t[0]], global_to_local[t[1]], global_to_local[t[2]]});
      for (Index v : t)
        if (owner[v] == rank && !seen[global_to_local[v]]) {
          seen[global_to_local[v]] = 1;
          lf.owned_nodes.push_back(global_to_local[v]);
        }
    }
    std::sort(lf.owned_nodes.begin(), lf.owned_nodes.end());
    faces_.push_back(std::move(lf));
  }

  // Exact preallocation from the replicated graph: rows of owned nodes, split by owner.
  d_nnz_.assign(n_owned_, 1); // the node itself
  o_nnz_.assign(n_owned_, 0);
  for (Index l = 0; l < n_owned_; ++l) {
    const Index v = local_to_original_[l];
    for (Index k = graph.offsets[v]; k < graph.offsets[v + 1]; ++k)
      ++(owner[graph.neighbours[k]] == rank ? d_nnz_[l] : o_nnz_[l]);
  }
}

const LocalFace& DistributedMesh::face(const std::string& name) const {
  for (const LocalFace& f : faces_)
    if (f.name == name)
      return f;
  input_error("mesh has no face named '{}'", name);
}

std::vector<double> gather_nodes(const DistributedMesh& mesh, Vec v, int block) {
  OwnedScatter to_all;
  OwnedVec all;
  TF_PETSC(VecScatterCreateToAll(v, to_all.out(), all.out()));
  TF_PETSC(VecScatterBegin(to_all, v, all, INSERT_VALUES, SCATTER_FORWARD));
  TF_PETSC(VecScatterEnd(to_all, v, all, INSERT_VALUES, SCATTER_FORWARD));
  const std::vector<Index>& o2g = mesh.original_to_global();
  std::vector<double> out(o2g.size() * static_cast<size_t>(block));
  ReadArray a(all);
  for (size_t n = 0; n < o2g.size(); ++n)
    for (int c = 0; c < block; ++c)
      out[block * n + c] = a[block * o2g[n] + c];
  return out;
}

void scatter_nodes(const DistributedMesh& mesh, const std::vector<double>& all, Vec v, int block) {
  WriteArray a(v);
  for (Index l = 0; l < mesh.num_owned(); ++l) {
    const Index n = mesh.original_index(l);
    for (int c = 0; c < block; ++c)
      a[block * l + c] = all[block * n + c];
  }
}

} // namespace tearflow::fem
