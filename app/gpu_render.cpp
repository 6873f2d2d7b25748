#include "gpu_render.h"

#include <vtkNew.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>

#include "gpu_volume_pass.h"
#include "sl_renderer_gpu.h"

namespace sl {

vtkSmartPointer<vtkRenderWindow> offscreen_window(int w, int h)
{
  auto window = vtkSmartPointer<vtkRenderWindow>::New();
  window->SetOffScreenRendering(1);
  window->SetSize(w, h);
  window->SetMultiSamples(0);
  return window;
}

bool gpu_render_volume(const sl_renderer *r, const sl_camera &cam, sl_image *volume, std::string *why,
                       GpuTimings *timings)
{
  const std::string unsupported = GpuVolumePass::Unsupported(r);
  if (!unsupported.empty()) {
    *why = unsupported;
    return false;
  }
  vtkSmartPointer<vtkRenderWindow> window = offscreen_window(cam.width, cam.height);
  vtkNew<vtkRenderer> renderer;
  window->AddRenderer(renderer);
  vtkNew<GpuVolumePass> pass;
  pass->SetRenderer(r);
  pass->SetCamera(cam);
  renderer->SetPass(pass);
  window->Render();
  if (!pass->Succeeded()) {
    *why = pass->Error();
    return false;
  }
  if (timings) {
    timings->light_seconds = pass->LightSeconds();
    timings->eye_seconds = pass->EyeSeconds();
  }
  sl_error err{};
  if (sl_renderer_resolve_accumulator(r, &cam, pass->Accumulator().data(), 5, volume, &err)) {
    *why = err.message;
    return false;
  }
  return true;
}

}  // namespace sl
