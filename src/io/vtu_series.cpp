#include "io/vtu_series.hpp"

#include <algorithm>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include <fmt/format.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkErrorCode.h>
#include <vtkFieldData.h>
#include <vtkIntArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkStringArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include "core/error.hpp"

namespace tearflow::io {

VtuSeries::VtuSeries(const mesh::Mesh& mesh, std::filesystem::path directory, std::string stem)
    : grid_(vtkSmartPointer<vtkUnstructuredGrid>::New()), directory_(std::move(directory)),
      stem_(std::move(stem)) {
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(mesh.num_nodes());
  for (Index v = 0; v < mesh.num_nodes(); ++v)
    points->SetPoint(v, mesh.points[v][0], mesh.points[v][1], mesh.points[v][2]);
  grid_->SetPoints(points);
  auto cells = vtkSmartPointer<vtkCellArray>::New();
  cells->AllocateExact(mesh.num_tets(), 4 * mesh.num_tets());
  for (const Tet& t : mesh.tets) {
    const vtkIdType ids[4] = {t[0], t[1], t[2], t[3]};
    cells->InsertNextCell(4, ids);
  }
  grid_->SetCells(VTK_TETRA, cells);
  // Several volume regions (fluid and wall): each cell's region index, and the names in the
  // field data, so that ParaView's Threshold and `tearflow analyze` can pick the fluid.
  if (mesh.regions.size() > 1) {
    auto region = vtkSmartPointer<vtkIntArray>::New();
    region->SetName(kRegionArray);
    region->SetNumberOfTuples(mesh.num_tets());
    std::copy(mesh.tet_region.begin(), mesh.tet_region.end(), region->GetPointer(0));
    grid_->GetCellData()->AddArray(region);
    auto names = vtkSmartPointer<vtkStringArray>::New();
    names->SetName(kRegionNamesArray);
    for (const std::string& name : mesh.regions)
      names->InsertNextValue(name);
    grid_->GetFieldData()->AddArray(names);
  }
}

VtuSeries::~VtuSeries() = default;

void VtuSeries::write(int step, double time, const std::vector<PointField>& fields) {
  vtkPointData* pd = grid_->GetPointData();
  pd->Initialize();
  for (const PointField& f : fields) {
    auto a = vtkSmartPointer<vtkDoubleArray>::New();
    a->SetName(f.name.c_str());
    a->SetNumberOfComponents(f.components);
    a->SetNumberOfTuples(grid_->GetNumberOfPoints());
    std::copy(f.values.begin(), f.values.end(), a->GetPointer(0));
    pd->AddArray(a);
  }
  const std::string name = fmt::format("{}_{:06d}.vtu", stem_, step);
  // Through a temporary file: a frame cut short by a full disk never replaces a whole one.
  const std::filesystem::path file = directory_ / name, tmp = file.string() + ".tmp";
  auto writer = vtkSmartPointer<vtkXMLUnstructuredGridWriter>::New();
  writer->SetFileName(tmp.c_str());
  writer->SetInputData(grid_);
  writer->SetDataModeToAppended();
  writer->SetCompressorTypeToLZ4(); // fast; ParaView reads it
  // A failure is reported below once, with the file and its cause; VTK's own banner (the
  // pipeline's request dump) would only repeat it.
  const vtkTypeBool shown = vtkObject::GetGlobalWarningDisplay();
  vtkObject::GlobalWarningDisplayOff();
  const int written = writer->Write();
  vtkObject::SetGlobalWarningDisplay(shown);
  if (written != 1 || writer->GetErrorCode() != 0) {
    const unsigned long code = writer->GetErrorCode();
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    input_error("cannot write frame '{}': {}", file.string(),
                code == vtkErrorCode::OutOfDiskSpaceError ? "no space left on the device"
                : code != 0 ? vtkErrorCode::GetStringFromErrorCode(code)
                            : "the VTK writer failed");
  }
  std::filesystem::rename(tmp, file);
  frames_.emplace_back(time, name);
  try {
    write_pvd();
  } catch (const InputError& e) {
    // The list could not take the frame (a disk that filled between the two): the frame goes
    // too, so that the list still names every frame on disk and nothing else.
    frames_.pop_back();
    std::error_code ignored;
    std::filesystem::remove(file, ignored);
    input_error("cannot write frame '{}' into the series' list: {}", file.string(), e.what());
  }
}

void VtuSeries::write_pvd() const {
  std::string xml = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n"
                    "  <Collection>\n";
  for (const auto& [t, file] : frames_)
    xml += fmt::format("    <DataSet timestep=\"{:.10g}\" part=\"0\" file=\"{}\"/>\n", t, file);
  xml += "  </Collection>\n</VTKFile>\n";
  write_file_atomically(directory_ / (stem_ + ".pvd"), xml);
}

void VtuSeries::load_existing(double time_step) {
  frames_.clear();
  std::map<std::string, double> listed;
  if (std::ifstream in(directory_ / (stem_ + ".pvd")); in) {
    const std::regex entry(R"re(timestep="([^"]+)".*file="([^"]+)")re");
    std::string line;
    std::smatch m;
    while (std::getline(in, line))
      if (std::regex_search(line, m, entry))
        listed[m[2]] = std::stod(m[1]);
  }
  const std::regex frame_file(stem_ + R"(_([0-9]{6})\.vtu)");
  std::smatch m;
  for (const auto& e : std::filesystem::directory_iterator(directory_)) {
    const std::string name = e.path().filename().string();
    if (!std::regex_match(name, m, frame_file))
      continue;
    const auto it = listed.find(name);
    frames_.emplace_back(it != listed.end() ? it->second : std::stoi(m[1]) * time_step, name);
  }
  std::sort(frames_.begin(), frames_.end());
}

void VtuSeries::truncate_after(double time) {
  // Frame times are printed with 10 significant digits; compare with matching slack.
  std::erase_if(frames_, [&](const auto& f) { return f.first > time * (1 + 1e-9) + 1e-12; });
  write_pvd();
}

} // namespace tearflow::io
