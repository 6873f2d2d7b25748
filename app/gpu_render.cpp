#include "gpu_render.h"

#include <vtkNew.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>

#include "gpu_volume_pass.h"
#include "x_display.h"

namespace sl {

vtkSmartPointer<vtkRenderWindow> offscreen_window(int w, int h)
{
  auto window = vtkSmartPointer<vtkRenderWindow>::New();
  window->SetOffScreenRendering(1);
  window->SetSize(w, h);
  window->SetMultiSamples(0);
  attach_x_display(window);
  return window;
}

struct GpuVolumeDrawer::Parts {
  vtkSmartPointer<vtkRenderWindow> window;
  vtkNew<vtkRenderer> renderer;
  vtkNew<GpuVolumePass> pass;
  const sl_renderer *source = nullptr;
};

GpuVolumeDrawer::GpuVolumeDrawer() : parts_(new Parts) {}

GpuVolumeDrawer::~GpuVolumeDrawer()
{
  if (parts_->window) parts_->window->Finalize();  // releases the pass's GL resources in its context
  delete parts_;
}

void GpuVolumeDrawer::resweep() { parts_->pass->Resweep(); }

bool GpuVolumeDrawer::draw(const sl_renderer *r, const sl_camera &cam, sl_image *volume, sl_image *background,
                           std::string *why, GpuTimings *timings)
{
  const std::string unsupported = GpuVolumePass::Unsupported(r);
  if (!unsupported.empty()) {
    *why = unsupported;
    return false;
  }
  Parts &p = *parts_;
  if (!p.window) {
    p.window = offscreen_window(cam.width, cam.height);
    p.window->AddRenderer(p.renderer);
    p.renderer->SetPass(p.pass);
  } else {
    p.window->SetSize(cam.width, cam.height);
  }
  if (p.source != r) p.pass->SetRenderer(r), p.source = r;
  p.pass->SetCamera(cam);
  p.pass->SetLayers(volume, background);
  p.window->Render();
  p.pass->SetLayers(nullptr, nullptr);
  if (!p.pass->Succeeded()) {
    *why = p.pass->Error();
    return false;
  }
  if (timings) {
    timings->light_seconds = p.pass->LightSeconds();
    timings->eye_seconds = p.pass->EyeSeconds();
    timings->resolve_seconds = p.pass->ResolveSeconds();
  }
  return true;
}

bool gpu_render_volume(const sl_renderer *r, const sl_camera &cam, sl_image *volume, std::string *why,
                       GpuTimings *timings)
{
  GpuVolumeDrawer drawer;
  return drawer.draw(r, cam, volume, nullptr, why, timings);
}

}  // namespace sl
