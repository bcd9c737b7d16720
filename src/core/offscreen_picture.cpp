#include "core/offscreen_picture.hpp"

#include <vtkCamera.h>
#include <vtkErrorCode.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkWindowToImageFilter.h>

#include "core/error.hpp"
#include "core/virtual_display.hpp"

namespace tearflow {

void look_from(vtkRenderer* renderer, const Vec3& from, const Vec3& up, const double* bounds) {
  const auto reset = [&] {
    if (bounds != nullptr)
      renderer->ResetCamera(bounds);
    else
      renderer->ResetCamera();
  };
  reset();
  vtkCamera* camera = renderer->GetActiveCamera();
  double focal[3];
  camera->GetFocalPoint(focal);
  const double d = camera->GetDistance();
  camera->SetPosition(focal[0] + d * from[0], focal[1] + d * from[1], focal[2] + d * from[2]);
  camera->SetViewUp(up[0], up[1], up[2]);
  reset();
  renderer->ResetCameraClippingRange();
}

void render_to_png(vtkRenderWindow* window, const std::filesystem::path& png,
                   const std::string& purpose) {
  // Debian's VTK renders through GLX even off-screen; without an X server it aborts, so one
  // of our own is started when there is none.
  ensure_display(purpose);
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(0); // multisampled buffers cannot be read back off-screen
  window->Render();
  vtkNew<vtkWindowToImageFilter> image;
  image->SetInput(window);
  image->ReadFrontBufferOff();
  image->Update();
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(png.c_str());
  writer->SetInputConnection(image->GetOutputPort());
  writer->Write();
  // A full disk or a read-only folder: VTK says so in the writer's error code only.
  if (const unsigned long code = writer->GetErrorCode(); code != vtkErrorCode::NoError)
    input_error("cannot write '{}': {}", png.string(), vtkErrorCode::GetStringFromErrorCode(code));
  std::error_code ec;
  if (!std::filesystem::is_regular_file(png, ec) || std::filesystem::file_size(png, ec) == 0)
    input_error("cannot render '{}': VTK wrote no picture", png.string());
}

} // namespace tearflow
