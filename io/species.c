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

/* The species every scheme's variables belong to, each with its own particle type (render/core,
 * render/optics). Variables by WRF name (with the number variable of double-moment schemes), by
 * CM1 name (Morrison's nci/ncs/ncr/ncg; CM1's qg is graupel or, with ihail = 1, hail, which CM1
 * does not record in the file: --field hail=qg), by CF standard name or by ECMWF short name. */
typedef struct species_def {
  const char *wrf, *wrf_number, *cm1, *cm1_number, *standard_name, *ecmwf, *kind;
  int type;
} species_def;

static const species_def SPECIES[] = {
    {"QCLOUD", "QNCLOUD", "qc", "ncc", "mass_fraction_of_cloud_liquid_water_in_air", "clwc", "cloud water", SL_CLOUD},
    {"QRAIN", "QNRAIN", "qr", "ncr", "mass_fraction_of_rain_in_air", "crwc", "rain", SL_RAIN},
    {"QICE", "QNICE", "qi", "nci", "mass_fraction_of_cloud_ice_in_air", "ciwc", "cloud ice", SL_ICE},
    {"QSNOW", "QNSNOW", "qs", "ncs", "mass_fraction_of_snow_in_air", "cswc", "snow", SL_SNOW},
    {"QGRAUP", "QNGRAUPEL", "qg", "ncg", "mass_fraction_of_graupel_in_air", NULL, "graupel", SL_GRAUPEL},
    {"QHAIL", "QNHAIL", "qhl", "nchl", "mass_fraction_of_hail_in_air", NULL, "hail", SL_HAIL},
};
#define NDEF (int)(sizeof SPECIES / sizeof SPECIES[0])

/* Size distributions per scheme (docs/DATA.md, "Sizes"): gamma in diameter for spheres of the
 * scheme's density. A density of 0 leaves the species to the representative particle of its
 * type unless the file gives a number concentration, in which case DEFAULT_SIZES apply. */
typedef struct scheme_sizes {
  sl_gamma_distribution psd[SL_PARTICLE_COUNT];
} scheme_sizes;

/* Morrison, Curry & Khvorostyanov 2005 and Morrison, Thompson & Tatarskii 2009 (WRF MP_PHYSICS 10,
 * CM1 ptype 5): every species exponential (mu 0) but cloud droplets (Martin et al. 1994's mu); cloud
 * droplets' number fixed at NDCNST = 250 cm^-3 (the scheme predicts none); densities rain 997,
 * cloud ice 500, snow 100, graupel 400, hail 900 kg/m3. */
static const scheme_sizes MORRISON = {{
    [SL_CLOUD] = {SL_SHAPE_MARTIN1994, 0.0, 997.0, 250e6, 0.0, "Morrison et al. 2005: gamma, Martin et al. 1994's mu"},
    [SL_RAIN] = {SL_SHAPE_FIXED, 0.0, 997.0, 0.0, 0.0, "Morrison et al. 2005: exponential"},
    [SL_ICE] = {SL_SHAPE_FIXED, 0.0, 500.0, 0.0, 0.0, "Morrison et al. 2005: exponential, 500 kg/m3 spheres"},
    [SL_SNOW] = {SL_SHAPE_FIXED, 0.0, 100.0, 0.0, 0.0, "Morrison et al. 2005: exponential, 100 kg/m3 spheres"},
    [SL_GRAUPEL] = {SL_SHAPE_FIXED, 0.0, 400.0, 0.0, 0.0, "Morrison et al. 2009: exponential, 400 kg/m3"},
    [SL_HAIL] = {SL_SHAPE_FIXED, 0.0, 900.0, 0.0, 0.0, "Morrison et al. 2009: exponential, 900 kg/m3"},
}};

/* Thompson et al. 2008 (WRF 8) and Thompson & Eidhammer 2014 (WRF 28, which predicts QNCLOUD): cloud
 * droplets gamma with mu = min(15, NINT(1000 / N) + 2), N fixed at 100 cm^-3 where not predicted;
 * rain exponential (1000 kg/m3); cloud ice exponential spheres of 890 kg/m3. Snow (m = 0.069 D^2,
 * Field et al. 2005's two-mode spectrum) and graupel (intercept diagnosed from the mixing ratio) are
 * not spheres of one density: they keep the representative particle. */
static const scheme_sizes THOMPSON = {{
    [SL_CLOUD] = {SL_SHAPE_THOMPSON2008, 0.0, 1000.0, 100e6, 0.0, "Thompson et al. 2008: gamma, mu = min(15, 1000/N + 2)"},
    [SL_RAIN] = {SL_SHAPE_FIXED, 0.0, 1000.0, 0.0, 0.0, "Thompson et al. 2008: exponential"},
    [SL_ICE] = {SL_SHAPE_FIXED, 0.0, 890.0, 0.0, 0.0, "Thompson et al. 2008: exponential, 890 kg/m3 spheres"},
}};

/* Single-moment schemes' exponentials of fixed intercept N0 (m^-4), n(D) = N0 exp(-lambda D), whose
 * slope the mass sets. WSM3/5/6/7 and WDM5/6/7 (Hong, Dudhia & Chen 2004, MWR 132, 103; Hong & Lim
 * 2006, JKMS 42, 129; WRF's module_mp_wsm6: n0r, n0g, deng, xncr): rain 8e6 at 1000 kg/m3 (Marshall
 * & Palmer 1948), graupel 4e6 at 500, hail (WSM7, WDM7) 4e4 at 912; cloud droplets 300 cm^-3, the
 * scheme's xncr, with Martin et al. 1994's shape (the scheme has no droplet spectrum). Snow's
 * intercept follows temperature, 2e6 exp(0.12 (T0 - T)), which the load does not carry: snow keeps
 * the representative particle. The WDM schemes predict cloud and rain numbers (QNCLOUD, QNRAIN),
 * read where present. */
static const scheme_sizes WSM = {{
    [SL_CLOUD] = {SL_SHAPE_MARTIN1994, 0.0, 1000.0, 300e6, 0.0, "WSM/WDM: gamma, Martin et al. 1994's mu"},
    [SL_RAIN] = {SL_SHAPE_FIXED, 0.0, 1000.0, 0.0, 8e6, "WSM/WDM: exponential, N0 8e6 m^-4 (Marshall-Palmer)"},
    [SL_GRAUPEL] = {SL_SHAPE_FIXED, 0.0, 500.0, 0.0, 4e6, "WSM/WDM: exponential, N0 4e6 m^-4, 500 kg/m3"},
    [SL_HAIL] = {SL_SHAPE_FIXED, 0.0, 912.0, 0.0, 4e4, "WSM7/WDM7: exponential, N0 4e4 m^-4, 912 kg/m3"},
}};

/* Purdue Lin (WRF 2; Lin, Farley & Orville 1983, JCAM 22, 1065, with Rutledge & Hobbs 1984's graupel,
 * the constants WRF's own effective-radius diagnostics use): rain 8e6 at 1000, snow 3e6 at 100,
 * graupel 4e6 at 400 kg/m3. Kessler (WRF 1) is warm rain with Marshall-Palmer drops. */
static const scheme_sizes LIN = {{
    [SL_RAIN] = {SL_SHAPE_FIXED, 0.0, 1000.0, 0.0, 8e6, "Lin et al. 1983: exponential, N0 8e6 m^-4"},
    [SL_SNOW] = {SL_SHAPE_FIXED, 0.0, 100.0, 0.0, 3e6, "Lin et al. 1983: exponential, N0 3e6 m^-4, 100 kg/m3"},
    [SL_GRAUPEL] = {SL_SHAPE_FIXED, 0.0, 400.0, 0.0, 4e6, "Rutledge & Hobbs 1984: exponential, N0 4e6 m^-4, 400 kg/m3"},
}};
static const scheme_sizes KESSLER = {{
    [SL_RAIN] = {SL_SHAPE_FIXED, 0.0, 1000.0, 0.0, 8e6, "Kessler 1969: exponential, N0 8e6 m^-4 (Marshall-Palmer)"},
}};

/* A double-moment variable of a scheme without a row above: exponential spheres of the type's
 * representative density; cloud droplets with Martin et al. 1994's shape. */
static const scheme_sizes DEFAULT_SIZES = {{
    [SL_CLOUD] = {SL_SHAPE_MARTIN1994, 0.0, 1000.0, 0.0, 0.0, "Stormlight default: gamma, Martin et al. 1994's mu"},
    [SL_RAIN] = {SL_SHAPE_FIXED, 0.0, 1000.0, 0.0, 0.0, "Stormlight default: exponential"},
    [SL_ICE] = {SL_SHAPE_FIXED, 0.0, 917.0, 0.0, 0.0, "Stormlight default: exponential, solid ice"},
    [SL_SNOW] = {SL_SHAPE_FIXED, 0.0, 100.0, 0.0, 0.0, "Stormlight default: exponential, 100 kg/m3"},
    [SL_GRAUPEL] = {SL_SHAPE_FIXED, 0.0, 400.0, 0.0, 0.0, "Stormlight default: exponential, 400 kg/m3"},
    [SL_HAIL] = {SL_SHAPE_FIXED, 0.0, 900.0, 0.0, 0.0, "Stormlight default: exponential, 900 kg/m3"},
}};

static const scheme_sizes *scheme_sizes_of(int wrf_mp_physics, int cm1_ptype)
{
  if (wrf_mp_physics == 10 || cm1_ptype == 5) return &MORRISON;
  if (wrf_mp_physics == 8 || wrf_mp_physics == 28 || cm1_ptype == 3) return &THOMPSON;
  switch (wrf_mp_physics) {
  case 3: case 4: case 6: case 14: case 16: case 24: case 26: return &WSM;
  case 2: return &LIN;
  case 1: return &KESSLER;
  default: break;
  }
  /* CM1's ptype 2 is Goddard-LFO (Lin-type), 4 the Lin-based GSFC scheme: left to the default. */
  return NULL;
}

static void species_from_def(const species_def *d, const char *variable, const scheme_sizes *sizes, sl_species *sp)
{
  memset(sp, 0, sizeof *sp);
  snprintf(sp->variable, sizeof sp->variable, "%s", variable);
  sp->warm = sp->cold = d->type;
  sp->kind = d->kind;
  if (sizes && sizes->psd[d->type].density_kg_m3 > 0.0) sp->sizes = sizes->psd[d->type];
}

/* A number variable needs a distribution to turn (q, N) into sizes: the scheme's, else the default. */
void sl_species_set_number(sl_species *sp, const char *number_variable)
{
  snprintf(sp->number_variable, sizeof sp->number_variable, "%s", number_variable);
  if (!(sp->sizes.density_kg_m3 > 0.0)) sp->sizes = DEFAULT_SIZES.psd[sp->warm];
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
  const scheme_sizes *sizes = scheme_sizes_of(mp_physics, -1);
  for (int d = 0; d < NDEF; ++d) {
    if (!sl_nc_has_var(f, SPECIES[d].wrf)) continue;
    sl_species *sp = &info->species[info->nspecies++];
    species_from_def(&SPECIES[d], SPECIES[d].wrf, sizes, sp);
    if (sl_nc_has_var(f, SPECIES[d].wrf_number)) sl_species_set_number(sp, SPECIES[d].wrf_number);
    /* Simple ice (WSM3) and warm rain (Kessler): cloud below 0 C is cloud ice, rain is snow. */
    if (split && SPECIES[d].type == SL_CLOUD) sp->cold = SL_ICE;
    if (split && SPECIES[d].type == SL_RAIN) sp->cold = SL_SNOW;
  }
}

/* CM1's ptype (its microphysics option, a global attribute of its netCDF output). */
static const struct {
  int ptype;
  const char *name;
} CM1_SCHEMES[] = {
    {1, "Kessler (warm rain)"}, {2, "Goddard-LFO"}, {3, "Thompson"},           {4, "Gilmore-Straka-Rasmussen LFO"},
    {5, "Morrison 2-moment"},   {6, "Rotunno-Emanuel"}, {26, "NSSL 2-moment"}, {27, "NSSL 3-moment"},
    {28, "NSSL 1-moment"},      {50, "P3 1-ice"},   {51, "P3 1-ice, 2-moment cloud"}, {52, "P3 2-ice"},
    {53, "P3 1-ice 3-moment"},
};

void sl_species_cm1_scheme(const sl_nc *f, sl_storm_info *info)
{
  const int ptype = (int)sl_nc_attr_double(f, NC_GLOBAL, "ptype", -1.0);
  info->cm1_ptype = ptype;
  const char *name = NULL;
  for (size_t i = 0; i < sizeof CM1_SCHEMES / sizeof CM1_SCHEMES[0]; ++i)
    if (CM1_SCHEMES[i].ptype == ptype) name = CM1_SCHEMES[i].name;
  if (name)
    snprintf(info->scheme, sizeof info->scheme, "%s (CM1 ptype %d)", name, ptype);
  else if (ptype >= 0)
    snprintf(info->scheme, sizeof info->scheme, "CM1 ptype %d (unknown to Stormlight; mapped by variable name)", ptype);
  else
    snprintf(info->scheme, sizeof info->scheme, "CM1, no ptype attribute (mapped by variable name)");
  const scheme_sizes *sizes = scheme_sizes_of(-1, ptype);
  for (int s = 0; s < info->nspecies; ++s) {
    sl_species *sp = &info->species[s];
    for (int d = 0; d < NDEF; ++d) {
      if (strcmp(sp->variable, SPECIES[d].cm1) != 0) continue;
      if (sizes && sizes->psd[SPECIES[d].type].density_kg_m3 > 0.0) sp->sizes = sizes->psd[SPECIES[d].type];
      if (sl_nc_has_var(f, SPECIES[d].cm1_number)) sl_species_set_number(sp, SPECIES[d].cm1_number);
    }
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
    species_from_def(&SPECIES[d], var_name, NULL, sp);
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
    sp->per_moist_air = info->kind == SL_STORM_CF;
    /* A variable the file's scheme sizes (CM1's qg as hail) keeps its number variable, with the
     * scheme's distribution of the type it is now drawn as. */
    const scheme_sizes *sizes = scheme_sizes_of(info->mp_physics, info->cm1_ptype);
    if (sizes && sizes->psd[p].density_kg_m3 > 0.0) sp->sizes = sizes->psd[p];
    for (int s = 0; s < info->nspecies; ++s) {
      if (strcmp(info->species[s].variable, var) != 0) continue;
      sp->kind = info->species[s].kind;
      if (info->species[s].number_variable[0]) sl_species_set_number(sp, info->species[s].number_variable);
    }
  }
  if (opt && opt->droplet_number_m3 > 0.0)
    for (int i = 0; i < n; ++i) {
      if (out[i].warm != SL_CLOUD || out[i].number_variable[0]) continue;
      if (!(out[i].sizes.density_kg_m3 > 0.0)) out[i].sizes = DEFAULT_SIZES.psd[SL_CLOUD];
      out[i].sizes.fixed_number_m3 = opt->droplet_number_m3;
    }
  if (opt && opt->representative_particles)
    for (int i = 0; i < n; ++i) {
      out[i].number_variable[0] = '\0';
      memset(&out[i].sizes, 0, sizeof out[i].sizes);
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

/* Effective radii outside [0.5 um, 5 cm] are no hydrometeor (a number of 1e-3 per kg beside a
 * trace of mass, quantisation's relics): clamped there, as the schemes bound their slopes. */
#define REFF_MIN 0.5e-6
#define REFF_MAX 0.05

int sl_species_sized(const sl_species *sp)
{
  const sl_gamma_distribution *d = &sp->sizes;
  return d->density_kg_m3 > 0.0 && (sp->number_variable[0] || d->fixed_number_m3 > 0.0 || d->fixed_intercept_m4 > 0.0);
}

double sl_species_eta(const sl_species *sp, int target, double rho_air, double q, double rho_dry, double qn,
                      double *r_eff)
{
  const sl_particle_props *tp = sl_particle_properties((sl_particle)target);
  *r_eff = 0.0;
  if (q <= 0.0) return 0.0;
  const double mass_conc = rho_air * q; /* kg/m3 */
  const sl_gamma_distribution *psd = &sp->sizes;
  const double number = qn > 0.0                     ? rho_dry * qn
                        : psd->fixed_number_m3 > 0.0 ? psd->fixed_number_m3
                                                     : sl_gamma_number_from_intercept(psd, mass_conc);
  if (target == sp->warm && psd->density_kg_m3 > 0.0 && number > 0.0) {
    /* Sizes from the microphysics: the gamma distribution that holds this mass in this number has
     * the effective radius r; its extinction per unit mass, 3 Q / (4 rho r), against the target
     * type's tables' (which average over a distribution of effective radius r_t and density rho_t),
     * as a number of the tables' representative particles. Q = 2 for both (large particles). */
    double r = sl_gamma_effective_radius(psd, mass_conc, number);
    r = r < REFF_MIN ? REFF_MIN : (r > REFF_MAX ? REFF_MAX : r);
    *r_eff = r;
    return mass_conc / sl_particle_mass((sl_particle)target) * (tp->density_kg_m3 * tp->effective_radius_m) /
           (psd->density_kg_m3 * r);
  }
  /* Single moment (and the cold branch of a split species, WSM3's QCLOUD below 0 C as cloud ice):
   * the target type's representative particle, eta = rho q / m_target. */
  return sl_number_concentration(rho_air, q, sl_particle_mass((sl_particle)target));
}

double sl_load_bytes(size_t nx, size_t ny, size_t nz_block, size_t nz_out, int types)
{
  /* Output fields (float), and beside them a block's work arrays and its top interfaces. */
  const double columns = (double)nx * ny;
  return columns * nz_out * sizeof(float) * types + columns * nz_block * SL_REMAP_BYTES_PER_CELL +
         columns * sizeof(double);
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
