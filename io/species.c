/* Microphysics schemes and the mapping of their hydrometeor variables to Stormlight's particle
 * types (docs/DATA.md has the table). Mapping is by variable name, so a scheme this table does not
 * name still loads whatever of QCLOUD/QRAIN/QICE/QSNOW/QGRAUP/QHAIL it writes. */
#include <math.h>
#include <netcdf.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "storm_internal.h"

/* WRF's MP_PHYSICS options (WRF Users' Guide, namelist physics). split: the scheme has no ice (or
 * no separate ice and liquid), so its liquid names hold ice and snow below 0 C. */
static const struct {
  int code;
  const char *name;
  int split;
} SCHEMES[] = {
    {0, "none (passive)", 0},        {1, "Kessler (warm rain)", 1},  {2, "Purdue Lin", 0},
    {3, "WSM3 (simple ice)", 1},     {4, "WSM5", 0},                 {5, "Ferrier (Eta)", 0},
    {6, "WSM6", 0},                  {7, "Goddard", 0},              {8, "Thompson", 0},
    {9, "Milbrandt-Yau 2-moment", 0}, {10, "Morrison 2-moment", 0},  {11, "CAM 5.1", 0},
    {13, "SBU-YLin", 0},             {14, "WDM5", 0},                {16, "WDM6", 0},
    {17, "NSSL 2-moment", 0},        {18, "NSSL 2-moment with CCN", 0}, {19, "NSSL 1-moment 7-class", 0},
    {21, "NSSL 1-moment 6-class", 0}, {24, "WSM7", 0},               {26, "WDM7", 0},
    {28, "Thompson aerosol-aware", 0}, {50, "P3 1-ice", 0},          {51, "P3 1-ice, 2-moment cloud", 0},
    {52, "P3 2-ice", 0},             {53, "P3 1-ice 3-moment", 0},
};

/* The species every scheme's variables belong to. Representative particles of cloud, rain, ice
 * and snow are render/core's (Riley et al. 2004, Table 2); graupel and hail have no type of their
 * own and are drawn with snow's optics (large irregular ice in the geometric-optics limit: no
 * rainbow, no halo, Q_ext = 2) at their own extinction per unit mass: graupel 2 mm across at
 * 400 kg/m3, hail 1 cm at 900 kg/m3 (Pruppacher & Klett 2000, ch. 2; WSM6's graupel density is
 * 500, Thompson's 400, Milbrandt-Yau's hail 900). */
typedef struct species_def {
  const char *wrf, *wrf_number, *cm1, *standard_name, *ecmwf, *kind;
  int type;
  double radius_m, density_kg_m3; /* 0: the target type's own particle */
} species_def;

static const species_def SPECIES[] = {
    {"QCLOUD", "QNCLOUD", "qc", "mass_fraction_of_cloud_liquid_water_in_air", "clwc", "cloud water", SL_CLOUD, 0, 0},
    {"QRAIN", "QNRAIN", "qr", "mass_fraction_of_rain_in_air", "crwc", "rain", SL_RAIN, 0, 0},
    {"QICE", "QNICE", "qi", "mass_fraction_of_cloud_ice_in_air", "ciwc", "cloud ice", SL_ICE, 0, 0},
    {"QSNOW", "QNSNOW", "qs", "mass_fraction_of_snow_in_air", "cswc", "snow", SL_SNOW, 0, 0},
    {"QGRAUP", "QNGRAUPEL", "qg", "mass_fraction_of_graupel_in_air", NULL, "graupel", SL_SNOW, 1.0e-3, 400.0},
    {"QHAIL", "QNHAIL", "qhl", "mass_fraction_of_hail_in_air", NULL, "hail", SL_SNOW, 5.0e-3, 900.0},
};
#define NDEF (int)(sizeof SPECIES / sizeof SPECIES[0])

static void species_from_def(const species_def *d, const char *variable, sl_species *sp)
{
  memset(sp, 0, sizeof *sp);
  snprintf(sp->variable, sizeof sp->variable, "%s", variable);
  sp->warm = sp->cold = d->type;
  sp->kind = d->kind;
  const sl_particle_props *pp = sl_particle_properties((sl_particle)d->type);
  sp->radius_m = d->radius_m > 0 ? d->radius_m : pp->radius_m;
  sp->density_kg_m3 = d->density_kg_m3 > 0 ? d->density_kg_m3 : pp->density_kg_m3;
}

static int scheme_splits(int mp_physics)
{
  for (size_t i = 0; i < sizeof SCHEMES / sizeof SCHEMES[0]; ++i)
    if (SCHEMES[i].code == mp_physics) return SCHEMES[i].split;
  return 0;
}

void sl_species_wrf(const sl_nc *f, int mp_physics, sl_storm_info *info)
{
  const char *name = mp_physics < 0 ? "unknown (no MP_PHYSICS)" : "unknown to Stormlight (mapped by variable name)";
  for (size_t i = 0; i < sizeof SCHEMES / sizeof SCHEMES[0]; ++i)
    if (SCHEMES[i].code == mp_physics) name = SCHEMES[i].name;
  snprintf(info->scheme, sizeof info->scheme, "%s", name);
  const int split = scheme_splits(mp_physics);
  info->nspecies = 0;
  for (int d = 0; d < NDEF; ++d) {
    if (!sl_nc_has_var(f, SPECIES[d].wrf)) continue;
    sl_species *sp = &info->species[info->nspecies++];
    species_from_def(&SPECIES[d], SPECIES[d].wrf, sp);
    if (sl_nc_has_var(f, SPECIES[d].wrf_number))
      snprintf(sp->number_variable, sizeof sp->number_variable, "%s", SPECIES[d].wrf_number);
    /* Simple ice (WSM3) and warm rain (Kessler): cloud below 0 C is cloud ice, rain is snow. */
    if (split && SPECIES[d].type == SL_CLOUD) sp->cold = SL_ICE;
    if (split && SPECIES[d].type == SL_RAIN) sp->cold = SL_SNOW;
  }
}

/* CM1 names (qc, qr, ...) or CF standard names; used by cf_read.c. ECMWF's specific contents
 * (ERA5, IFS: clwc, crwc, ciwc, cswc, per kg of moist air) have no CF standard name; they are
 * taken by their short names where the variable claims no other (none, or cfgrib's "unknown"). */
int sl_species_cf_match(const char *var_name, const char *standard_name, int cm1, sl_species *sp)
{
  const int unnamed = !standard_name || !standard_name[0] || strcmp(standard_name, "unknown") == 0;
  for (int d = 0; d < NDEF; ++d) {
    const int hit = cm1 ? strcmp(var_name, SPECIES[d].cm1) == 0
                        : (standard_name && strcmp(standard_name, SPECIES[d].standard_name) == 0) ||
                              (unnamed && SPECIES[d].ecmwf && strcmp(var_name, SPECIES[d].ecmwf) == 0);
    if (!hit) continue;
    species_from_def(&SPECIES[d], var_name, sp);
    sp->per_moist_air = !cm1; /* CF mass fractions are per kg of (moist) air; CM1 writes mixing ratios */
    return 1;
  }
  return 0;
}

int sl_species_type_count(const sl_species *species, int n)
{
  int used[SL_PARTICLE_COUNT] = {0}, count = 0;
  for (int s = 0; s < n; ++s) used[species[s].warm] = used[species[s].cold] = 1;
  for (int p = 0; p < SL_PARTICLE_COUNT; ++p) count += used[p];
  return count;
}

int sl_map_species_nc(const sl_nc *f, const sl_storm_info *info, const sl_load_options *opt,
                      sl_species out[SL_MAX_SPECIES], int *count, sl_error *err)
{
  int n = 0;
  int overridden[SL_PARTICLE_COUNT] = {0};
  for (int p = 0; p < SL_PARTICLE_COUNT; ++p) overridden[p] = opt && opt->field_variable[p] != NULL;
  /* Defaults that survive: a species whose targets are all overridden is dropped; a split species
   * that loses one branch sends all its mass to the other (no split). A variable named by an
   * override is used only there. */
  for (int s = 0; s < info->nspecies; ++s) {
    sl_species sp = info->species[s];
    int named = 0;
    for (int p = 0; p < SL_PARTICLE_COUNT; ++p)
      if (overridden[p] && strcmp(opt->field_variable[p], sp.variable) == 0) named = 1;
    if (named) continue;
    if (overridden[sp.warm] && overridden[sp.cold]) continue;
    if (overridden[sp.warm]) sp.warm = sp.cold;
    if (overridden[sp.cold]) sp.cold = sp.warm;
    out[n++] = sp;
  }
  for (int p = 0; p < SL_PARTICLE_COUNT; ++p) {
    if (!overridden[p] || strcmp(opt->field_variable[p], "none") == 0) continue;
    const char *var = opt->field_variable[p];
    if (!sl_nc_has_var(f, var))
      return sl_fail(err, SL_ERR_ARG, "%s: --field %s=%s: the file has no variable '%s'", info->path,
                     sl_particle_name((sl_particle)p), var, var);
    if (n == SL_MAX_SPECIES) return sl_fail(err, SL_ERR_ARG, "%s: too many --field overrides", info->path);
    sl_species *sp = &out[n++];
    memset(sp, 0, sizeof *sp);
    snprintf(sp->variable, sizeof sp->variable, "%s", var);
    sp->warm = sp->cold = p;
    sp->kind = "override";
    sp->radius_m = sl_particle_properties((sl_particle)p)->radius_m;
    sp->density_kg_m3 = sl_particle_properties((sl_particle)p)->density_kg_m3;
    sp->per_moist_air = info->kind == SL_STORM_CF;
  }
  *count = n;
  return SL_OK;
}

int sl_storm_map_species(const sl_storm_info *info, const sl_load_options *opt, sl_species out[SL_MAX_SPECIES],
                         int *count, sl_error *err)
{
  sl_nc f;
  if (sl_nc_open(info->path, NULL, 0, &f, err)) return err->code;
  const int rc = sl_map_species_nc(&f, info, opt, out, count, err);
  nc_close(f.id);
  return rc;
}

/* Extinction per unit mass (m2/kg) of spheres of radius r and density rho in the geometric-optics
 * limit: 2 pi r^2 / (4/3 pi r^3 rho) = 3 / (2 rho r) (Riley et al. 2004, Table 2's sigma = 2 pi r^2). */
static double extinction_per_mass(double radius, double density) { return 3.0 / (2.0 * density * radius); }

double sl_species_eta(const sl_species *sp, int target, double rho_air, double q, double rho_dry, double qn)
{
  const sl_particle_props *tp = sl_particle_properties((sl_particle)target);
  if (q <= 0.0) return 0.0;
  const double mass_conc = rho_air * q; /* kg/m3 */
  if (qn > 0.0 && target == sp->warm) {
    /* Double moment: number concentration rho_d * QN, each particle of the mean mass q / QN (a
     * monodisperse population); as extinction-equivalent target particles: N (r / r_target)^2. */
    const double number = rho_dry * qn;
    const double mean_mass = mass_conc / number;
    const double r = cbrt(3.0 * mean_mass / (4.0 * M_PI * sp->density_kg_m3));
    return number * (r * r) / (tp->radius_m * tp->radius_m);
  }
  /* Single moment: the species' representative particle's extinction per unit mass. The target
   * type's own species reduces to eta = rho q / m_target exactly, and so does the cold branch of
   * a split species (WSM3's QCLOUD below 0 C is cloud ice: ice's own particle). */
  if (target != sp->warm || (sp->radius_m == tp->radius_m && sp->density_kg_m3 == tp->density_kg_m3))
    return sl_number_concentration(rho_air, q, sl_particle_mass((sl_particle)target));
  return mass_conc * extinction_per_mass(sp->radius_m, sp->density_kg_m3) / tp->sigma_ext_m2;
}

double sl_load_bytes(size_t nx, size_t ny, size_t nz_model, size_t nz_out, int types)
{
  /* Output fields (float), and beside them for the whole load (remap.c): interface heights
   * (double), dry density (float), a freezing flag (byte) and one hydrometeor variable (float). */
  const double columns = (double)nx * ny;
  return columns * nz_out * sizeof(float) * types + columns * (nz_model + 1) * sizeof(double) +
         columns * nz_model * (2 * sizeof(float) + 1);
}

double sl_machine_memory(void)
{
  FILE *f = fopen("/proc/meminfo", "r");
  if (f) {
    char line[256];
    double kb = -1;
    while (fgets(line, sizeof line, f))
      if (sscanf(line, "MemAvailable: %lf kB", &kb) == 1) break;
    fclose(f);
    if (kb > 0) return kb * 1024.0;
  }
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  return pages > 0 && page > 0 ? (double)pages * (double)page : 0.0;
}

int sl_check_memory(const char *path, double need, const sl_load_options *opt, sl_error *err)
{
  const int given = opt && opt->max_memory > 0;
  const double limit = given ? opt->max_memory : sl_machine_memory();
  if (limit <= 0 || need <= limit) return SL_OK;
  return sl_fail(err, SL_ERR_NOMEM,
                 "%s: a load needs about %.3g GB, more than %s (%.3g GB): read a subset with --region "
                 "lat0,lat1,lon0,lon1, --levels K0:K1 or --stride N%s",
                 path, need / 1e9, given ? "--max-memory" : "this machine has available", limit / 1e9,
                 given ? ", or raise --max-memory" : "");
}
