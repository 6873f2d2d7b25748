#include "sl_synth.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sl_geo.h"
#include "sl_noise.h"
#include "sl_wrf_write.h"

/* Constants shared with the reader's conventions (WRF's): R_d, c_p = 3.5 R_d, g, p0, theta0. */
#define RD 287.0
#define CP (3.5 * RD)
#define G 9.81
#define P_SURFACE 101325.0
#define T_SURFACE 300.0   /* K: a warm-season boundary layer, freezing level near 4.2 km */
#define LAPSE 0.0065      /* K/m, up to the tropopause */
#define Z_TROPOPAUSE 12000.0

static const char *const KIND_NAMES[] = {"cumulonimbus", "cirrus", "stratocumulus", "cumulus"};
#define KIND_COUNT 4

int sl_synth_kind_from_name(const char *name)
{
  for (int k = 0; k < KIND_COUNT; ++k)
    if (strcmp(name, KIND_NAMES[k]) == 0) return k;
  return -1;
}

const char *sl_synth_kind_name(sl_synth_kind kind) { return (unsigned)kind < KIND_COUNT ? KIND_NAMES[kind] : "unknown"; }

void sl_synth_defaults(sl_synth_kind kind, sl_synth_options *o)
{
  memset(o, 0, sizeof *o);
  o->kind = kind;
  o->seed = 1;
  o->ntimes = 1;
  o->minutes_per_step = 10;
  switch (kind) {
  case SL_SYNTH_CUMULONIMBUS:
    o->nx = o->ny = 48, o->nz = 40, o->dx = 500.0, o->top = 16000.0;
    o->center_lat = 35.2, o->center_lon = -97.4; /* central Oklahoma, late afternoon local time */
    snprintf(o->start_time, sizeof o->start_time, "2024-06-15_22:00:00");
    break;
  case SL_SYNTH_CIRRUS:
    o->nx = o->ny = 48, o->nz = 24, o->dx = 1000.0, o->top = 14000.0;
    o->center_lat = 47.0, o->center_lon = 8.0;
    snprintf(o->start_time, sizeof o->start_time, "2024-04-10_10:00:00");
    break;
  case SL_SYNTH_CUMULUS:
    /* Small enough that the Monte Carlo reference converges in minutes (issue 7, item 6). */
    o->nx = o->ny = 32, o->nz = 24, o->dx = 125.0, o->top = 3000.0;
    o->center_lat = 35.2, o->center_lon = -97.4;
    snprintf(o->start_time, sizeof o->start_time, "2024-06-15_16:00:00");
    break;
  case SL_SYNTH_STRATOCUMULUS:
  default:
    o->nx = o->ny = 48, o->nz = 24, o->dx = 250.0, o->top = 3000.0;
    o->center_lat = 32.0, o->center_lon = -121.0; /* the subtropical eastern Pacific deck */
    snprintf(o->start_time, sizeof o->start_time, "2024-07-01_19:00:00");
    break;
  }
}

/* International Standard Atmosphere shape with a warmer surface: temperature and hydrostatic
 * pressure at height z (m). */
static void base_state(double z, double *temperature, double *pressure)
{
  const double t_trop = T_SURFACE - LAPSE * Z_TROPOPAUSE;
  if (z <= Z_TROPOPAUSE) {
    *temperature = T_SURFACE - LAPSE * z;
    *pressure = P_SURFACE * pow(*temperature / T_SURFACE, G / (RD * LAPSE));
  } else {
    const double p_trop = P_SURFACE * pow(t_trop / T_SURFACE, G / (RD * LAPSE));
    *temperature = t_trop;
    *pressure = p_trop * exp(-G * (z - Z_TROPOPAUSE) / (RD * t_trop));
  }
}

static double smoothstep(double e0, double e1, double x)
{
  double t = (x - e0) / (e1 - e0);
  t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
  return t * t * (3.0 - 2.0 * t);
}

/* Fraction of condensate that is liquid: all above 0 C, none below -40 C (homogeneous freezing). */
static double liquid_fraction(double temperature) { return smoothstep(233.15, 273.15, temperature); }

typedef struct hydrometeors {
  double cloud, rain, ice, snow;
} hydrometeors;

static hydrometeors cumulonimbus(uint64_t seed, double x, double y, double z, double temperature, double t)
{
  hydrometeors h = {0};
  const double km = 1.0 / 1000.0;
  /* Two octaves from 2.5 km: the finest detail stays above the grid's Nyquist length at 500 m. */
  const double n = sl_fractal_noise(seed, x * km / 2.5 + 0.3 * t, y * km / 2.5, z * km / 2.5, 2);
  /* Tower: cloud base 1.5 km, widening slightly with height, lumpy edge from the noise. */
  const double base = 1500.0, tower_top = 11500.0;
  const double radius = 3200.0 + 0.12 * (z - base) + 1800.0 * (n - 0.5);
  const double r = hypot(x + 500.0, y);
  const double tower = smoothstep(radius, radius * 0.55, r) * smoothstep(base, base + 400.0, z) *
                       smoothstep(tower_top, tower_top - 1500.0, z);
  const double fl = liquid_fraction(temperature);
  h.cloud = 2.2e-3 * tower * fl * (0.6 + 0.8 * n);
  h.ice = 8e-4 * tower * (1.0 - fl) * (0.6 + 0.8 * n);
  h.snow = 6e-4 * tower * (1.0 - fl) * smoothstep(0.3, 0.7, n);
  /* Anvil: spreading downwind (east) between 10 and 12.5 km. */
  const double ax = x - 3500.0, ar = hypot(ax * 0.8, y);
  const double anvil_radius = 9000.0 + 2500.0 * (n - 0.5);
  const double anvil = smoothstep(anvil_radius, anvil_radius * 0.75, ar) * smoothstep(9800.0, 10600.0, z) *
                       smoothstep(12600.0, 11800.0, z);
  h.ice += 3e-4 * anvil * (0.5 + n);
  h.snow += 4e-4 * anvil * smoothstep(0.35, 0.75, n) * smoothstep(11500.0, 10200.0, z);
  /* Rain shaft: from the melting level to the ground, offset up-shear of the tower's centre. */
  const double rs = hypot(x + 1500.0, y - 500.0);
  const double shaft_radius = 2300.0 + 600.0 * (n - 0.5);
  const double shaft = smoothstep(shaft_radius, shaft_radius * 0.6, rs) * smoothstep(4600.0, 3800.0, z);
  h.rain = 1.8e-3 * shaft * (0.7 + 0.6 * n);
  /* A lighter rain curtain on the south flank, falling from the anvil into sunlight: where a
   * viewer with the sun at their back sees the rainbow. */
  const double curtain = smoothstep(2600.0, 1400.0, hypot((x + 1500.0) * 0.6, y + 5200.0)) * smoothstep(4200.0, 3000.0, z);
  h.rain += 3e-4 * curtain * (0.8 + 0.4 * n);
  return h;
}

static hydrometeors cirrus(uint64_t seed, double x, double y, double z, double t)
{
  hydrometeors h = {0};
  const double km = 1.0 / 1000.0;
  /* Fall streaks: noise stretched along the wind (x). */
  const double n = sl_fractal_noise(seed, x * km / 12.0 + 0.2 * t, y * km / 2.5, z * km / 0.8, 4);
  const double deck = smoothstep(8800.0, 9600.0, z) * smoothstep(11200.0, 10400.0, z);
  const double edge = smoothstep(24000.0, 16000.0, hypot(x, y));
  h.ice = 1.6e-4 * deck * edge * smoothstep(0.42, 0.7, n);
  return h;
}

static hydrometeors stratocumulus(uint64_t seed, double x, double y, double z, double t)
{
  hydrometeors h = {0};
  const double km = 1.0 / 1000.0;
  const double cells = sl_fractal_noise(seed, x * km / 1.2 + 0.1 * t, y * km / 1.2, 0.0, 3);
  const double base = 750.0 + 120.0 * (0.5 - cells);
  const double top = 1150.0 + 40.0 * (cells - 0.5);
  const double in_layer = smoothstep(base - 30.0, base + 30.0, z) * smoothstep(top + 20.0, top - 20.0, z);
  const double cover = smoothstep(0.38, 0.55, cells);
  /* Adiabatic liquid water: rising linearly above cloud base. */
  const double adiabatic = (z - base) / (top - base);
  h.cloud = 5e-4 * in_layer * cover * (adiabatic > 0.0 ? adiabatic : 0.0) + 2e-5 * in_layer * cover;
  /* Light drizzle under the thickest cells. */
  h.rain = 2e-5 * smoothstep(0.62, 0.75, cells) * smoothstep(base + 50.0, base - 100.0, z) * smoothstep(0.0, 200.0, z);
  return h;
}

/* A thin, lumpy fair-weather cumulus (humilis) of moderate optical thickness: optical depths of
 * about 1-10 through it, the range where the Monte Carlo reference converges in minutes and
 * where thin and dense pixels both occur (issue 7's validation). Liquid only, well below the
 * freezing level; liquid water rises from the base as in an adiabatic parcel. */
static hydrometeors cumulus(uint64_t seed, double x, double y, double z, double t)
{
  hydrometeors h = {0};
  const double km = 1.0 / 1000.0;
  /* Two octaves from 0.8 km: above the 125 m grid's Nyquist length. */
  const double n = sl_fractal_noise(seed, x * km / 0.8 + 0.2 * t, y * km / 0.8, z * km / 0.8, 2);
  const double base = 1000.0, top = 2300.0 + 300.0 * (n - 0.5);
  /* A dome: the radius shrinks toward the top, the edge is lumpy. */
  const double height = (z - base) / (top - base);
  const double radius = (1150.0 + 350.0 * (n - 0.5)) * sqrt(fmax(0.0, 1.0 - height * height));
  if (!(radius > 1.0)) return h; /* above the top (smoothstep of an empty edge would be 1) */
  const double r = hypot(x, y + 150.0);
  const double inside = smoothstep(radius, 0.7 * radius, r) * smoothstep(base, base + 120.0, z);
  h.cloud = 7e-5 * inside * (0.15 + (height > 0.0 ? height : 0.0)) * (0.5 + n);
  return h;
}

/* Gentle terrain: a low ridge, so the reader's terrain-following path is exercised. */
static double terrain_height(const sl_synth_options *o, double x, double y)
{
  if (o->kind == SL_SYNTH_STRATOCUMULUS) return 0.0; /* over the ocean */
  if (o->kind == SL_SYNTH_CUMULUS) return 0.0;        /* a flat field: nothing but the cloud */
  const double half = 0.5 * o->nx * o->dx;
  return 250.0 * exp(-pow((x + 0.5 * half) / (0.3 * half), 2.0)) * (0.8 + 0.2 * cos(y / half * M_PI));
}

static int add_minutes(const char *start, int minutes, char out[20])
{
  struct tm tm = {0};
  if (sscanf(start, "%d-%d-%d_%d:%d:%d", &tm.tm_year, &tm.tm_mon, &tm.tm_mday, &tm.tm_hour, &tm.tm_min,
             &tm.tm_sec) != 6)
    return 1;
  tm.tm_year -= 1900;
  tm.tm_mon -= 1;
  tm.tm_min += minutes;
  time_t tt = timegm(&tm);
  struct tm u;
  gmtime_r(&tt, &u);
  char text[64];
  snprintf(text, sizeof text, "%04d-%02d-%02d_%02d:%02d:%02d", u.tm_year + 1900, u.tm_mon + 1, u.tm_mday,
           u.tm_hour, u.tm_min, u.tm_sec);
  if (strlen(text) != 19) return 1;
  memcpy(out, text, 20);
  return 0;
}

int sl_synth_write(const char *path, const sl_synth_options *o, sl_error *err)
{
  if (o->nx < 2 || o->ny < 2 || o->nz < 2 || o->nx > 2048 || o->ny > 2048 || o->nz > 512)
    return sl_fail(err, SL_ERR_ARG, "synthetic grid %dx%dx%d out of range (2..2048 horizontally, 2..512 levels)",
                   o->nx, o->ny, o->nz);
  if (o->ntimes < 1 || o->ntimes > 1000) return sl_fail(err, SL_ERR_ARG, "times %d out of range (1..1000)", o->ntimes);
  if (!(o->dx >= 10.0 && o->dx <= 100000.0)) return sl_fail(err, SL_ERR_ARG, "grid spacing %g m out of range", o->dx);
  const int nx = o->nx, ny = o->ny, nz = o->nz, nt = o->ntimes;
  const size_t n2 = (size_t)nx * ny, n3 = n2 * nz, n3s = n2 * (nz + 1);
  char (*times)[20] = calloc((size_t)nt, 20);
  float *buf = calloc(nt * (9 * n3 + 2 * n3s + 3 * n2), sizeof(float));
  if (!times || !buf) {
    free(times);
    free(buf);
    return sl_fail(err, SL_ERR_NOMEM, "out of memory for a %dx%dx%dx%d synthetic storm", nx, ny, nz, nt);
  }
  float *qc = buf, *qr = qc + nt * n3, *qi = qr + nt * n3, *qs = qi + nt * n3, *qv = qs + nt * n3;
  float *p = qv + nt * n3, *pb = p + nt * n3, *th = pb + nt * n3, *spare = th + nt * n3;
  float *ph = spare + nt * n3, *phb = ph + nt * n3s, *hgt = phb + nt * n3s, *lat = hgt + nt * n2,
        *lon = lat + nt * n2;
  sl_lambert proj;
  const double truelat1 = o->center_lat - 5.0, truelat2 = o->center_lat + 5.0;
  sl_lambert_init(&proj, truelat1, truelat2, o->center_lon, o->center_lat, o->center_lon);
  for (int t = 0; t < nt; ++t) {
    if (add_minutes(o->start_time, t * o->minutes_per_step, times[t])) {
      free(times);
      free(buf);
      return sl_fail(err, SL_ERR_ARG, "start time '%s' is not YYYY-MM-DD_hh:mm:ss", o->start_time);
    }
    const double phase = t * o->minutes_per_step / 10.0;
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const double x = (i - 0.5 * (nx - 1)) * o->dx, y = (j - 0.5 * (ny - 1)) * o->dx;
        const size_t c = (size_t)j * nx + i;
        const double ground = terrain_height(o, x, y);
        double la, lo;
        sl_lambert_reverse(&proj, x, y, &la, &lo);
        hgt[t * n2 + c] = (float)ground;
        lat[t * n2 + c] = (float)la;
        lon[t * n2 + c] = (float)lo;
        /* Terrain-following levels, finer near the ground: s -> (s + s^2) / 2. */
        for (int k = 0; k <= nz; ++k) {
          const double s = (double)k / nz;
          const double z = ground + (o->top - ground) * 0.5 * (s + s * s);
          phb[t * n3s + k * n2 + c] = (float)(G * z);
          ph[t * n3s + k * n2 + c] = 0.0f;
        }
        for (int k = 0; k < nz; ++k) {
          const double z = 0.5 * (phb[t * n3s + k * n2 + c] + phb[t * n3s + (k + 1) * n2 + c]) / G;
          double temperature, pressure;
          base_state(z, &temperature, &pressure);
          const size_t idx = t * n3 + k * n2 + c;
          pb[idx] = (float)pressure;
          p[idx] = 0.0f;
          th[idx] = (float)(temperature * pow(1.0e5 / pressure, RD / CP) - 300.0);
          qv[idx] = (float)(0.016 * exp(-z / 2500.0));
          hydrometeors h;
          if (o->kind == SL_SYNTH_CUMULONIMBUS) h = cumulonimbus(o->seed, x, y, z, temperature, phase);
          else if (o->kind == SL_SYNTH_CIRRUS) h = cirrus(o->seed, x, y, z, phase);
          else if (o->kind == SL_SYNTH_CUMULUS) h = cumulus(o->seed, x, y, z, phase);
          else h = stratocumulus(o->seed, x, y, z, phase);
          qc[idx] = (float)h.cloud;
          qr[idx] = (float)h.rain;
          qi[idx] = (float)h.ice;
          qs[idx] = (float)h.snow;
        }
      }
  }
  char title[128];
  snprintf(title, sizeof title, " OUTPUT FROM STORMLIGHT SYNTH: %s, seed %llu", sl_synth_kind_name(o->kind),
           (unsigned long long)o->seed);
  sl_wrf_fields f = {
      .nx = nx, .ny = ny, .nz = nz, .ntimes = nt, .dx = o->dx, .dy = o->dx, .map_proj = 1,
      .truelat1 = truelat1, .truelat2 = truelat2, .stand_lon = o->center_lon, .cen_lat = o->center_lat,
      .cen_lon = o->center_lon, .moad_cen_lat = o->center_lat,
      /* No scheme made these fields (they are prescribed): MP_PHYSICS 0, so the reader draws them with
       * Riley et al.'s representative particles, the model of the paper's figures, and sizes none. */
      .mp_physics = 0,
      .title = title, .times = (const char(*)[20])times, .qcloud = qc, .qrain = qr, .qice = qi, .qsnow = qs,
      .qvapor = qv, .p = p, .pb = pb, .t = th, .ph = ph, .phb = phb, .hgt = hgt, .xlat = lat, .xlong = lon};
  const int rc = sl_wrf_write(path, &f, err);
  free(times);
  free(buf);
  return rc;
}
