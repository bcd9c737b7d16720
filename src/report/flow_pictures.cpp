#include "report/flow_pictures.hpp"

#include <algorithm>
#include <cmath>

#include <vtkActor.h>
#include <vtkArrowSource.h>
#include <vtkAutoInit.h>
#include <vtkCamera.h>
#include <vtkDoubleArray.h>
#include <vtkFeatureEdges.h>
#include <vtkGeometryFilter.h>
#include <vtkGlyph3D.h>
#include <vtkLookupTable.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkScalarsToColors.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkUnstructuredGrid.h>

#include "core/error.hpp"
#include "core/offscreen_picture.hpp"
#include "core/virtual_display.hpp"

// The rendering classes come from object factories these modules register (the text of the
// scalar bar and the caption from FreeType's).
VTK_MODULE_INIT(vtkRenderingOpenGL2);
VTK_MODULE_INIT(vtkRenderingFreeType);

namespace tearflow::report {

namespace {

constexpr const char* kDisplacementMm = "displacement_magnitude_mm";
// The model's share of the picture's width; the colour legend has the rest.
constexpr double kModelWidth = 0.82;

/// Blue (low) to red (high) through the rainbow's middle: the convention of flow pictures,
/// where readers look for the fast jet in red.
vtkSmartPointer<vtkLookupTable> speed_table(const ColourScale& scale) {
  auto table = vtkSmartPointer<vtkLookupTable>::New();
  table->SetHueRange(0.667, 0.0);
  table->SetTableRange(scale.min, scale.max);
  table->SetNumberOfTableValues(256);
  table->Build();
  return table;
}

/// Blue (against the normal, backflow) - white (0) - red (along it) for the through-plane
/// velocity, so that reversed flow stands out.
vtkSmartPointer<vtkLookupTable> diverging_table(const ColourScale& scale) {
  auto table = vtkSmartPointer<vtkLookupTable>::New();
  table->SetNumberOfTableValues(256);
  table->SetTableRange(scale.min, scale.max);
  for (int i = 0; i < 256; ++i) {
    const double s = i / 255.0; // 0 blue, 0.5 white, 1 red
    const double r = s < 0.5 ? 2 * s : 1.0, b = s < 0.5 ? 1.0 : 2 * (1 - s);
    const double g = s < 0.5 ? 2 * s : 2 * (1 - s);
    table->SetTableValue(i, r, g, b, 1.0);
  }
  return table;
}

vtkNew<vtkScalarBarActor> scalar_bar(vtkLookupTable* table, const ColourScale& scale) {
  vtkNew<vtkScalarBarActor> bar;
  bar->SetLookupTable(table);
  bar->SetTitle(scale.title.c_str());
  bar->SetNumberOfLabels(5);
  bar->SetLabelFormat("%.2g");
  // In the legend's own viewport (write_png), so that it never covers the model.
  bar->SetPosition(0.2, 0.1);
  bar->SetWidth(0.6);
  bar->SetHeight(0.8);
  bar->UnconstrainedFontSizeOn();
  for (vtkTextProperty* text : {bar->GetTitleTextProperty(), bar->GetLabelTextProperty()}) {
    text->SetColor(0, 0, 0);
    text->ItalicOff();
    text->ShadowOff();
    text->BoldOff();
    text->SetFontSize(16);
  }
  return bar;
}

/// The caption at the picture's foot, a line per "; "-separated part (the map's part of a
/// plane picture is 574 pixels wide: one line would be cut).
vtkNew<vtkTextActor> caption_actor(const std::string& caption) {
  std::string lines;
  for (std::size_t i = 0; i < caption.size(); ++i)
    if (caption.compare(i, 2, "; ") == 0)
      lines += '\n', ++i;
    else
      lines += caption[i];
  vtkNew<vtkTextActor> text;
  text->SetInput(lines.c_str());
  text->GetTextProperty()->SetColor(0, 0, 0);
  text->GetTextProperty()->SetFontSize(18);
  text->SetPosition(12, 12);
  return text;
}

vtkNew<vtkActor> coloured_actor(vtkPolyData* data, const char* array, vtkLookupTable* table,
                                const ColourScale& scale) {
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(data);
  mapper->SetScalarModeToUsePointFieldData();
  mapper->SelectColorArray(array);
  mapper->SetLookupTable(table);
  mapper->SetScalarRange(scale.min, scale.max);
  mapper->UseLookupTableScalarRangeOn();
  mapper->ScalarVisibilityOn();
  // The value is interpolated across a polygon and then looked up, so that each pixel shows
  // the table's colour of its value (interpolating the corners' colours would not be one).
  mapper->InterpolateScalarsBeforeMappingOn();
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  return actor;
}

vtkNew<vtkActor> plain_actor(vtkPolyData* data, const std::array<double, 3>& rgb, double opacity) {
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(data);
  mapper->ScalarVisibilityOff();
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(rgb[0], rgb[1], rgb[2]);
  actor->GetProperty()->SetOpacity(opacity);
  return actor;
}

/// Renders `renderer` into `png`; InputError when no picture results.
Picture write_png(vtkRenderer* renderer, vtkScalarBarActor* bar, const PictureSize& size,
                  const std::filesystem::path& png) {
  ensure_display(fmt::format("render '{}'", png.string()));
  vtkNew<vtkRenderer> legend;
  legend->SetViewport(kModelWidth, 0.0, 1.0, 1.0);
  legend->SetBackground(1, 1, 1);
  if (bar != nullptr)
    legend->AddActor2D(bar);
  vtkNew<vtkRenderWindow> window;
  window->AddRenderer(renderer);
  window->AddRenderer(legend);
  window->SetSize(size.width, size.height);
  render_to_png(window, png, fmt::format("render '{}'", png.string()));
  const int* model = renderer->GetSize();
  if (bar == nullptr) // a picture of lines only: no colour scale
    return {png, "", 0.0, 0.0, model[0], model[1], std::nullopt};
  const double* range = bar->GetLookupTable()->GetRange();
  return {png, bar->GetTitle(), range[0], range[1], model[0], model[1], std::nullopt};
}

/// The rim of a section (its boundary edges) as a line actor.
vtkNew<vtkActor> rim_actor(vtkPolyData* section, const std::array<double, 3>& rgb, double width) {
  vtkNew<vtkFeatureEdges> rim;
  rim->SetInputData(section);
  rim->BoundaryEdgesOn();
  rim->FeatureEdgesOff();
  rim->NonManifoldEdgesOff();
  rim->ManifoldEdgesOff();
  rim->ColoringOff();
  rim->Update();
  auto outline = plain_actor(rim->GetOutput(), rgb, 1.0);
  outline->GetProperty()->SetLineWidth(width);
  return outline;
}

/// Points the renderer's camera as `view` says (parallel projection).
void look_at_plane(vtkRenderer* renderer, const PlaneView& view) {
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->ParallelProjectionOn();
  const Vec3& c = view.centre;
  const double distance = 10 * view.half_height; // any: the projection is parallel
  camera->SetFocalPoint(c[0], c[1], c[2]);
  camera->SetPosition(c[0] + distance * view.from[0], c[1] + distance * view.from[1],
                      c[2] + distance * view.from[2]);
  camera->SetViewUp(view.up[0], view.up[1], view.up[2]);
  camera->SetParallelScale(view.half_height);
  renderer->ResetCameraClippingRange();
}

vtkNew<vtkRenderer> white_renderer() {
  vtkNew<vtkRenderer> renderer;
  renderer->SetBackground(1, 1, 1);
  renderer->SetViewport(0.0, 0.0, kModelWidth, 1.0);
  return renderer;
}

/// One picture per view of what `add(renderer)` puts in a fresh renderer, with the scale's
/// bar and a caption naming the view: DIRECTORY/STEM_<view>.png.
template <typename AddActors>
std::vector<Picture> render_views(const std::vector<View>& views, vtkLookupTable* table,
                                  const ColourScale& scale, const std::string& caption,
                                  const std::filesystem::path& directory, const std::string& stem,
                                  const PictureSize& size, const double* bounds, AddActors&& add) {
  std::vector<Picture> written;
  for (const View& view : views) {
    auto renderer = white_renderer();
    add(renderer.Get());
    auto bar = scalar_bar(table, scale);
    renderer->AddActor2D(caption_actor(caption + ", " + view.name));
    look_from(renderer, view.from, view.up, bounds);
    written.push_back(
        write_png(renderer, bar, size, directory / (stem + "_" + view.name + ".png")));
  }
  return written;
}

} // namespace

std::vector<View> standard_views(const geometry::Landmarks& landmarks) {
  std::vector<View> views = {{"anterior", {0, -1, 0}, {0, 0, 1}},
                             {"left-lateral", {1, 0, 0}, {0, 0, 1}}};
  if (!landmarks.tears.empty()) {
    const Vec3 n = landmarks.tears.front().normal;
    // Up is the head's direction as far as it is not the viewing direction.
    Vec3 up = Vec3{0, 0, 1} - n[2] * n;
    if (dot(up, up) < 1e-6)
      up = {0, 1, 0};
    views.push_back({"flap", n, up});
  }
  return views;
}

vtkSmartPointer<vtkPolyData> boundary_surface(vtkUnstructuredGrid* volume) {
  auto surface = vtkSmartPointer<vtkGeometryFilter>::New();
  surface->SetInputData(volume);
  surface->Update();
  return surface->GetOutput();
}

std::vector<Picture> render_streamlines(vtkPolyData* streamlines, vtkPolyData* lumen,
                                        const std::vector<View>& views, const ColourScale& speed,
                                        const std::string& caption,
                                        const std::filesystem::path& directory,
                                        const std::string& stem, const PictureSize& size,
                                        const double* bounds) {
  const auto table = speed_table(speed);
  return render_views(
      views, table, speed, caption, directory, stem, size, bounds, [&](vtkRenderer* renderer) {
        auto lines = coloured_actor(streamlines, analysis::kSpeedArray, table, speed);
        lines->GetProperty()->SetLineWidth(2.0);
        renderer->AddActor(lines);
        auto wall = plain_actor(lumen, {0.75, 0.6, 0.55}, 0.12);
        renderer->AddActor(wall);
      });
}

Picture render_plane_map(const std::vector<const analysis::PlaneMap*>& maps,
                         const ColourScale& through_plane, double arrow_speed,
                         const std::string& caption, const std::filesystem::path& png,
                         const PictureSize& size, const std::optional<PlaneView>& given) {
  if (maps.empty())
    input_error("cannot render '{}': no section", png.string());
  const PlaneView view = given ? *given : plane_view(maps, size);
  const auto table = diverging_table(through_plane);
  auto renderer = white_renderer();
  for (const analysis::PlaneMap* m : maps) {
    auto section = coloured_actor(m->section, analysis::kThroughPlaneArray, table, through_plane);
    section->GetProperty()->LightingOff(); // a map: the table's colours, unshaded
    renderer->AddActor(section);
    renderer->AddActor(rim_actor(m->section, lumen_colour(m->landmark.lumen), 3.0));
    if (m->vectors->GetNumberOfPoints() == 0)
      continue;
    vtkNew<vtkArrowSource> arrow;
    vtkNew<vtkGlyph3D> arrows;
    arrows->SetInputData(m->vectors);
    arrows->SetSourceConnection(arrow->GetOutputPort());
    arrows->SetInputArrayToProcess(1, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS,
                                   analysis::kInPlaneArray);
    arrows->SetVectorModeToUseVector();
    arrows->SetScaleModeToScaleByVector();
    arrows->OrientOn();
    arrows->SetScaleFactor(1.5 * m->vector_spacing / arrow_speed);
    arrows->Update();
    renderer->AddActor(plain_actor(arrows->GetOutput(), {0, 0, 0}, 1.0));
  }
  auto bar = scalar_bar(table, through_plane);
  renderer->AddActor2D(caption_actor(caption));
  look_at_plane(renderer, view);
  Picture p = write_png(renderer, bar, size, png);
  p.plane = view;
  return p;
}

std::array<double, 3> lumen_colour(const std::string& lumen, bool light) {
  if (lumen == "TL")
    return light ? std::array{0.55, 0.65, 1.0} : std::array{0.0, 0.2, 0.9};
  if (lumen == "FL")
    return light ? std::array{1.0, 0.6, 0.6} : std::array{0.85, 0.0, 0.0};
  return light ? std::array{0.6, 0.6, 0.6} : std::array{0.0, 0.0, 0.0};
}

Picture render_outlines(const std::vector<Outline>& outlines, const std::string& caption,
                        const std::filesystem::path& png, const PlaneView& view,
                        const PictureSize& size) {
  auto renderer = white_renderer();
  for (const Outline& o : outlines)
    renderer->AddActor(rim_actor(o.section, o.rgb, o.width));
  renderer->AddActor2D(caption_actor(caption));
  look_at_plane(renderer, view);
  Picture p = write_png(renderer, nullptr, size, png);
  p.plane = view;
  return p;
}

PlaneView plane_view(const std::vector<const analysis::PlaneMap*>& maps, const PictureSize& size) {
  if (maps.empty())
    input_error("plane view: no section to frame");
  // From upstream, looking down the plane's normal; up the head's direction in the plane.
  PlaneView v;
  const Vec3 n = maps.front()->landmark.normal;
  v.from = (-1.0 / std::sqrt(dot(n, n))) * n;
  Vec3 up = Vec3{0, 0, 1} - (dot(Vec3{0, 0, 1}, v.from)) * v.from;
  if (dot(up, up) < 1e-6)
    up = Vec3{0, 1, 0} - (dot(Vec3{0, 1, 0}, v.from)) * v.from;
  v.up = (1.0 / std::sqrt(dot(up, up))) * up;
  // The camera looks along -from: the picture's x axis is (-from) x up.
  v.right = cross(-1.0 * v.from, v.up);
  // The sections' extent along right and up, about the plane's own origin.
  const Vec3 o = maps.front()->landmark.origin;
  double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
  for (const analysis::PlaneMap* m : maps)
    for (vtkIdType i = 0; i < m->section->GetNumberOfPoints(); ++i) {
      Vec3 x;
      m->section->GetPoint(i, x.data());
      const double a[2] = {dot(x - o, v.right), dot(x - o, v.up)};
      for (int k = 0; k < 2; ++k) {
        lo[k] = std::min(lo[k], a[k]);
        hi[k] = std::max(hi[k], a[k]);
      }
    }
  if (lo[0] > hi[0])
    input_error("plane view of '{}': its section holds no point", maps.front()->landmark.name);
  v.centre = o + (0.5 * (lo[0] + hi[0])) * v.right + (0.5 * (lo[1] + hi[1])) * v.up;
  // The half height that fits both extents in the map's part of the picture, 10 % margin.
  const double aspect = kModelWidth * size.width / size.height;
  v.half_height = 0.55 * std::max(hi[1] - lo[1], (hi[0] - lo[0]) / aspect);
  return v;
}

vtkSmartPointer<vtkLookupTable> through_plane_table(const ColourScale& scale) {
  return diverging_table(scale);
}

std::vector<Picture> render_wall_displacement(vtkPolyData* wall, const std::vector<View>& views,
                                              const ColourScale& displacement,
                                              const std::string& caption,
                                              const std::filesystem::path& directory,
                                              const std::string& stem, const PictureSize& size) {
  vtkDataArray* d = wall->GetPointData()->GetArray("displacement");
  if (d == nullptr || d->GetNumberOfComponents() != 3)
    input_error("cannot render '{}': the wall has no point field 'displacement' with 3 "
                "components",
                (directory / stem).string());
  // The deformed wall, coloured by |d| in mm (the unit its scale states).
  vtkNew<vtkPolyData> moved;
  moved->ShallowCopy(wall);
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(wall->GetNumberOfPoints());
  vtkNew<vtkDoubleArray> magnitude;
  magnitude->SetName(kDisplacementMm);
  magnitude->SetNumberOfTuples(wall->GetNumberOfPoints());
  for (vtkIdType i = 0; i < wall->GetNumberOfPoints(); ++i) {
    double x[3], u[3];
    wall->GetPoint(i, x);
    d->GetTuple(i, u);
    points->SetPoint(i, x[0] + u[0], x[1] + u[1], x[2] + u[2]);
    magnitude->SetValue(i, 1e3 * std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]));
  }
  moved->SetPoints(points);
  moved->GetPointData()->AddArray(magnitude);
  const auto table = speed_table(displacement);
  return render_views(views, table, displacement, caption, directory, stem, size, nullptr,
                      [&](vtkRenderer* renderer) {
                        auto surface = coloured_actor(moved, kDisplacementMm, table, displacement);
                        surface->GetProperty()->SetOpacity(0.5);
                        renderer->AddActor(surface);
                      });
}

} // namespace tearflow::report
