// SimVascular "mesh-complete" directories through VTK's XML readers, and read_mesh.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <system_error>
#include <unordered_map>

#include <vtkCellArray.h>
#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkLogger.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkOutputWindow.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkStaticPointLocator.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "core/error.hpp"
#include "mesh/readers.hpp"

namespace tearflow::mesh {

namespace fs = std::filesystem;

namespace {

// Collects what VTK would print. VTK readers report errors only through vtkOutputWindow
// (and vtkLogger), never to the caller, so we capture the text for the InputError.
class CaptureWindow : public vtkOutputWindow {
public:
  static CaptureWindow* New();
  vtkTypeMacro(CaptureWindow, vtkOutputWindow) void DisplayText(const char* text) override {
    captured += text;
  }
  std::string captured;
};
vtkStandardNewMacro(CaptureWindow)

    // While alive, VTK's messages go to `window` instead of the terminal. VTK 9 also logs errors
    // to stderr through vtkLogger; we mute that and restore the previous cutoff afterwards.
    class VtkMessageCapture {
public:
  VtkMessageCapture()
      : window_(vtkSmartPointer<CaptureWindow>::New()), previous_(vtkOutputWindow::GetInstance()),
        verbosity_(vtkLogger::GetCurrentVerbosityCutoff()) {
    vtkOutputWindow::SetInstance(window_);
    vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
  }
  ~VtkMessageCapture() {
    vtkOutputWindow::SetInstance(previous_);
    vtkLogger::SetStderrVerbosity(verbosity_);
  }
  VtkMessageCapture(const VtkMessageCapture&) = delete;
  VtkMessageCapture& operator=(const VtkMessageCapture&) = delete;

  // The first error, without VTK's "ERROR: In file, line" header and object address.
  std::string first_error() const {
    const std::string& text = window_->captured;
    std::size_t at = text.find("ERROR");
    if (at == std::string::npos)
      return {};
    at = text.find('\n', at);
    const std::size_t end = text.find('\n', at + 1);
    std::string line = text.substr(at + 1, end == std::string::npos ? end : end - at - 1);
    if (const std::size_t colon = line.find("): "); colon != std::string::npos)
      line.erase(0, colon + 3);
    return line;
  }

private:
  vtkSmartPointer<CaptureWindow> window_;
  vtkSmartPointer<vtkOutputWindow> previous_;
  vtkLogger::Verbosity verbosity_;
};

// Reads an XML VTK file; any reported error or an empty result is an InputError.
template <typename Reader> auto read_vtk(const fs::path& file, const char* what) {
  auto reader = vtkSmartPointer<Reader>::New();
  reader->SetFileName(file.c_str());
  VtkMessageCapture capture;
  reader->Update();
  if (const std::string error = capture.first_error(); !error.empty())
    input_error("{} '{}' could not be read: {}", what, file.string(), error);
  vtkSmartPointer<typename std::remove_pointer_t<decltype(reader->GetOutput())>> out =
      reader->GetOutput();
  if (out->GetNumberOfPoints() == 0 || out->GetNumberOfCells() == 0)
    input_error("{} '{}' has no points or no cells", what, file.string());
  return out;
}

// The GlobalNodeID point array as integers, or empty if the file has none.
std::vector<long long> global_node_ids(vtkDataSet* data, const fs::path& file) {
  vtkDataArray* array = data->GetPointData()->GetArray("GlobalNodeID");
  if (!array)
    return {};
  if (array->GetNumberOfComponents() != 1 ||
      array->GetNumberOfTuples() != data->GetNumberOfPoints())
    input_error("'{}': GlobalNodeID has {} components for {} points, expected one per point",
                file.string(), array->GetNumberOfComponents(), data->GetNumberOfPoints());
  std::vector<long long> ids(static_cast<std::size_t>(array->GetNumberOfTuples()));
  for (std::size_t i = 0; i < ids.size(); ++i)
    ids[i] = std::llround(array->GetTuple1(static_cast<vtkIdType>(i)));
  return ids;
}

// The volume: tets only, as read (orientation is dealt with by the caller).
void read_volume(vtkUnstructuredGrid* grid, const fs::path& file, Mesh& mesh) {
  const vtkIdType np = grid->GetNumberOfPoints(), nc = grid->GetNumberOfCells();
  mesh.points.resize(static_cast<std::size_t>(np));
  for (vtkIdType i = 0; i < np; ++i) {
    grid->GetPoint(i, mesh.points[i].data());
    // Checked here, not only in check_mesh: the point locator must not see NaN or inf.
    if (!std::isfinite(mesh.points[i][0] + mesh.points[i][1] + mesh.points[i][2]))
      input_error("'{}': point {} has a non-finite coordinate", file.string(), i);
  }
  mesh.tets.resize(static_cast<std::size_t>(nc));
  vtkCellArray* cells = grid->GetCells();
  vtkIdType n = 0;
  const vtkIdType* ids = nullptr;
  for (vtkIdType c = 0; c < nc; ++c) {
    cells->GetCellAtId(c, n, ids);
    if (grid->GetCellType(c) != VTK_TETRA || n != 4)
      input_error("'{}': cell {} is of VTK type {} with {} points; only linear tetrahedra "
                  "(VTK_TETRA = {}) are supported",
                  file.string(), c, grid->GetCellType(c), n, VTK_TETRA);
    for (int k = 0; k < 4; ++k) {
      if (ids[k] < 0 || ids[k] >= np)
        input_error("'{}': cell {} refers to point {}, expected 0 to {}", file.string(), c, ids[k],
                    np - 1);
      mesh.tets[c][k] = static_cast<Index>(ids[k]);
    }
  }
}

// Maps the points of one face file to volume node indices.
class VolumeNodeFinder {
public:
  VolumeNodeFinder(vtkUnstructuredGrid* grid, const fs::path& file) : grid_(grid), file_(file) {
    // Match tolerance: the files store Float32 coordinates (about 7 digits), so 1e-6 of the
    // mesh size or of the largest coordinate is well above rounding and far below any edge.
    double b[6];
    grid->GetBounds(b);
    const double diagonal = std::hypot(b[1] - b[0], b[3] - b[2], b[5] - b[4]);
    double largest = 0;
    for (double x : b)
      largest = std::max(largest, std::abs(x));
    tolerance_ = 1e-6 * std::max(diagonal, largest);
    locator_->SetDataSet(grid);
    locator_->BuildLocator();
    for (std::size_t i = 0; const long long id : global_node_ids(grid, file)) {
      if (!index_of_id_.emplace(id, static_cast<Index>(i++)).second)
        input_error("'{}': GlobalNodeID {} appears twice", file.string(), id);
    }
  }

  std::vector<Index> map(vtkPolyData* surface, const std::string& face,
                         const fs::path& file) const {
    const std::vector<long long> ids =
        index_of_id_.empty() ? std::vector<long long>{} : global_node_ids(surface, file);
    std::vector<Index> volume_node(static_cast<std::size_t>(surface->GetNumberOfPoints()));
    for (vtkIdType p = 0; p < surface->GetNumberOfPoints(); ++p) {
      double x[3];
      surface->GetPoint(p, x);
      if (!std::isfinite(x[0] + x[1] + x[2]))
        input_error("face '{}' ('{}'): point {} has a non-finite coordinate", face, file.string(),
                    p);
      Index v = -1;
      if (!ids.empty()) {
        const auto it = index_of_id_.find(ids[p]);
        if (it == index_of_id_.end())
          input_error("face '{}' ('{}'): point {} has GlobalNodeID {}, which no node of '{}' has",
                      face, file.string(), p, ids[p], file_.string());
        v = it->second;
        double y[3];
        grid_->GetPoint(v, y);
        if (std::hypot(x[0] - y[0], x[1] - y[1], x[2] - y[2]) > tolerance_)
          input_error("face '{}' ('{}'): point {} at ({}, {}, {}) has GlobalNodeID {}, but that "
                      "volume node is at ({}, {}, {})",
                      face, file.string(), p, x[0], x[1], x[2], ids[p], y[0], y[1], y[2]);
      } else {
        double dist2 = 0;
        v = static_cast<Index>(locator_->FindClosestPointWithinRadius(tolerance_, x, dist2));
        if (v < 0)
          input_error("face '{}' ('{}'): point {} at ({}, {}, {}) matches no node of '{}' within "
                      "{:.3g}",
                      face, file.string(), p, x[0], x[1], x[2], file_.string(), tolerance_);
      }
      volume_node[p] = v;
    }
    return volume_node;
  }

private:
  vtkUnstructuredGrid* grid_;
  fs::path file_;
  double tolerance_ = 0;
  vtkNew<vtkStaticPointLocator> locator_;
  std::unordered_map<long long, Index> index_of_id_;
};

Face read_face(const fs::path& file, const VolumeNodeFinder& finder) {
  Face face{file.stem().string(), {}};
  const auto surface = read_vtk<vtkXMLPolyDataReader>(file, "face file");
  if (surface->GetNumberOfVerts() + surface->GetNumberOfLines() + surface->GetNumberOfStrips() > 0)
    input_error("face '{}' ('{}'): has vertices, lines or strips; expected triangles only",
                face.name, file.string());
  const std::vector<Index> volume_node = finder.map(surface, face.name, file);
  vtkCellArray* polys = surface->GetPolys();
  face.triangles.resize(static_cast<std::size_t>(polys->GetNumberOfCells()));
  vtkIdType n = 0;
  const vtkIdType* ids = nullptr;
  for (vtkIdType c = 0; c < polys->GetNumberOfCells(); ++c) {
    polys->GetCellAtId(c, n, ids);
    if (n != 3)
      input_error("face '{}' ('{}'): polygon {} has {} points, expected triangles only", face.name,
                  file.string(), c, n);
    for (int k = 0; k < 3; ++k) {
      if (ids[k] < 0 || ids[k] >= static_cast<vtkIdType>(volume_node.size()))
        input_error("face '{}' ('{}'): polygon {} refers to point {}, which does not exist",
                    face.name, file.string(), c, ids[k]);
      face.triangles[c][k] = volume_node[ids[k]];
    }
  }
  return face;
}

// SimVascular (MeshSim/TetGen) writes tets of either orientation, consistently within a
// file. If every tet is negative that is the file's convention: flip them all. A mix is left
// alone so that check_mesh reports the inverted element.
void orient_tets(Mesh& mesh) {
  std::size_t negative = 0;
  for (const Tet& t : mesh.tets)
    negative += signed_volume(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]],
                              mesh.points[t[3]]) < 0;
  if (negative == mesh.tets.size())
    for (Tet& t : mesh.tets)
      std::swap(t[2], t[3]);
}

} // namespace

Mesh read_simvascular(const fs::path& dir, double length_scale, const std::string& region) {
  if (!(length_scale > 0) || !std::isfinite(length_scale))
    input_error("mesh directory '{}': length scale {} must be positive", dir.string(),
                length_scale);
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    input_error("mesh directory '{}' not found", dir.string());
  const fs::path volume_file = dir / "mesh-complete.mesh.vtu";
  if (!fs::is_regular_file(volume_file, ec))
    input_error("mesh directory '{}' has no mesh-complete.mesh.vtu (expected a SimVascular "
                "mesh-complete directory)",
                dir.string());
  const fs::path surface_dir = dir / "mesh-surfaces";
  std::vector<fs::path> face_files;
  if (fs::is_directory(surface_dir, ec))
    for (const auto& entry : fs::directory_iterator(surface_dir, ec))
      if (entry.path().extension() == ".vtp")
        face_files.push_back(entry.path());
  if (face_files.empty())
    input_error("mesh directory '{}' has no mesh-surfaces/*.vtp face files", dir.string());
  std::sort(face_files.begin(), face_files.end()); // directory order is unspecified

  Mesh mesh;
  mesh.source = "mesh directory '" + dir.string() + "'";
  const auto grid = read_vtk<vtkXMLUnstructuredGridReader>(volume_file, "volume mesh");
  read_volume(grid, volume_file, mesh);
  const VolumeNodeFinder finder(grid, volume_file);
  for (const fs::path& file : face_files)
    mesh.faces.push_back(read_face(file, finder));

  mesh.regions = {region};
  mesh.tet_region.assign(mesh.tets.size(), 0);
  orient_tets(mesh);
  for (Vec3& p : mesh.points)
    p = length_scale * p;
  drop_unused_nodes(mesh);
  check_mesh(mesh);
  return mesh;
}

Mesh read_mesh(const fs::path& path, double length_scale) {
  std::error_code ec;
  if (fs::is_directory(path, ec))
    return read_simvascular(path, length_scale);
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  if (ext == ".msh")
    return read_gmsh(path, length_scale);
  if (!fs::exists(path, ec))
    input_error("mesh file '{}' not found", path.string());
  input_error("mesh '{}': unknown format; expected a .msh file (Gmsh) or a SimVascular "
              "mesh-complete directory",
              path.string());
}

} // namespace tearflow::mesh
