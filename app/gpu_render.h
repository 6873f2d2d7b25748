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
  double light_seconds = 0.0, eye_seconds = 0.0;
};

// Draws r's volume for cam into volume (allocated at the camera's size) with the GPU pass and
// the CPU's resolve. Returns false with a one-line reason when the OpenGL context lacks what
// the shaders need or the model is not one the GPU path carries.
bool gpu_render_volume(const sl_renderer *r, const sl_camera &cam, sl_image *volume, std::string *why,
                       GpuTimings *timings);

}  // namespace sl
