/* A horizontally inhomogeneous cloud with periodic sides against the I3RC intercomparison:
 * Case 1 ("step cloud", Cahalan et al. 2005, BAMS 86, 1275): 32 columns across 0.5 km, 0.25 km
 * deep, optical depth 2 in the first 16 and 18 in the other 16, Henyey-Greenstein g = 0.85,
 * periodic in x, black surface. Experiment 1: albedo 1, sun overhead; experiment 4: albedo 0.99,
 * sun 60 degrees from the zenith in the x-z plane. The column values below are the I3RC consensus
 * results (i3rc.gsfc.nasa.gov/consensus_result/consensus_result_case1.tar, files
 * I3RC_cons_res_case1_exp{1,4}_{R,T,A}.txt, read from the copy in tamarloeub/MitsubaGradient);
 * their domain means are compared with the reference's domain-averaged fluxes. The geometry
 * follows the I3RC community model's i3rcStepCloud example (domain 500 m, 32 columns, 250 m).
 * The independent-column (1D) answer from adding-doubling is also computed, to show the test
 * sees the 3-D effect it is meant to check. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "adding_doubling.h"
#include "sl_reference.h"
#include "sl_testing.h"

static const double R1[32] = {0.27859, 0.26712, 0.25531, 0.24542, 0.23761, 0.23207, 0.22805, 0.22592,
                              0.22597, 0.22796, 0.23176, 0.23787, 0.24578, 0.25563, 0.26676, 0.27939,
                              0.32332, 0.36758, 0.39589, 0.41544, 0.43034, 0.44028, 0.44675, 0.45022,
                              0.44978, 0.44676, 0.44118, 0.43032, 0.41623, 0.39624, 0.36826, 0.32325};
static const double T1[32] = {0.84654, 0.94825, 1.0049,  1.0359,  1.0539,  1.0638,  1.0697,  1.0706,
                              1.0703,  1.0697,  1.0640,  1.0543,  1.0363,  1.0045,  0.94871, 0.84774,
                              0.44446, 0.35244, 0.32505, 0.31401, 0.30884, 0.30715, 0.30596, 0.30572,
                              0.30614, 0.30642, 0.30683, 0.30907, 0.31385, 0.32537, 0.35255, 0.44375};
static const double R4[32] = {0.38919, 0.33814, 0.30943, 0.29164, 0.28112, 0.27579, 0.27479, 0.27608,
                              0.28105, 0.28895, 0.29862, 0.31206, 0.32827, 0.34823, 0.37136, 0.39690,
                              0.50371, 0.61392, 0.67620, 0.70765, 0.71969, 0.71838, 0.70939, 0.69644,
                              0.67965, 0.66247, 0.64396, 0.62474, 0.60415, 0.58147, 0.55020, 0.49561};
static const double T4[32] = {0.22620, 0.24431, 0.25894, 0.27104, 0.28272, 0.29476, 0.30722, 0.32081,
                              0.33567, 0.35257, 0.37056, 0.38990, 0.40756, 0.42551, 0.43743, 0.43396,
                              0.41504, 0.40732, 0.39876, 0.38867, 0.37543, 0.35982, 0.34274, 0.32379,
                              0.30480, 0.28645, 0.26937, 0.25403, 0.24120, 0.23123, 0.22294, 0.21616};
static const double A4[32] = {0.024271, 0.024508, 0.025229, 0.026102, 0.027169, 0.028302, 0.029572, 0.030917,
                              0.032386, 0.033928, 0.035557, 0.037288, 0.039187, 0.041246, 0.043587, 0.046427,
                              0.46854,  0.48537,  0.47449,  0.45396,  0.43004,  0.40671,  0.38477,  0.36505,
                              0.34694,  0.33051,  0.31566,  0.30203,  0.28894,  0.27553,  0.26076,  0.23949};

static double mean32(const double *v)
{
  double s = 0.0;
  for (int i = 0; i < 32; ++i) s += v[i];
  return s / 32.0;
}

int main(int argc, char **argv)
{
  const long scale = argc > 1 && atol(argv[1]) > 0 ? atol(argv[1]) : 1;
  float extinction[32];
  for (int i = 0; i < 32; ++i) extinction[i] = (float)((i < 16 ? 2.0 : 18.0) / 250.0);
  const double albedo[2] = {1.0, 0.99}, zenith[2] = {0.0, 60.0};
  const double *want_R[2] = {R1, R4}, *want_T[2] = {T1, T4};
  for (int e = 0; e < 2; ++e) {
    sl_ref_medium_desc d;
    sl_ref_medium_desc_defaults(&d);
    d.n[0] = 32;
    d.spacing[0] = d.spacing[1] = 500.0 / 32.0;
    d.spacing[2] = 250.0;
    d.origin[0] = d.origin[1] = 0.5 * d.spacing[0];
    d.origin[2] = 125.0;
    d.component[0].density = extinction;
    d.component[0].sigma[0] = 1.0;
    d.component[0].albedo[0] = albedo[e];
    d.component[0].phase[0].kind = SL_REF_PHASE_HG;
    d.component[0].phase[0].g = 0.85;
    d.interpolation = SL_REF_CELL;
    d.lateral = SL_REF_PERIODIC;
    d.black_surface = 1;
    sl_error err = {0};
    sl_ref_medium *m = sl_ref_medium_create(&d, &err);
    CHECK_MSG(m != NULL, err.message);
    if (!m) continue;
    sl_ref_flux_options o;
    sl_ref_flux_options_defaults(&o);
    o.sun_zenith_deg = zenith[e];
    o.sun_azimuth_deg = 90.0; /* in the x-z plane: across the step */
    o.photons = 120000 * scale;
    o.seed = 17 + e;
    sl_ref_fluxes_result r;
    CHECK(sl_ref_fluxes(m, &o, &r, &err) == SL_OK);
    const double R = mean32(want_R[e]), T = mean32(want_T[e]), A = e == 1 ? mean32(A4) : 0.0;
    /* The independent-column answer: the mean of the two plane-parallel slabs. */
    double ipa_R = 0.0;
    for (int k = 0; k < 2; ++k) {
      ad_slab s = {k == 0 ? 2.0 : 18.0, albedo[e], NULL, 0, 0.85, cos(zenith[e] * 3.14159265358979323846 / 180.0), 32, 0};
      ad_fluxes f;
      CHECK(ad_slab_fluxes(&s, &f) == 0);
      ipa_R += 0.5 * f.reflectance;
    }
    char what[200];
    snprintf(what, sizeof what,
             "experiment %d: R %.5f +- %.5f (I3RC %.5f, 1D columns %.5f), T %.5f +- %.5f (I3RC %.5f), A %.5f +- %.5f "
             "(I3RC %.5f)",
             e == 0 ? 1 : 4, r.reflectance, r.se_reflectance, R, ipa_R, r.transmittance, r.se_transmittance, T,
             r.absorptance, r.se_absorptance, A);
    printf("%s\n", what);
    /* 4 standard errors plus 1e-3 for the consensus (5 digits per column; the models' spread
     * is not restated in the files). */
    CHECK_MSG(fabs(r.reflectance - R) <= 4.0 * r.se_reflectance + 1e-3, what);
    CHECK_MSG(fabs(r.transmittance - T) <= 4.0 * r.se_transmittance + 1e-3, what);
    CHECK_MSG(fabs(r.absorptance - A) <= 4.0 * r.se_absorptance + 1e-3, what);
    /* The 3-D effect is far outside the noise: the test can tell a 1-D answer from the right one. */
    CHECK_MSG(fabs(ipa_R - R) > 6.0 * r.se_reflectance, what);
    sl_ref_medium_destroy(m);
  }
  return sl_test_finish("test_ref_i3rc");
}
