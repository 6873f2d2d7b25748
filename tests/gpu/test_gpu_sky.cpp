// The sky's per-sample light (render/sky/sky_sample_shared.h: Riley et al. 2004 eqs. 1, 9-15,
// corrected) is one text for the CPU and the GPU:
// 1. the text the shaders embed is the file's, byte for byte;
// 2. compiled as GLSL it gives the C results (double) on a spread of rays to float accuracy:
//    flat and round earth, rays up, down and horizontal, finite and infinite segments, day and
//    night (infinite air mass), the series branch of exprel and the closed form, and the pieces
//    sl_sky_view_segment is made of (the ray's geometry, one wavelength's light and transparency)
//    and those of the sun's disk (solid angle, the in-disk test, the disk's radiance).
// Needs an X display (xvfb-run).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "case_shader.h"
#include "sl_shaders.h"
extern "C" {
#include "sl_sky_sample.h"
}

namespace {

int failures = 0;

struct Lcg {
  unsigned long long s = 0x2545f4914f6cdd1dull;
  double next()
  {
    s = s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(s >> 11) / 9007199254740992.0;
  }
};

// Float accuracy of the GLSL against the double C: relative rel, or absolute abs_tol; infinities
// must agree.
bool agrees(double gpu, double cpu, double rel, double abs_tol)
{
  if (std::isinf(cpu) || std::isinf(gpu)) return std::isinf(cpu) && std::isinf(gpu) && (cpu > 0) == (gpu > 0);
  return std::isfinite(gpu) && std::fabs(gpu - cpu) <= rel * std::fabs(cpu) + abs_tol;
}

const char *kShader = R"GLSL(//VTK::System::Dec
//SL::Sky
uniform sampler2D cases; // texel (i, 0): x, z_eye, mu, distance; (i, 1): airmass, cos, ground radius, beta
in vec2 texCoord;
//VTK::Output::Dec
void main()
{
  if (texCoord.x < -1.0) discard;
  int i = int(gl_FragCoord.x);
  vec4 a = texelFetch(cases, ivec2(i, 0), 0), b = texelFetch(cases, ivec2(i, 1), 0);
  float gamma = 1.0 / 8000.0;
  float near_length = min(a.w, 1.0e5);
  gl_FragData[0] = vec4(sl_sky_exprel(a.x), sl_sky_rayleigh_phase(b.y),
                        sl_sky_optical_depth(b.w, gamma, a.y, a.y + a.z * near_length, near_length),
                        sl_sky_sun_optical_depth(b.w, gamma, a.y, b.x));
  gl_FragData[1] = vec4(sl_sky_ground_distance(a.y, a.z, b.z), sl_sky_segment_length(a.y, a.z, a.w, b.z),
                        sl_sky_segment_length_factor(gamma, a.z, sl_sky_segment_length(a.y, a.z, a.w, b.z)),
                        sl_sky_inscatter(b.w, gamma, a.y, a.z, sl_sky_segment_length(a.y, a.z, a.w, b.z), b.x, b.y));
  float end = sl_sky_segment_length(a.y, a.z, a.w, b.z), near = 0.5 * min(end, 3000.0);
  float g[5];
  sl_sky_segment_geometry(gamma, a.y, a.z, near, end, g);
  gl_FragData[2] = vec4(sl_sky_path_length_factor(gamma, a.z * 1000.0, 1000.0),
                        sl_sky_segment_radiance(b.w, 1.0, sl_sky_rayleigh_phase(b.y), gamma, a.z, near, b.x, g),
                        sl_sky_segment_transparency(b.w, g), g[3]);
  gl_FragData[3] = vec4(sl_sun_disk_solid_angle(), float(sl_sky_in_sun_disk_at(a.x * 1.0e-3, a.z * 2.0e-3, 0.0, b.y)),
                        sl_sky_sun_disk_light(1.0, b.w, gamma, a.y, b.x), 1.0);
}
)GLSL";

}  // namespace

int main(int argc, char **argv)
{
  if (argc != 2) {
    std::fprintf(stderr, "usage: test_gpu_sky SOURCE_DIR\n");
    return 2;
  }
  if (!sl_test::embedded_text_is_file(argv[1], "render/sky/sky_sample_shared.h", sl_shader_sky_sample_shared)) return 1;
  const double inf = std::numeric_limits<double>::infinity();
  const int count = 512;
  std::vector<float> cases(count * 2 * 4, 0.0f);
  Lcg rng;
  for (int i = 0; i < count; ++i) {
    float *a = &cases[4 * i], *b = &cases[4 * (count + i)];
    const double u = rng.next();
    a[0] = (float)(i % 4 == 0 ? 0.1 * (u - 0.5) : 8.0 * (u - 0.5));                   // exprel's argument
    a[1] = (float)(i % 9 == 0 ? 0.0 : 2.0e4 * rng.next());                            // eye height, m
    a[2] = (float)(i % 11 == 0 ? 0.0 : 2.0 * rng.next() - 1.0);                       // mu
    a[3] = (float)(i % 5 == 0 ? inf : std::pow(10.0, 5.3 * rng.next()));              // distance, m
    b[0] = (float)(i % 7 == 0 ? inf : 1.0 / std::max(0.025, rng.next()));             // air mass
    b[1] = (float)(2.0 * rng.next() - 1.0);                                           // cos(view, sun)
    b[2] = (float)(i % 2 ? 6.371e6 : 0.0);                                            // ground radius
    b[3] = (float)(5.0e-6 + 3.0e-5 * rng.next());                                     // beta at sea level
  }
  std::string shader = kShader, why;
  shader.replace(shader.find("//SL::Sky"), 9, sl::gpu_sky_prelude());  // as the resolve compiles it
  sl_test::CaseShader gpu;
  if (!gpu.init(count, cases, shader, 4, &why)) {
    std::fprintf(stderr, "FAIL %s\n", why.c_str());
    return 1;
  }
  gpu.program()->SetUniformf("slInfinity", std::numeric_limits<float>::infinity());
  std::vector<float> out[4];
  gpu.run(out);
  const int nf = 15;
  const char *names[nf] = {"exprel", "Rayleigh phase", "optical depth", "sun optical depth", "ground distance",
                           "segment length", "segment length factor", "in-scattering", "path length factor",
                           "view-segment light", "view-segment transparency", "view-segment length factor",
                           "sun disk solid angle", "in the sun's disk", "sun disk radiance"};
  double worst[nf] = {0};
  int infinite = 0, series = 0, night = 0, lit = 0, in_disk = 0;
  const double gamma = 1.0 / 8000.0;
  for (int i = 0; i < count; ++i) {
    // The C side takes the same float inputs the GPU read.
    const float *a = &cases[4 * i], *b = &cases[4 * (count + i)];
    const double near_length = std::min((double)a[3], 1.0e5);
    const double segment = sl_sky_segment_length(a[1], a[2], a[3], b[2]);
    double cpu[nf] = {sl_sky_exprel(a[0]),
                           sl_sky_rayleigh_phase(b[1]),
                           sl_sky_optical_depth(b[3], gamma, a[1], a[1] + a[2] * near_length, near_length),
                           sl_sky_sun_optical_depth(b[3], gamma, a[1], b[0]),
                           sl_sky_ground_distance(a[1], a[2], b[2]),
                           segment,
                           sl_sky_segment_length_factor(gamma, a[2], segment),
                           sl_sky_inscatter(b[3], gamma, a[1], a[2], segment, b[0], b[1]),
                           sl_sky_path_length_factor(gamma, a[2] * 1000.0, 1000.0), 0.0, 0.0, 0.0,
                           sl_sun_disk_solid_angle(),
                           (double)sl_sky_in_sun_disk_at(a[0] * 1.0e-3f, a[2] * 2.0e-3f, 0.0, b[1]),
                           sl_sky_sun_disk_light(1.0, b[3], gamma, a[1], b[0])};
    // The view-segment pieces over [near, end], near halfway to 1.5 km or to the ground.
    const float end = (float)segment, near = 0.5f * std::min(end, 3000.0f);
    double g[5];
    sl_sky_segment_geometry(gamma, a[1], a[2], near, end, g);
    cpu[9] = sl_sky_segment_radiance(b[3], 1.0, sl_sky_rayleigh_phase(b[1]), gamma, a[2], near, b[0], g);
    cpu[10] = sl_sky_segment_transparency(b[3], g);
    cpu[11] = g[3];
    const double gpu[nf] = {out[0][4 * i], out[0][4 * i + 1], out[0][4 * i + 2], out[0][4 * i + 3],
                            out[1][4 * i], out[1][4 * i + 1], out[1][4 * i + 2], out[1][4 * i + 3],
                            out[2][4 * i], out[2][4 * i + 1], out[2][4 * i + 2], out[2][4 * i + 3],
                            out[3][4 * i], out[3][4 * i + 1], out[3][4 * i + 2]};
    for (int f = 0; f < nf; ++f) {
      // Float's own rounding through a few exponentials and a square root: 1e-5 relative (the
      // worst measured is 5e-6); absolute 1e-12 per unit irradiance for the in-scattering (a
      // night or empty ray is exactly 0), 1e-9 otherwise.
      const double rel = 1e-5, abs_tol = f == 7 || f == 9 ? 1e-12 : 1e-9;
      if (!agrees(gpu[f], cpu[f], rel, abs_tol)) {
        if (++failures <= 20)
          std::fprintf(stderr, "FAIL %s case %d: GPU %.9g, C %.9g (z %g, mu %g, distance %g, air mass %g, R %g)\n",
                       names[f], i, gpu[f], cpu[f], a[1], a[2], a[3], b[0], b[2]);
      } else if (std::isfinite(cpu[f]) && cpu[f] != 0.0) {
        worst[f] = std::max(worst[f], std::fabs(gpu[f] - cpu[f]) / std::fabs(cpu[f]));
      }
    }
    infinite += std::isinf(cpu[4]);
    series += std::fabs(a[0]) < 0.05;
    night += std::isinf(b[0]);
    lit += cpu[7] > 0.0;
    in_disk += cpu[13] > 0.0;
  }
  for (int f = 0; f < nf; ++f) std::printf("%-26s worst relative difference %.2e\n", names[f], worst[f]);
  std::printf("%d cases: %d rays missing the ground, %d in exprel's series, %d at night, %d lit, %d in the sun's disk\n",
              count, infinite, series, night, lit, in_disk);
  if (infinite < 20 || series < 20 || night < 20 || lit < 100 || in_disk < 20 || in_disk > count - 20) {
    std::fprintf(stderr, "FAIL the cases do not reach every branch\n");
    ++failures;
  }
  std::printf("%s\n", failures ? "FAILED" : "passed");
  return failures ? 1 : 0;
}
