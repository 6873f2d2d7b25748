// Night scenes for stormlight render: a stated night-sky luminance and a town of emissive street
// lamps from the scene's keys (declare_night_options, app/scene.cpp), drawn through
// render/volume's sl_point_lights.h: projected through the camera, their eye rays stopped at
// them so the volume renderer's transparency is the cloud's transmittance, their depth in Z
// and their pixels marked as glow sources. docs/SCENES.md, "Night and lights".
#pragma once

#include <string>
#include <vector>

#include "cli.h"
#include "sl_point_lights.h"
#include "sl_settings.h"
#include "sl_sky.h"
#ifndef SL_WITHOUT_APSF
#include "sl_apsf.h"
#endif
#include "sl_storm.h"

namespace sl {

struct NightScene {
  double night_sky[3] = {0, 0, 0};  // sun units per sr, added above the horizon
  std::vector<sl_point_light> lights;
  std::vector<sl_light_pixel> pixels;      // the lights in this camera's frame
  std::vector<float> opaque_distance;      // the camera's, lights merged in
  std::vector<unsigned char> source_mask;  // width x height, 1 on light pixels
  bool any_lights() const { return !lights.empty(); }
};

// Reads the night options and builds the lamps on the frame's ground (HGT). One-line error in why.
bool read_night_scene(const sl_settings &s, const sl_storm_frame &frame, NightScene *night, std::string *why);

// Projects the lamps through cam and stops cam's eye rays at them (merging any opaque distance cam
// already has, e.g. the terrain's); cam.opaque_distance then points into night.
bool night_prepare_view(NightScene *night, sl_camera *cam, std::string *why);

#ifndef SL_WITHOUT_APSF
// Eq. 31's L_sky for a haze or fog bank around the camera, per pixel and channel (650, 515,
// 440 nm; 3 floats a pixel into map): the medium's single scattering (albedo, asymmetry per
// channel) of the diffuse light along each pixel's sight line (sl_airlight_source): the sky above
// (the analytic sky's irradiance E_sky at the camera as a uniform hemisphere, E_sky / pi, plus
// the night sky) and the ground below (Lambertian, albedo 0.15, lit by sky and sun). The sun's
// own light is not in it: the sun's disk is a glow source, its scattered light is its glow.
bool fog_airlight(const sl_atmosphere *atm, const double sun_direction[3], const sl_camera &cam,
                  const double night_sky[3], const sl_apsf_medium *const media[3], std::vector<float> *map,
                  std::string *why);
#endif

}  // namespace sl
