// The step functions the CPU and the GPU pass share (render/volume/sl_sample_physics.h and
// render/core/sl_guards.h, embedded byte for byte): the eye march's step length, opacity and the
// light one step gathers; the sweep's footprint test and fresh-light weight; the resolve's split,
// layer and depth; the cosine clamp and the guarded square root. Each is checked in C against what
// it must satisfy from outside (its defining integral by quadrature, its limits and symmetries),
// and the GLSL copy against the C on the same inputs. Needs an X display (xvfb-run).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "case_shader.h"
#include "sl_shaders.h"
extern "C" {
#include "sl_guards.h"
#include "sl_sample_physics.h"
}

namespace {

using sl_test::check;
using sl_test::close;

// The plane (n1 x n2 samples), the lattice's spacing and the march's samples per cell.
const double kN1 = 5, kN2 = 3, kSpacing[3] = {250.0, 400.0, 100.0}, kSamples = 2;

const char *kShader = R"GLSL(//VTK::System::Dec
//SL::Physics
uniform sampler2D cases; // texel (i, 0): u, w, beta, dt; (i, 1): l0, l1, phase, c
uniform vec3 spacing;
uniform float n1, n2, samples;
in vec2 texCoord;
//VTK::Output::Dec
void main()
{
  if (texCoord.x < -1.0) discard;
  int i = int(gl_FragCoord.x);
  vec4 a = texelFetch(cases, ivec2(i, 0), 0), b = texelFetch(cases, ivec2(i, 1), 0);
  vec3 d = normalize(vec3(a.x, a.y, b.w));
  float opacity = sl_step_opacity(a.z, a.w);
  float moments[2];
  sl_segment_scatter_moments_exp(a.z, a.w, 1.0, 1.0 - opacity, moments);
  gl_FragData[0] = vec4(sl_sweep_in_plane(a.x, a.y, n1, n2) ? 1.0 : 0.0, sl_sweep_fresh_weight(a.x, a.y, n1, n2),
                        sl_march_max_step(spacing, d, samples), opacity);
  float t0 = 100.0 * b.x, t1 = t0 + 1000.0 * b.y;
  gl_FragData[1] = vec4(sl_march_step_light(b.x, b.y, moments[0], moments[1], b.z, 1.0 / a.z),
                        sl_resolve_split(b.w, a.w, t0, t1), sl_resolve_layer(b.x, b.y, b.z, 1.0 - b.y),
                        sl_resolve_depth(a.w * b.y, b.y * b.y, -1.0));
  gl_FragData[2] = vec4(sl_clamp_cosine(b.w), sl_safe_sqrt(b.w), moments[0], moments[1]);
}
)GLSL";

// The light a step of length dt through extinction beta sends toward the eye per unit sunlight,
// from its definition: (phase / beta) int_0^dt beta exp(-beta s) l(s) ds with l linear from l0 to
// l1, by composite Simpson quadrature.
double step_light_by_quadrature(double beta, double dt, double l0, double l1, double phase)
{
  const int n = 20000;
  const double h = dt / n;
  double sum = 0.0;
  for (int k = 0; k <= n; ++k) {
    const double s = k * h, w = (k == 0 || k == n) ? 1.0 : (k % 2 ? 4.0 : 2.0);
    sum += w * beta * std::exp(-beta * s) * (l0 + (l1 - l0) * s / dt);
  }
  return phase / beta * sum * h / 3.0;
}

}  // namespace

int main(int argc, char **argv)
{
  if (argc != 2) {
    std::fprintf(stderr, "usage: test_gpu_steps SOURCE_DIR\n");
    return 2;
  }
  if (!sl_test::embedded_text_is_file(argv[1], "render/volume/sl_sample_physics.h", sl_shader_sl_sample_physics) ||
      !sl_test::embedded_text_is_file(argv[1], "render/core/sl_guards.h", sl_shader_sl_guards))
    return 1;
  const int count = 256;
  std::vector<float> cases(count * 2 * 4);
  sl_test::Lcg rng;
  for (int i = 0; i < count; ++i) {
    float *a = &cases[4 * i], *b = &cases[4 * (count + i)];
    a[0] = (float)(-1.0 + (kN1 + 1.0) * rng.next());  // u across the plane and half a sample beyond
    a[1] = (float)(-1.0 + (kN2 + 1.0) * rng.next());
    if (i == 0) a[0] = -0.5f, a[1] = 1.0f;             // on the face: all fresh light
    if (i == 1) a[0] = 2.0f, a[1] = (float)(kN2 - 0.5); // on the far face
    a[2] = (float)std::pow(10.0, -6.0 + 5.0 * rng.next());  // extinction, m^-1
    a[3] = (float)std::pow(10.0, 3.0 * rng.next());          // step, 1 m .. 1 km
    b[0] = (float)rng.next(), b[1] = (float)rng.next();      // light at the step's ends; coverage
    b[2] = (float)(1e-3 + rng.next());                       // the angular term
    b[3] = (float)(-1.02 + 2.04 * rng.next());               // a cosine a little beyond +-1 at times
    if (i % 16 == 2) b[1] = (float)(1e-5 * rng.next());      // nearly no coverage
  }
  // 1. The C functions against what they must satisfy.
  int fresh_inside = 0, fresh_edge = 0, clamped = 0, thin = 0;
  for (int i = 0; i < count; ++i) {
    const float *a = &cases[4 * i], *b = &cases[4 * (count + i)];
    const double u = a[0], w = a[1];
    const double fresh = sl_sweep_fresh_weight(u, w, kN1, kN2);
    const bool inside = u >= 0.0 && u <= kN1 - 1 && w >= 0.0 && w <= kN2 - 1;
    // No fresh light among the samples, all of it on the faces, none outside [0, 1], and the same
    // seen from the plane's other side (mirror symmetry).
    if (inside) check(fresh == 0.0, "fresh light between samples", i, fresh, 0.0), ++fresh_inside;
    if (i < 2) check(fresh == 1.0, "fresh light on the face", i, fresh, 1.0);
    check(fresh >= 0.0 && fresh <= 1.0, "fresh weight in [0, 1]", i, fresh, 0.5);
    const double mirrored = sl_sweep_fresh_weight(kN1 - 1 - u, kN2 - 1 - w, kN1, kN2);
    check(close(fresh, mirrored, 1e-12, 1e-12), "fresh weight mirrored", i, fresh, mirrored);
    fresh_edge += !inside && sl_sweep_in_plane(u, w, kN1, kN2);
    check(sl_sweep_in_plane(u, w, kN1, kN2) == (std::fabs(u - 0.5 * (kN1 - 1)) <= 0.5 * kN1 &&
                                                 std::fabs(w - 0.5 * (kN2 - 1)) <= 0.5 * kN2),
          "footprint", i, u, w);
    // The step: within 1/samples of a cell along every axis, and exactly that along one.
    double d[3] = {a[0], a[1], b[3]};
    const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (double &x : d) x /= len;
    const double dt = sl_march_max_step(kSpacing, d, kSamples);
    double binding = 0.0;
    for (int ax = 0; ax < 3; ++ax) binding = std::max(binding, std::fabs(d[ax]) * dt * kSamples / kSpacing[ax]);
    check(close(binding, 1.0, 1e-12, 0.0), "march step: a cell's share along the binding axis", i, binding, 1.0);
    // Opacity: the series where 1 - exp(-x) cancels, the plain form elsewhere.
    const double x = (double)a[2] * a[3], opacity = sl_step_opacity(a[2], a[3]);
    const double want = x < 1e-3 ? x * (1.0 - x / 2.0 * (1.0 - x / 3.0 * (1.0 - x / 4.0))) : 1.0 - std::exp(-x);
    check(close(opacity, want, 1e-12, 0.0), "opacity", i, opacity, want);
    thin += x < 1e-3;
    // The light one step gathers, against its integral.
    double m[2];
    sl_segment_scatter_moments_exp(a[2], a[3], 1.0, 1.0 - opacity, m);
    const double light = sl_march_step_light(b[0], b[1], m[0], m[1], b[2], 1.0 / a[2]);
    const double quad = step_light_by_quadrature(a[2], a[3], b[0], b[1], b[2]);
    check(close(light, quad, 1e-8, 1e-15), "step light vs quadrature", i, light, quad);
    // The split lies in the span, at the midplane where the midplane crosses it.
    const double t0 = 100.0 * b[0], t1 = t0 + 1000.0 * b[1], split = sl_resolve_split(b[3], a[3], t0, t1);
    check(split >= t0 && split <= t1, "split in the span", i, split, t0);
    const double at = (double)a[3] / b[3];
    if (at > t0 && at < t1) check(split == at, "split at the midplane", i, split, at);
    // A covering layer behind air of optical depth tau and source S: the slab's transfer
    // solution acc e^-tau + S (1 - e^-tau).
    const double tau = 3.0 * b[1], S = b[2], T = std::exp(-tau);
    const double layer = sl_resolve_layer(b[0], 1.0, S * (1.0 - T), T);
    check(close(layer, b[0] * T + S * (1.0 - T), 1e-14, 0.0), "layer through air", i, layer, b[0] * T + S * (1.0 - T));
    const double cov = (double)b[1] * b[1], depth = sl_resolve_depth(a[3] * b[1], cov, -1.0);
    check(cov > 1e-4 ? close(depth, a[3] * b[1] / cov, 1e-15, 0.0) : depth == -1.0, "depth", i, depth, cov);
    // Guards.
    const double c = sl_clamp_cosine(b[3]);
    check(c >= -1.0 && c <= 1.0 && (std::fabs(b[3]) > 1.0 || c == b[3]), "clamped cosine", i, c, b[3]);
    clamped += std::fabs(b[3]) > 1.0;
    const double r = sl_safe_sqrt(b[3]);
    check(b[3] > 0.0 ? r == std::sqrt((double)b[3]) : r == 0.0, "guarded square root", i, r, b[3]);
  }
  check(std::isnan(sl_clamp_cosine(NAN)), "a NaN cosine stays NaN", 0, sl_clamp_cosine(NAN), NAN);
  if (fresh_inside < 20 || fresh_edge < 20 || clamped < 3 || thin < 3) {
    std::fprintf(stderr, "FAIL the cases do not reach every branch (%d %d %d %d)\n", fresh_inside, fresh_edge, clamped,
                 thin);
    ++sl_test::failures();
  }
  // 2. The GLSL copies against the C on the same (float) inputs.
  std::string why, shader = kShader;
  shader.replace(shader.find("//SL::Physics"), 13, sl::gpu_physics_prelude());
  sl_test::CaseShader gpu;
  if (!gpu.init(count, cases, shader, 3, &why)) {
    std::fprintf(stderr, "FAIL %s (run under xvfb-run)\n", why.c_str());
    return 1;
  }
  const float spacing[3] = {(float)kSpacing[0], (float)kSpacing[1], (float)kSpacing[2]};
  gpu.program()->SetUniform3f("spacing", spacing);
  gpu.program()->SetUniformf("n1", (float)kN1);
  gpu.program()->SetUniformf("n2", (float)kN2);
  gpu.program()->SetUniformf("samples", (float)kSamples);
  std::vector<float> out[3];
  gpu.run(out);
  double worst[12] = {0};
  for (int i = 0; i < count; ++i) {
    const float *a = &cases[4 * i], *b = &cases[4 * (count + i)];
    double d[3] = {a[0], a[1], b[3]};
    const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (double &x : d) x /= len;
    const double opacity = sl_step_opacity(a[2], a[3]);
    double m[2];
    sl_segment_scatter_moments_exp(a[2], a[3], 1.0, 1.0 - opacity, m);
    const double t0 = 100.0 * b[0], t1 = t0 + 1000.0 * b[1];
    const double cpu[12] = {sl_sweep_in_plane(a[0], a[1], kN1, kN2) ? 1.0 : 0.0,
                            sl_sweep_fresh_weight(a[0], a[1], kN1, kN2),
                            sl_march_max_step(kSpacing, d, kSamples),
                            opacity,
                            sl_march_step_light(b[0], b[1], m[0], m[1], b[2], 1.0 / a[2]),
                            sl_resolve_split(b[3], a[3], t0, t1),
                            sl_resolve_layer(b[0], b[1], b[2], 1.0 - b[1]),
                            sl_resolve_depth((double)a[3] * b[1], (double)b[1] * b[1], -1.0),
                            sl_clamp_cosine(b[3]),
                            sl_safe_sqrt(b[3]),
                            m[0],
                            m[1]};
    const char *names[12] = {"footprint", "fresh weight", "march step", "opacity", "step light", "split",
                             "layer", "depth", "clamped cosine", "guarded sqrt", "moment 0", "moment 1"};
    for (int k = 0; k < 12; ++k) {
      const double g = out[k / 4][4 * i + k % 4];
      // float against double: relative 1e-5; 1e-4 for the opacity (GLSL's expm1 is exp(x) - 1
      // from |x| = 1e-3 up) and for the moments and what they weight, as in test_gpu_physics.
      // A split or depth at a tiny cosine or coverage divides by a rounded small number and is
      // compared loosely.
      const double rel = k == 5 || k == 7 ? 2e-3 : k == 3 || k == 4 || k >= 10 ? 1e-4 : 1e-5;
      const bool ok = close(g, cpu[k], rel, k >= 10 ? 1e-7 : 1e-12);
      check(ok, names[k], i, g, cpu[k]);
      if (cpu[k] != 0.0) worst[k] = std::max(worst[k], std::fabs(g - cpu[k]) / std::fabs(cpu[k]));
    }
  }
  std::printf("%d cases: %d among the samples, %d between them and the faces, %d cosines beyond +-1, %d thin "
              "steps; worst relative GLSL - C difference:",
              count, fresh_inside, fresh_edge, clamped, thin);
  for (int k = 0; k < 12; ++k) std::printf(" %.1e", worst[k]);
  std::printf("\n");
  std::printf("%s\n", sl_test::failures() ? "FAILED" : "passed");
  return sl_test::failures() ? 1 : 0;
}
