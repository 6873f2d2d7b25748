// stormlight apsf: the atmospheric point spread function of Narasimhan, Ramamoorthi and Nayar
// at chosen angles (--json for scripts), or a plot of it for the paper's Fig. 2/3 parameter
// ranges drawn with VTK's charts. Computes nothing itself: everything comes from render/apsf.
#include <cjson/cJSON.h>

#include <vtkAxis.h>
#include <vtkChartLegend.h>
#include <vtkChartXY.h>
#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPlot.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTable.h>


#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "cli.h"
#include "vtk_png.h"
#include "commands.h"
#include "sl_apsf.h"
#include "sl_optics.h"

namespace {

const double kPi = 3.14159265358979323846;
const char *kCmd = "apsf";
const double kReferenceDeg = 1.0; /* psf reference angle below T = 1.5 */

// Fluence weight (1/sr, sl_apsf.h) at each angle, plus the Dirac's weight and the term count.
struct Psf {
  std::vector<double> weight;
  double direct = 0.0, blend = 1.0, forward = 0.0, back_fraction = -1.0;
  int terms = 0;
};

bool evaluate(const sl_apsf_medium &m, double T, double tolerance, const std::vector<double> &angles_deg, Psf *out,
              std::string *why, bool series_only = false)
{
  sl_error err{};
  out->weight.assign(angles_deg.size(), 0.0);
  if (T >= SL_APSF_BLEND_HI || series_only) {
    // The series regime: exact evaluation, no table.
    sl_apsf_series s;
    if (sl_apsf_series_init(&s, &m, T, tolerance, 0, &err)) {
      *why = err.message;
      return false;
    }
    for (size_t i = 0; i < angles_deg.size(); ++i)
      out->weight[i] = sl_apsf_fluence_weight(T, sl_apsf_series_eval(&s, std::cos(angles_deg[i] * kPi / 180.0)));
    out->forward = sl_apsf_fluence_weight(T, sl_apsf_series_eval(&s, 1.0));
    out->back_fraction = sl_apsf_series_back_fraction(&s);
    out->terms = s.terms;
    sl_apsf_series_free(&s);
    return true;
  }
  sl_apsf_profile p;
  if (sl_apsf_profile_build(&p, &m, T, tolerance, kPi, 16384, &err)) {
    *why = err.message;
    return false;
  }
  for (size_t i = 0; i < angles_deg.size(); ++i) out->weight[i] = sl_apsf_profile_eval(&p, angles_deg[i] * kPi / 180.0);
  // Single scattering diverges as 1/gamma at the source: the reference is 1 degree instead.
  out->forward = sl_apsf_profile_eval(&p, kReferenceDeg * kPi / 180.0);
  out->direct = p.direct;
  out->blend = p.blend;
  out->terms = p.terms;
  sl_apsf_profile_free(&p);
  return true;
}

void progress_hook(void *user, double fraction) { static_cast<sl::Progress *>(user)->update(fraction); }

// The medium: Henyey-Greenstein (--q, --albedo) or, with --particle, the moments and albedo of a
// render/optics table at --wavelength (tables are cached on disk by render/optics).
struct Medium {
  sl_apsf_medium m{1.0, 0.9, nullptr, 0};
  sl_optics_tables *tables = nullptr;
  std::string label;
  ~Medium() { sl_optics_free(tables); }
};

bool read_medium(sl::Options &o, Medium *med, double *tolerance, std::string *why)
{
  double q, albedo;
  if (!o.number("q", &q) || !o.number("albedo", &albedo) || !o.number("tolerance", tolerance)) {
    *why = o.error();
    return false;
  }
  if (!(q > -1.0 && q < 1.0)) *why = "--q must be in (-1, 1)";
  else if (!(albedo > 0.0 && albedo <= 1.0)) *why = "--albedo must be in (0, 1]";
  else if (!(*tolerance > 0.0 && *tolerance < 0.1)) *why = "--tolerance must be in (0, 0.1)";
  if (!why->empty()) return false;
  med->m = sl_apsf_medium{albedo, q, nullptr, 0};
  char label[96];
  std::snprintf(label, sizeof label, "HG q = %.3g, albedo %.3g", q, albedo);
  med->label = label;
  if (!o.has("particle")) return true;
  const int p = sl_particle_from_name(o.str("particle").c_str());
  double nm;
  if (p < 0) *why = "--particle must be cloud, rain, ice or snow";
  else if (!o.number("wavelength", &nm)) *why = o.error();
  else if (!(nm >= 300 && nm <= 1000)) *why = "--wavelength must be in 300..1000 nm";
  if (!why->empty()) return false;
  sl_optics_request req;
  sl_optics_request_defaults(&req);
  req.particles = 1u << p;
  req.n_wavelengths = 1;
  req.wavelengths_nm[0] = nm;
  sl::Progress bar("optics tables", true);
  req.progress = progress_hook;
  req.progress_user = &bar;
  sl_error err{};
  med->tables = sl_optics_build(&req, &err);
  bar.done();
  if (!med->tables) {
    *why = err.message;
    return false;
  }
  const sl_phase_table *t = sl_optics_table(med->tables, (sl_particle)p, 0);
  med->m = sl_apsf_medium{t->albedo, t->moments[1], t->moments, t->n_moments};
  std::snprintf(label, sizeof label, "%s %.0f nm: g = %.4f, albedo %.6f", o.str("particle").c_str(), nm, t->moments[1],
                t->albedo);
  med->label = label;
  return true;
}

const char *kNormalisation =
    "psf: fluence weight relative to its value at psf_reference_deg (0, the forward direction, in the series regime; 1 "
    "degree below T = 1.5, where single scattering diverges as 1/gamma at the source); fluence_weight: T^2 S / (4 pi) "
    "per sr, the radiance relative to the vacuum fluence I0/R^2 of the source (the series' integral over the sphere is "
    "exp(-3(1-W0)T)); direct: the weight of the unscattered Dirac at gamma = 0 (below T = 1.5 only)";

int plot(sl::Options &o)
{
  if (!o.has("out")) return sl::fail(kCmd, "--plot needs --out FILE.png", 2);
  Medium med;
  double tolerance;
  std::string why;
  if (!read_medium(o, &med, &tolerance, &why)) return sl::fail(kCmd, why, 2);
  const sl_apsf_medium &m = med.m;
  std::vector<double> size;
  if (!o.list("size", &size)) return sl::fail(kCmd, o.error(), 2);
  if (size.size() != 2 || size[0] < 200 || size[1] < 150 || size[0] > 8000 || size[1] > 8000)
    return sl::fail(kCmd, "--size needs W,H between 200x150 and 8000x8000", 2);
  const bool back = o.str("figure") == "back";
  if (!back && o.str("figure") != "psf") return sl::fail(kCmd, "--figure must be psf or back", 2);
  // psf: the paper's Figs. 2 and 4 range, T from just above 1 (hundreds of terms) to 6.
  // back: Fig. 3, the energy in the back hemisphere (mu <= 0) against T for several q.
  const std::vector<double> Ts = {1.02, 1.1, 1.2, 1.5, 2.0, 3.0, 4.0, 6.0};
  const std::vector<double> qs = {0.5, 0.7, 0.8, 0.9, 0.95};
  static const unsigned char kColour[8][3] = {{120, 0, 160}, {60, 60, 220}, {0, 140, 220}, {0, 160, 120},
                                              {90, 170, 0},  {220, 160, 0}, {230, 90, 0},  {200, 0, 40}};
  const int n_points = back ? 200 : 721;
  std::vector<double> xs_v(n_points);
  for (int i = 0; i < n_points; ++i)
    xs_v[i] = back ? 1.02 * std::pow(10.0 / 1.02, (double)i / (n_points - 1)) : 180.0 * i / (n_points - 1);
  vtkNew<vtkTable> table;
  vtkNew<vtkDoubleArray> xs;
  xs->SetName(back ? "optical thickness T" : "angle from the source (degrees)");
  xs->SetNumberOfValues(n_points);
  for (int i = 0; i < n_points; ++i) xs->SetValue(i, xs_v[i]);
  table->AddColumn(xs);
  const size_t n_curves = back ? qs.size() : Ts.size();
  for (size_t k = 0; k < n_curves; ++k) {
    vtkNew<vtkDoubleArray> ys;
    char label[64];
    ys->SetNumberOfValues(n_points);
    if (back) {
      sl_apsf_medium mq = m;
      mq.q = qs[k];
      mq.chi = nullptr;
      std::snprintf(label, sizeof label, "q = %.2f", qs[k]);
      for (int i = 0; i < n_points; ++i) {
        sl_apsf_series s;
        sl_error err{};
        if (sl_apsf_series_init(&s, &mq, xs_v[i], tolerance, 0, &err)) return sl::fail(kCmd, err.message);
        // Absolute energy with I0 = 1, c_m = 1 as in the paper: fraction times 4 pi g_1.
        ys->SetValue(i, std::max(1e-9, sl_apsf_series_back_fraction(&s) * 4.0 * kPi * std::exp(sl_apsf_log_g(&mq, 1, xs_v[i]))));
        sl_apsf_series_free(&s);
      }
    } else {
      // The paper's series itself, also below T = 1.5 where 'glow' blends in single scattering.
      Psf psf;
      if (!evaluate(m, Ts[k], tolerance, xs_v, &psf, &why, true)) return sl::fail(kCmd, why);
      std::snprintf(label, sizeof label, "T = %.2f (%d terms)", Ts[k], psf.terms);
      for (int i = 0; i < n_points; ++i) ys->SetValue(i, std::max(1e-6, psf.weight[i] / psf.forward));
    }
    ys->SetName(label);
    table->AddColumn(ys);
  }
  std::string display_error;
  if (!sl::have_display(&display_error)) return sl::fail(kCmd, display_error);
  vtkNew<vtkContextView> view;
  view->GetRenderer()->SetBackground(1.0, 1.0, 1.0);
  view->GetRenderWindow()->SetOffScreenRendering(1);
  view->GetRenderWindow()->SetSize((int)size[0], (int)size[1]);
  vtkNew<vtkChartXY> chart;
  view->GetScene()->AddItem(chart);
  chart->SetShowLegend(true);
  char title[160];
  if (back)
    std::snprintf(title, sizeof title, "energy in the back hemisphere (Narasimhan et al. Fig. 3; I0 = 1, c_m = 1), albedo %.2f",
                  m.albedo);
  else
    std::snprintf(title, sizeof title, "Narasimhan et al. eq. 27 (the series alone), %s, relative to forward",
                  med.label.c_str());
  chart->SetTitle(title);
  chart->GetAxis(vtkAxis::LEFT)->SetTitle(back ? "2 pi int_{-1}^{0} I dmu" : "PSF / PSF(0)");
  chart->GetAxis(vtkAxis::LEFT)->SetLogScale(true);
  chart->GetAxis(vtkAxis::BOTTOM)->SetTitle(back ? "optical thickness T" : "angle from the source (degrees)");
  chart->GetAxis(vtkAxis::BOTTOM)->SetRange(back ? 1.0 : 0.0, back ? 10.0 : 180.0);
  chart->GetAxis(vtkAxis::BOTTOM)->SetBehavior(vtkAxis::FIXED);
  for (size_t k = 0; k < n_curves; ++k) {
    vtkPlot *line = chart->AddPlot(vtkChart::LINE);
    line->SetInputData(table, 0, (vtkIdType)k + 1);
    line->SetColor(kColour[k][0], kColour[k][1], kColour[k][2], 255);
    line->SetWidth(1.5);
  }
  const std::string out = o.str("out");
  std::string png_error;
  if (!sl::write_window_png(view->GetRenderWindow(), out, &png_error)) return sl::fail(kCmd, png_error);
  std::printf("wrote %s\n", out.c_str());
  return 0;
}

}  // namespace

int sl_cmd_apsf(int argc, char **argv)
{
  sl::Options o(kCmd, "--T T --q Q [--albedo W0] [--angles A,B,...] [--tolerance E] [--json] | --plot --out FILE.png",
                "The light field of an isotropic point source in a homogeneous medium at optical distance T\n"
                "(Narasimhan, Ramamoorthi and Nayar, eq. 27) against the angle from the source direction, for a\n"
                "Henyey-Greenstein medium of parameter q and single-scattering albedo W0 (or, with --particle, the\n"
                "phase moments and albedo of render/optics' particle tables). Below T = 1.05 the series\n"
                "diverges and single scattering plus the attenuated direct beam is used; up to T = 1.5 the two are\n"
                "blended (docs/APSF.md). With --plot, PSFs for T from 1.02 to 6 drawn with VTK's charts.");
  o.option("T", "T", "optical thickness sigma * R between source and observer (> 0)");
  o.option("q", "Q", "Henyey-Greenstein forward-scattering parameter, (-1, 1)", "0.9");
  o.option("albedo", "W0", "single-scattering albedo, (0, 1]", "1");
  o.option("particle", "NAME", "instead of --q/--albedo: the render/optics table of cloud, rain, ice or snow");
  o.option("wavelength", "NM", "with --particle: the wavelength of the table", "515");
  o.option("angles", "A,B,...", "angles from the source direction in degrees", "0,1,2,5,10,20,30,45,60,90,120,150,180");
  o.option("tolerance", "E", "series truncation error as a fraction of the forward value", "1e-6");
  o.flag("json", "print one JSON object");
  o.flag("plot", "draw PSFs for the paper's range of T with VTK's charts (needs --out)");
  o.option("out", "FILE.png", "with --plot: the image to write");
  o.option("size", "W,H", "with --plot: image size in pixels", "1000,650");
  o.option("figure", "psf|back", "with --plot: PSFs for T 1.02..6 (Figs. 2, 4) or the back-hemisphere energy against T "
           "for q 0.5..0.95 (Fig. 3)", "psf");
  const int early = sl::parse_or_exit(o, argc, argv);
  if (early >= 0) return early;
  if (o.has("plot")) return plot(o);
  if (!o.has("T")) return sl::fail(kCmd, "missing --T (optical thickness)", 2);
  double T, tolerance;
  std::vector<double> angles;
  Medium med;
  std::string why;
  if (!o.number("T", &T) || !o.list("angles", &angles)) return sl::fail(kCmd, o.error(), 2);
  if (!(T > 0.0 && std::isfinite(T))) return sl::fail(kCmd, "--T must be > 0", 2);
  for (double a : angles)
    if (!(a >= 0.0 && a <= 180.0)) return sl::fail(kCmd, "--angles must lie in 0..180 degrees", 2);
  if (!read_medium(o, &med, &tolerance, &why)) return sl::fail(kCmd, why, 2);
  const sl_apsf_medium &m = med.m;
  Psf psf;
  if (!evaluate(m, T, tolerance, angles, &psf, &why)) return sl::fail(kCmd, why, 2);
  std::vector<double> relative(angles.size());
  for (size_t i = 0; i < angles.size(); ++i) relative[i] = psf.forward > 0 ? psf.weight[i] / psf.forward : 0.0;
  const char *regime = psf.blend >= 1.0 ? "series" : (psf.blend <= 0.0 ? "single scattering" : "blend");
  if (o.has("json")) {
    cJSON *root = cJSON_CreateObject();
    cJSON_AddNumberToObject(root, "T", T);
    cJSON_AddNumberToObject(root, "q", m.q);
    cJSON_AddNumberToObject(root, "albedo", m.albedo);
    cJSON_AddNumberToObject(root, "terms", psf.terms);
    cJSON_AddStringToObject(root, "medium", med.label.c_str());
    cJSON_AddNumberToObject(root, "tolerance", tolerance);
    cJSON_AddStringToObject(root, "regime", regime);
    cJSON_AddItemToObject(root, "angles_deg", cJSON_CreateDoubleArray(angles.data(), (int)angles.size()));
    cJSON_AddItemToObject(root, "psf", cJSON_CreateDoubleArray(relative.data(), (int)relative.size()));
    cJSON_AddNumberToObject(root, "psf_reference_deg", psf.blend >= 1.0 ? 0.0 : kReferenceDeg);
    cJSON_AddItemToObject(root, "fluence_weight", cJSON_CreateDoubleArray(psf.weight.data(), (int)psf.weight.size()));
    cJSON_AddNumberToObject(root, "direct", psf.direct);
    if (psf.back_fraction >= 0) cJSON_AddNumberToObject(root, "back_hemisphere_fraction", psf.back_fraction);
    cJSON_AddStringToObject(root, "normalisation", kNormalisation);
    char *text = cJSON_PrintUnformatted(root);
    std::printf("%s\n", text);
    std::free(text);
    cJSON_Delete(root);
  } else {
    std::printf("T %.6g  %s  %s, %d terms (tolerance %g); psf relative to %g degrees\n", T, med.label.c_str(), regime,
                psf.terms, tolerance, psf.blend >= 1.0 ? 0.0 : kReferenceDeg);
    if (psf.direct > 0) std::printf("unscattered Dirac at the source: weight %.6g\n", psf.direct);
    for (size_t i = 0; i < angles.size(); ++i)
      std::printf("  %7.2f deg  psf %.9g  fluence weight %.9g /sr\n", angles[i], relative[i], psf.weight[i]);
  }
  return 0;
}
