// bench_render [STORM.nc] [--size N] [--slices N] [--repeat N]
// Renders a storm with the CPU half-angle slicer and prints load / light pass / eye pass / write
// times; then, in the same run, on the same grid at the same image size, times VTK's
// vtkFixedPointVolumeRayCastMapper with shading, and prints the ratio.
#include <omp.h>
#include <vtkCamera.h>
#include <vtkColorTransferFunction.h>
#include <vtkFixedPointVolumeRayCastMapper.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPiecewiseFunction.h>
#include <vtkPointData.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkVolume.h>
#include <vtkVolumeProperty.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "cli.h"
#include "sl_image_io.h"
#include "sl_renderer.h"
#include "sl_storm.h"

int main(int argc, char **argv)
{
  std::string storm = "datasets/cumulonimbus.nc";
  int size = 512, slices = 256, repeat = 3;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--size") && i + 1 < argc) size = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--slices") && i + 1 < argc) slices = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--repeat") && i + 1 < argc) repeat = std::atoi(argv[++i]);
    else storm = argv[i];
  }
  const int threads = omp_get_max_threads();
  sl_error err{};
  double t0 = sl::now_seconds();
  sl_storm_frame frame;
  sl_load_options lo{0, 0.0};
  if (sl_storm_load(storm.c_str(), &lo, &frame, &err)) {
    std::fprintf(stderr, "bench_render: %s\n", err.message);
    return 1;
  }
  const double t_load = sl::now_seconds() - t0;
  sl_scene sc{};
  sc.volume = &frame.volume;
  sc.termination_transparency = 1e-6;
  sc.slices = slices;
  sl_sun_vector(240.0, 35.0, sc.sun_direction);
  for (int c = 0; c < SL_CHANNELS; ++c) sc.sun_irradiance[c] = 1.0, sc.sky_radiance[c] = 0.05;
  t0 = sl::now_seconds();
  sl_renderer *r = sl_renderer_create(&sc, &err);
  const double t_plan = sl::now_seconds() - t0;
  double lo_box[3], hi_box[3];
  sl_renderer_content_bounds(r, lo_box, hi_box);
  sl_camera cam;
  sl_camera_frame(lo_box, hi_box, 200.0, 12.0, 40.0, size, size, &cam);
  sl_image img;
  sl_image_alloc(&img, size, size, &err);
  double best_light = 1e30, best_eye = 1e30, best_total = 1e30;
  sl_render_stats st{};
  for (int k = 0; k < repeat; ++k) {
    t0 = sl::now_seconds();
    sl_renderer_render(r, &cam, &img, &st, &err);
    best_total = std::min(best_total, sl::now_seconds() - t0);
    best_light = std::min(best_light, st.light_seconds);
    best_eye = std::min(best_eye, st.eye_seconds);
  }
  t0 = sl::now_seconds();
  sl_write_exr("/tmp/bench_render.exr", &img, SL_EXR_HALF, &err);
  const double t_write = sl::now_seconds() - t0;

  // The peer: VTK's CPU ray caster with shading on the same grid (total extinction as scalars).
  std::vector<float> beta(sl_volume_count(&frame.volume));
  sl_total_extinction(&frame.volume, beta.data(), &err);
  const float beta_max = *std::max_element(beta.begin(), beta.end());
  vtkNew<vtkImageData> grid;
  grid->SetDimensions(frame.volume.nx, frame.volume.ny, frame.volume.nz);
  grid->SetOrigin(frame.volume.origin);
  grid->SetSpacing(frame.volume.spacing);
  vtkNew<vtkFloatArray> scalars;
  scalars->SetNumberOfTuples((vtkIdType)beta.size());
  for (size_t i = 0; i < beta.size(); ++i) scalars->SetValue((vtkIdType)i, beta[i]);
  grid->GetPointData()->SetScalars(scalars);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(0.0, 0.0);
  opacity->AddPoint(0.01 * beta_max, 0.5);
  opacity->AddPoint(beta_max, 1.0);
  vtkNew<vtkColorTransferFunction> color;
  color->AddRGBPoint(0.0, 1, 1, 1);
  color->AddRGBPoint(beta_max, 1, 1, 1);
  vtkNew<vtkVolumeProperty> prop;
  prop->SetScalarOpacity(opacity);
  prop->SetColor(color);
  prop->ShadeOn();
  prop->SetInterpolationTypeToLinear();
  vtkNew<vtkFixedPointVolumeRayCastMapper> mapper;
  mapper->SetInputData(grid);
  mapper->SetNumberOfThreads(threads);
  // The same number of samples along a ray as slices across the box: world-unit sample spacing
  // of the box diagonal over the slice count (VTK's default of 1 unit would mean 1 m here).
  double diagonal = 0.0;
  for (int a = 0; a < 3; ++a) {
    const int n = a == 0 ? frame.volume.nx : a == 1 ? frame.volume.ny : frame.volume.nz;
    diagonal += (n * frame.volume.spacing[a]) * (n * frame.volume.spacing[a]);
  }
  diagonal = std::sqrt(diagonal);
  mapper->SetAutoAdjustSampleDistances(0);
  mapper->SetSampleDistance(diagonal / st.slices);
  mapper->SetInteractiveSampleDistance(diagonal / st.slices);
  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(prop);
  vtkNew<vtkRenderer> ren;
  ren->AddVolume(volume);
  vtkNew<vtkRenderWindow> win;
  win->SetOffScreenRendering(1);
  win->SetSize(size, size);
  win->AddRenderer(ren);
  vtkCamera *c = ren->GetActiveCamera();
  c->SetPosition(cam.position);
  c->SetFocalPoint(cam.target);
  c->SetViewUp(cam.up);
  c->SetViewAngle(cam.fov_deg);
  ren->ResetCameraClippingRange();
  t0 = sl::now_seconds();
  win->Render();
  const double vtk_first = sl::now_seconds() - t0;
  double vtk_best = 1e30;
  for (int k = 0; k < repeat; ++k) {
    c->Azimuth(0.5);  // a camera move, so the mapper really renders again
    t0 = sl::now_seconds();
    win->Render();
    vtk_best = std::min(vtk_best, sl::now_seconds() - t0);
  }
  std::printf("storm %s: grid %dx%dx%d, image %dx%d, %d slices, light buffer %dx%d, %d threads\n", storm.c_str(),
              frame.volume.nx, frame.volume.ny, frame.volume.nz, size, size, st.slices, st.light_width,
              st.light_height, threads);
  std::printf("stormlight: load %.3f s, plan %.3f s, light pass %.3f s, eye pass %.3f s, frame %.3f s (best of %d), "
              "write EXR %.3f s\n",
              t_load, t_plan, best_light, best_eye, best_total, repeat, t_write);
  std::printf("vtkFixedPointVolumeRayCastMapper (shading on): first frame %.3f s, frame %.3f s (best of %d)\n",
              vtk_first, vtk_best, repeat);
  std::printf("ratio stormlight frame / VTK frame: %.2f\n", best_total / vtk_best);
  sl_image_free(&img);
  sl_renderer_destroy(r);
  sl_storm_frame_free(&frame);
  return 0;
}
