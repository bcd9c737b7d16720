#pragma once
// Off-screen pictures with VTK, the steps every picture of the project shares: a camera
// looking at a scene from a direction, and a render window written as PNG (on a machine
// without a display through our own virtual X server, core/virtual_display.hpp).
#include <filesystem>
#include <string>

#include "core/types.hpp"

class vtkRenderWindow;
class vtkRenderer;

namespace tearflow {

/// Points the renderer's camera from direction `from` (towards the scene), `up` upwards, at
/// everything the renderer holds, or at the box `bounds` (xmin, xmax, ymin, ymax, zmin, zmax)
/// when given: two scenes framed on one box are seen by the same camera.
void look_from(vtkRenderer* renderer, const Vec3& from, const Vec3& up,
               const double* bounds = nullptr);

/// Renders `window` off-screen and writes it as `png`. `purpose` heads the error when no X
/// display can be had; InputError naming the file when VTK writes no picture.
void render_to_png(vtkRenderWindow* window, const std::filesystem::path& png,
                   const std::string& purpose);

} // namespace tearflow
