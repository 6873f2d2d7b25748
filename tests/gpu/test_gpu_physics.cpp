// The GPU and the CPU evaluate the same per-sample physics (render/volume/sl_sample_physics.h):
// 1. the text the shaders embed is the header's text, byte for byte;
// 2. the shared functions compiled as GLSL (with the model in float textures and uniforms, as
//    the GPU pass holds it) give the C results on a spread of inputs: the light fraction of
//    eqs. 24 and 25 and of the low-albedo model, the expected scattering count (eq. 21), the
//    eye gather's Ams_{n+1} + xi term (eq. 26), the segment moments, which are checked against a
//    Simpson quadrature of their defining integrals, and the scattering angle's table row and
//    weight (sl_angle_grid_position), checked against the angle the case was drawn with, down to
//    a thousandth of a degree from 0 and 180 degrees.
// Needs an X display (xvfb-run); particle tables come from the optics cache.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "case_shader.h"
#include "sl_shaders.h"
extern "C" {
#include "renderer_internal.h"
#include "sl_sample_physics.h"
}

namespace {

using sl_test::check;
using sl_test::close;
using sl_test::Lcg;

const char *kShader = R"GLSL(//VTK::System::Dec
//SL::Physics
uniform sampler2D cases; // texel (i, 0): beta0, beta1, n, len; (i, 1): angle u, rate, sin, cos
uniform float angleInvStep;
in vec2 texCoord;
//VTK::Output::Dec
void main()
{
  if (texCoord.x < -1.0) discard;
  int i = int(gl_FragCoord.x);
  vec4 a = texelFetch(cases, ivec2(i, 0), 0), b = texelFetch(cases, ivec2(i, 1), 0);
  float beta[SL_MAX_FIELDS];
  for (int j = 0; j < SL_MAX_FIELDS; ++j) beta[j] = 0.0;
  beta[0] = a.x;
  beta[1] = a.y;
  float fraction[SL_MAX_WAVELENGTHS], phase[SL_MAX_WAVELENGTHS], moments[2];
  sl_light_fraction_at(beta, a.z, a.w, fraction);
  int index = int(b.x);
  sl_eye_phase_at(beta, a.z, index, b.x - float(index), phase);
  sl_segment_scatter_moments(a.x + a.y, a.w, b.y, moments);
  gl_FragData[0] = vec4(fraction[0], fraction[1], fraction[2], sl_expected_scatter_count(beta, a.z, a.w));
  gl_FragData[1] = vec4(phase[0], phase[1], phase[2], moments[0]);
  float u = sl_angle_grid_position(b.z, b.w, angleInvStep);
  int row = sl_angle_row(u, SL_ANGLE_ROWS);
  gl_FragData[2] = vec4(moments[1], u, float(row), sl_angle_weight(u, row));
}
)GLSL";

}  // namespace

// The segment moments by composite Simpson quadrature of their defining integrals (an outside
// check of sl_segment_scatter_moments' closed forms and Taylor series, which the GLSL and the CPU
// both run): m0 = beta int_0^len exp(-beta rate u) du, m1 = (beta / len) int_0^len u exp(...) du.
static void segment_moments_by_quadrature(double beta, double len, double rate, double m[2])
{
  const int n = 4000;
  const double h = len / n;
  m[0] = m[1] = 0.0;
  for (int k = 0; k <= n; ++k) {
    const double u = k * h, w = (k == 0 || k == n) ? 1.0 : (k % 2 ? 4.0 : 2.0);
    const double f = std::exp(-beta * rate * u);
    m[0] += w * f;
    m[1] += w * u * f;
  }
  m[0] *= beta * h / 3.0;
  m[1] *= beta / len * h / 3.0;
}

int main(int argc, char **argv)
{
  if (argc != 2) {
    std::fprintf(stderr, "usage: test_gpu_physics SOURCE_DIR\n");
    return 2;
  }
  // 1. The embedded text is the header.
  if (!sl_test::embedded_text_is_file(argv[1], "render/volume/sl_sample_physics.h", sl_shader_sl_sample_physics))
    return 1;
  std::string why;
  // 2. A model with two fields (cloud and rain) and real tables.
  sl_optics_request req;
  sl_optics_request_defaults(&req);
  req.particles = (1u << SL_CLOUD) | (1u << SL_RAIN);
  sl_error err{};
  sl_optics_tables *optics = sl_optics_build(&req, &err);
  if (!optics) {
    std::fprintf(stderr, "FAIL optics: %s\n", err.message);
    return 1;
  }
  float dummy = 1.0f;
  sl_volume volume{};
  volume.eta[SL_CLOUD] = volume.eta[SL_RAIN] = &dummy;
  sl_scene scene{};
  scene.volume = &volume;
  scene.optics = optics;
  scene.lighting = SL_LIGHTING_MULTIPLE;
  scene.xi = 0.01;
  sl_light_model m;
  if (sl_light_model_init(&m, &scene, &err) || m.nf != 2) {
    std::fprintf(stderr, "FAIL model: %s\n", err.message);
    return 1;
  }
  int max_n = 0;
  for (int j = 0; j < 2; ++j)
    for (int c = 0; c < 3; ++c) max_n = std::max(max_n, m.max_order[j][c]);
  const int angles = m.table[0][0]->n_angles;
  const int count = 256;
  std::vector<float> cases(count * 2 * 4, 0.0f);
  std::vector<double> theta(count);
  Lcg rng;
  for (int i = 0; i < count; ++i) {
    float *a = &cases[4 * i], *b = &cases[4 * (count + i)];
    a[0] = (float)std::pow(10.0, -5.0 + 4.0 * rng.next());            // cloud extinction, m^-1
    a[1] = i % 3 == 0 ? 0.0f : (float)std::pow(10.0, -6.0 + 3.0 * rng.next()); // rain, sometimes none
    a[2] = (float)(1.5 * max_n * rng.next());                           // n, past the tables' N too
    a[3] = (float)std::pow(10.0, 3.3 * rng.next());                     // path, 1 m .. 2 km
    b[0] = (float)((angles - 1.001) * rng.next());                      // angle grid position
    b[1] = (float)(-2.0 + 5.0 * rng.next());                            // moments' rate
    // A scattering angle, every eighth within 0.001-0.01 degrees of 0 or 180 (where acos fails).
    const double near = (1e-3 + 9e-3 * rng.next()) * M_PI / 180.0;
    theta[i] = i % 8 == 0 ? near : i % 8 == 1 ? M_PI - near : M_PI * rng.next();
    b[2] = (float)std::sin(theta[i]), b[3] = (float)std::cos(theta[i]);
  }
  std::string shader = kShader;
  shader.replace(shader.find("//SL::Physics"), 13,
                 sl::gpu_physics_prelude() + "#define SL_ANGLE_ROWS " + std::to_string(angles) + "\n");
  sl_test::CaseShader gpu;
  if (!gpu.init(count, cases, shader, 3, &why)) {
    std::fprintf(stderr, "FAIL %s (run under xvfb-run)\n", why.c_str());
    return 1;
  }
  sl::GpuModelTextures model;
  if (!model.Upload(gpu.window(), &m, &why)) {
    std::fprintf(stderr, "FAIL %s\n", why.c_str());
    return 1;
  }
  const sl_lighting modes[3] = {SL_LIGHTING_MULTIPLE, SL_LIGHTING_MULTIPLE_EQ25, SL_LIGHTING_LOW_ALBEDO};
  const char *names[3] = {"eq. 24", "eq. 25", "low albedo"};
  int taylor = 0, closed = 0, past_n = 0;
  for (int mode = 0; mode < 3; ++mode) {
    m.mode = modes[mode];
    model.Activate();
    model.SetUniforms(gpu.program());
    gpu.program()->SetUniformf("angleInvStep", (float)m.table[0][0]->inv_step_rad);
    std::vector<float> out[3];
    gpu.run(out);
    model.Deactivate();
    double worst_fraction = 0.0, worst_phase = 0.0, worst_moments = 0.0;
    for (int i = 0; i < count; ++i) {
      const float *a = &cases[4 * i], *b = &cases[4 * (count + i)];
      const float beta[SL_MAX_FIELDS] = {a[0], a[1], 0.0f, 0.0f};
      double fraction[SL_MAX_WAVELENGTHS], phase[SL_MAX_WAVELENGTHS], moments[2];
      sl_light_fraction(&m, beta, a[2], a[3], fraction);
      const int index = (int)b[0];
      sl_eye_phase(&m, beta, a[2], index, b[0] - index, phase);
      const double total = (double)a[0] + a[1];
      segment_moments_by_quadrature(total, a[3], b[1], moments);
      const double count_after = a[2] + (m.albedo_mean[0] * a[0] + m.albedo_mean[1] * a[1]) * a[3];
      for (int c = 0; c < 3; ++c) {
        const double g = out[0][4 * i + c], p = out[1][4 * i + c];
        check(close(g, fraction[c], 2e-4, 1e-6), names[mode], i, g, fraction[c]);
        check(close(p, phase[c], 2e-4, 1e-12), "eye phase", i, p, phase[c]);
        worst_fraction = std::max(worst_fraction, std::fabs(g - fraction[c]));
        worst_phase = std::max(worst_phase, std::fabs(p - phase[c]) / std::fabs(phase[c]));
      }
      check(close(out[0][4 * i + 3], count_after, 1e-5, 1e-6), "expected count", i, out[0][4 * i + 3], count_after);
      const double gm[2] = {out[1][4 * i + 3], out[2][4 * i]};
      for (int k = 0; k < 2; ++k) {
        check(close(gm[k], moments[k], 1e-4, 1e-7 * total * a[3]), "segment moment", i, gm[k], moments[k]);
        worst_moments = std::max(worst_moments, std::fabs(gm[k] - moments[k]) / std::fabs(moments[k]));
      }
      // The angle: the C function at the case's float sine and cosine, and the angle drawn.
      const double inv_step = m.table[0][0]->inv_step_rad, u = sl_angle_grid_position(b[2], b[3], inv_step);
      const int row = sl_angle_row(u, angles);
      check(close(u, theta[i] * inv_step, 1e-6, 1e-5), "angle position (C)", i, u, theta[i] * inv_step);
      // GLSL does not bound atan's error; Mesa's llvmpipe is within 2e-5 of it (0.004 degrees at 180).
      check(close(out[2][4 * i + 1], u, 1e-4, 1e-4), "angle position", i, out[2][4 * i + 1], u);
      check(std::fabs(out[2][4 * i + 2] - row) <= (std::fabs(u - std::round(u)) < 0.05 ? 1.0 : 0.0), "angle row", i,
            out[2][4 * i + 2], row);
      check(row <= angles - 2 && close(sl_angle_weight(u, row), u - row > 1.0 ? 1.0 : u - row, 0, 1e-12),
            "angle weight (C)", i, sl_angle_weight(u, row), u - row);
      if (mode == 0) {
        std::fabs(total * b[1] * a[3]) < 0.25 ? ++taylor : ++closed;
        past_n += a[2] + 1.0 > max_n;
      }
    }
    std::printf("%-10s: %d cases, worst |fraction difference| %.2e, worst relative eye-phase difference %.2e, "
                "worst relative moment difference %.2e\n",
                names[mode], count, worst_fraction, worst_phase, worst_moments);
  }
  std::printf("cases in the moments' series branch %d, closed form %d; n past the tables' last order %d\n", taylor,
              closed, past_n);
  if (taylor < 10 || closed < 10 || past_n < 10) {
    std::fprintf(stderr, "FAIL the cases do not reach every branch\n");
    ++sl_test::failures();
  }
  model.Release(gpu.window());
  sl_light_model_free(&m);
  sl_optics_free(optics);
  std::printf("%s\n", sl_test::failures() ? "FAILED" : "passed");
  return sl_test::failures() ? 1 : 0;
}
