// Off-screen picture of a geometry: the outer wall translucent, the lumen wall and flap
// half-transparent with the tears' rims in red, the caps coloured, and a disk at every
// landmark plane. Viewed along the flap's normal, so the tears are seen face-on.
#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include <vtkActor.h>
#include <vtkAutoInit.h>
#include <vtkBillboardTextActor3D.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRegularPolygonSource.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>

#include "core/error.hpp"
#include "core/offscreen_picture.hpp"
#include "core/virtual_display.hpp"
#include "geometry/geometry_report.hpp"

// The rendering classes come from object factories that these modules register; without
// them vtkRenderWindow::New() has no implementation.
VTK_MODULE_INIT(vtkRenderingOpenGL2);
VTK_MODULE_INIT(vtkRenderingFreeType); // the labels' text

namespace tearflow::geometry {

namespace {

constexpr double kMm = 1e3; // the picture in mm

vtkNew<vtkActor> triangles_actor(const mesh::Mesh& m, const std::vector<Tri>& tris,
                                 const std::array<double, 3>& rgb, double opacity) {
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> cells;
  std::map<Index, vtkIdType> local;
  for (const Tri& t : tris) {
    vtkIdType ids[3];
    for (int k = 0; k < 3; ++k) {
      auto [it, fresh] = local.emplace(t[k], 0);
      if (fresh) {
        const Vec3& p = m.points[t[k]];
        it->second = points->InsertNextPoint(p[0] * kMm, p[1] * kMm, p[2] * kMm);
      }
      ids[k] = it->second;
    }
    cells->InsertNextCell(3, ids);
  }
  vtkNew<vtkPolyData> pd;
  pd->SetPoints(points);
  pd->SetPolys(cells);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(pd);
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(rgb[0], rgb[1], rgb[2]);
  actor->GetProperty()->SetOpacity(opacity);
  return actor;
}

vtkNew<vtkActor> disk_actor(const Vec3& centre, const Vec3& normal, double radius,
                            const std::array<double, 3>& rgb) {
  vtkNew<vtkRegularPolygonSource> disk;
  disk->SetNumberOfSides(48);
  disk->SetCenter(centre[0] * kMm, centre[1] * kMm, centre[2] * kMm);
  disk->SetNormal(normal[0], normal[1], normal[2]);
  disk->SetRadius(radius * kMm);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(disk->GetOutputPort());
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(rgb[0], rgb[1], rgb[2]);
  actor->GetProperty()->SetOpacity(0.45);
  return actor;
}

// Interface triangles on a tear's rim: within 1.1 semi-axes of its centre and within half the
// across semi-axis of the flap's mid-plane (the rim spans the flap's 2 mm: a 62 mm^2 tear's
// across semi-axis is about 3 mm, so a third of it missed the rim's outer half).
bool on_tear(const mesh::Mesh& m, const Tri& t, const TearLandmark& tear) {
  Vec3 c{0, 0, 0};
  for (Index n : t)
    c = c + (1.0 / 3.0) * m.points[n];
  const Vec3 d = c - tear.centroid, across = cross(tear.normal, tear.axis);
  const double u = dot(d, tear.axis) / tear.axial, w = dot(d, across) / tear.across;
  return std::abs(dot(d, tear.normal)) < 0.5 * tear.across && u * u + w * w < 1.21;
}

/// A name written at a model point (mm), facing the camera, in `rgb`, above and right of it.
vtkNew<vtkBillboardTextActor3D> label(const std::string& text, const Vec3& at,
                                      const std::array<double, 3>& rgb, bool left = false) {
  vtkNew<vtkBillboardTextActor3D> l;
  l->SetInput(text.c_str());
  l->SetPosition(at[0] * kMm, at[1] * kMm, at[2] * kMm);
  vtkTextProperty* t = l->GetTextProperty();
  t->SetFontSize(20);
  t->SetColor(rgb[0], rgb[1], rgb[2]);
  t->BoldOn();
  t->SetBackgroundColor(1, 1, 1);
  t->SetBackgroundOpacity(0.6);
  if (left) // ending at the point: faces and tears, clear of the planes' names on the right
    t->SetJustificationToRight();
  l->SetDisplayOffset(left ? -12 : 8, 8);
  return l;
}

/// The centroid of a face's triangles (area-weighted).
Vec3 face_centroid(const mesh::Mesh& m, const std::vector<Tri>& tris) {
  Vec3 c{0, 0, 0};
  double area = 0;
  for (const Tri& t : tris) {
    const Vec3 &a = m.points[t[0]], &b = m.points[t[1]], &d = m.points[t[2]];
    const Vec3 n = cross(b - a, d - a);
    const double w = 0.5 * std::sqrt(dot(n, n));
    c = c + (w / 3.0) * (a + b + d);
    area += w;
  }
  return area > 0 ? (1.0 / area) * c : c;
}

} // namespace

void render_geometry(const mesh::Mesh& m, const Landmarks& landmarks,
                     const std::filesystem::path& png) {
  // Debian's VTK renders through GLX even off-screen; without an X server it aborts, so
  // one of our own is started when there is none.
  ensure_display(fmt::format("cannot render '{}' (or pass --no-png)", png.string()));
  vtkNew<vtkRenderer> renderer;
  renderer->SetBackground(1, 1, 1);
  std::vector<Tri> lumen_wall, tear_rims;
  for (const mesh::Face& f : m.faces) {
    if (f.name == "outer_wall") {
      renderer->AddActor(triangles_actor(m, f.triangles, {0.75, 0.75, 0.75}, 0.15));
    } else if (f.name == "interface" || f.name == "wall") {
      for (const Tri& t : f.triangles) {
        bool rim = false;
        for (const TearLandmark& tear : landmarks.tears)
          rim = rim || on_tear(m, t, tear);
        (rim ? tear_rims : lumen_wall).push_back(t);
      }
    } else if (f.name.rfind("wall_", 0) != 0) { // fluid caps
      renderer->AddActor(triangles_actor(m, f.triangles, {0.2, 0.6, 0.2}, 1.0));
      renderer->AddActor(label(f.name, face_centroid(m, f.triangles), {0.1, 0.45, 0.1}, true));
    }
  }
  renderer->AddActor(triangles_actor(m, lumen_wall, {0.85, 0.55, 0.45}, 0.35));
  renderer->AddActor(triangles_actor(m, tear_rims, {0.9, 0.0, 0.0}, 1.0));
  std::set<std::string> drawn; // TLk and FLk share one plane
  for (const Landmark& l : landmarks.planes) {
    const std::string station = l.lumen == "aorta" ? l.name : l.name.substr(2);
    if (!drawn.insert(station).second)
      continue;
    const std::array<double, 3> rgb =
        l.lumen == "aorta" ? std::array{0.1, 0.3, 0.9} : std::array{0.6, 0.1, 0.8};
    renderer->AddActor(disk_actor(l.origin, l.normal, 20e-3, rgb));
    // A station's planes by its number; the disk's rim, away from the lumen it cuts.
    const Vec3 n = (1.0 / std::sqrt(dot(l.normal, l.normal))) * l.normal;
    Vec3 side = cross(n, Vec3{0, 0, 1});
    if (dot(side, side) < 1e-6)
      side = cross(n, Vec3{0, 1, 0});
    side = (20e-3 / std::sqrt(dot(side, side))) * side;
    const bool face = std::any_of(m.faces.begin(), m.faces.end(),
                                  [&](const mesh::Face& f) { return f.name == l.name; });
    if (!face) // the inlet and outlet planes lie on their faces, named already
      renderer->AddActor(
          label(l.lumen == "aorta" ? l.name : "station " + station, l.origin + side, rgb));
  }
  for (const TearLandmark& tear : landmarks.tears)
    renderer->AddActor(
        label(fmt::format("{} tear", tear.name), tear.centroid, {0.8, 0.0, 0.0}, true));
  vtkNew<vtkTextActor> key;
  key->SetInput("green: inlet and outlet faces;  red: tear rims;  grey: outer wall\n"
                "disks: landmark planes (blue: aorta, purple: TL-FL stations)");
  key->GetTextProperty()->SetFontSize(16);
  key->GetTextProperty()->SetColor(0, 0, 0);
  key->SetPosition(10, 10);
  renderer->AddActor2D(key);
  // Look along the flap's normal (the first tear's), at the whole model.
  look_from(renderer, landmarks.tears.empty() ? Vec3{1, 0, 0} : landmarks.tears[0].normal,
            {0, 0, 1});
  renderer->GetActiveCamera()->Zoom(0.95); // room for the names at the model's ends

  vtkNew<vtkRenderWindow> window;
  window->AddRenderer(renderer);
  window->SetSize(900, 1400);
  render_to_png(window, png, fmt::format("cannot render '{}' (or pass --no-png)", png.string()));
}

} // namespace tearflow::geometry
