// stormlight optics: particle optics from the command line: Mie for one sphere, phase
// functions and Ams_n of the scene's particle types, table building (and its timing), and
// plots of the phase functions (Riley et al. 2004, Figures 2 and 3). Computes nothing itself:
// everything comes from render/optics.
#include <cjson/cJSON.h>

#include <vtkAxis.h>
#include <vtkChartXY.h>
#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPen.h>
#include <vtkPlot.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTable.h>
#include <vtkTextProperty.h>


#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "cli.h"
#include "vtk_png.h"
#include "commands.h"
#include "sl_mie.h"
#include "sl_optics.h"
#include "sl_air.h"

namespace {

const double kPi = 3.14159265358979323846;

void print_json(cJSON *root)
{
  char *text = cJSON_PrintUnformatted(root);
  std::printf("%s\n", text);
  std::free(text);
  cJSON_Delete(root);
}

cJSON *json_array(const std::vector<double> &v)
{
  return cJSON_CreateDoubleArray(v.data(), (int)v.size());
}

// Options shared by the subcommands that build tables.
void table_options(sl::Options &o)
{
  o.option("step", "DEG", "angular grid of the tables", "0.1");
  o.option("radii", "N", "quadrature points across each size distribution", "256");
  o.option("rays", "N", "ice ray-tracing rays per wavelength and habit", "400000");
  o.option("cache-dir", "DIR", "table cache (default $SL_CACHE_DIR, $XDG_CACHE_HOME/stormlight, ~/.cache/stormlight)");
  o.flag("no-cache", "neither read nor write the table cache");
}

bool read_table_options(sl::Options &o, sl_optics_request *req, std::string *cache_dir)
{
  long radii, rays;
  if (!o.number("step", &req->angle_step_deg) || !o.integer("radii", &radii, 1, 10000) ||
      !o.integer("rays", &rays, 64, 2000000000L))
    return false;
  req->radius_samples = (int)radii;
  req->ice_rays = rays;
  req->use_cache = o.has("no-cache") ? 0 : 1;
  if (o.has("cache-dir")) {
    *cache_dir = o.str("cache-dir");
    req->cache_dir = cache_dir->c_str();
  }
  return true;
}

struct ProgressBridge {
  sl::Progress *bar;
  static void call(void *user, double fraction) { static_cast<ProgressBridge *>(user)->bar->update(fraction); }
};

sl_optics_tables *build_with_progress(sl_optics_request *req, const char *label, sl_error *err)
{
  sl::Progress bar(label, sl::stderr_is_tty());
  ProgressBridge bridge{&bar};
  req->progress = &ProgressBridge::call;
  req->progress_user = &bridge;
  sl_optics_tables *t = sl_optics_build(req, err);
  bar.done();
  req->progress = nullptr;
  return t;
}

int cmd_mie(int argc, char **argv)
{
  sl::Options o("optics mie", "--x X --m RE,IM [--angles A,B,...] [--json]",
                "Lorenz-Mie scattering by one homogeneous sphere (Bohren & Huffman's algorithm).\n"
                "IM >= 0 absorbs (Bohren & Huffman's sign; Wiscombe's 1.33-1e-5i is --m 1.33,1e-5).\n"
                "s11 = (|S1|^2+|S2|^2)/2 in Bohren & Huffman's normalisation, at the angles in degrees.");
  o.option("x", "X", "size parameter 2 pi r / lambda (1e-6 .. 1e5)");
  o.option("m", "RE,IM", "refractive index of the sphere relative to the medium");
  o.option("angles", "A,B,...", "scattering angles in degrees", "0,30,60,90,120,150,180");
  o.flag("json", "print one JSON object");
  const int early = sl::parse_or_exit(o, argc, argv);
  if (early >= 0) return early;
  if (!o.has("x") || !o.has("m")) return sl::fail("optics mie", "--x and --m are required", 2);
  double x;
  std::vector<double> m, angles;
  if (!o.number("x", &x) || !o.list("m", &m) || !o.list("angles", &angles)) return sl::fail("optics mie", o.error(), 2);
  if (m.size() != 2) return sl::fail("optics mie", "--m needs two numbers RE,IM", 2);
  if (m[1] < 0)
    return sl::fail("optics mie", "--m: IM must be >= 0 (absorbing spheres have IM > 0 in this convention)", 2);
  std::vector<double> mu(angles.size()), s11(angles.size());
  for (size_t i = 0; i < angles.size(); ++i) {
    if (angles[i] < 0 || angles[i] > 180) return sl::fail("optics mie", "--angles must lie in 0..180 degrees", 2);
    mu[i] = std::cos(angles[i] * kPi / 180.0);
  }
  sl_error err{};
  sl_mie_efficiencies e;
  if (sl_mie(x, m[0], m[1], mu.data(), (int)mu.size(), &e, nullptr, nullptr, s11.data(), &err))
    return sl::fail("optics mie", err.message, 2);
  if (o.has("json")) {
    cJSON *root = cJSON_CreateObject();
    cJSON_AddNumberToObject(root, "x", x);
    cJSON_AddNumberToObject(root, "m_re", m[0]);
    cJSON_AddNumberToObject(root, "m_im", m[1]);
    cJSON_AddNumberToObject(root, "qext", e.qext);
    cJSON_AddNumberToObject(root, "qsca", e.qsca);
    cJSON_AddNumberToObject(root, "qback", e.qback);
    cJSON_AddNumberToObject(root, "g", e.g);
    cJSON_AddNumberToObject(root, "terms", e.terms);
    cJSON_AddItemToObject(root, "angles", json_array(angles));
    cJSON_AddItemToObject(root, "s11", json_array(s11));
    print_json(root);
  } else {
    std::printf("x %.9g  m %.9g%+.9gi  terms %d\nQext %.9g  Qsca %.9g  Qback %.9g  g %.9g\n", x, m[0], m[1], e.terms,
                e.qext, e.qsca, e.qback, e.g);
    for (size_t i = 0; i < angles.size(); ++i) std::printf("  %8.3f deg  S11 %.9g\n", angles[i], s11[i]);
  }
  return 0;
}

int cmd_phase(int argc, char **argv)
{
  sl::Options o("optics phase", "--particle air|cloud|rain|ice|snow --wavelength NM [--order N] --angles A,B,... [--json]",
                "The phase function P (1/sr, normalised to 1 over the sphere) or, with --order N, the\n"
                "multiple-scattering distribution Ams_N (Riley et al. 2004, eq. 20) at the given scattering\n"
                "angles, with the forward fraction F_N (eq. 23) and the extinction cross-section. The forward\n"
                "diffraction peak narrower than the grid is reported apart as \"forward_delta\", the weight of\n"
                "a Dirac at 0 degrees (docs/OPTICS.md). JSON keys: angles, phase (order 1) or ams (other\n"
                "orders), forward_delta, forward_fraction, sigma_ext (m^2), albedo, asymmetry, max_order.");
  o.option("particle", "NAME", "air, cloud, rain, ice or snow");
  o.option("wavelength", "NM", "wavelength in nanometres", "515");
  o.option("order", "N", "scattering order n of Ams_n (1 = the phase function)", "1");
  o.option("angles", "A,B,...", "scattering angles in degrees", "0,10,22,46,90,120,138,170,180");
  o.flag("json", "print one JSON object");
  table_options(o);
  const int early = sl::parse_or_exit(o, argc, argv);
  if (early >= 0) return early;
  if (!o.has("particle")) return sl::fail("optics phase", "--particle is required", 2);
  const std::string name = o.str("particle");
  double nm;
  long order;
  std::vector<double> angles;
  if (!o.number("wavelength", &nm) || !o.integer("order", &order, 0, SL_OPTICS_MAX_ORDER) || !o.list("angles", &angles))
    return sl::fail("optics phase", o.error(), 2);
  for (double a : angles)
    if (a < 0 || a > 180) return sl::fail("optics phase", "--angles must lie in 0..180 degrees", 2);
  std::vector<double> values(angles.size());
  double forward = 0, sigma = 0, albedo = 1, g = 0, delta = 0;
  int max_order = (int)order;
  if (name == "air") {
    if (!(nm >= 300 && nm <= 1000)) return sl::fail("optics phase", "--wavelength must lie in 300..1000 nm", 2);
    for (size_t i = 0; i < angles.size(); ++i) {
      const double mu = std::cos(angles[i] * kPi / 180.0);
      values[i] = order == 0 ? 0.0 : sl_rayleigh_ams((int)order, mu);
    }
    forward = order == 0 ? 1.0 : 0.5;
    delta = order == 0 ? 1.0 : 0.0;
    sigma = sl_air_cross_section(nm);
  } else {
    const int p = sl_particle_from_name(name.c_str());
    if (p < 0) return sl::fail("optics phase", "--particle must be air, cloud, rain, ice or snow, not '" + name + "'", 2);
    sl_optics_request req;
    sl_optics_request_defaults(&req);
    std::string cache_dir;
    if (!read_table_options(o, &req, &cache_dir)) return sl::fail("optics phase", o.error(), 2);
    req.particles = 1u << p;
    req.n_wavelengths = 1;
    req.wavelengths_nm[0] = nm;
    sl_error err{};
    sl_optics_tables *T = build_with_progress(&req, "optics tables", &err);
    if (!T) return sl::fail("optics phase", err.message);
    const sl_phase_table *t = sl_optics_table(T, (sl_particle)p, 0);
    for (size_t i = 0; i < angles.size(); ++i)
      values[i] = sl_phase_table_ams(t, (int)order, std::cos(angles[i] * kPi / 180.0));
    max_order = t->max_order;
    forward = sl_phase_table_forward(t, (int)order);
    delta = t->delta[order < t->max_order ? order : t->max_order];
    sigma = t->sigma_ext;
    albedo = t->albedo;
    g = t->asymmetry;
    sl_optics_free(T);
  }
  if (o.has("json")) {
    cJSON *root = cJSON_CreateObject();
    cJSON_AddStringToObject(root, "particle", name.c_str());
    cJSON_AddNumberToObject(root, "wavelength_nm", nm);
    cJSON_AddNumberToObject(root, "order", (double)order);
    cJSON_AddNumberToObject(root, "max_order", max_order);
    cJSON_AddItemToObject(root, "angles", json_array(angles));
    cJSON_AddItemToObject(root, order == 1 ? "phase" : "ams", json_array(values));
    cJSON_AddNumberToObject(root, "forward_delta", delta);
    cJSON_AddNumberToObject(root, "forward_fraction", forward);
    cJSON_AddNumberToObject(root, "sigma_ext", sigma);
    cJSON_AddNumberToObject(root, "albedo", albedo);
    if (name != "air") cJSON_AddNumberToObject(root, "asymmetry", g);
    print_json(root);
  } else {
    std::printf("%s at %g nm, %s: sigma_ext %.6g m^2, albedo %.6f, F_%ld %.6f, forward Dirac %.6g\n", name.c_str(), nm,
                order == 1 ? "phase function" : ("Ams_" + std::to_string(order)).c_str(), sigma, albedo, order, forward,
                delta);
    for (size_t i = 0; i < angles.size(); ++i) std::printf("  %8.3f deg  %.9g /sr\n", angles[i], values[i]);
  }
  return 0;
}

int cmd_build(int argc, char **argv)
{
  sl::Options o("optics build", "[--particles cloud,rain,ice,snow] [--wavelengths rgb|spectral16] [--json]",
                "Builds (or loads from the cache) the tables of the named particle types and reports the time it\n"
                "took, the orders N reached and the cache's activity. Run twice to time a warm cache.");
  o.option("particles", "LIST", "comma-separated particle types", "cloud,rain,ice,snow");
  o.option("wavelengths", "SET", "rgb (650, 515, 440 nm) or spectral16 (380..720 nm)", "rgb");
  o.option("max-order", "N", "highest order N (0 = until isotropic within 1e-4)", "0");
  o.flag("json", "print one JSON object");
  table_options(o);
  const int early = sl::parse_or_exit(o, argc, argv);
  if (early >= 0) return early;
  sl_optics_request req;
  sl_optics_request_defaults(&req);
  std::string cache_dir;
  long max_order;
  if (!read_table_options(o, &req, &cache_dir) || !o.integer("max-order", &max_order, 0, SL_OPTICS_MAX_ORDER))
    return sl::fail("optics build", o.error(), 2);
  req.max_order = (int)max_order;
  sl_error err{};
  if (sl_optics_request_wavelengths(&req, o.str("wavelengths").c_str(), &err)) return sl::fail("optics build", err.message, 2);
  req.particles = 0;
  std::string list = o.str("particles") + ",";
  for (size_t start = 0, comma; (comma = list.find(',', start)) != std::string::npos; start = comma + 1) {
    const std::string item = list.substr(start, comma - start);
    if (item.empty()) continue;
    const int p = sl_particle_from_name(item.c_str());
    if (p < 0) return sl::fail("optics build", "unknown particle type '" + item + "'", 2);
    req.particles |= 1u << p;
  }
  const double t0 = sl::now_seconds();
  sl_optics_tables *T = build_with_progress(&req, "optics tables", &err);
  const double seconds = sl::now_seconds() - t0;
  if (!T) return sl::fail("optics build", err.message);
  sl_optics_stats s;
  sl_optics_get_stats(T, &s);
  cJSON *root = cJSON_CreateObject();
  cJSON_AddNumberToObject(root, "seconds", seconds);
  cJSON_AddNumberToObject(root, "build_seconds", s.build_seconds);
  cJSON_AddNumberToObject(root, "load_seconds", s.load_seconds);
  cJSON_AddNumberToObject(root, "tables_built", s.tables_built);
  cJSON_AddNumberToObject(root, "tables_loaded", s.tables_loaded);
  cJSON_AddNumberToObject(root, "cache_rejected", s.cache_rejected);
  cJSON_AddStringToObject(root, "cache_dir", req.use_cache ? s.cache_dir : "");
  cJSON *parts = cJSON_AddArrayToObject(root, "tables");
  for (int p = 0; p < SL_PARTICLE_COUNT; ++p)
    for (int w = 0; w < sl_optics_wavelength_count(T); ++w) {
      const sl_phase_table *t = sl_optics_table(T, (sl_particle)p, w);
      if (!t) continue;
      cJSON *e = cJSON_CreateObject();
      cJSON_AddStringToObject(e, "particle", sl_particle_name((sl_particle)p));
      cJSON_AddNumberToObject(e, "wavelength_nm", t->wavelength_nm);
      cJSON_AddNumberToObject(e, "sigma_ext", t->sigma_ext);
      cJSON_AddNumberToObject(e, "albedo", t->albedo);
      cJSON_AddNumberToObject(e, "asymmetry", t->asymmetry);
      cJSON_AddNumberToObject(e, "forward_delta", t->truncated_fraction);
      cJSON_AddNumberToObject(e, "max_order", t->max_order);
      // First n with max |4 pi Ams_n - 1| below 1e-2, 1e-4, 1e-6 (-1: not reached by N).
      const double tol[3] = {1e-2, 1e-4, 1e-6};
      double iso[3];
      for (int k = 0; k < 3; ++k) iso[k] = sl_phase_table_isotropic_order(t, tol[k]);
      cJSON_AddItemToObject(e, "isotropic_order", cJSON_CreateDoubleArray(iso, 3));
      cJSON_AddItemToArray(parts, e);
    }
  if (o.has("json")) {
    print_json(root);
  } else {
    std::printf("%.3f s: %d particle types built (%.3f s), %d loaded from the cache (%.3f s), %d cache files rejected\n",
                seconds, s.tables_built, s.build_seconds, s.tables_loaded, s.load_seconds, s.cache_rejected);
    cJSON *e;
    cJSON_ArrayForEach(e, parts)
    {
      cJSON *iso = cJSON_GetObjectItem(e, "isotropic_order");
      std::printf("  %-5s %5.1f nm  sigma_ext %.4g m^2  albedo %.6f  g %.4f  forward Dirac %.4f  N %d  "
                  "isotropic within 1e-2/1e-4/1e-6 at n = %d/%d/%d\n",
                  cJSON_GetObjectItem(e, "particle")->valuestring, cJSON_GetObjectItem(e, "wavelength_nm")->valuedouble,
                  cJSON_GetObjectItem(e, "sigma_ext")->valuedouble, cJSON_GetObjectItem(e, "albedo")->valuedouble,
                  cJSON_GetObjectItem(e, "asymmetry")->valuedouble, cJSON_GetObjectItem(e, "forward_delta")->valuedouble,
                  cJSON_GetObjectItem(e, "max_order")->valueint, cJSON_GetArrayItem(iso, 0)->valueint,
                  cJSON_GetArrayItem(iso, 1)->valueint, cJSON_GetArrayItem(iso, 2)->valueint);
    }
    cJSON_Delete(root);
  }
  sl_optics_free(T);
  return 0;
}

int cmd_plot(int argc, char **argv)
{
  sl::Options o("optics plot", "--particle air|cloud|rain|ice|snow|all --out FILE.png [--order N]",
                "Plots phase functions on a log scale against scattering angle with VTK's charts: one particle\n"
                "for red, green and blue (650, 515, 440 nm; Riley et al. 2004, Figure 2), or with --particle all\n"
                "every particle type at 515 nm (Figure 3). With --order N, Ams_N instead of P.");
  o.option("particle", "NAME", "air, cloud, rain, ice, snow or all");
  o.option("out", "FILE.png", "output image");
  o.option("order", "N", "scattering order (1 = the phase function)", "1");
  o.option("size", "W,H", "image size in pixels", "1000,650");
  table_options(o);
  const int early = sl::parse_or_exit(o, argc, argv);
  if (early >= 0) return early;
  if (!o.has("particle") || !o.has("out")) return sl::fail("optics plot", "--particle and --out are required", 2);
  long order;
  std::vector<double> size;
  if (!o.integer("order", &order, 0, SL_OPTICS_MAX_ORDER) || !o.list("size", &size))
    return sl::fail("optics plot", o.error(), 2);
  if (size.size() != 2 || size[0] < 200 || size[1] < 150 || size[0] > 8000 || size[1] > 8000)
    return sl::fail("optics plot", "--size needs W,H between 200x150 and 8000x8000", 2);
  const std::string name = o.str("particle");
  const bool all = name == "all";
  struct Curve {
    std::string label;
    unsigned char rgb[3];
    std::vector<double> y;
  };
  std::vector<Curve> curves;
  sl_optics_request req;
  sl_optics_request_defaults(&req);
  std::string cache_dir;
  if (!read_table_options(o, &req, &cache_dir)) return sl::fail("optics plot", o.error(), 2);
  const int n_points = 1801;
  std::vector<double> angle(n_points);
  for (int i = 0; i < n_points; ++i) angle[i] = 180.0 * i / (n_points - 1);
  auto sample = [&](const sl_phase_table *t) {
    std::vector<double> y(n_points);
    for (int i = 0; i < n_points; ++i)
      y[i] = std::max(1e-6, sl_phase_table_ams(t, (int)order, std::cos(angle[i] * kPi / 180.0)));
    return y;
  };
  auto air_curve = [&]() {
    std::vector<double> y(n_points);
    for (int i = 0; i < n_points; ++i) y[i] = sl_rayleigh_ams((int)order, std::cos(angle[i] * kPi / 180.0));
    return y;
  };
  if (all) {
    req.particles = (1u << SL_PARTICLE_COUNT) - 1;
    req.n_wavelengths = 1;
    req.wavelengths_nm[0] = 515.0;
  } else if (name != "air") {
    const int p = sl_particle_from_name(name.c_str());
    if (p < 0) return sl::fail("optics plot", "--particle must be air, cloud, rain, ice, snow or all", 2);
    req.particles = 1u << p;
  }
  static const unsigned char kRGB[3][3] = {{220, 30, 30}, {20, 160, 40}, {40, 70, 230}};
  static const unsigned char kParticle[5][3] = {{90, 90, 90}, {30, 120, 220}, {20, 160, 120}, {200, 60, 200}, {230, 140, 20}};
  if (name == "air") {
    curves.push_back({"air (Rayleigh)", {90, 90, 90}, air_curve()});
  } else {
    sl_error err{};
    sl_optics_tables *T = build_with_progress(&req, "optics tables", &err);
    if (!T) return sl::fail("optics plot", err.message);
    if (all) {
      curves.push_back({"air", {kParticle[0][0], kParticle[0][1], kParticle[0][2]}, air_curve()});
      for (int p = 0; p < SL_PARTICLE_COUNT; ++p)
        curves.push_back({sl_particle_name((sl_particle)p),
                          {kParticle[p + 1][0], kParticle[p + 1][1], kParticle[p + 1][2]},
                          sample(sl_optics_table(T, (sl_particle)p, 0))});
    } else {
      const int p = sl_particle_from_name(name.c_str());
      for (int w = 0; w < 3; ++w) {
        char label[64];
        std::snprintf(label, sizeof label, "%s %.0f nm", name.c_str(), sl_optics_wavelength(T, w));
        curves.push_back({label, {kRGB[w][0], kRGB[w][1], kRGB[w][2]}, sample(sl_optics_table(T, (sl_particle)p, w))});
      }
    }
    sl_optics_free(T);
  }

  vtkNew<vtkTable> table;
  vtkNew<vtkDoubleArray> xs;
  xs->SetName("scattering angle (degrees)");
  xs->SetNumberOfValues(n_points);
  for (int i = 0; i < n_points; ++i) xs->SetValue(i, angle[i]);
  table->AddColumn(xs);
  for (const Curve &c : curves) {
    vtkNew<vtkDoubleArray> ys;
    ys->SetName(c.label.c_str());
    ys->SetNumberOfValues(n_points);
    for (int i = 0; i < n_points; ++i) ys->SetValue(i, c.y[i]);
    table->AddColumn(ys);
  }
  std::string display_error;
  if (!sl::have_display(&display_error)) return sl::fail("optics plot", display_error);
  vtkNew<vtkContextView> view;
  view->GetRenderer()->SetBackground(1.0, 1.0, 1.0);
  view->GetRenderWindow()->SetOffScreenRendering(1);
  view->GetRenderWindow()->SetSize((int)size[0], (int)size[1]);
  vtkNew<vtkChartXY> chart;
  view->GetScene()->AddItem(chart);
  chart->SetShowLegend(true);
  const std::string what = order == 1 ? "phase function" : "Ams_" + std::to_string(order);
  chart->SetTitle((all ? what + " of every particle type at 515 nm" : name + " " + what + ", red, green and blue").c_str());
  chart->GetAxis(vtkAxis::LEFT)->SetTitle(order == 1 ? "P (1/sr)" : "Ams_n (1/sr)");
  chart->GetAxis(vtkAxis::LEFT)->SetLogScale(true);
  chart->GetAxis(vtkAxis::BOTTOM)->SetTitle("scattering angle (degrees)");
  chart->GetAxis(vtkAxis::BOTTOM)->SetRange(0.0, 180.0);
  chart->GetAxis(vtkAxis::BOTTOM)->SetBehavior(vtkAxis::FIXED);
  for (size_t k = 0; k < curves.size(); ++k) {
    vtkPlot *line = chart->AddPlot(vtkChart::LINE);
    line->SetInputData(table, 0, (vtkIdType)k + 1);
    line->SetColor(curves[k].rgb[0], curves[k].rgb[1], curves[k].rgb[2], 255);
    line->SetWidth(1.5);
  }
  const std::string out = o.str("out");
  std::string png_error;
  if (!sl::write_window_png(view->GetRenderWindow(), out, &png_error)) return sl::fail("optics plot", png_error);
  std::printf("wrote %s\n", out.c_str());
  return 0;
}

}  // namespace

int sl_cmd_optics(int argc, char **argv)
{
  const char *usage =
      "usage: stormlight optics <mie|phase|build|plot> [options]\n\n"
      "  mie    Lorenz-Mie efficiencies and S11 for one sphere\n"
      "  phase  phase function P or Ams_n of air, cloud, rain, ice or snow at one wavelength\n"
      "  build  build (or load) the tables of a scene's particle types; timings and cache activity\n"
      "  plot   phase functions on a log scale (Riley et al. 2004, Figures 2 and 3) as PNG\n\n"
      "Run 'stormlight optics <sub> --help' for its options.\n";
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h")) {
    std::fputs(usage, argc < 2 ? stderr : stdout);
    return argc < 2 ? 2 : 0;
  }
  const std::string sub = argv[1];
  if (sub == "mie") return cmd_mie(argc - 1, argv + 1);
  if (sub == "phase") return cmd_phase(argc - 1, argv + 1);
  if (sub == "build") return cmd_build(argc - 1, argv + 1);
  if (sub == "plot") return cmd_plot(argc - 1, argv + 1);
  return sl::fail("optics", "unknown subcommand '" + sub + "' (mie, phase, build, plot)", 2);
}
