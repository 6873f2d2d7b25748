/* Seeded 3D value noise and its fractal sum: the texture of synthetic clouds. Pure functions of
 * (seed, position), so results never depend on evaluation order or thread count. */
#ifndef SL_NOISE_H
#define SL_NOISE_H

#include <stdint.h>

double sl_value_noise(uint64_t seed, double x, double y, double z);         /* in [0, 1] */
double sl_fractal_noise(uint64_t seed, double x, double y, double z, int octaves); /* in [0, 1] */

#endif
