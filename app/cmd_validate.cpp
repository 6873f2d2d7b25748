// stormlight validate: the fast model (render/volume) at several settings against the Monte Carlo
// reference (render/reference) on one scene, with time and error for each. The
// table, error maps and the speed-against-error plot go to a report folder; docs/ACCURACY.md says
// what the numbers mean and how they were made.
#include <cjson/cJSON.h>
#include <omp.h>
#include <vtkAxis.h>
#include <vtkChartLegend.h>
#include <vtkChartXY.h>
#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPen.h>
#include <vtkPlot.h>
#include <vtkPlotPoints.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTable.h>

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "cli.h"
#include "commands.h"
#include "scene.h"
#include "sl_image_io.h"
#include "sl_optics.h"
#include "sl_reference.h"
#include "sl_renderer.h"
#include "sl_sky.h"
#include "sl_tempfile.h"
#include "sl_validation.h"
#include "vtk_png.h"

namespace {

const char *kCmd = "validate";

// Pixels are classed by the optical depth tau along the view ray (the fast renderer's transparency,
// a deterministic quadrature): none below kVolumeTau (sky, where both renderers draw the same air),
// thin below kThinTau, dense above.
const double kVolumeTau = 0.01;
const double kThinTau = 2.0;
// A volume block whose pixels' visible surfaces (optical depth 1 along the view ray) keep less than
// this of the sunlight is also in the class "shadowed": faces in the cloud's own shadow, which only
// the sky lights (sl_renderer_surface_sunlight).
const double kShadowedSun = 1e-2;

void progress_hook(void *user, double fraction) { static_cast<sl::Progress *>(user)->update(fraction); }

using TablesPtr = std::unique_ptr<sl_optics_tables, void (*)(sl_optics_tables *)>;

// One setting of the fast renderer. Zero means "automatic" as in sl_scene.
struct Setting {
  std::string name, family;
  int slices = 0, light_resolution = 0, max_order = 0, march_samples = 0;
  sl_lighting lighting = SL_LIGHTING_MULTIPLE;
  double xi = 0, march_thin_depth = 0, march_refine_tolerance = 0;
  bool spectral = false, light_volume = false, skylight = true, diffuse_sunlight = true;
};

struct Row {
  Setting s;
  double seconds = 0;
  sl_error_sums all{}, thin{}, dense{};  // per pixel class, over its pixels and R, G, B
  sl_error_sums shadowed{};              // volume blocks in the cloud's own shadow (thin or dense)
  double mc_seconds = 0, speedup = 0;
  bool pareto = false;
};

struct Reference {
  sl_image layer{};
  std::vector<float> se;  // 3 per pixel
  long spp = 0;
  double seconds = 0;
  int threads = 0;
  std::string wavelengths, origin;
  ~Reference() { sl_image_free(&layer); }
};

bool ends_with(const std::string &s, const std::string &tail)
{
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

std::string fmt(const char *f, double v)
{
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

bool write_text(const std::string &path, const std::string &body, std::string *why)
{
  char tmp[4096];
  sl_error err{};
  if (sl_temp_name(path.c_str(), tmp, sizeof tmp, &err)) return *why = err.message, false;
  {
    std::ofstream f(tmp);
    f << body;
    if (!f) return *why = path + ": cannot write", false;
  }
  if (sl_temp_commit(tmp, path.c_str(), &err)) return *why = err.message, false;
  return true;
}

// The variants: one axis at a time away from the scene's own setting, plus two cheap combinations
// for the fast end of the Pareto front.
std::vector<Setting> variants(const Setting &base, bool quick, bool spectral_allowed)
{
  std::vector<Setting> v;
  auto add = [&](const std::string &family, const std::string &name, auto change) {
    Setting s = base;
    s.family = family, s.name = name;
    change(s);
    v.push_back(s);
  };
  add("scene", "scene's settings", [](Setting &) {});
  add("skylight", base.skylight ? "sun only (no skylight)" : "skylight", [](Setting &s) { s.skylight = !s.skylight; });
  add("diffuse sunlight", base.diffuse_sunlight ? "no diffuse sunlight" : "diffuse sunlight",
      [](Setting &s) { s.diffuse_sunlight = !s.diffuse_sunlight; });
  // The paper's model: the light buffer alone, with eq. 26's xi standing in for what it drops.
  if (base.diffuse_sunlight)
    add("diffuse sunlight", "no diffuse sunlight, xi 0.05", [](Setting &s) { s.diffuse_sunlight = false, s.xi = 0.05; });
  if (quick) {
    add("slices", "slices 64", [](Setting &s) { s.slices = 64; });
    add("lighting", "eq. 25", [](Setting &s) { s.lighting = SL_LIGHTING_MULTIPLE_EQ25; });
    const double other_xi = base.xi != 0 ? 0.0 : 0.05;
    add("xi", "xi " + fmt("%g", other_xi), [other_xi](Setting &s) { s.xi = other_xi; });
    return v;
  }
  for (int n : {32, 64, 128, 512}) add("slices", "slices " + std::to_string(n), [n](Setting &s) { s.slices = n; });
  for (int n : {32, 64, 128, 256})
    add("light buffer", "light buffer " + std::to_string(n), [n](Setting &s) { s.light_resolution = n; });
  for (int n : {1, 2, 4, 8, 16, 32})
    add("max order", "max order " + std::to_string(n), [n](Setting &s) { s.max_order = n; });
  add("lighting", "eq. 25", [](Setting &s) { s.lighting = SL_LIGHTING_MULTIPLE_EQ25; });
  add("lighting", "low albedo", [](Setting &s) { s.lighting = SL_LIGHTING_LOW_ALBEDO; });
  // A scene without air (no-atmosphere) is rgb only (sl_settings_check), so it has no spectral variant.
  if (spectral_allowed)
    add("wavelengths", base.spectral ? "3 wavelengths" : "16 wavelengths", [](Setting &s) { s.spectral = !s.spectral; });
  for (double xi : {0.0, 0.01, 0.02, 0.03, 0.075, 0.1, 0.15, 0.2, 0.3})
    if (xi != base.xi) add("xi", "xi " + fmt("%g", xi), [xi](Setting &s) { s.xi = xi; });
  add("light volume", "light volume", [](Setting &s) { s.light_volume = true; });
  for (int n : {2, 4})
    add("light volume", "light volume, " + std::to_string(n) + " samples per cell",
        [n](Setting &s) { s.light_volume = true, s.march_samples = n; });
  add("light volume", "light volume, thin steps 0.3",
      [](Setting &s) { s.light_volume = true, s.march_thin_depth = 0.3; });
  for (double tol : {0.02, 0.1, 0.2})
    add("light volume", "light volume, adaptive pixels " + fmt("%g", tol),
        [tol](Setting &s) { s.light_volume = true, s.march_refine_tolerance = tol; });
  add("fast", "slices 64, light buffer 64", [](Setting &s) { s.slices = 64, s.light_resolution = 64; });
  add("fast", "slices 32, light buffer 32", [](Setting &s) { s.slices = 32, s.light_resolution = 32; });
  return v;
}

// Block means (sl_block_means) freed with their owner.
struct Blocks : sl_blocks {
  Blocks() : sl_blocks{} {}
  Blocks(const Blocks &) = delete;
  Blocks &operator=(const Blocks &) = delete;
  ~Blocks() { sl_blocks_free(this); }
};

std::string file_name(const std::string &name)
{
  std::string f;
  for (char c : name)
    if (std::isalnum((unsigned char)c)) f += c;
    else if (!f.empty() && f.back() != '_') f += '_';
  while (!f.empty() && f.back() == '_') f.pop_back();
  return f;
}

cJSON *class_json(const sl_error_sums &e)
{
  cJSON *o = cJSON_CreateObject();
  cJSON_AddNumberToObject(o, "pixels", (double)e.pixels);
  cJSON_AddNumberToObject(o, "relative_rmse", sl_error_relative_rmse(&e));
  cJSON_AddNumberToObject(o, "mean_relative_error", sl_error_mean_relative(&e));
  cJSON_AddNumberToObject(o, "bias", sl_error_bias(&e));
  cJSON_AddNumberToObject(o, "reference_noise_rmse", sl_error_noise_rmse(&e));
  cJSON_AddNumberToObject(o, "reference_noise_mean", sl_error_noise_mean(&e));
  cJSON_AddNumberToObject(o, "model_rmse", sl_error_model_rmse(&e));
  return o;
}

// Speed against error: one point set per family, the Pareto front and the Monte Carlo reference's
// own error against time (its variance falls as 1/spp), on log axes.
bool plot(const std::vector<Row> &rows, const Reference &ref, double ref_noise, const std::string &title,
          const std::string &out, std::string *why)
{
  vtkNew<vtkContextView> view;
  view->GetRenderer()->SetBackground(1.0, 1.0, 1.0);
  view->GetRenderWindow()->SetOffScreenRendering(1);
  view->GetRenderWindow()->SetSize(900, 650);
  vtkNew<vtkChartXY> chart;
  view->GetScene()->AddItem(chart);
  chart->SetShowLegend(true);
  chart->GetLegend()->SetHorizontalAlignment(vtkChartLegend::RIGHT);
  chart->GetLegend()->SetVerticalAlignment(vtkChartLegend::TOP);
  chart->SetTitle(title.c_str());
  chart->GetAxis(vtkAxis::LEFT)->SetTitle("relative RMSE against the reference (volume pixels)");
  chart->GetAxis(vtkAxis::LEFT)->SetLogScale(true);
  chart->GetAxis(vtkAxis::BOTTOM)->SetTitle("wall time per frame (s)");
  chart->GetAxis(vtkAxis::BOTTOM)->SetLogScale(true);
  const unsigned char palette[][3] = {{0, 0, 0},     {31, 119, 180}, {255, 127, 14}, {44, 160, 44},  {214, 39, 40},
                                      {148, 103, 189}, {140, 86, 75}, {227, 119, 194}, {127, 127, 127}, {23, 190, 207}};
  std::vector<std::string> families;
  for (const Row &r : rows)
    if (std::find(families.begin(), families.end(), r.s.family) == families.end()) families.push_back(r.s.family);
  std::vector<vtkSmartPointer<vtkTable>> keep;
  auto series = [&](const std::vector<double> &x, const std::vector<double> &y, const std::string &label, int type,
                    const unsigned char *rgb, float width) {
    vtkNew<vtkTable> t;
    vtkNew<vtkDoubleArray> xs, ys;
    xs->SetName("seconds");
    ys->SetName(label.c_str());
    for (size_t i = 0; i < x.size(); ++i) xs->InsertNextValue(x[i]), ys->InsertNextValue(y[i]);
    t->AddColumn(xs);
    t->AddColumn(ys);
    vtkPlot *p = chart->AddPlot(type);
    p->SetInputData(t, 0, 1);
    p->SetColor(rgb[0], rgb[1], rgb[2], 255);
    p->SetWidth(width);
    p->SetLabel(label.c_str());
    if (type == vtkChart::POINTS) vtkPlotPoints::SafeDownCast(p)->SetMarkerSize(9);
    keep.push_back(t.GetPointer());
  };
  double tmin = 1e30, tmax = 0;
  for (size_t f = 0; f < families.size(); ++f) {
    std::vector<double> x, y;
    for (const Row &r : rows)
      if (r.s.family == families[f]) {
        x.push_back(r.seconds), y.push_back(std::max(sl_error_relative_rmse(&r.all), 1e-4));
        tmin = std::min(tmin, r.seconds), tmax = std::max(tmax, r.seconds);
      }
    series(x, y, families[f], vtkChart::POINTS, palette[(f + 1) % 10], 1.0f);
  }
  std::vector<std::pair<double, double>> front;
  for (const Row &r : rows)
    if (r.pareto) front.emplace_back(r.seconds, std::max(sl_error_relative_rmse(&r.all), 1e-4));
  std::sort(front.begin(), front.end());
  std::vector<double> px, py;
  for (const auto &p : front) px.push_back(p.first), py.push_back(p.second);
  series(px, py, "Pareto front", px.size() > 1 ? vtkChart::LINE : vtkChart::POINTS, palette[0], 2.0f);
  // Monte Carlo: error = noise * sqrt(T_ref / t), drawn over the times the chart shows.
  std::vector<double> mx, my;
  const double t0 = std::min(tmin, ref.seconds) * 0.5, t1 = std::max(tmax, ref.seconds) * 2;
  for (int i = 0; i <= 20; ++i) {
    const double t = t0 * std::pow(t1 / t0, i / 20.0);
    mx.push_back(t), my.push_back(ref_noise * std::sqrt(ref.seconds / t));
  }
  const unsigned char grey[3] = {150, 150, 150};
  series(mx, my, "Monte Carlo (its noise)", vtkChart::LINE, grey, 2.0f);
  return sl::write_window_png(view->GetRenderWindow(), out, why);
}

}  // namespace

int sl_cmd_validate(int argc, char **argv)
{
  sl::Options o(kCmd, "--scene S.json [--ref report/reference.exr] --out report/ [--json]",
                "Renders a scene of `stormlight render` with the fast model (half-angle slicing, Riley et al.\n"
                "2004) at several settings - slices, light-buffer resolution, the highest scattering order n\n"
                "of Ams_n, eq. 24 against eq. 25, 3 against 16 wavelengths, several xi, the light volume - and\n"
                "compares each with the Monte Carlo reference (render/reference) of the same scene: wall time,\n"
                "relative RMSE, mean relative error and bias over the volume's pixels, separately for thin\n"
                "(tau < 2 along the view ray) and dense ones, the reference's own noise beside every error, and\n"
                "the Monte Carlo time that reaches the same error (its variance falls as 1/spp). Writes\n"
                "report.json, table.md, error maps (PNG), speed_error.png (VTK chart; needs an X display:\n"
                "xvfb-run -a) and, unless --ref names one, the reference (reference.exr: the volume layer,\n"
                "reference_stderr.exr, reference.json), which a later --ref can reuse.");
  o.option("scene", "FILE", "a `stormlight render` scene (docs/SCENES.md)");
  o.option("out", "DIR", "report folder (created)");
  o.option("ref", "FILE.exr[,...]", "a reference.exr of an earlier report, with reference_stderr.exr and reference.json beside it; several independent ones (other --seed) are pooled");
  o.option("spp", "N", "reference: samples per pixel and wavelength", "256");
  o.option("seconds", "T", "reference: stop after whole passes once T seconds have passed (0: no limit)", "0");
  o.option("seed", "N", "reference: random seed", "1");
  o.option("roulette-depth", "N", "reference: scatterings before Russian roulette at survival 0.98 (0: the library's 16)", "0");
  o.option("width", "PX", "override the scene's image width");
  o.option("height", "PX", "override the scene's image height");
  o.option("skylight", "on|off", "override the scene's skylight (both renderers: the reference's scattered paths "
           "collect the sky where they leave the box)");
  o.option("block", "B", "compare means over B x B pixel blocks (the reference's noise falls by B)", "1");
  o.option("repeat", "N", "render each setting N times and keep the fastest (least disturbed) time", "3");
  o.option("interactive", "S", "frame time counted as interactive (seconds)", "0.1");
  o.option("threads", "N", "OpenMP threads for both renderers (0: all)", "0");
  o.option("max-error", "E", "exit 1 when the scene's own setting's relative RMSE exceeds E (regression guard)");
  o.flag("quick", "four settings only (tests)");
  o.flag("no-plot", "skip the VTK chart (no X display needed)");
  o.flag("json", "print report.json on stdout");
  o.flag("quiet", "no progress or table");
  const int early = sl::parse_or_exit(o, argc, argv);
  if (early >= 0) return early;
  if (!o.has("scene") || !o.has("out")) return sl::fail(kCmd, "--scene FILE and --out DIR are required", 2);
  long spp, seed, repeat, threads, block, roulette_depth;
  double max_seconds, interactive, max_error = INFINITY;
  if (!o.integer("spp", &spp, 1, 100000000) || !o.integer("seed", &seed, 0, 0x7fffffffffffffffL) ||
      !o.integer("roulette-depth", &roulette_depth, 0, 100000000) ||
      !o.integer("repeat", &repeat, 1, 100) || !o.integer("block", &block, 1, 64) || !o.integer("threads", &threads, 0, 4096) ||
      !o.number("seconds", &max_seconds) || !o.number("interactive", &interactive) ||
      (o.has("max-error") && !o.number("max-error", &max_error)))
    return sl::fail(kCmd, o.error(), 2);
  if (max_seconds < 0) return sl::fail(kCmd, "--seconds must be >= 0", 2);
  if (threads > 0) omp_set_num_threads((int)threads);
  const bool json = o.has("json"), quiet = o.has("quiet") || json, want_plot = !o.has("no-plot");
  std::string why;
  if (want_plot && !sl::have_display(&why)) return sl::fail(kCmd, why + " (or pass --no-plot)", 2);
  const std::string dir = o.str("out"), scene_path = o.str("scene");
  // The scene as render reads it (sl_settings_from_scene), at the size asked for; its storm and sun
  // as render loads and places them (sl_scene_load).
  std::vector<std::string> overrides;
  for (const char *k : {"width", "height", "skylight"})
    if (o.has(k)) overrides.push_back(std::string("--") + k), overrides.push_back(o.str(k));
  std::vector<char *> override_argv;
  for (std::string &a : overrides) override_argv.push_back(&a[0]);
  std::unique_ptr<sl_settings> settings(new sl_settings);
  sl::BuiltScenePtr built(new sl_built_scene{});
  sl_error err{};
  if (sl_settings_from_scene(settings.get(), scene_path.c_str(), (int)override_argv.size(), override_argv.data(), &err))
    return sl::fail(kCmd, err.message, 2);
  if (sl_scene_load(settings.get(), 0, built.get(), &err)) return sl::fail(kCmd, scene_path + ": " + err.message, 2);
  const bool with_air = !settings->no_atmosphere;
  if (mkdir(dir.c_str(), 0777) != 0 && errno != EEXIST) return sl::fail(kCmd, dir + ": cannot create the folder", 2);
  Setting base;  // the scene's own setting
  base.family = "scene";
  base.slices = settings->slices, base.light_resolution = settings->light_resolution, base.xi = settings->xi;
  base.lighting = (sl_lighting)settings->lighting;
  base.spectral = settings->spectral;
  base.light_volume = settings->light_volume, base.march_samples = settings->march_samples;
  base.march_thin_depth = settings->march_thin_depth;
  base.march_refine_tolerance = settings->march_refine_tolerance;
  base.skylight = settings->skylight;
  base.diffuse_sunlight = settings->diffuse_sunlight;
  // Air and particle tables per wavelength set (and per highest order), built once; tables come
  // from the on-disk cache after the first run, so they are not part of any frame's time.
  sl_atmosphere air[2];
  for (int sp = 0; sp < 2; ++sp)
    if (with_air && sl_scene_air(settings.get(), sp, &air[sp], &err)) return sl::fail(kCmd, err.message);
  std::map<std::pair<int, int>, TablesPtr> tables;
  auto tables_for = [&](bool spectral, int max_order) -> const sl_optics_tables * {
    const auto key = std::make_pair((int)spectral, max_order);
    auto it = tables.find(key);
    if (it != tables.end()) return it->second.get();
    sl::Progress progress("tables", !quiet);
    TablesPtr t(sl_scene_tables(&built->frame.volume, spectral, max_order, progress_hook, &progress, &err), sl_optics_free);
    progress.done();
    if (!t) return nullptr;
    return tables.emplace(key, std::move(t)).first->second.get();
  };
  // Each setting's scene as render fills it (sl_scene_fill), from the scene's settings with the
  // setting's changes.
  auto scene_for = [&](const Setting &s, sl_scene *sc) -> bool {
    const sl_optics_tables *optics = tables_for(s.spectral, s.max_order);
    if (!optics) return false;
    std::unique_ptr<sl_settings> v(new sl_settings(*settings));
    v->lighting = s.lighting, v->xi = s.xi, v->slices = s.slices, v->light_resolution = s.light_resolution;
    v->light_volume = s.light_volume, v->march_samples = s.march_samples, v->spectral = s.spectral;
    v->march_thin_depth = s.march_thin_depth, v->march_refine_tolerance = s.march_refine_tolerance;
    v->skylight = s.skylight, v->diffuse_sunlight = s.diffuse_sunlight;
    sl_scene_fill(v.get(), built.get(), with_air ? &air[s.spectral] : nullptr, optics, sc);
    return true;
  };

  // The camera as render frames it, from the baseline renderer's content bounds, and what stops its
  // rays: the round ground under --curvature drop, as render's.
  sl_scene base_scene;
  if (!scene_for(base, &base_scene)) return sl::fail(kCmd, std::string("particle tables: ") + err.message);
  sl_camera cam{};
  std::unique_ptr<sl_renderer, void (*)(sl_renderer *)> base_renderer(sl_renderer_create(&base_scene, &err),
                                                                      sl_renderer_destroy);
  if (!base_renderer) return sl::fail(kCmd, scene_path + ": " + err.message);
  {
    double lo[3], hi[3];
    sl_renderer_content_bounds(base_renderer.get(), lo, hi);
    sl_scene_camera(settings.get(), &built->frame.volume, lo, hi, base_scene.sun_direction, &cam);
  }
  std::vector<float> ground((size_t)cam.width * cam.height, INFINITY);
  if (sl_scene_ground_opaque(base_scene.atmosphere, &cam, ground.data())) cam.opaque_distance = ground.data();
  const size_t np = (size_t)cam.width * cam.height;
  // Each pixel's sunlight at its visible surface, for the class "shadowed".
  std::vector<float> surface_sun(np);
  if (sl_renderer_surface_sunlight(base_renderer.get(), &cam, surface_sun.data(), &err))
    return sl::fail(kCmd, scene_path + ": " + err.message);
  base_renderer.reset();

  // The reference: read, or rendered now at the scene's wavelengths.
  Reference ref;
  ref.wavelengths = base.spectral ? "spectral16" : "rgb";
  ref.threads = omp_get_max_threads();
  sl_ref_scene rsc;
  sl_ref_scene_defaults(&rsc);
  std::unique_ptr<sl_ref_medium, void (*)(sl_ref_medium *)> medium(
      sl_ref_medium_from_volume(&built->frame.volume, tables_for(base.spectral, 0), &err), sl_ref_medium_destroy);
  if (!medium) return sl::fail(kCmd, scene_path + ": " + err.message);
  rsc.medium = medium.get();
  for (int a = 0; a < 3; ++a) rsc.sun_direction[a] = base_scene.sun_direction[a];  // render's sun
  rsc.atmosphere = with_air ? &air[base.spectral] : nullptr;
  for (int c = 0; c < 3; ++c) rsc.sky_radiance[c] = settings->sky[c];
  rsc.seed = (unsigned long long)seed;
  rsc.roulette_depth = (int)roulette_depth;
  rsc.skylight = base.skylight;  // the fast renderer's default lights the volume by the sky too
  if (o.has("ref")) {
    // One reference, or several independent ones of the same scene (other seeds), comma-separated:
    // their means are pooled weighted by their samples, the standard errors accordingly, and their
    // times added, as if one run had taken all the samples.
    std::vector<std::string> paths;
    {
      std::stringstream list(o.str("ref"));
      std::string p;
      while (std::getline(list, p, ','))
        if (!p.empty()) paths.push_back(p);
    }
    if (paths.empty()) return sl::fail(kCmd, "--ref names no file", 2);
    std::vector<double> sum(4 * np, 0.0), var(3 * np, 0.0);
    std::vector<double> seeds;
    for (size_t i = 0; i < paths.size(); ++i) {
      const std::string &path = paths[i];
      if (!ends_with(path, ".exr")) return sl::fail(kCmd, path + ": --ref must name an .exr", 2);
      const std::string stem = path.substr(0, path.size() - 4);
      sl_image layer{}, se_img{};
      std::unique_ptr<sl_image, void (*)(sl_image *)> layer_guard(&layer, sl_image_free), se_guard(&se_img, sl_image_free);
      if (sl_read_exr(path.c_str(), &layer, &err) || sl_read_exr((stem + "_stderr.exr").c_str(), &se_img, &err))
        return sl::fail(kCmd, err.message, 2);
      if (layer.width != cam.width || layer.height != cam.height || se_img.width != cam.width ||
          se_img.height != cam.height)
        return sl::fail(kCmd, path + ": the reference is " + std::to_string(layer.width) + "x" +
                                  std::to_string(layer.height) + ", the scene's camera " + std::to_string(cam.width) +
                                  "x" + std::to_string(cam.height), 2);
      std::ifstream in(stem + ".json");
      std::stringstream ss;
      ss << in.rdbuf();
      std::unique_ptr<cJSON, void (*)(cJSON *)> meta(cJSON_Parse(ss.str().c_str()), cJSON_Delete);
      const cJSON *jspp = meta ? cJSON_GetObjectItem(meta.get(), "spp") : nullptr;
      const cJSON *jsec = meta ? cJSON_GetObjectItem(meta.get(), "seconds") : nullptr;
      const cJSON *jwl = meta ? cJSON_GetObjectItem(meta.get(), "wavelengths") : nullptr;
      const cJSON *jthr = meta ? cJSON_GetObjectItem(meta.get(), "threads") : nullptr;
      const cJSON *jseed = meta ? cJSON_GetObjectItem(meta.get(), "seed") : nullptr;
      if (!cJSON_IsNumber(jspp) || jspp->valuedouble < 1 || !cJSON_IsNumber(jsec) || !cJSON_IsString(jwl))
        return sl::fail(kCmd, stem + ".json: missing or without spp, seconds and wavelengths", 2);
      if (ref.wavelengths != jwl->valuestring)
        return sl::fail(kCmd, stem + ".json: the reference has wavelengths " + jwl->valuestring + ", the scene " +
                                  ref.wavelengths, 2);
      // A reference without the key predates skylight: it was drawn without it.
      const cJSON *jsky = cJSON_GetObjectItem(meta.get(), "skylight");
      if (cJSON_IsTrue(jsky) != base.skylight)
        return sl::fail(kCmd, stem + ".json: the reference was drawn with skylight " +
                                  (cJSON_IsTrue(jsky) ? "on" : "off") + ", the scene asks for it " +
                                  (base.skylight ? "on" : "off"), 2);
      if (paths.size() > 1) {
        // Pooling is only right for independent runs.
        if (!cJSON_IsNumber(jseed)) return sl::fail(kCmd, stem + ".json: no seed, so it cannot be pooled", 2);
        if (std::find(seeds.begin(), seeds.end(), jseed->valuedouble) != seeds.end())
          return sl::fail(kCmd, stem + ".json: seed " + fmt("%g", jseed->valuedouble) +
                                    " repeats an earlier --ref: the runs are not independent", 2);
        seeds.push_back(jseed->valuedouble);
      }
      const double n = jspp->valuedouble;
      for (size_t q = 0; q < np; ++q) {
        for (int c = 0; c < 4; ++c) sum[4 * q + c] += n * layer.rgba[4 * q + c];
        for (int c = 0; c < 3; ++c) var[3 * q + c] += n * n * (double)se_img.rgba[4 * q + c] * se_img.rgba[4 * q + c];
      }
      ref.spp += (long)n, ref.seconds += jsec->valuedouble;
      if (i == 0) {
        ref.threads = cJSON_IsNumber(jthr) ? (int)jthr->valuedouble : 0;
        std::swap(ref.layer, layer);  // the first keeps its depth; the others' radiance is pooled below
      }
    }
    ref.se.resize(3 * np);
    const double total = (double)ref.spp;
    for (size_t q = 0; q < np; ++q) {
      for (int c = 0; c < 4; ++c) ref.layer.rgba[4 * q + c] = (float)(sum[4 * q + c] / total);
      for (int c = 0; c < 3; ++c) ref.se[3 * q + c] = (float)(std::sqrt(var[3 * q + c]) / total);
      ref.layer.transparency[q] = 1.0f - ref.layer.rgba[4 * q + 3];
    }
    ref.origin = o.str("ref");
  } else {
    sl_ref_accum acc{};
    if (sl_ref_accum_init(&acc, cam.width, cam.height, sl_ref_medium_wavelength_count(medium.get()), &err) ||
        sl_image_alloc(&ref.layer, cam.width, cam.height, &err))
      return sl::fail(kCmd, err.message);
    std::unique_ptr<sl_ref_accum, void (*)(sl_ref_accum *)> acc_guard(&acc, sl_ref_accum_free);
    sl::Progress progress("reference", !quiet);
    sl_ref_budget budget{spp, max_seconds, progress_hook, &progress};
    ref.se.resize(3 * np);
    if (sl_ref_render(&rsc, &cam, &budget, &acc, &err) || sl_ref_accum_image(&acc, medium.get(), &ref.layer, ref.se.data(), &err))
      return sl::fail(kCmd, scene_path + ": " + err.message);
    progress.done();
    ref.spp = acc.samples, ref.seconds = acc.seconds;
    ref.origin = dir + "/reference.exr";
    sl_image se_img{};
    if (sl_image_alloc(&se_img, cam.width, cam.height, &err)) return sl::fail(kCmd, err.message);
    std::unique_ptr<sl_image, void (*)(sl_image *)> se_guard(&se_img, sl_image_free);
    for (size_t q = 0; q < np; ++q) {
      for (int c = 0; c < 3; ++c) se_img.rgba[4 * q + c] = ref.se[3 * q + c];
      se_img.rgba[4 * q + 3] = 1.0f, se_img.depth[q] = INFINITY, se_img.transparency[q] = 0.0f;
    }
    cJSON *meta = cJSON_CreateObject();
    cJSON_AddStringToObject(meta, "scene", scene_path.c_str());
    cJSON_AddNumberToObject(meta, "spp", (double)ref.spp);
    cJSON_AddNumberToObject(meta, "seconds", ref.seconds);
    cJSON_AddNumberToObject(meta, "threads", ref.threads);
    cJSON_AddNumberToObject(meta, "seed", (double)seed);
    cJSON_AddNumberToObject(meta, "roulette_depth", (double)roulette_depth);
    cJSON_AddStringToObject(meta, "wavelengths", ref.wavelengths.c_str());
    cJSON_AddBoolToObject(meta, "skylight", base.skylight);
    char *text = cJSON_Print(meta);
    const std::string body = std::string(text) + "\n";
    std::free(text);
    cJSON_Delete(meta);
    if (sl_write_exr((dir + "/reference.exr").c_str(), &ref.layer, SL_EXR_FLOAT, &err) ||
        sl_write_exr((dir + "/reference_stderr.exr").c_str(), &se_img, SL_EXR_FLOAT, &err))
      return sl::fail(kCmd, err.message);
    if (!write_text(dir + "/reference.json", body, &why)) return sl::fail(kCmd, why);
  }

  // Frames to look at: the reference over its background, and each setting's error map.
  sl_image background{}, frame{}, img{};
  std::unique_ptr<sl_image, void (*)(sl_image *)> g1(&background, sl_image_free), g2(&frame, sl_image_free),
      g3(&img, sl_image_free);
  if (sl_image_alloc(&background, cam.width, cam.height, &err) || sl_image_alloc(&frame, cam.width, cam.height, &err) ||
      sl_image_alloc(&img, cam.width, cam.height, &err) || sl_ref_background(&rsc, &cam, &background, &err))
    return sl::fail(kCmd, err.message);
  sl_image_over(&ref.layer, &background, &frame);
  if (sl_write_png((dir + "/reference.png").c_str(), &frame, 12.0f, &err)) return sl::fail(kCmd, err.message);

  if (cam.width < block || cam.height < block) return sl::fail(kCmd, "--block is larger than the image", 2);
  Blocks ref_blocks;
  if (sl_block_means(&ref.layer, ref.se.data(), (int)block, &ref_blocks, &err)) return sl::fail(kCmd, err.message);
  const size_t nb = (size_t)ref_blocks.width * ref_blocks.height;
  std::vector<Row> rows;
  std::vector<unsigned char> cls;  // per block: 0 no volume, 1 thin, 2 dense, from the scene's own setting
  std::vector<unsigned char> shadowed;  // per volume block: its visible surfaces lie in the cloud's shadow
  double floor = 0;
  for (const Setting &s : variants(base, o.has("quick"), with_air)) {
    sl_scene sc;
    if (!scene_for(s, &sc)) return sl::fail(kCmd, std::string("particle tables: ") + err.message);
    Row row;
    row.s = s;
    row.seconds = INFINITY;
    for (long k = 0; k < repeat; ++k) {
      const double t0 = sl::now_seconds();
      sl_renderer *r = sl_renderer_create(&sc, &err);
      sl_render_stats stats{};
      int rc = r ? sl_renderer_render(r, &cam, &img, &stats, &err) : 1;
      // The scene's own frame as `stormlight render --cpu-composite` draws it: over the fast
      // renderer's own sky (frame.exr).
      if (!rc && rows.empty() && k == 0) {
        sl_image own{}, composite{};
        rc = sl_image_alloc(&own, cam.width, cam.height, &err) || sl_image_alloc(&composite, cam.width, cam.height, &err) ||
             sl_renderer_background(r, &cam, &own, &err);
        if (!rc) {
          sl_image_over(&img, &own, &composite);
          rc = sl_write_exr((dir + "/frame.exr").c_str(), &composite, SL_EXR_FLOAT, &err);
        }
        sl_image_free(&own), sl_image_free(&composite);
      }
      sl_renderer_destroy(r);
      if (rc) return sl::fail(kCmd, scene_path + " (" + s.name + "): " + err.message);
      row.seconds = std::min(row.seconds, sl::now_seconds() - t0);
    }
    Blocks fast;
    if (sl_block_means(&img, nullptr, (int)block, &fast, &err)) return sl::fail(kCmd, err.message);
    if (cls.empty()) {
      cls.resize(nb);
      double sum = 0;
      long count = 0;
      for (size_t q = 0; q < nb; ++q) {
        const double tau = -std::log(std::max(fast.transparency[q], 1e-300));
        cls[q] = tau < kVolumeTau ? 0 : tau < kThinTau ? 1 : 2;
        // Shadowed: most of the block's pixels see a surface, and the sun reaching them is below
        // kShadowedSun on average.
        {
          const long bx = (long)(q % fast.width), by = (long)(q / fast.width);
          double sun = 0;
          long seen = 0;
          for (long y = by * block; y < (by + 1) * block; ++y)
            for (long x = bx * block; x < (bx + 1) * block; ++x) {
              const float v = surface_sun[(size_t)y * cam.width + x];
              if (std::isfinite(v)) sun += v, ++seen;
            }
          shadowed.push_back(cls[q] && 2 * seen >= block * block && sun / seen < kShadowedSun);
        }
        if (cls[q]) sum += ref_blocks.rgb[3 * q] + ref_blocks.rgb[3 * q + 1] + ref_blocks.rgb[3 * q + 2], ++count;
      }
      floor = count ? 0.05 * sum / count : 1.0;
      sl_image_over(&img, &background, &frame);
      if (sl_write_png((dir + "/fast.png").c_str(), &frame, 12.0f, &err)) return sl::fail(kCmd, err.message);
    }
    for (size_t q = 0; q < nb; ++q) {
      if (!cls[q]) continue;
      for (int c = 0; c < 3; ++c) {
        const double a = fast.rgb[3 * q + c], b = ref_blocks.rgb[3 * q + c], se = ref_blocks.se[3 * q + c];
        sl_error_sums_add(&row.all, a, b, se);
        sl_error_sums_add(cls[q] == 1 ? &row.thin : &row.dense, a, b, se);
        if (shadowed[q]) sl_error_sums_add(&row.shadowed, a, b, se);
      }
      ++row.all.pixels, ++(cls[q] == 1 ? row.thin : row.dense).pixels;
      if (shadowed[q]) ++row.shadowed.pixels;
    }
    std::vector<unsigned char> map(3 * (size_t)fast.width * fast.height);
    sl_error_map(&fast, &ref_blocks, cls.data(), floor, 0.5, map.data());
    if (sl_write_png_rgb8((dir + "/error_" + file_name(s.name) + ".png").c_str(), fast.width, fast.height, map.data(),
                          &err))
      return sl::fail(kCmd, err.message);
    if (!quiet)
      std::fprintf(stderr, "%-30s %8.4f s  relative RMSE %.4f (thin %.4f, dense %.4f, shadowed %.4f; bias %+.3f)\n",
                   s.name.c_str(), row.seconds, sl_error_relative_rmse(&row.all), sl_error_relative_rmse(&row.thin),
                   sl_error_relative_rmse(&row.dense), sl_error_relative_rmse(&row.shadowed),
                   sl_error_bias(&row.shadowed));
    rows.push_back(row);
  }
  if (rows.empty() || rows[0].all.pixels == 0) return sl::fail(kCmd, scene_path + ": no pixel of the frame sees the volume", 2);

  // Equal error: the reference's relative noise falls as 1/sqrt(spp) (its variance estimate), so
  // Monte Carlo needs T_ref (noise / e)^2 to reach a measured error e.
  const double noise = sl_error_noise_rmse(&rows[0].all);
  // How concentrated the reference's noise is: the share of its variance (sum of se^2 over the
  // volume's blocks) that its noisiest block carries. Near 1, a single firefly dominates the RMSE
  // measures and the mean relative error is the one to read (docs/ACCURACY.md).
  double worst_share = 0;
  {
    double total = 0, worst = 0;
    for (size_t q = 0; q < nb; ++q) {
      if (!cls[q]) continue;
      double v = 0;
      for (int c = 0; c < 3; ++c) v += ref_blocks.se[3 * q + c] * ref_blocks.se[3 * q + c];
      total += v, worst = std::max(worst, v);
    }
    worst_share = total > 0 ? worst / total : 0;
  }
  {
    std::vector<double> seconds, errors;
    for (const Row &r : rows) seconds.push_back(r.seconds), errors.push_back(sl_error_relative_rmse(&r.all));
    std::vector<unsigned char> front(rows.size());
    sl_pareto_front((int)rows.size(), seconds.data(), errors.data(), front.data());
    for (size_t i = 0; i < rows.size(); ++i) {
      rows[i].mc_seconds = sl_equal_error_seconds(ref.seconds, noise, errors[i]);
      rows[i].speedup = rows[i].mc_seconds / rows[i].seconds;
      rows[i].pareto = front[i];
    }
  }
  std::sort(rows.begin() + 1, rows.end(), [](const Row &a, const Row &b) {
    return a.s.family != b.s.family ? a.s.family < b.s.family : a.seconds < b.seconds;
  });
  const Row *best_interactive = nullptr, *best_xi = nullptr;
  for (const Row &r : rows) {
    if (r.seconds <= interactive && (!best_interactive || sl_error_relative_rmse(&r.all) < sl_error_relative_rmse(&best_interactive->all)))
      best_interactive = &r;
    const bool xi_only = (r.s.family == "xi" || r.s.family == "scene");
    if (xi_only && (!best_xi || sl_error_relative_rmse(&r.all) < sl_error_relative_rmse(&best_xi->all))) best_xi = &r;
  }

  // The report: JSON, a Markdown table, the chart.
  cJSON *root = cJSON_CreateObject();
  cJSON_AddStringToObject(root, "scene", scene_path.c_str());
  cJSON_AddNumberToObject(root, "width", cam.width);
  cJSON_AddNumberToObject(root, "height", cam.height);
  cJSON_AddNumberToObject(root, "block", (double)block);
  cJSON_AddNumberToObject(root, "threads", omp_get_max_threads());
  cJSON_AddNumberToObject(root, "thin_tau_below", kThinTau);
  cJSON_AddNumberToObject(root, "volume_tau_above", kVolumeTau);
  cJSON *jr = cJSON_AddObjectToObject(root, "reference");
  cJSON_AddStringToObject(jr, "file", ref.origin.c_str());
  cJSON_AddNumberToObject(jr, "spp", (double)ref.spp);
  cJSON_AddNumberToObject(jr, "seconds", ref.seconds);
  cJSON_AddNumberToObject(jr, "threads", ref.threads);
  cJSON_AddStringToObject(jr, "wavelengths", ref.wavelengths.c_str());
  cJSON_AddNumberToObject(jr, "noise", noise);
  cJSON_AddNumberToObject(jr, "noise_thin", sl_error_noise_rmse(&rows[0].thin));
  cJSON_AddNumberToObject(jr, "noise_dense", sl_error_noise_rmse(&rows[0].dense));
  cJSON_AddNumberToObject(jr, "noise_shadowed", sl_error_noise_rmse(&rows[0].shadowed));
  cJSON_AddBoolToObject(jr, "skylight", base.skylight);
  cJSON_AddNumberToObject(root, "shadowed_sun_below", kShadowedSun);
  cJSON_AddNumberToObject(jr, "noise_worst_block_share", worst_share);
  cJSON_AddStringToObject(jr, "equal_error_model",
                          "Monte Carlo seconds to reach error e = seconds * (noise / e)^2: the variance estimate, "
                          "which falls as 1/spp");
  cJSON *jrows = cJSON_AddArrayToObject(root, "settings");
  std::string md;
  md += "| setting | s/frame | rel. RMSE all | thin | dense | shadowed | mean rel. all | thin | dense | shadowed | bias | "
        "shadowed bias | MC s, same error | speed-up | Pareto |\n"
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
  for (const Row &r : rows) {
    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(j, "name", r.s.name.c_str());
    cJSON_AddStringToObject(j, "family", r.s.family.c_str());
    cJSON_AddNumberToObject(j, "slices", r.s.slices);
    cJSON_AddNumberToObject(j, "light_resolution", r.s.light_resolution);
    cJSON_AddNumberToObject(j, "max_order", r.s.max_order);
    cJSON_AddStringToObject(j, "lighting", r.s.lighting == SL_LIGHTING_MULTIPLE ? "multiple"
                                           : r.s.lighting == SL_LIGHTING_MULTIPLE_EQ25 ? "eq25" : "low-albedo");
    cJSON_AddNumberToObject(j, "xi", r.s.xi);
    cJSON_AddStringToObject(j, "wavelengths", r.s.spectral ? "spectral" : "rgb");
    cJSON_AddBoolToObject(j, "light_volume", r.s.light_volume);
    cJSON_AddNumberToObject(j, "march_thin_depth", r.s.march_thin_depth);
    cJSON_AddNumberToObject(j, "march_refine_tolerance", r.s.march_refine_tolerance);
    cJSON_AddNumberToObject(j, "seconds", r.seconds);
    cJSON_AddItemToObject(j, "all", class_json(r.all));
    cJSON_AddItemToObject(j, "thin", class_json(r.thin));
    cJSON_AddItemToObject(j, "dense", class_json(r.dense));
    cJSON_AddItemToObject(j, "shadowed", class_json(r.shadowed));
    cJSON_AddBoolToObject(j, "skylight", r.s.skylight);
    cJSON_AddNumberToObject(j, "mc_seconds_equal_error", r.mc_seconds);
    cJSON_AddNumberToObject(j, "speedup", r.speedup);
    cJSON_AddBoolToObject(j, "pareto", r.pareto);
    cJSON_AddStringToObject(j, "error_map", ("error_" + file_name(r.s.name) + ".png").c_str());
    cJSON_AddItemToArray(jrows, j);
    // A class without pixels has no error: a dash, not a zero.
    const auto cell = [](const sl_error_sums &e, double v) { return e.pixels ? fmt("%.3f", v) : std::string("–"); };
    md += "| " + r.s.name + " | " + fmt("%.3g", r.seconds) + " | " + fmt("%.3f", sl_error_relative_rmse(&r.all)) + " | " +
          cell(r.thin, sl_error_relative_rmse(&r.thin)) + " | " + cell(r.dense, sl_error_relative_rmse(&r.dense)) + " | " +
          cell(r.shadowed, sl_error_relative_rmse(&r.shadowed)) + " | " + fmt("%.3f", sl_error_mean_relative(&r.all)) +
          " | " + cell(r.thin, sl_error_mean_relative(&r.thin)) + " | " + cell(r.dense, sl_error_mean_relative(&r.dense)) +
          " | " + cell(r.shadowed, sl_error_mean_relative(&r.shadowed)) + " | " + fmt("%+.3f", sl_error_bias(&r.all)) +
          " | " + (r.shadowed.pixels ? fmt("%+.3f", sl_error_bias(&r.shadowed)) : std::string("–")) + " | " +
          fmt("%.3g", r.mc_seconds) +
          " | " + fmt("%.3g", r.speedup) + " | " + (r.pareto ? "yes" : "") + " |\n";
  }
  {
    const Row &r = rows[0];
    const auto cell = [](const sl_error_sums &e, double v) { return e.pixels ? fmt("%.3f", v) : std::string("–"); };
    md += "| *reference noise* | " + fmt("%.3g", ref.seconds) + " | " + fmt("%.3f", noise) + " | " +
          cell(r.thin, sl_error_noise_rmse(&r.thin)) + " | " + cell(r.dense, sl_error_noise_rmse(&r.dense)) + " | " +
          cell(r.shadowed, sl_error_noise_rmse(&r.shadowed)) + " | " + fmt("%.3f", sl_error_noise_mean(&r.all)) + " | " +
          cell(r.thin, sl_error_noise_mean(&r.thin)) + " | " + cell(r.dense, sl_error_noise_mean(&r.dense)) + " | " +
          cell(r.shadowed, sl_error_noise_mean(&r.shadowed)) + " | | | | | |\n";
  }
  char head[800];
  std::snprintf(head, sizeof head,
                "%s, %dx%d, compared in %ldx%ld blocks: %ld volume blocks (%ld thin, tau < 2; %ld dense; %ld shadowed, "
                "sunlight < %g at the visible surface); reference %ld spp (%s, skylight %s) in %.1f s, %d threads; its "
                "noisiest block carries %.0f %% of its noise variance.\n\n",
                scene_path.c_str(), cam.width, cam.height, block, block, rows[0].all.pixels, rows[0].thin.pixels,
                rows[0].dense.pixels, rows[0].shadowed.pixels, kShadowedSun, ref.spp, ref.wavelengths.c_str(),
                base.skylight ? "on" : "off", ref.seconds, ref.threads, 100 * worst_share);
  md = head + md;
  if (best_interactive) {
    cJSON *b = cJSON_AddObjectToObject(root, "best_interactive");
    cJSON_AddStringToObject(b, "name", best_interactive->s.name.c_str());
    cJSON_AddNumberToObject(b, "seconds", best_interactive->seconds);
    cJSON_AddNumberToObject(b, "relative_rmse", sl_error_relative_rmse(&best_interactive->all));
    cJSON_AddNumberToObject(b, "speedup", best_interactive->speedup);
    md += "\nBest setting at or under " + fmt("%g", interactive) + " s per frame: " + best_interactive->s.name + ", " +
          fmt("%.3g", best_interactive->seconds) + " s, relative RMSE " + fmt("%.3f", sl_error_relative_rmse(&best_interactive->all)) +
          "; Monte Carlo needs " + fmt("%.3g", best_interactive->mc_seconds) + " s for the same error (speed-up " +
          fmt("%.3g", best_interactive->speedup) + ").\n";
  }
  if (best_xi) {
    cJSON_AddNumberToObject(root, "best_xi", best_xi->s.xi);
    md += "Lowest error over xi (other settings the scene's): xi " + fmt("%g", best_xi->s.xi) + ", relative RMSE " +
          fmt("%.3f", sl_error_relative_rmse(&best_xi->all)) + ".\n";
  }
  char *text = cJSON_Print(root);
  const std::string body = std::string(text) + "\n";
  std::free(text);
  if (json) {
    char *flat = cJSON_PrintUnformatted(root);
    std::printf("%s\n", flat);
    std::free(flat);
  }
  cJSON_Delete(root);
  if (!write_text(dir + "/report.json", body, &why) || !write_text(dir + "/table.md", md, &why))
    return sl::fail(kCmd, why);
  if (want_plot) {
    const std::string title = scene_path.substr(scene_path.find_last_of('/') + 1) + ": speed against error";
    if (!plot(rows, ref, noise, title, dir + "/speed_error.png", &why)) return sl::fail(kCmd, why);
  }
  if (!quiet) std::printf("%s", md.c_str());
  const Row &scene_row = *std::find_if(rows.begin(), rows.end(), [](const Row &r) { return r.s.family == "scene"; });
  if (sl_error_relative_rmse(&scene_row.all) > max_error) {
    std::fprintf(stderr, "stormlight validate: %s: relative RMSE %.4f of the scene's setting exceeds --max-error %g\n",
                 scene_path.c_str(), sl_error_relative_rmse(&scene_row.all), max_error);
    return 1;
  }
  return 0;
}
