#include "camera_path.h"

#include <cjson/cJSON.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "sl_sky.h"

bool sl_parse_iso8601_utc(const std::string &text, sl_utc *out, std::string *why);  // cmd_sun.cpp

namespace sl {

namespace {

bool read_vec3(const cJSON *key, const char *name, double out[3])
{
  const cJSON *a = cJSON_GetObjectItemCaseSensitive(key, name);
  if (!cJSON_IsArray(a) || cJSON_GetArraySize(a) != 3) return false;
  int i = 0;
  for (const cJSON *e = a->child; e; e = e->next, ++i) {
    if (!cJSON_IsNumber(e) || !std::isfinite(e->valuedouble)) return false;
    out[i] = e->valuedouble;
  }
  return true;
}

bool read_number(const cJSON *key, const char *name, double *out)
{
  const cJSON *n = cJSON_GetObjectItemCaseSensitive(key, name);
  if (!cJSON_IsNumber(n) || !std::isfinite(n->valuedouble)) return false;
  *out = n->valuedouble;
  return true;
}

double norm(const double v[3]) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

// The cubic Hermite curve through the keys' values with Catmull-Rom (finite-difference) tangents,
// one-sided at the ends; non-uniform key spacing is handled by taking tangents per unit of t.
double hermite_catmull_rom(const std::vector<double> &t, const std::vector<double> &v, size_t k, double u)
{
  const size_t n = t.size();
  auto tangent = [&](size_t i) {
    const size_t a = i == 0 ? 0 : i - 1, b = i + 1 >= n ? n - 1 : i + 1;
    return (v[b] - v[a]) / (t[b] - t[a]);
  };
  const double span = t[k + 1] - t[k];
  const double u2 = u * u, u3 = u2 * u;
  return (2 * u3 - 3 * u2 + 1) * v[k] + (u3 - 2 * u2 + u) * span * tangent(k) + (-2 * u3 + 3 * u2) * v[k + 1] +
         (u3 - u2) * span * tangent(k + 1);
}

}  // namespace

bool camera_path_read(const std::string &scene_path, CameraPath *path, std::string *error)
{
  *path = CameraPath();
  if (scene_path.empty()) return true;
  std::ifstream in(scene_path);
  std::stringstream text;
  text << in.rdbuf();
  cJSON *root = cJSON_Parse(text.str().c_str());
  if (!root) {
    *error = scene_path + ": not a JSON object";
    return false;
  }
  const cJSON *keys = cJSON_GetObjectItemCaseSensitive(root, "camera_keys");
  bool ok = true;
  const auto bad = [&](int i, const std::string &why) {
    *error = scene_path + ": camera_keys[" + std::to_string(i) + "]: " + why;
    ok = false;
  };
  if (keys && (!cJSON_IsArray(keys) || cJSON_GetArraySize(keys) < 1)) {
    *error = scene_path + ": camera_keys must be a non-empty array of key objects";
    ok = false;
  }
  int i = 0;
  for (const cJSON *key = keys ? keys->child : nullptr; key && ok; key = key->next, ++i) {
    CameraKey c;
    const cJSON *time = cJSON_GetObjectItemCaseSensitive(key, "time");
    const bool dated = cJSON_IsString(time);
    if (!cJSON_IsObject(key) || !(dated || cJSON_IsNumber(time))) {
      bad(i, "needs \"time\": a series index or an ISO 8601 date-time");
      break;
    }
    if (i > 0 && dated != path->by_date) {
      bad(i, "all keys give their time the same way (series indices or date-times)");
      break;
    }
    path->by_date = dated;
    if (dated) {
      sl_utc utc{};
      std::string why;
      if (!sl_parse_iso8601_utc(time->valuestring, &utc, &why)) {
        bad(i, why);
        break;
      }
      c.t = sl_julian_day(&utc);
    } else {
      c.t = time->valuedouble;
    }
    const bool absolute = cJSON_HasObjectItem(key, "position") || cJSON_HasObjectItem(key, "look_at");
    const bool orbit = cJSON_HasObjectItem(key, "view-azimuth") || cJSON_HasObjectItem(key, "view-elevation");
    if (absolute == orbit) {
      bad(i, "give either \"position\" and \"look_at\" ([x, y, z] metres) or \"view-azimuth\" and "
             "\"view-elevation\" (degrees)");
      break;
    }
    if (i > 0 && absolute != path->absolute) {
      bad(i, "all keys are of one kind (position/look_at or view-azimuth/view-elevation)");
      break;
    }
    path->absolute = absolute;
    if (absolute) {
      if (!read_vec3(key, "position", c.position) || !read_vec3(key, "look_at", c.look_at)) {
        bad(i, "\"position\" and \"look_at\" must both be [x, y, z] in metres");
        break;
      }
      const double d[3] = {c.look_at[0] - c.position[0], c.look_at[1] - c.position[1], c.look_at[2] - c.position[2]};
      if (!(norm(d) > 0)) {
        bad(i, "\"look_at\" equals \"position\"");
        break;
      }
    } else if (!read_number(key, "view-azimuth", &c.azimuth) || !read_number(key, "view-elevation", &c.elevation) ||
               std::fabs(c.elevation) >= 90) {
      bad(i, "\"view-azimuth\" and \"view-elevation\" must both be numbers, elevation in (-90, 90)");
      break;
    }
    const bool fov = cJSON_HasObjectItem(key, "fov");
    if (i > 0 && fov != path->has_fov) {
      bad(i, "either every key sets \"fov\" or none does");
      break;
    }
    path->has_fov = fov;
    if (fov && (!read_number(key, "fov", &c.fov) || !(c.fov > 0 && c.fov < 170))) {
      bad(i, "\"fov\" must be in (0, 170) degrees");
      break;
    }
    for (const cJSON *f = key->child; f && ok; f = f->next) {
      const std::string name = f->string ? f->string : "";
      if (name != "time" && name != "position" && name != "look_at" && name != "view-azimuth" &&
          name != "view-elevation" && name != "fov" && name != "comment")
        bad(i, "unknown key '" + name + "'");
    }
    if (!ok) break;
    if (!path->keys.empty() && !(c.t > path->keys.back().t)) {
      bad(i, "key times must increase");
      break;
    }
    path->keys.push_back(c);
  }
  cJSON_Delete(root);
  if (!ok) path->keys.clear();
  return ok;
}

CameraAt camera_path_at(const CameraPath &path, double t)
{
  CameraAt at;
  at.absolute = path.absolute;
  at.has_fov = path.has_fov;
  const std::vector<CameraKey> &keys = path.keys;
  if (keys.empty()) return at;
  // Segment k holds t in [t_k, t_k+1); outside the keys the end keys hold.
  size_t k = 0;
  double u = 0;
  if (keys.size() == 1 || t <= keys.front().t) {
    k = 0;
  } else if (t >= keys.back().t) {
    k = keys.size() - 2;
    u = 1;
  } else {
    while (t >= keys[k + 1].t) ++k;
    u = (t - keys[k].t) / (keys[k + 1].t - keys[k].t);
  }
  if (keys.size() == 1) {
    const CameraKey &c = keys[0];
    std::copy(c.position, c.position + 3, at.position);
    std::copy(c.look_at, c.look_at + 3, at.look_at);
    at.azimuth = c.azimuth, at.elevation = c.elevation, at.fov = c.fov;
    return at;
  }
  std::vector<double> ts;
  for (const CameraKey &c : keys) ts.push_back(c.t);
  const CameraKey &a = keys[k], &b = keys[k + 1];
  at.fov = a.fov + u * (b.fov - a.fov);
  if (path.absolute) {
    for (int x = 0; x < 3; ++x) {
      std::vector<double> v;
      for (const CameraKey &c : keys) v.push_back(c.position[x]);
      at.position[x] = hermite_catmull_rom(ts, v, k, u);
    }
    for (int x = 0; x < 3; ++x) {
      std::vector<double> v;
      for (const CameraKey &c : keys) v.push_back(c.look_at[x]);
      at.look_at[x] = hermite_catmull_rom(ts, v, k, u);
    }
    // Between keys that look different ways the interpolated target could fall onto the camera.
    double d[3];
    for (int x = 0; x < 3; ++x) d[x] = at.look_at[x] - at.position[x];
    if (!(norm(d) > 1e-6 * (1.0 + norm(at.position))))
      for (int x = 0; x < 3; ++x) at.look_at[x] = at.position[x] + (u < 0.5 ? a.look_at[x] - a.position[x] : b.look_at[x] - b.position[x]);
  } else {
    // Azimuths unwrapped along the shortest turn between neighbouring keys, so 350 -> 10 passes north.
    std::vector<double> az, el;
    for (const CameraKey &c : keys) {
      double v = c.azimuth;
      if (!az.empty()) v = az.back() + std::remainder(v - az.back(), 360.0);
      az.push_back(v);
      el.push_back(c.elevation);
    }
    at.azimuth = std::fmod(hermite_catmull_rom(ts, az, k, u), 360.0);
    if (at.azimuth < 0) at.azimuth += 360.0;
    at.elevation = std::max(-89.0, std::min(89.0, hermite_catmull_rom(ts, el, k, u)));
  }
  return at;
}

}  // namespace sl
