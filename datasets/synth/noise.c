#include "sl_noise.h"

#include <math.h>

/* SplitMix64 finaliser (Steele, Lea & Flood 2014) as a lattice hash. */
static uint64_t mix64(uint64_t z)
{
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

static double lattice(uint64_t seed, int64_t i, int64_t j, int64_t k)
{
  uint64_t h = mix64(seed ^ mix64((uint64_t)i * 0x9E3779B97F4A7C15ULL ^ mix64((uint64_t)j + 0x632BE59BD9B4E019ULL) ^
                                  mix64((uint64_t)k * 0x85EBCA77C2B2AE63ULL)));
  return (double)(h >> 11) * (1.0 / 9007199254740992.0);
}

static double smooth(double t) { return t * t * (3.0 - 2.0 * t); }

double sl_value_noise(uint64_t seed, double x, double y, double z)
{
  const double fx = floor(x), fy = floor(y), fz = floor(z);
  const int64_t i = (int64_t)fx, j = (int64_t)fy, k = (int64_t)fz;
  const double u = smooth(x - fx), v = smooth(y - fy), w = smooth(z - fz);
  double c[2][2][2];
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      for (int d = 0; d < 2; ++d) c[a][b][d] = lattice(seed, i + a, j + b, k + d);
  const double x00 = c[0][0][0] + u * (c[1][0][0] - c[0][0][0]);
  const double x10 = c[0][1][0] + u * (c[1][1][0] - c[0][1][0]);
  const double x01 = c[0][0][1] + u * (c[1][0][1] - c[0][0][1]);
  const double x11 = c[0][1][1] + u * (c[1][1][1] - c[0][1][1]);
  const double y0 = x00 + v * (x10 - x00), y1 = x01 + v * (x11 - x01);
  return y0 + w * (y1 - y0);
}

double sl_fractal_noise(uint64_t seed, double x, double y, double z, int octaves)
{
  double sum = 0.0, amp = 0.5, norm = 0.0, f = 1.0;
  for (int o = 0; o < octaves; ++o) {
    sum += amp * sl_value_noise(seed + (uint64_t)o * 7919u, x * f, y * f, z * f);
    norm += amp;
    amp *= 0.5;
    f *= 2.0;
  }
  return sum / norm;
}
