// A camera path through a series: key frames from a scene file's "camera_keys", interpolated per
// frame (docs/SCENES.md, "Camera paths"). Pure geometry: no VTK, no rendering.
#pragma once

#include <string>
#include <vector>

namespace sl {

struct CameraKey {
  double t = 0;                // series index, or Julian day (UT) when the keys give dates
  double position[3] = {0, 0, 0}, look_at[3] = {0, 0, 0}; // ENU metres (absolute keys)
  double azimuth = 0, elevation = 0;                      // degrees (orbit keys)
  double fov = 0;
};

struct CameraPath {
  std::vector<CameraKey> keys; // strictly increasing t; empty when the scene has none
  bool by_date = false;        // keys' "time" are ISO 8601 date-times (else series indices)
  bool absolute = false;       // position/look_at keys (else view-azimuth/view-elevation keys)
  bool has_fov = false;        // every key sets fov
};

// The camera at one instant: the arguments stormlight render takes for it.
struct CameraAt {
  bool absolute = false;
  double position[3] = {0, 0, 0}, look_at[3] = {0, 0, 0};
  double azimuth = 0, elevation = 0;
  bool has_fov = false;
  double fov = 0;
};

// Reads "camera_keys" from a scene file (path empty or no key: an empty path, true). Fails with
// one line naming the file for a malformed key, mixed key kinds, or times out of order.
bool camera_path_read(const std::string &scene_path, CameraPath *path, std::string *error);

// The camera at t (same units as the keys' t): held at the end keys outside their range; between
// keys, the camera's position and the point it looks at (or the orbit's azimuth and elevation)
// each follow a cubic Hermite curve with Catmull-Rom tangents, which passes through every key,
// has a continuous velocity, reproduces uniform motion exactly and keeps a target shared by
// neighbouring keys fixed; the field of view is linear. Azimuths turn the short way round.
CameraAt camera_path_at(const CameraPath &path, double t);

}  // namespace sl
