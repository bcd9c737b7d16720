#pragma once
// Off-screen pictures of the flow (issue 30): streamlines coloured by speed inside the
// translucent lumen from standard views, plane maps of the landmark sections, and the wall's
// displacement magnitude of an FSI run. The geometry comes from analysis/flow_features.hpp;
// each colour scale is fixed by the caller (the same for every run and frame, so pictures
// compare) and stated on the picture's scalar bar with its unit. Renders through VTK's
// OpenGL2 window, off-screen, on this process's X display (core/virtual_display.hpp starts
// one when there is none).
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "analysis/flow_features.hpp"
#include "core/types.hpp"

class vtkLookupTable;
class vtkPolyData;
class vtkUnstructuredGrid;

namespace tearflow::report {

/// A camera direction: the picture looks from `from` (unit vector from the model's centre
/// toward the camera), `up` upward on the picture.
struct View {
  std::string name; ///< in file names: "anterior", "left-lateral", "flap"
  Vec3 from{}, up{};
};

/// The standard views: anterior (from -y) and left lateral (from +x), the model's axes read
/// as patient LPS (x toward the patient's left, y posterior, z head), and along the flap's
/// normal (the first tear's), which shows the tears face on, when the landmarks have tears.
std::vector<View> standard_views(const geometry::Landmarks& landmarks);

/// A fixed colour scale and what it shows.
struct ColourScale {
  std::string title; ///< on the scalar bar, with the unit: "speed [m/s]"
  double min = 0.0, max = 1.0;
};

/// The scales every picture of a run shares, so that its pictures, animations and ParaView
/// state compare: speed on 0..speed_max, through-plane velocity on +-speed_max [m/s].
inline constexpr const char* kSpeedTitle = "speed [m/s]";
inline constexpr const char* kThroughPlaneTitle = "u.n [m/s]";
inline ColourScale speed_scale(double speed_max) {
  return {kSpeedTitle, 0.0, speed_max};
}
inline ColourScale through_plane_scale(double speed_max) {
  return {kThroughPlaneTitle, -speed_max, speed_max};
}

struct PictureSize {
  int width = 900, height = 1100; ///< [pixels]
};

inline constexpr PictureSize kPlaneMapSize{700, 700};

/// How a plane map is seen: from upstream along the plane's normal (`from` points from the
/// plane to the camera), in parallel projection, the picture's centre at `centre`, its x
/// axis along `right` and y along `up` (unit, in the plane), `half_height` [m] from the
/// centre to the top of the map's part of the picture. Pixel (i, j) of that part (j from the
/// bottom, w x h pixels) shows the point
///   centre + ((i + 1/2) - w/2) s right + ((j + 1/2) - h/2) s up,   s = 2 half_height / h.
struct PlaneView {
  Vec3 centre{}, right{}, up{}, from{};
  double half_height = 0.0;
};

/// The view that frames the sections of `maps` (one plane) with a margin, for a picture of
/// `size`; pass it to render_plane_map of another field's maps on the same plane (a scan's
/// beside the simulation's) so that the same pixel shows the same point in both.
PlaneView plane_view(const std::vector<const analysis::PlaneMap*>& maps, const PictureSize& size);

/// A picture written, with the colour scale its scalar bar shows (read back from the bar's
/// lookup table after rendering: what the reader sees, not what was asked for).
struct Picture {
  std::filesystem::path file;
  std::string scale_title;
  double scale_min = 0.0, scale_max = 0.0;
  int model_width = 0, model_height = 0; ///< pixels of the part left of the legend
  std::optional<PlaneView> plane;        ///< a plane map's view
};

/// Streamlines (point array `speed`) coloured on `speed`'s scale inside `lumen` (the fluid's
/// boundary surface, translucent), one PNG per view: `<stem>_<view>.png` in `directory`.
/// Returns the pictures written; InputError naming a PNG VTK did not write.
/// `bounds` (xmin, xmax, ..., zmax), when given, is the box each view frames instead of the
/// scene's own: another field's lumen (a scan's beside the simulation's) seen by one camera.
std::vector<Picture> render_streamlines(vtkPolyData* streamlines, vtkPolyData* lumen,
                                        const std::vector<View>& views, const ColourScale& speed,
                                        const std::string& caption,
                                        const std::filesystem::path& directory,
                                        const std::string& stem, const PictureSize& size = {},
                                        const double* bounds = nullptr);

/// One plane's map: each section (one, or TLk and FLk of a paired station) coloured by its
/// through-plane velocity on `through_plane`'s scale, its rim outlined (true lumen blue, false
/// red, else black), the in-plane velocity as black arrows (an arrow of length 1.5 grid
/// spacings at `arrow_speed` [m/s]); seen as `view` says (plane_view(maps) when none). The
/// sections are unlit and their colour is looked up per pixel from the interpolated value, so
/// that a pixel's colour is the table's colour of u.n there.
Picture render_plane_map(const std::vector<const analysis::PlaneMap*>& maps,
                         const ColourScale& through_plane, double arrow_speed,
                         const std::string& caption, const std::filesystem::path& png,
                         const PictureSize& size = kPlaneMapSize,
                         const std::optional<PlaneView>& view = std::nullopt);

/// A lumen's colour in the plane pictures: true lumen blue, false red, else black; `light`
/// the paler tone of a second instant.
std::array<double, 3> lumen_colour(const std::string& lumen, bool light = false);

/// A section's rim drawn in a flap picture.
struct Outline {
  vtkPolyData* section = nullptr;
  std::array<double, 3> rgb{};
  double width = 2.0; ///< [pixels]
};

/// The rims of sections on one plane seen as `view` says, with a caption and no colour scale:
/// the flap's position at two instants.
Picture render_outlines(const std::vector<Outline>& outlines, const std::string& caption,
                        const std::filesystem::path& png, const PlaneView& view,
                        const PictureSize& size = kPlaneMapSize);

/// The through-plane velocity's colour table (blue - white - red over `scale`), for a reader
/// of the pictures that turns colours back into values.
vtkSmartPointer<vtkLookupTable> through_plane_table(const ColourScale& scale);

/// The wall's surface (point array `displacement` [m]) moved by its displacement and
/// coloured by its magnitude on `displacement`'s scale (in mm: title "... [mm]"), one PNG per
/// view: `<stem>_<view>.png`. The wall is drawn half-transparent so that the flap shows
/// through the outer wall.
std::vector<Picture> render_wall_displacement(vtkPolyData* wall, const std::vector<View>& views,
                                              const ColourScale& displacement,
                                              const std::string& caption,
                                              const std::filesystem::path& directory,
                                              const std::string& stem,
                                              const PictureSize& size = {});

/// The boundary surface of a volume mesh (the lumen of a fluid grid, the wall of a wall grid).
vtkSmartPointer<vtkPolyData> boundary_surface(vtkUnstructuredGrid* volume);

} // namespace tearflow::report
