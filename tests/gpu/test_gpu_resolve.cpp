// The GPU resolve (shaders/volume_resolve.glsl) against the CPU's of the same eye accumulator: the
// pass draws a frame, reads its accumulator back for sl_renderer_resolve_accumulator and
// sl_renderer_background, and resolves it on the GPU; the two sets of layers must agree to float
// accuracy. Cases: the cloud and the flat ground seen from 12 degrees above, the round earth's
// horizon from 30 km and from 300 m at dawn, the sun's disk filling a narrow view, night, no air.
//
// Tolerances. The resolve evaluates render/sky/sky_sample_shared.h in float where the CPU uses
// double; test_gpu_sky finds every one of those functions within 1e-5 relative of the C (worst
// measured 4.5e-6), and the resolve only multiplies and adds their results, so each layer's
// relative RMSE over R, G, B is held to 1e-5. Two things float cannot place to the pixel, counted
// and left out of the RMSE: the sun's disk edge (a pixel centre within 1e-4 of the disk's radius
// may fall either side: the in-disk test of d - sun in float has ~1e-7 error against a 4.4e-3
// chord) and the ground's edge at the horizon (a ray grazing the sphere). Transparency is the
// accumulator's own float on both sides (equal); depths are one float division (1e-6).
// Needs an X display (xvfb-run).
#include <vtkNew.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "gpu_render.h"
#include "gpu_volume_pass.h"
#include "vtk_png.h"
#include "sl_renderer_gpu.h"
#include "sl_sky.h"

namespace {

int failures = 0;

void check(bool ok, const char *what, const std::string &name)
{
  if (!ok) {
    ++failures;
    std::fprintf(stderr, "FAIL %s: %s\n", name.c_str(), what);
  }
}

// A 33 x 29 x 17 lattice, 100 m apart, its floor 500 m up: two cloud blobs.
void fill(sl_volume *v)
{
  float *eta = v->eta[SL_CLOUD];
  const double centres[2][4] = {{12, 14, 8, 7}, {22, 12, 7, 5}};  // i, j, k, radius in cells
  for (int k = 0; k < v->nz; ++k)
    for (int j = 0; j < v->ny; ++j)
      for (int i = 0; i < v->nx; ++i) {
        float value = 0.0f;
        for (const auto &c : centres) {
          const double di = i - c[0], dj = j - c[1], dk = k - c[2], r2 = (di * di + dj * dj + dk * dk) / (c[3] * c[3]);
          if (r2 < 1.0) value += (float)(3e7 * (1.0 - r2));
        }
        eta[sl_volume_index(v, i, j, k)] = value;
      }
}

struct Case {
  const char *name;
  bool air;
  double ground_radius, sun_azimuth, sun_elevation;
  // 0: framed on the cloud; 1: from 30 km toward a far horizon; 2: at the sun through 3 degrees;
  // 3: level from 300 m at dawn
  int kind;
};

// The whole frame's relative RMSE over R, G, B of gpu against cpu, leaving out the pixels in
// `skip`; and the largest channel difference.
double relative_rmse(const sl_image &gpu, const sl_image &cpu, const std::vector<char> &skip, double *max_diff)
{
  double num = 0.0, den = 0.0;
  *max_diff = 0.0;
  for (size_t q = 0; q < skip.size(); ++q) {
    if (skip[q]) continue;
    for (int c = 0; c < 3; ++c) {
      const double a = gpu.rgba[4 * q + c], b = cpu.rgba[4 * q + c];
      num += (a - b) * (a - b), den += b * b;
      *max_diff = std::max(*max_diff, std::fabs(a - b));
    }
  }
  return den > 0.0 ? std::sqrt(num / den) : num > 0.0 ? INFINITY : 0.0;
}

}  // namespace

int main()
{
  sl_error err{};
  std::string why;
  if (!sl::have_display(&why)) {
    std::fprintf(stderr, "FAIL %s\n", why.c_str());
    return 1;
  }
  sl_volume vol;
  const double spacing[3] = {100.0, 100.0, 100.0}, origin[3] = {-1600.0, -1400.0, 500.0};
  if (sl_volume_init(&vol, 33, 29, 17, origin, spacing, &err) || sl_volume_add_field(&vol, SL_CLOUD, &err)) {
    std::fprintf(stderr, "FAIL %s\n", err.message);
    return 1;
  }
  fill(&vol);
  const Case cases[] = {
      {"flat ground, day", true, 0.0, 240.0, 35.0, 0},
      {"round earth from 30 km", true, 6.37e6, 150.0, 20.0, 1},
      {"the sun's disk", true, 0.0, 200.0, 25.0, 2},
      {"round earth at dawn from 300 m", true, 6.37e6, 90.0, 2.0, 3},
      {"night", true, 0.0, 240.0, -8.0, 0},
      {"no air", false, 0.0, 240.0, 35.0, 0},
  };
  vtkSmartPointer<vtkRenderWindow> window = sl::offscreen_window(96, 72);
  vtkNew<vtkRenderer> ren;
  window->AddRenderer(ren);
  vtkNew<sl::GpuVolumePass> pass;
  ren->SetPass(pass);
  pass->SetReadAccumulator(true);
  int disk_pixels = 0, horizon_pixels = 0;
  for (const Case &k : cases) {
    sl_atmosphere atm;
    sl_atmosphere_init(&atm, sl_sky_rgb_wavelengths_nm, 3, SL_EARTH_ROUND, SL_RAYLEIGH_BODHAINE1999, &err);
    atm.ground_radius = k.ground_radius;
    sl_scene sc{};
    sc.volume = &vol;
    sc.atmosphere = k.air ? &atm : nullptr;
    sc.lighting = SL_LIGHTING_LOW_ALBEDO;
    sc.light_volume = 1;
    sc.termination_transparency = 1e-6;
    sl_sun_direction(k.sun_elevation, k.sun_azimuth, sc.sun_direction);
    for (int c = 0; c < 3; ++c) sc.sun_irradiance[c] = 1.0, sc.sky_radiance[c] = 0.1 * (c + 1);
    sl_renderer *r = sl_renderer_create(&sc, &err);
    if (!r) {
      std::fprintf(stderr, "FAIL %s: %s\n", k.name, err.message);
      return 1;
    }
    double lo[3], hi[3];
    sl_renderer_content_bounds(r, lo, hi);
    sl_camera cam;
    sl_camera_frame(lo, hi, 200.0, 12.0, 40.0, 96, 72, &cam);
    if (k.kind == 1) {
      const double p[3] = {0.0, -60000.0, 30000.0}, t[3] = {0.0, 230000.0, -4000.0};
      std::copy(p, p + 3, cam.position), std::copy(t, t + 3, cam.target);
      cam.fov_deg = 50.0;
    } else if (k.kind == 2) {
      for (int a = 0; a < 3; ++a) cam.target[a] = cam.position[a] + 1000.0 * sc.sun_direction[a];
      cam.fov_deg = 3.0;
    } else if (k.kind == 3) {
      const double p[3] = {0.0, -6000.0, 300.0}, t[3] = {10000.0, -6000.0, 300.0};
      std::copy(p, p + 3, cam.position), std::copy(t, t + 3, cam.target);
      cam.fov_deg = 60.0;
    }
    sl_image gpu_volume, gpu_background, cpu_volume, cpu_background;
    for (sl_image *img : {&gpu_volume, &gpu_background, &cpu_volume, &cpu_background})
      sl_image_alloc(img, cam.width, cam.height, &err);
    pass->SetRenderer(r);
    pass->SetCamera(cam);
    pass->SetLayers(&gpu_volume, &gpu_background);
    window->Render();
    pass->SetLayers(nullptr, nullptr);
    if (!pass->Succeeded()) {
      std::fprintf(stderr, "FAIL %s: %s\n", k.name, pass->Error().c_str());
      return 1;
    }
    if (sl_renderer_resolve_accumulator(r, &cam, pass->Accumulator().data(), 5, &cpu_volume, &err) ||
        sl_renderer_background(r, &cam, &cpu_background, &err)) {
      std::fprintf(stderr, "FAIL %s: %s\n", k.name, err.message);
      return 1;
    }
    // The pixels float cannot place: the disk's edge, the ground's edge.
    const size_t np = (size_t)cam.width * cam.height;
    std::vector<char> none(np, 0), edge(np, 0);
    const double chord = 2.0 * std::sin(0.25 * SL_SUN_ANGULAR_DIAMETER_DEG * M_PI / 180.0);
    int in_disk = 0, sky = 0, ground = 0;
    double worst_depth = 0.0, worst_ground = 0.0, worst_transparency = 0.0;
    for (size_t q = 0; q < np; ++q) {
      double d[3];
      sl_camera_ray(&cam, (int)(q % cam.width), (int)(q / cam.width), d);
      double s2 = 0.0;
      for (int a = 0; a < 3; ++a) s2 += (d[a] - sc.sun_direction[a]) * (d[a] - sc.sun_direction[a]);
      in_disk += k.air && sc.sun_direction[2] > 0.0 && s2 <= chord * chord;
      const float gd = gpu_background.depth[q], cd = cpu_background.depth[q];
      const bool disk_edge = k.air && std::fabs(std::sqrt(s2) / chord - 1.0) < 1e-4;
      const bool ground_edge = std::isinf(gd) != std::isinf(cd);
      if (disk_edge || ground_edge) {
        edge[q] = 1;
        disk_pixels += disk_edge, horizon_pixels += ground_edge;
        continue;
      }
      sky += std::isinf(cd), ground += !std::isinf(cd);
      if (!std::isinf(cd)) worst_ground = std::max(worst_ground, std::fabs((double)gd - cd) / std::fabs(cd));
      worst_transparency = std::max(worst_transparency, (double)std::fabs(gpu_volume.transparency[q] -
                                                                          cpu_volume.transparency[q]));
      const float gv = gpu_volume.depth[q], cv = cpu_volume.depth[q];
      if (std::isinf(gv) != std::isinf(cv)) worst_depth = INFINITY;
      else if (!std::isinf(cv)) worst_depth = std::max(worst_depth, (double)std::fabs(gv - cv) / std::fabs(cv));
    }
    double volume_max, background_max;
    const double volume_rmse = relative_rmse(gpu_volume, cpu_volume, none, &volume_max);
    const double background_rmse = relative_rmse(gpu_background, cpu_background, edge, &background_max);
    std::printf("%-32s volume layer rmse %.2e, background rmse %.2e (max |diff| %.2e, %.2e); depth %.1e, ground "
                "%.1e; %d sky, %d ground, %d sun's-disk pixels\n",
                k.name, volume_rmse, background_rmse, volume_max, background_max, worst_depth, worst_ground, sky,
                ground, in_disk);
    check(volume_rmse <= 1e-5, "the volume layer differs from the CPU's resolve by more than 1e-5", k.name);
    check(background_rmse <= 1e-5, "the background differs from the CPU's by more than 1e-5", k.name);
    check(worst_transparency == 0.0, "the transparency is not the accumulator's", k.name);
    check(worst_depth <= 1e-6, "the volume's depth differs by more than 1e-6", k.name);
    check(worst_ground <= 1e-5, "the ground's depth differs by more than 1e-5", k.name);
    // Every case must show what it is for.
    double volume_sum = 0.0;
    for (size_t q = 0; q < np; ++q) volume_sum += cpu_volume.rgba[4 * q + 3];
    if (k.kind == 0) check(volume_sum > 100.0, "the cloud is not in view", k.name);
    if (k.air && k.kind != 2) check(sky > 100 && ground > 100, "not both sky and ground in view", k.name);
    if (k.kind == 2) check(in_disk > 100, "the sun's disk covers too few pixels", k.name);
    for (sl_image *img : {&gpu_volume, &gpu_background, &cpu_volume, &cpu_background}) sl_image_free(img);
    pass->SetRenderer(nullptr);
    sl_renderer_destroy(r);
  }
  std::printf("left out of the background's RMSE: %d pixels on the sun's disk edge, %d on the ground's edge\n",
              disk_pixels, horizon_pixels);
  check(disk_pixels + horizon_pixels <= 20, "too many pixels on an edge", "all cases");
  sl_volume_free(&vol);
  std::printf("%s\n", failures ? "FAILED" : "passed");
  return failures ? 1 : 0;
}
