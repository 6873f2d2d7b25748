// The volume layer of a frame drawn by the GPU pass in an off-screen VTK window.
#pragma once

#include <vtkRenderWindow.h>
#include <vtkSmartPointer.h>

#include <string>

#include "sl_image.h"
#include "sl_renderer.h"

namespace sl {

// An off-screen VTK window of w x h without multisampling: float passes read back exact pixels.
vtkSmartPointer<vtkRenderWindow> offscreen_window(int w, int h);

struct GpuTimings {
  double light_seconds = 0.0, eye_seconds = 0.0;  // light: 0 when the frame reused the sweep
  double resolve_seconds = 0.0;                   // the GPU resolve and the layers' read-back
};

class GpuVolumePass;

// The GPU pass in its own off-screen window, kept between frames: the fields and tables are
// uploaded once, the light volume swept once per sun (resweep()), and each draw costs the eye
// pass and the resolve, both on the GPU. r must stay the same renderer for the drawer's life.
class GpuVolumeDrawer {
 public:
  GpuVolumeDrawer();
  ~GpuVolumeDrawer();
  // Draws r's volume for cam into volume and, when not null, the background (the sky and the
  // sun's disk) into background, both allocated at the camera's size: what sl_renderer_render
  // and sl_renderer_background write. False with a one-line reason when the OpenGL context or
  // the model is not enough for the GPU path.
  bool draw(const sl_renderer *r, const sl_camera &cam, sl_image *volume, sl_image *background, std::string *why,
            GpuTimings *timings);
  // The renderer's sun changed: the next draw sweeps the light volume again.
  void resweep();

 private:
  struct Parts;
  Parts *parts_;
};

// Draws r's volume for cam into volume (allocated at the camera's size) with the GPU pass.
// Returns false with a one-line reason when the OpenGL context lacks what
// the shaders need or the model is not one the GPU path carries.
bool gpu_render_volume(const sl_renderer *r, const sl_camera &cam, sl_image *volume, std::string *why,
                       GpuTimings *timings);

}  // namespace sl
