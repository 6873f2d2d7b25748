/* Number concentration from a mixing ratio against a hand calculation from stated constants. */
#include <math.h>

#include "sl_particles.h"
#include "sl_storm.h"
#include "sl_testing.h"

int main(void)
{
  /* Hand calculation: p = 90 000 Pa, T = 280 K, qv = 8 g/kg, R_d = 287, R_v = 461.6 J/(kg K):
   * rho_d = p / (R_d T (1 + qv R_v / R_d)) = 90000 / (80360 * 1.0128669...) = 1.1057328266 kg/m3. */
  CHECK_CLOSE(sl_dry_air_density(90000.0, 280.0, 0.008), 1.1057328266423, 1e-10, 0.0);
  /* Dry air alone: the ideal gas law p / (R_d T). */
  CHECK_CLOSE(sl_dry_air_density(101325.0, 288.15, 0.0), 101325.0 / (287.0 * 288.15), 1e-14, 0.0);
  /* A 10 um water droplet weighs 1000 * 4/3 pi (1e-5)^3 = 4.18879020e-12 kg. */
  CHECK_CLOSE(sl_particle_mass(SL_CLOUD), 4.1887902047864e-12, 1e-12, 0.0);
  /* q = 1 g/kg of cloud water in that air: eta = 1.10573 * 1e-3 / 4.18879e-12 = 2.6397e8 m^-3. */
  CHECK_CLOSE(sl_number_concentration(1.1057328266423, 1e-3, sl_particle_mass(SL_CLOUD)), 263974267.64865, 1e-10,
              0.0);
  /* q = 2 g/kg of rain as 1 mm drops: 527.95 m^-3. */
  CHECK_CLOSE(sl_number_concentration(1.1057328266423, 2e-3, sl_particle_mass(SL_RAIN)), 527.94853529730, 1e-10,
              0.0);
  /* Table 2's extinction cross-sections are 2 pi r^2 for the stated radii. */
  CHECK_CLOSE(sl_particle_properties(SL_CLOUD)->sigma_ext_m2, 2.0 * M_PI * 1e-10, 1e-3, 0.0);
  CHECK_CLOSE(sl_particle_properties(SL_RAIN)->sigma_ext_m2, 2.0 * M_PI * 1e-6, 1e-3, 0.0);
  for (int p = 0; p < SL_PARTICLE_COUNT; ++p) {
    const sl_particle_props *pp = sl_particle_properties((sl_particle)p);
    CHECK_CLOSE(2.0 * M_PI * pp->radius_m * pp->radius_m, pp->sigma_ext_m2, 1e-3, 0.0);
  }
  /* WRF temperature: theta = T' + 300 K; T = theta (p / 1e5)^(R_d / c_p) with c_p = 3.5 R_d. */
  CHECK_CLOSE(sl_temperature_from_wrf(0.0, 1.0e5), 300.0, 1e-14, 0.0);
  CHECK_CLOSE(sl_temperature_from_wrf(0.0, 5.0e4), 300.0 * pow(0.5, 2.0 / 7.0), 1e-14, 0.0);
  CHECK_CLOSE(sl_temperature_from_wrf(0.0, 5.0e4), 246.1006068023, 1e-11, 0.0);
  return sl_test_finish("test_concentration");
}
