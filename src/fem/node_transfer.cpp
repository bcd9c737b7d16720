#include "fem/node_transfer.hpp"

#include <algorithm>
#include <cmath>

#include <vtkCellArray.h>
#include <vtkGenericCell.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkStaticCellLocator.h>
#include <vtkUnstructuredGrid.h>

#include "core/error.hpp"

namespace tearflow::fem {

namespace {

/// Barycentric coordinates of p in tet (a, b, c, d), by Cramer's rule on
/// p - a = l1 (b - a) + l2 (c - a) + l3 (d - a).
std::array<double, 4> barycentric(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d,
                                  const Vec3& p) {
  const double v = mesh::signed_volume(a, b, c, d);
  const double l1 = mesh::signed_volume(a, p, c, d) / v;
  const double l2 = mesh::signed_volume(a, b, p, d) / v;
  const double l3 = mesh::signed_volume(a, b, c, p) / v;
  return {1.0 - l1 - l2 - l3, l1, l2, l3};
}

int region_index(const mesh::Mesh& m, const std::string& name) {
  const auto it = std::find(m.regions.begin(), m.regions.end(), name);
  return it == m.regions.end() ? -1 : static_cast<int>(it - m.regions.begin());
}

int tet_region(const mesh::Mesh& m, size_t e) {
  return m.tet_region.empty() ? 0 : m.tet_region[e];
}

} // namespace

NodeTransfer::NodeTransfer(const mesh::Mesh& from, const mesh::Mesh& to) : from_(from) {
  regions_ = to.regions.empty() ? std::vector<std::string>{""} : to.regions;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(from.num_nodes());
  for (Index n = 0; n < from.num_nodes(); ++n)
    points->SetPoint(n, from.points[n].data());

  for (size_t r = 0; r < regions_.size(); ++r) {
    const int source = to.regions.empty() ? 0 : region_index(from, regions_[r]);
    if (source < 0)
      input_error("mesh '{}' has no region '{}' to take the state of '{}' from", from.source,
                  regions_[r], to.source);
    // The source region's tets, and the target nodes that belong to the region.
    std::vector<Index> cell_tet;
    vtkNew<vtkCellArray> cells;
    for (size_t e = 0; e < from.tets.size(); ++e)
      if (tet_region(from, e) == source) {
        const vtkIdType ids[4] = {from.tets[e][0], from.tets[e][1], from.tets[e][2],
                                  from.tets[e][3]};
        cells->InsertNextCell(4, ids);
        cell_tet.push_back(static_cast<Index>(e));
      }
    vtkNew<vtkUnstructuredGrid> grid;
    grid->SetPoints(points);
    grid->SetCells(VTK_TETRA, cells);
    vtkNew<vtkStaticCellLocator> locator;
    locator->SetDataSet(grid);
    locator->BuildLocator();

    std::vector<unsigned char> member(to.num_nodes(), 0);
    for (size_t e = 0; e < to.tets.size(); ++e)
      if (to.regions.empty() || tet_region(to, e) == static_cast<int>(r))
        for (Index v : to.tets[e])
          member[v] = 1;

    std::vector<Location>& located = located_.emplace_back(to.num_nodes());
    vtkNew<vtkGenericCell> cell;
    vtkNew<vtkIdList> candidates;
    const auto weights_in = [&](vtkIdType id, const Vec3& p) {
      const Tet& t = from.tets[cell_tet[id]];
      return barycentric(from.points[t[0]], from.points[t[1]], from.points[t[2]], from.points[t[3]],
                         p);
    };
    for (Index n = 0; n < to.num_nodes(); ++n) {
      if (!member[n])
        continue;
      Vec3 p = to.points[n];
      // The tets whose boxes hold p, the one p is deepest in (VTK's FindCell accepts points
      // up to 1e-3 of a cell outside it, which would not reproduce a linear field).
      double box[6] = {p[0], p[0], p[1], p[1], p[2], p[2]};
      locator->FindCellsWithinBounds(box, candidates);
      vtkIdType id = -1;
      double deepest = -1e-12;
      for (vtkIdType k = 0; k < candidates->GetNumberOfIds(); ++k) {
        const std::array<double, 4> w = weights_in(candidates->GetId(k), p);
        if (const double depth = *std::min_element(w.begin(), w.end()); depth > deepest) {
          deepest = depth;
          id = candidates->GetId(k);
        }
      }
      if (id < 0) { // outside: the region's closest point
        Vec3 closest{};
        int sub = 0;
        double dist2 = 0.0;
        locator->FindClosestPoint(p.data(), closest.data(), cell, id, sub, dist2);
        largest_distance_ = std::max(largest_distance_, std::sqrt(dist2));
        p = closest;
      }
      std::array<double, 4> w = weights_in(id, p);
      double sum = 0.0; // on a face or edge: round-off below 0 clipped
      for (double& x : w)
        sum += (x = std::clamp(x, 0.0, 1.0));
      for (double& x : w)
        x /= sum;
      located[n] = {cell_tet[id], w};
    }
  }
}

std::vector<double> NodeTransfer::apply(const std::vector<double>& field, int block,
                                        const std::vector<std::string>& component_region) const {
  const size_t nodes = located_.front().size();
  std::vector<double> out(nodes * block, 0.0);
  for (int c = 0; c < block; ++c) {
    // The regions component c may come from, the first that holds the node wins.
    std::vector<size_t> from_regions;
    for (size_t r = 0; r < regions_.size(); ++r)
      if (component_region[c].empty() || component_region[c] == regions_[r])
        from_regions.push_back(r);
    for (size_t n = 0; n < nodes; ++n)
      for (size_t r : from_regions) {
        const Location& at = located_[r][n];
        if (at.tet < 0)
          continue;
        double value = 0.0;
        for (int k = 0; k < 4; ++k)
          value += at.weight[k] * field[static_cast<size_t>(from_.tets[at.tet][k]) * block + c];
        out[n * block + c] = value;
        break;
      }
  }
  return out;
}

} // namespace tearflow::fem
