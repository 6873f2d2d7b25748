// bench_gpu [STORM.nc] [--grid N] [--repeat N] [--sizes 512,1024] [--no-cpu] [--no-peer]
// Times the GPU pass (app/gpu_volume_pass): the light sweep (what a sun change costs) and the
// eye pass per frame (a camera move), multiple-scattering lighting, 3 wavelengths, and the
// resolve of the eye accumulator into the frame's layers (aerial perspective in front of the
// volume, the sky and the sun's disk behind it) two ways in the same run: on the GPU
// (shaders/volume_resolve.glsl, what --gpu does now) and, as --gpu did before, the accumulator
// read back for the CPU's sl_renderer_resolve_accumulator and sl_renderer_background. In the same
// run, on the same grid, camera and image sizes: VTK's vtkGPUVolumeRayCastMapper with shading
// (two samples per grid cell, as the pass marches; --no-peer skips it), and the CPU path with the
// same method (light volume built once, then the ray-marched eye pass; --no-cpu skips it). Prints
// seconds, frames per second and ratios. Under Xvfb the "GPU" is Mesa's llvmpipe on the CPU cores:
// the GL strings printed first say which.
#include <omp.h>
#include <vtkCamera.h>
#include <vtkColorTransferFunction.h>
#include <vtkFloatArray.h>
#include <vtkGPUVolumeRayCastMapper.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkOpenGLRenderWindow.h>
#include <vtkPiecewiseFunction.h>
#include <vtkPointData.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkVolume.h>
#include <vtkVolumeProperty.h>
#include <vtk_glew.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "bench_common.h"
#include "cli.h"
#include "gpu_render.h"
#include "gpu_volume_pass.h"
#include "sl_optics.h"
#include "sl_renderer.h"
#include "sl_renderer_gpu.h"
#include "sl_storm.h"

int main(int argc, char **argv)
{
  std::string storm = "datasets/cumulonimbus.nc";
  int grid = 0, repeat = 3;
  bool cpu = true, peer = true;
  std::vector<int> sizes = {512, 1024};
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--grid") && i + 1 < argc) grid = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--repeat") && i + 1 < argc) repeat = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--no-cpu")) cpu = false;
    else if (!std::strcmp(argv[i], "--no-peer")) peer = false;
    else if (!std::strcmp(argv[i], "--sizes") && i + 1 < argc) {
      sizes.clear();
      std::stringstream ss(argv[++i]);
      std::string item;
      while (std::getline(ss, item, ',')) sizes.push_back(std::atoi(item.c_str()));
    } else storm = argv[i];
  }
  sl_error err{};
  sl_storm_frame frame;
  sl_load_options lo{};
  if (sl_storm_load(storm.c_str(), &lo, &frame, &err)) {
    std::fprintf(stderr, "bench_gpu: %s\n", err.message);
    return 1;
  }
  sl_volume resampled{};
  const sl_volume *vol = &frame.volume;
  if (grid > 0) {
    if (!resample(frame.volume, grid, &resampled)) return 1;
    vol = &resampled;
  }
  unsigned mask = 0;
  for (int p = 0; p < SL_PARTICLE_COUNT; ++p)
    if (vol->eta[p]) mask |= 1u << p;
  sl_atmosphere atm;
  sl_atmosphere_init(&atm, sl_sky_rgb_wavelengths_nm, 3, SL_EARTH_ROUND, SL_RAYLEIGH_BODHAINE1999, &err);
  sl_optics_request req;
  sl_optics_request_defaults(&req);
  req.particles = mask;
  std::unique_ptr<sl_optics_tables, void (*)(sl_optics_tables *)> opt(sl_optics_build(&req, &err), sl_optics_free);
  if (!opt) {
    std::fprintf(stderr, "bench_gpu: %s\n", err.message);
    return 1;
  }
  sl_scene sc{};
  sc.volume = vol;
  sc.atmosphere = &atm;
  sc.optics = opt.get();
  sc.lighting = SL_LIGHTING_MULTIPLE;
  sc.termination_transparency = 1e-6;
  sc.light_volume = 1;
  sl_sun_direction(35.0, 240.0, sc.sun_direction);
  sl_renderer *r = sl_renderer_create(&sc, &err);
  if (!r) {
    std::fprintf(stderr, "bench_gpu: %s\n", err.message);
    return 1;
  }
  double blo[3], bhi[3];
  sl_renderer_content_bounds(r, blo, bhi);

  vtkSmartPointer<vtkRenderWindow> window = sl::offscreen_window(sizes[0], sizes[0]);
  vtkNew<vtkRenderer> ren;
  window->AddRenderer(ren);
  vtkNew<sl::GpuVolumePass> pass;
  pass->SetRenderer(r);
  ren->SetPass(pass);
  window->Render();  // the context, for the GL strings
  std::printf("storm %s, grid %dx%dx%d, 3 wavelengths, multiple scattering, %d CPU threads, best of %d frames\n",
              storm.c_str(), vol->nx, vol->ny, vol->nz, omp_get_max_threads(), repeat);
  std::printf("OpenGL: %s / %s / %s\n", (const char *)glGetString(GL_VENDOR), (const char *)glGetString(GL_RENDERER),
              (const char *)glGetString(GL_VERSION));

  // The VTK peer: total extinction as scalars, shading on, two samples per grid cell.
  vtkNew<vtkImageData> image;
  vtkNew<vtkVolumeProperty> prop;
  peer_volume(vol, image, prop);
  vtkNew<vtkGPUVolumeRayCastMapper> mapper;
  mapper->SetInputData(image);
  mapper->SetAutoAdjustSampleDistances(0);
  mapper->SetSampleDistance((float)(0.5 * std::min({vol->spacing[0], vol->spacing[1], vol->spacing[2]})));
  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(prop);
  vtkNew<vtkRenderer> vtk_ren;
  vtk_ren->AddVolume(volume);
  vtkSmartPointer<vtkRenderWindow> vtk_win = sl::offscreen_window(sizes[0], sizes[0]);
  vtk_win->AddRenderer(vtk_ren);

  bool swept = false;
  for (int size : sizes) {
    sl_camera cam;
    sl_camera_frame(blo, bhi, 200.0, 12.0, 40.0, size, size, &cam);
    window->SetSize(size, size);
    pass->SetCamera(cam);
    double t0 = sl::now_seconds();
    window->Render();
    if (!pass->Succeeded()) {
      std::fprintf(stderr, "bench_gpu: %s\n", pass->Error().c_str());
      return 1;
    }
    if (!swept) {
      std::printf("GPU first frame (upload, shader compile, sweep, eye): %.3f s\n", sl::now_seconds() - t0);
      double sweep = 1e30;
      for (int k = 0; k < repeat; ++k) {
        pass->Resweep();
        window->Render();
        sweep = std::min(sweep, pass->LightSeconds());
      }
      std::printf("GPU light sweep (a sun change): %.3f s\n", sweep);
      swept = true;
    }
    // Before: the accumulator read back, resolved and the sky drawn on the CPU. After: both on
    // the GPU, the layers read back. Alternating, best of each.
    double eye = 1e30, read = 1e30, cpu_resolve = 1e30, cpu_background = 1e30, gpu_resolve = 1e30;
    double layers_read = 1e30;
    sl_image img, bg;
    sl_image_alloc(&img, size, size, &err);
    sl_image_alloc(&bg, size, size, &err);
    for (int k = 0; k < repeat; ++k) {
      sl_camera_frame(blo, bhi, 200.0 + 0.5 * (k + 1), 12.0, 40.0, size, size, &cam);
      pass->SetCamera(cam);
      pass->SetReadAccumulator(true);
      pass->SetLayers(nullptr, nullptr);
      window->Render();
      eye = std::min(eye, pass->EyeSeconds());
      read = std::min(read, pass->AccumulatorReadSeconds());
      t0 = sl::now_seconds();
      sl_renderer_resolve_accumulator(r, &cam, pass->Accumulator().data(), 5, &img, &err);
      const double t1 = sl::now_seconds();
      sl_renderer_background(r, &cam, &bg, &err);
      cpu_resolve = std::min(cpu_resolve, t1 - t0);
      cpu_background = std::min(cpu_background, sl::now_seconds() - t1);
      pass->SetReadAccumulator(false);
      pass->SetLayers(&img, &bg);
      window->Render();
      pass->SetLayers(nullptr, nullptr);
      eye = std::min(eye, pass->EyeSeconds());
      gpu_resolve = std::min(gpu_resolve, pass->ResolveSeconds());
      layers_read = std::min(layers_read, pass->LayersReadSeconds());
    }
    std::printf("GPU eye pass %dx%d (a camera move): %.3f s, %.2f fps\n", size, size, eye, 1.0 / eye);
    const double before = read + cpu_resolve + cpu_background;
    std::printf("after the eye pass %dx%d: before %.3f s (accumulator read-back %.3f, CPU resolve %.3f, CPU sky and "
                "sun's disk %.3f); after %.3f s (GPU resolve, of which the layers' read-back %.3f); removed per "
                "frame %.3f s, ratio after / before %.3f\n",
                size, size, before, read, cpu_resolve, cpu_background, gpu_resolve, layers_read, before - gpu_resolve,
                gpu_resolve / before);
    std::printf("whole frame %dx%d (eye + the above): before %.3f s, after %.3f s, ratio %.3f\n", size, size,
                eye + before, eye + gpu_resolve, (eye + gpu_resolve) / (eye + before));
    // VTK's GPU ray caster, same camera and size.
    if (peer) {
      vtk_win->SetSize(size, size);
      vtkCamera *c = vtk_ren->GetActiveCamera();
      c->SetPosition(cam.position);
      c->SetFocalPoint(cam.target);
      c->SetViewUp(cam.up);
      c->SetViewAngle(cam.fov_deg);
      vtk_ren->ResetCameraClippingRange();
      vtk_win->Render();
      double vtk_best = 1e30;
      for (int k = 0; k < repeat; ++k) {
        c->Azimuth(0.5);
        t0 = sl::now_seconds();
        vtk_win->Render();
        glFinish();
        vtk_best = std::min(vtk_best, sl::now_seconds() - t0);
    }
    std::printf("vtkGPUVolumeRayCastMapper %dx%d (shading on, 2 samples per cell): %.3f s, %.2f fps\n", size, size,
                vtk_best, 1.0 / vtk_best);
    std::printf("ratio GPU pass eye frame / VTK GPU frame at %d: %.2f\n", size, eye / vtk_best);
    }
    if (cpu) {
      sl_render_stats st{};
      double cpu_eye = 1e30, cpu_light = 0.0;
      for (int k = 0; k < repeat; ++k) {
        sl_renderer_render(r, &cam, &img, &st, &err);
        cpu_eye = std::min(cpu_eye, st.eye_seconds);
        cpu_light = st.light_seconds;
      }
      std::printf("CPU light volume build %.3f s; CPU eye pass %dx%d %.3f s, %.2f fps\n", cpu_light, size, size, cpu_eye,
                  1.0 / cpu_eye);
      std::printf("ratio GPU pass / CPU path at %d: eye %.2f; light (sweep / build) printed above\n", size, eye / cpu_eye);
    }
    sl_image_free(&img);
    sl_image_free(&bg);
  }
  sl_renderer_destroy(r);
  sl_volume_free(&resampled);
  sl_storm_frame_free(&frame);
  return 0;
}
