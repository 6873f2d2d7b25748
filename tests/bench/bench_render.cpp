// bench_render [STORM.nc] [--grid N] [--repeat N] [--quick] [--only I,J,...] [--march-samples N]
//              [--slices N] [--light-resolution N] [--termination T] [--thin-depth T] [--contention]
//              [--alternate]
// Times the CPU half-angle slicer: load, plan, light pass, eye pass, frame and EXR write, for the
// low-albedo model and the multiple-scattering lighting at 3 and 16 wavelengths, at 512x512 with
// 256 slices and 768x768 with 512 slices. With --grid N the storm is resampled (trilinearly) to
// N^3 samples over its box first. In the same run, on the same grid at 512x512, it times VTK's
// vtkFixedPointVolumeRayCastMapper with shading and prints the ratios. --slices overrides the
// slicer rows' slice counts, --light-resolution sets square texels (0: the renderer's choice) and
// --termination the eye's termination transparency (1e-6, as stormlight render): the knobs whose
// speed and image cost docs/PERFORMANCE.md measures. The 3-wavelength 512^2 frame is written to
// /tmp/bench_render.exr for 'stormlight compare'. --contention adds the 3-wavelength 512^2 frame
// and the light volume's eye pass at 1 and 2 threads, idle and with one and two processes spinning.
// --thin-depth sets the thin-step rows' optical depth (sl_scene.march_thin_depth, 0.05), --refine
// the adaptive-pixel rows' tolerance (sl_scene.march_refine_tolerance, 0.02). --alternate times
// the camera move against VTK's frame frame by frame (camera_moves_alternated).
#include <omp.h>
#include <signal.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
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
#include <memory>
#include <string>
#include <vector>

#include "bench_common.h"
#include "cli.h"
#include "sl_image_io.h"
#include "sl_optics.h"
#include "sl_renderer.h"
#include "sl_storm.h"

namespace {

// CPU time of the whole process (all threads): on a shared machine, wall time counts the time
// other programs hold the cores; CPU time does not.
double cpu_seconds()
{
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

struct Timing {
  double light = 1e30, eye = 1e30, frame = 1e30, cpu = 1e30, sky = 1e30;
  double frame_mean = 0.0, eye_mean = 0.0;  // over all frames, as a user running a series sees them
  int slices = 0, lw = 0, lh = 0, wide_isa = 0;
  long eye_samples = 0, light_samples = 0;
};

// sun_moves: each frame under a sun 0.01 degree from the last one's, as in a time series, so that
// nothing that depends on the sun is kept from the frame before (the slicer's light texels' spans).
Timing time_frames(const sl_scene &sc, int size, int repeat, sl_image *keep, bool sun_moves = false)
{
  sl_error err{};
  Timing t;
  sl_renderer *r = sl_renderer_create(&sc, &err);
  if (!r) {
    std::fprintf(stderr, "bench_render: %s\n", err.message);
    std::exit(1);
  }
  double lo[3], hi[3];
  sl_renderer_content_bounds(r, lo, hi);
  sl_camera cam;
  sl_camera_frame(lo, hi, 200.0, 12.0, 40.0, size, size, &cam);
  sl_image img;
  sl_image_alloc(&img, size, size, &err);
  for (int k = 0; k < repeat; ++k) {
    sl_render_stats st{};
    // The light volume's frames are camera moves: 0.5 degree around the storm each (as VTK's
    // peer below), so that nothing that depends on the camera could be kept.
    if (sc.light_volume) sl_camera_frame(lo, hi, 200.0 + 0.5 * k, 12.0, 40.0, size, size, &cam);
    if (sun_moves) {
      double sun[3];
      sl_sun_direction(35.0, 240.0 + 0.01 * (k + 1), sun);
      if (sl_renderer_set_sun(r, sun, &err)) {
        std::fprintf(stderr, "bench_render: %s\n", err.message);
        std::exit(1);
      }
    }
    const double t0 = sl::now_seconds(), c0 = cpu_seconds();
    sl_renderer_render(r, &cam, &img, &st, &err);
    const double seconds = sl::now_seconds() - t0;
    t.frame = std::min(t.frame, seconds);
    t.frame_mean += seconds / repeat, t.eye_mean += st.eye_seconds / repeat;
    t.cpu = std::min(t.cpu, cpu_seconds() - c0);
    t.light = std::min(t.light, st.light_seconds);
    t.eye = std::min(t.eye, st.eye_seconds);
    t.sky = std::min(t.sky, st.sky_seconds);
    t.slices = st.slices, t.lw = st.light_width, t.lh = st.light_height;
    t.eye_samples = st.eye_samples, t.light_samples = st.light_samples;
    t.wide_isa = st.wide_isa;
  }
  if (keep) {
    std::swap(*keep, img);
  }
  sl_image_free(&img);
  sl_renderer_destroy(r);
  return t;
}

// The median of a few timings.
double median(std::vector<double> v)
{
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n ? (n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2])) : 0.0;
}

// What a user with another job on the machine sees: the slicer's frame and the light volume's eye
// pass with 1 and 2 threads, idle and with one and two processes spinning (forked here). The
// thread counts alternate frame by frame on one renderer, so that the VM's drift (a quarter within
// minutes) falls on both alike; medians of `repeat` frames each. The slicer's threads meet twice
// per slice, where a descheduled thread would hold up the other (tiles.h, slice_barrier.h).
void contention(const sl_scene &slicer, const sl_scene &light_volume, int repeat)
{
  const int threads = omp_get_max_threads();
  sl_error err{};
  sl_renderer *r[2] = {sl_renderer_create(&slicer, &err), sl_renderer_create(&light_volume, &err)};
  if (!r[0] || !r[1]) {
    std::fprintf(stderr, "bench_render: %s\n", err.message);
    std::exit(1);
  }
  double lo[3], hi[3];
  sl_renderer_content_bounds(r[0], lo, hi);
  sl_camera cam;
  sl_camera_frame(lo, hi, 200.0, 12.0, 40.0, 512, 512, &cam);
  sl_image img;
  sl_image_alloc(&img, 512, 512, &err);
  for (int m = 0; m < 2; ++m) sl_renderer_render(r[m], &cam, &img, nullptr, &err);  // the light volume's sweep
  // 0, 1 and 2 other processes spinning: a second core busy, then more runnable work than cores.
  for (int busy = 0; busy <= 2; ++busy) {
    pid_t spinner[2] = {0, 0};
    for (int p = 0; p < busy; ++p)
      if ((spinner[p] = fork()) == 0)
        for (volatile unsigned long spin = 0;; spin = spin + 1) {
        }
    std::vector<double> t[2][2];  // [slicer frame, light-volume eye pass][threads - 1]
    for (int k = 0; k < repeat; ++k)
      for (int n = 1; n <= 2; ++n) {
        omp_set_num_threads(n);
        sl_render_stats st{};
        const double t0 = sl::now_seconds();
        sl_renderer_render(r[0], &cam, &img, &st, &err);
        t[0][n - 1].push_back(sl::now_seconds() - t0);
        sl_renderer_render(r[1], &cam, &img, &st, &err);
        t[1][n - 1].push_back(st.eye_seconds);
      }
    for (int p = 0; p < busy; ++p)
      if (spinner[p] > 0) {
        kill(spinner[p], SIGKILL);
        waitpid(spinner[p], nullptr, 0);
      }
    const double f1 = median(t[0][0]), f2 = median(t[0][1]), e1 = median(t[1][0]), e2 = median(t[1][1]);
    std::printf("%-14s slicer frame 1 thread %.3f s, 2 threads %.3f s (2/1 %.2f); light-volume eye pass 1 thread "
                "%.3f s, 2 threads %.3f s (2/1 %.2f); medians of %d alternated\n",
                busy == 0 ? "idle:" : busy == 1 ? "one core busy:" : "two processes:", f1, f2, f2 / f1, e1, e2,
                e2 / e1, repeat);
  }
  sl_image_free(&img);
  for (int m = 0; m < 2; ++m) sl_renderer_destroy(r[m]);
  omp_set_num_threads(threads);
}

// The camera move as a user turning around the storm sees it against VTK's peer: the light
// volume's eye pass (every pixel, and adaptive pixels at `refine`) and VTK's frame, alternated frame
// by frame, each camera 0.5 degree around from the last, so that the VM's drift falls on all three
// alike; medians and minima of `repeat` each, and the ratios of the medians.
void camera_moves_alternated(const sl_scene &light_volume, double refine, int repeat, const double lo[3],
                             const double hi[3], vtkRenderWindow *win, vtkCamera *vtk_camera)
{
  sl_error err{};
  sl_scene adaptive = light_volume;
  adaptive.march_refine_tolerance = refine;
  sl_renderer *r[2] = {sl_renderer_create(&light_volume, &err), sl_renderer_create(&adaptive, &err)};
  if (!r[0] || !r[1]) {
    std::fprintf(stderr, "bench_render: %s\n", err.message);
    std::exit(1);
  }
  sl_camera cam;
  sl_camera_frame(lo, hi, 200.0, 12.0, 40.0, 512, 512, &cam);
  sl_image img;
  sl_image_alloc(&img, 512, 512, &err);
  for (int m = 0; m < 2; ++m) sl_renderer_render(r[m], &cam, &img, nullptr, &err);  // the light volume's sweep
  std::vector<double> t[3];  // every pixel, adaptive pixels, VTK
  for (int k = 0; k < repeat; ++k) {
    sl_camera_frame(lo, hi, 200.0 + 0.5 * (k + 1), 12.0, 40.0, 512, 512, &cam);
    for (int m = 0; m < 2; ++m) {
      sl_render_stats st{};
      sl_renderer_render(r[m], &cam, &img, &st, &err);
      t[m].push_back(st.eye_seconds);
    }
    vtk_camera->Azimuth(0.5);
    const double t0 = sl::now_seconds();
    win->Render();
    t[2].push_back(sl::now_seconds() - t0);
  }
  double med[3], least[3];
  for (int m = 0; m < 3; ++m) med[m] = median(t[m]), least[m] = *std::min_element(t[m].begin(), t[m].end());
  std::printf("camera move alternated with VTK's frame, medians of %d (minima): every pixel %.3f s (%.3f), adaptive "
              "pixels %g %.3f s (%.3f), VTK %.3f s (%.3f)\n",
              repeat, med[0], least[0], refine, med[1], least[1], med[2], least[2]);
  std::printf("ratio camera move / VTK frame, medians alternated: every pixel %.2f, adaptive pixels %g %.2f\n",
              med[0] / med[2], refine, med[1] / med[2]);
  sl_image_free(&img);
  for (int m = 0; m < 2; ++m) sl_renderer_destroy(r[m]);
}

}  // namespace

int main(int argc, char **argv)
{
  std::string storm = "datasets/cumulonimbus.nc";
  int grid = 0, repeat = 3, march_samples = 0, light_resolution = 0, slices = 0;
  double termination = 1e-6, thin_depth = 0.05, refine = 0.02;
  bool quick = false, busy = false, alternate = false;
  std::string only;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--grid") && i + 1 < argc) grid = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--repeat") && i + 1 < argc) repeat = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--quick")) quick = true;
    else if (!std::strcmp(argv[i], "--contention")) busy = true;
    else if (!std::strcmp(argv[i], "--alternate")) alternate = true;
    else if (!std::strcmp(argv[i], "--march-samples") && i + 1 < argc) march_samples = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--only") && i + 1 < argc) only = argv[++i];
    else if (!std::strcmp(argv[i], "--light-resolution") && i + 1 < argc) light_resolution = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--slices") && i + 1 < argc) slices = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--termination") && i + 1 < argc) termination = std::atof(argv[++i]);
    else if (!std::strcmp(argv[i], "--thin-depth") && i + 1 < argc) thin_depth = std::atof(argv[++i]);
    else if (!std::strcmp(argv[i], "--refine") && i + 1 < argc) refine = std::atof(argv[++i]);
    else storm = argv[i];
  }
  const int threads = omp_get_max_threads();
  sl_error err{};
  double t0 = sl::now_seconds();
  sl_storm_frame frame;
  sl_load_options lo{};
  if (sl_storm_load(storm.c_str(), &lo, &frame, &err)) {
    std::fprintf(stderr, "bench_render: %s\n", err.message);
    return 1;
  }
  const double t_load = sl::now_seconds() - t0;
  sl_volume resampled{};
  const sl_volume *vol = &frame.volume;
  if (grid > 0) {
    if (!resample(frame.volume, grid, &resampled)) return 1;
    vol = &resampled;
  }
  std::printf("storm %s, grid %dx%dx%d, %d threads, best of %d frames\n", storm.c_str(), vol->nx, vol->ny, vol->nz,
              threads, repeat);
  std::printf("load %.3f s\n", t_load);

  unsigned mask = 0;
  for (int p = 0; p < SL_PARTICLE_COUNT; ++p)
    if (vol->eta[p]) mask |= 1u << p;
  sl_atmosphere atm3, atm16;
  double spectral[SL_SKY_SPECTRAL_COUNT];
  sl_sky_spectral_wavelengths(spectral);
  sl_atmosphere_init(&atm3, sl_sky_rgb_wavelengths_nm, 3, SL_EARTH_ROUND, SL_RAYLEIGH_BODHAINE1999, &err);
  sl_atmosphere_init(&atm16, spectral, SL_SKY_SPECTRAL_COUNT, SL_EARTH_ROUND, SL_RAYLEIGH_BODHAINE1999, &err);
  std::unique_ptr<sl_optics_tables, void (*)(sl_optics_tables *)> opt3(nullptr, sl_optics_free), opt16(nullptr, sl_optics_free);
  for (int s = 0; s < (quick ? 1 : 2); ++s) {
    sl_optics_request req;
    sl_optics_request_defaults(&req);
    req.particles = mask;
    sl_optics_request_wavelengths(&req, s ? "spectral16" : "rgb", &err);
    t0 = sl::now_seconds();
    sl_optics_tables *t = sl_optics_build(&req, &err);
    if (!t) {
      std::fprintf(stderr, "bench_render: %s\n", err.message);
      return 1;
    }
    std::printf("particle tables, %s: %.3f s (from the cache when it holds them)\n", s ? "16 wavelengths" : "3 wavelengths",
                sl::now_seconds() - t0);
    (s ? opt16 : opt3).reset(t);
  }

  // The light-volume march's scene as its rows set it (3 wavelengths, sun only), at `samples` per cell.
  auto light_volume_scene = [&](int samples) {
    sl_scene s{};
    s.volume = vol;
    s.atmosphere = &atm3;
    s.optics = opt3.get();
    s.lighting = SL_LIGHTING_MULTIPLE;
    s.termination_transparency = termination;
    s.light_resolution = light_resolution;
    s.light_volume = 1;
    s.march_samples = samples;
    sl_sun_direction(35.0, 240.0, s.sun_direction);
    return s;
  };

  // The faster marches' settings as their lines name them: thin steps, adaptive pixels, both.
  auto fast_name = [&](int k) {
    char what[96];
    if (k == 0) std::snprintf(what, sizeof what, "thin steps (optical depth %g)", thin_depth);
    else if (k == 1) std::snprintf(what, sizeof what, "adaptive pixels (tolerance %g)", refine);
    else std::snprintf(what, sizeof what, "thin steps %g and adaptive pixels %g", thin_depth, refine);
    return std::string(what);
  };

  struct Case {
    const char *name;
    sl_lighting lighting;
    int spectral, size, slices, light_volume;
    int baseline_isa = 0;  // 1: the passes' baseline x86-64 copy even where AVX-512 is there
    int sun_moves = 0;     // 1: a new sun every frame (time_frames)
    int skylight = 0;      // 1: the CLI's diffuse light: the sky dome and the diffuse sunlight (a lattice per sun)
    int thin_steps = 0;    // 1: the light volume's march with --thin-depth (sl_scene.march_thin_depth)
    int adaptive = 0;      // 1: the light volume's march with --refine (sl_scene.march_refine_tolerance)
  };
  std::vector<Case> cases = {{"low-albedo", SL_LIGHTING_LOW_ALBEDO, 0, 512, 256, 0},
                             {"multiple, 3 wl", SL_LIGHTING_MULTIPLE, 0, 512, 256, 0},
                             {"light volume, 3 wl", SL_LIGHTING_MULTIPLE, 0, 512, 0, 1},
                             {"multiple, 16 wl", SL_LIGHTING_MULTIPLE, 1, 512, 256, 0},
                             {"multiple, 3 wl", SL_LIGHTING_MULTIPLE, 0, 768, 512, 0},
                             {"multiple, 16 wl", SL_LIGHTING_MULTIPLE, 1, 768, 512, 0},
                             {"3 wl, x86-64 base", SL_LIGHTING_MULTIPLE, 0, 512, 256, 0, 1},
                             {"3 wl, sun moves", SL_LIGHTING_MULTIPLE, 0, 512, 256, 0, 0, 1},
                             {"3 wl, diffuse, mv", SL_LIGHTING_MULTIPLE, 0, 512, 256, 0, 0, 1, 1},
                             {"light vol., thin", SL_LIGHTING_MULTIPLE, 0, 512, 0, 1, 0, 0, 0, 1},
                             {"light vol., adapt", SL_LIGHTING_MULTIPLE, 0, 512, 0, 1, 0, 0, 0, 0, 1},
                             {"lv., thin+adapt", SL_LIGHTING_MULTIPLE, 0, 512, 0, 1, 0, 0, 0, 1, 1}};
  if (quick) cases.resize(3);
  if (!only.empty()) {
    // --only 2,3: the listed cases (1-based), for profiling one configuration.
    std::vector<Case> keep_cases;
    for (const char *p = only.c_str(); *p;) {
      const int k = std::atoi(p);
      if (k >= 1 && k <= (int)cases.size()) keep_cases.push_back(cases[k - 1]);
      while (*p && *p != ',') ++p;
      if (*p == ',') ++p;
    }
    cases = keep_cases;
  }
  double frame_512_ms = 0.0, lv_eye_ms = 0.0, base_512_ms = 0.0, moving_sun_512_ms = 0.0;
  Timing sky_512{};  // the moving-sun frame with the skylight and the diffuse sunlight
  int wide_512 = 0;
  sl_image keep{}, keep_base{}, keep_marched{};
  // The light volume's faster marches (thin steps, adaptive pixels, both), each against every step.
  sl_image keep_fast[3]{};
  double fast_eye_ms[3] = {0, 0, 0};
  long lv_samples = 0, fast_samples[3] = {0, 0, 0};
  std::printf("%-18s %9s %7s %12s %10s %10s %10s %8s\n", "lighting", "image", "slices", "light buffer", "light s",
              "eye s", "frame s", "fps");
  for (const Case &c : cases) {
    sl_scene sc{};
    sc.volume = vol;
    sc.atmosphere = c.spectral ? &atm16 : &atm3;
    sc.optics = c.spectral ? opt16.get() : opt3.get();
    sc.lighting = c.lighting;
    sc.slices = slices > 0 && c.slices > 0 ? slices : c.slices;
    sc.termination_transparency = termination;
    sc.light_resolution = light_resolution;
    sc.light_volume = c.light_volume;
    sc.march_samples = march_samples;  // the light-volume rows' eye samples per cell (0: the default, 1)
    sc.baseline_isa = c.baseline_isa;
    sc.skylight = c.skylight, sc.diffuse_sunlight = c.skylight;
    sc.march_thin_depth = c.thin_steps ? thin_depth : 0.0;
    sc.march_refine_tolerance = c.adaptive ? refine : 0.0;
    const int fast = c.thin_steps + 2 * c.adaptive - 1;  // -1: every step and pixel
    sl_sun_direction(35.0, 240.0, sc.sun_direction);
    const bool slicer_512 =
        c.size == 512 && c.lighting == SL_LIGHTING_MULTIPLE && !c.spectral && !c.light_volume && !c.sun_moves;
    sl_image *kept = slicer_512       ? (c.baseline_isa ? &keep_base : &keep)
                     : c.light_volume ? (fast >= 0 ? &keep_fast[fast] : &keep_marched)
                                      : nullptr;
    const Timing t = time_frames(sc, c.size, repeat, kept, c.sun_moves);
    if (c.sun_moves && !c.skylight) moving_sun_512_ms = 1e3 * t.frame;
    if (c.sun_moves && c.skylight) sky_512 = t;
    if (slicer_512 && !c.baseline_isa) frame_512_ms = 1e3 * t.frame, wide_512 = t.wide_isa;
    if (slicer_512 && c.baseline_isa) base_512_ms = 1e3 * t.frame;
    char image[32], buffer[32];
    std::snprintf(image, sizeof image, "%dx%d", c.size, c.size);
    std::snprintf(buffer, sizeof buffer, "%dx%d", t.lw, t.lh);
    if (c.light_volume)
      std::printf("%-18s %9s %7s %12s %10.3f %10.3f %10.3f %8.2f   (light volume built once; frames pay the eye pass: "
                  "%.1fM eye samples; %.3f CPU s)\n",
                  c.name, image, "-", "grid", t.light, t.eye, t.eye, 1.0 / t.eye, 1e-6 * t.eye_samples, t.cpu);
    else
      std::printf("%-18s %9s %7d %12s %10.3f %10.3f %10.3f %8.2f   (%.1fM light, %.1fM eye samples; %.3f CPU s)\n",
                  c.name, image, t.slices, buffer, t.light, t.eye, t.frame, 1.0 / t.frame, 1e-6 * t.light_samples,
                  1e-6 * t.eye_samples, t.cpu);
    if (c.light_volume && fast < 0) lv_eye_ms = 1e3 * t.eye, lv_samples = t.eye_samples;
    if (fast >= 0) fast_eye_ms[fast] = 1e3 * t.eye, fast_samples[fast] = t.eye_samples;
  }
  if (keep_marched.rgba) {
    // The march's own limit: 8 samples per cell on the same cameras (its last frame), against which
    // the light-volume row's samples per cell are an approximation.
    const sl_scene ref = light_volume_scene(8);
    sl_image fine{};
    const Timing t = time_frames(ref, 512, repeat, &fine);
    sl_image_metrics im{};
    sl_image_compare(&keep_marched, &fine, &im, &err);
    std::printf("light volume at %d samples per cell against 8 (the last camera): relative RMSE %.3g, max |diff| %.3g; "
                "eye pass %.3f s against %.3f s\n",
                march_samples > 0 ? march_samples : 1, im.relative_rmse, im.max_abs_diff, lv_eye_ms / 1e3, t.eye);
    sl_image_free(&fine);
  }
  for (int k = 0; k < 3; ++k) {
    if (!keep_marched.rgba || !keep_fast[k].rgba) continue;
    // Against every step and pixel, on the same last camera.
    const std::string what = fast_name(k);
    sl_image_metrics im{};
    sl_image_compare(&keep_fast[k], &keep_marched, &im, &err);
    std::printf("light volume, %s against every step and pixel (the last camera): relative RMSE %.3g, max |diff| "
                "%.3g; eye pass %.3f s against %.3f s (%.2fx), samples %.1fM against %.1fM\n",
                what.c_str(), im.relative_rmse, im.max_abs_diff, fast_eye_ms[k] / 1e3, lv_eye_ms / 1e3,
                lv_eye_ms / fast_eye_ms[k], 1e-6 * fast_samples[k], 1e-6 * lv_samples);
    sl_image_free(&keep_fast[k]);
  }
  sl_image_free(&keep_marched);
  if (busy) {
    sl_scene slicer{}, lv{};
    slicer.volume = lv.volume = vol;
    slicer.atmosphere = lv.atmosphere = &atm3;
    slicer.optics = lv.optics = opt3.get();
    slicer.lighting = lv.lighting = SL_LIGHTING_MULTIPLE;
    slicer.slices = 256;
    slicer.termination_transparency = lv.termination_transparency = termination;
    lv.light_volume = 1;
    sl_sun_direction(35.0, 240.0, slicer.sun_direction);
    sl_sun_direction(35.0, 240.0, lv.sun_direction);
    contention(slicer, lv, repeat);
  }
  if (base_512_ms > 0.0 && frame_512_ms > 0.0 && keep.rgba && keep_base.rgba) {
    // The two instruction sets run the same loops: they may differ only by libmvec's last bits.
    sl_image_metrics im{};
    sl_image_compare(&keep, &keep_base, &im, &err);
    std::printf("ratio 3 wl frame, baseline x86-64 / %s: %.2f (images: relative RMSE %.2g, max |diff| %.2g)\n",
                wide_512 ? "AVX-512 copy" : "baseline (no AVX-512 here)", base_512_ms / frame_512_ms, im.relative_rmse,
                im.max_abs_diff);
  }
  if (moving_sun_512_ms > 0.0 && frame_512_ms > 0.0)
    std::printf("ratio 3 wl frame, sun moving / sun kept (the light texels' spans kept from the frame before): %.3f\n",
                moving_sun_512_ms / frame_512_ms);
  if (moving_sun_512_ms > 0.0 && sky_512.frame < 1e30)
    std::printf("ratio 3 wl frame (a new sun every frame), with skylight and diffuse sunlight / without: %.3f (the lattice %.3f s, %.0f %% of "
                "the frame; the eye pass's gather the rest)\n",
                1e3 * sky_512.frame / moving_sun_512_ms, sky_512.sky, 100.0 * sky_512.sky / sky_512.frame);
  sl_image_free(&keep_base);
  t0 = sl::now_seconds();
  sl_write_exr("/tmp/bench_render.exr", &keep, SL_EXR_HALF, &err);
  std::printf("write EXR 512x512: %.3f s\n", sl::now_seconds() - t0);
  sl_image_free(&keep);

  // The peer: VTK's CPU ray caster with shading on the same grid (total extinction as scalars),
  // the same camera and as many samples along a ray as slices across the box.
  vtkNew<vtkImageData> image;
  vtkNew<vtkVolumeProperty> prop;
  peer_volume(vol, image, prop);
  vtkNew<vtkFixedPointVolumeRayCastMapper> mapper;
  mapper->SetInputData(image);
  mapper->SetNumberOfThreads(threads);
  double diagonal = 0.0;
  const int n[3] = {vol->nx, vol->ny, vol->nz};
  for (int a = 0; a < 3; ++a) diagonal += (n[a] * vol->spacing[a]) * (n[a] * vol->spacing[a]);
  diagonal = std::sqrt(diagonal);
  mapper->SetAutoAdjustSampleDistances(0);
  mapper->SetSampleDistance(diagonal / 256);
  mapper->SetInteractiveSampleDistance(diagonal / 256);
  vtkNew<vtkVolume> volume;
  volume->SetMapper(mapper);
  volume->SetProperty(prop);
  vtkNew<vtkRenderer> ren;
  ren->AddVolume(volume);
  vtkNew<vtkRenderWindow> win;
  win->SetOffScreenRendering(1);
  win->SetSize(512, 512);
  win->AddRenderer(ren);
  double blo[3], bhi[3];
  {
    sl_scene sc{};
    sc.volume = vol;
    sl_sun_direction(35.0, 240.0, sc.sun_direction);
    sl_renderer *r = sl_renderer_create(&sc, &err);
    sl_renderer_content_bounds(r, blo, bhi);
    sl_renderer_destroy(r);
  }
  sl_camera cam;
  sl_camera_frame(blo, bhi, 200.0, 12.0, 40.0, 512, 512, &cam);
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
  std::printf("vtkFixedPointVolumeRayCastMapper (shading on, 512x512, 256 samples across): first frame %.3f s, frame "
              "%.3f s\n",
              vtk_first, vtk_best);
  std::printf("ratio stormlight multiple/3 wl frame (512x512, 256 slices) / VTK frame: %.2f\n",
              frame_512_ms / 1e3 / vtk_best);
  std::printf("ratio light-volume camera move (eye pass only) / VTK frame: %.2f\n", lv_eye_ms / 1e3 / vtk_best);
  for (int k = 0; k < 3; ++k) {
    if (!(fast_eye_ms[k] > 0.0)) continue;
    const std::string what = fast_name(k);
    std::printf("ratio light-volume camera move with %s / VTK frame: %.2f\n", what.c_str(), fast_eye_ms[k] / 1e3 / vtk_best);
  }
  if (alternate) camera_moves_alternated(light_volume_scene(march_samples), refine, repeat, blo, bhi, win, c);
  sl_volume_free(&resampled);
  sl_storm_frame_free(&frame);
  return 0;
}
