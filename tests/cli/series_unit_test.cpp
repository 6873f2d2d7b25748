// The pieces of a series that need no rendering: the camera path's interpolation against values
// from geometry, the --times slices, frame-name patterns, and the time order across files.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "camera_path.h"
#include "series.h"
extern "C" {
#include "sl_testing.h"
}

namespace {

std::string write_scene(const std::string &name, const std::string &json)
{
  const std::string path = name;
  std::ofstream(path) << json;
  return path;
}

void test_uniform_motion_is_reproduced()
{
  // Keys on a straight line at 10 km per series step, unevenly spaced in t: the Hermite curve with
  // Catmull-Rom tangents reproduces uniform motion exactly, so t = 2 is at 20 km.
  const std::string scene = write_scene("path_line.json", R"({"camera_keys": [
    {"time": 0, "position": [0, -50000, 2000], "look_at": [0, 0, 1000], "fov": 30},
    {"time": 1, "position": [10000, -50000, 2000], "look_at": [10000, 0, 1000], "fov": 40},
    {"time": 3, "position": [30000, -50000, 2000], "look_at": [30000, 0, 1000], "fov": 60}]})");
  sl::CameraPath path;
  std::string error;
  CHECK(sl::camera_path_read(scene, &path, &error));
  CHECK(path.absolute && path.has_fov && !path.by_date && path.keys.size() == 3);
  const sl::CameraAt at2 = sl::camera_path_at(path, 2.0);
  CHECK_CLOSE(at2.position[0], 20000.0, 0, 1e-6);
  CHECK_CLOSE(at2.position[1], -50000.0, 0, 1e-6);
  CHECK_CLOSE(at2.position[2], 2000.0, 0, 1e-6);
  CHECK_CLOSE(at2.look_at[0], 20000.0, 0, 1e-6);  // every key looks due north, 50 km away
  CHECK_CLOSE(at2.look_at[1], 0.0, 0, 1e-6);
  CHECK_CLOSE(at2.fov, 50.0, 0, 1e-12);           // linear between 40 (t = 1) and 60 (t = 3)
  const sl::CameraAt at1 = sl::camera_path_at(path, 1.0);  // passes through the keys
  CHECK_CLOSE(at1.position[0], 10000.0, 0, 1e-9);
  CHECK_CLOSE(at1.fov, 40.0, 0, 1e-12);
  const sl::CameraAt before = sl::camera_path_at(path, -4.0), after = sl::camera_path_at(path, 9.0);
  CHECK_CLOSE(before.position[0], 0.0, 0, 1e-9);  // held outside the keys
  CHECK_CLOSE(after.position[0], 30000.0, 0, 1e-9);
  CHECK_CLOSE(after.fov, 60.0, 0, 1e-12);
}

void test_fixed_target_stays_fixed()
{
  // Flying past a storm while looking at its centre: every key looks at the same point, so every
  // frame does, and the camera at t = 1 of keys at t = 0 and 2 sits halfway along the line.
  const std::string scene = write_scene("path_target.json", R"({"camera_keys": [
    {"time": 0, "position": [-60000, -300000, 20000], "look_at": [0, 0, 2000]},
    {"time": 2, "position": [60000, -300000, 20000], "look_at": [0, 0, 2000]},
    {"time": 4, "position": [300000, 0, 20000], "look_at": [0, 0, 2000]}]})");
  sl::CameraPath path;
  std::string error;
  CHECK(sl::camera_path_read(scene, &path, &error));
  CHECK(!path.has_fov);
  for (double t = 0; t <= 4; t += 0.25) {
    const sl::CameraAt at = sl::camera_path_at(path, t);
    CHECK_CLOSE(at.look_at[0], 0.0, 0, 1e-9);
    CHECK_CLOSE(at.look_at[1], 0.0, 0, 1e-9);
    CHECK_CLOSE(at.look_at[2], 2000.0, 0, 1e-9);
  }
  const sl::CameraAt at2 = sl::camera_path_at(path, 2.0);
  CHECK_CLOSE(at2.position[0], 60000.0, 0, 1e-9);
  // Catmull-Rom's tangent at t = 2 is the chord from key 0 to key 2 over its time, m1 = (90, 75, 0)
  // km per unit; at the last key it is one-sided, m2 = (240, 300, 0) / 2 = (120, 150, 0). The cubic
  // Hermite curve halfway through a span of 2 is (p1 + p2) / 2 + 2 (m1 - m2) / 8:
  // x = 180 - 7.5 = 172.5 km, y = -150 - 18.75 = -168.75 km.
  const sl::CameraAt at3 = sl::camera_path_at(path, 3.0);
  CHECK_CLOSE(at3.position[0], 172500.0, 0, 1e-6);
  CHECK_CLOSE(at3.position[1], -168750.0, 0, 1e-6);
  CHECK_CLOSE(at3.position[2], 20000.0, 0, 1e-6);
}

void test_orbit_takes_the_short_way_round()
{
  const std::string scene = write_scene("path_orbit.json", R"({"camera_keys": [
    {"time": 0, "view-azimuth": 350, "view-elevation": 10},
    {"time": 2, "view-azimuth": 10, "view-elevation": 30}]})");
  sl::CameraPath path;
  std::string error;
  CHECK(sl::camera_path_read(scene, &path, &error));
  const sl::CameraAt at = sl::camera_path_at(path, 1.0);
  CHECK(!at.absolute);
  CHECK_CLOSE(std::remainder(at.azimuth, 360.0), 0.0, 0, 1e-9);  // through north, not south
  CHECK_CLOSE(at.elevation, 20.0, 0, 1e-9);
}

void test_keys_by_date()
{
  // 2005-08-28 12:00 and 18:00 UT; 15:00 is halfway (JD 2453611.125, from the calendar).
  const std::string scene = write_scene("path_dates.json", R"({"camera_keys": [
    {"time": "2005-08-28T12:00:00Z", "view-azimuth": 100, "view-elevation": 10, "fov": 20},
    {"time": "2005-08-28T18:00:00Z", "view-azimuth": 160, "view-elevation": 10, "fov": 40}]})");
  sl::CameraPath path;
  std::string error;
  CHECK(sl::camera_path_read(scene, &path, &error));
  CHECK(path.by_date);
  CHECK_CLOSE(path.keys[0].t, 2453610.5 + 0.5, 0, 1e-9);
  const sl::CameraAt at = sl::camera_path_at(path, 2453611.125);
  CHECK_CLOSE(at.azimuth, 130.0, 0, 1e-6);
  CHECK_CLOSE(at.fov, 30.0, 0, 1e-6);
}

void test_bad_keys_are_refused()
{
  const char *bad[] = {
      R"({"camera_keys": [{"time": 0, "view-azimuth": 1, "view-elevation": 2}, {"time": 1, "position": [0,0,0], "look_at": [1,0,0]}]})",
      R"({"camera_keys": [{"time": 2, "view-azimuth": 1, "view-elevation": 2}, {"time": 1, "view-azimuth": 1, "view-elevation": 2}]})",
      R"({"camera_keys": [{"time": 0, "view-azimuth": 1, "view-elevation": 2, "zoom": 3}]})",
      R"({"camera_keys": [{"time": 0, "position": [0,0,0], "look_at": [0,0,0]}]})",
      R"({"camera_keys": [{"time": 0, "view-azimuth": 1, "view-elevation": 2, "fov": 30}, {"time": 1, "view-azimuth": 1, "view-elevation": 2}]})",
      R"({"camera_keys": []})",
  };
  for (const char *json : bad) {
    const std::string scene = write_scene("path_bad.json", json);
    sl::CameraPath path;
    std::string error;
    CHECK_MSG(!sl::camera_path_read(scene, &path, &error), json);
    CHECK_MSG(error.rfind("path_bad.json: ", 0) == 0, error.c_str());
  }
}

void test_times_and_patterns()
{
  std::vector<int> c;
  std::string error;
  CHECK(sl::series_select("all", 4, &c, &error) && c == std::vector<int>({0, 1, 2, 3}));
  CHECK(sl::series_select("1:3", 4, &c, &error) && c == std::vector<int>({1, 2}));
  CHECK(sl::series_select("::2", 5, &c, &error) && c == std::vector<int>({0, 2, 4}));
  CHECK(sl::series_select("2:", 4, &c, &error) && c == std::vector<int>({2, 3}));
  CHECK(sl::series_select("3", 4, &c, &error) && c == std::vector<int>({3}));
  CHECK(!sl::series_select("3:1", 4, &c, &error));
  CHECK(!sl::series_select("0:5", 4, &c, &error));
  CHECK(!sl::series_select("0:2:0", 4, &c, &error));
  CHECK(!sl::series_select("a:b", 4, &c, &error));
  CHECK(sl::frame_pattern_expand("f/s_%04d.exr", 7) == "f/s_0007.exr");
  CHECK(sl::frame_pattern_expand("s%d.png", 12) == "s12.png");
  CHECK(sl::frame_pattern_expand("100%%_%03d.png", 5) == "100%_005.png");
  CHECK(sl::frame_pattern_check("s_%04d.exr", 4, &error));
  CHECK(sl::frame_pattern_check("single.exr", 1, &error));
  CHECK(!sl::frame_pattern_check("single.exr", 2, &error));
  CHECK(!sl::frame_pattern_check("s_%s.exr", 2, &error));
  CHECK(!sl::frame_pattern_check("s_%d_%d.exr", 2, &error));
}

void test_series_in_time_order(const std::string &data)
{
  // Tibet (2005-09-21) given first, Katrina (2005-08-28) second: the series is in time order.
  const std::string katrina = data + "/wrf_katrina2005_d02_mercator_wsm3_4t.nc";
  const std::string tibet = data + "/wrf_tibet2005_d01_lambert_thompson_4t_tiny.nc";
  std::vector<sl::SeriesFrame> s;
  std::string error;
  CHECK_MSG(sl::series_build({tibet, katrina}, &s, &error), error.c_str());
  CHECK(s.size() == 8);
  if (s.size() == 8) {
    CHECK(s[0].file == katrina && s[0].time == "2005-08-28_12:00:00" && s[0].time_index == 0);
    CHECK(s[3].file == katrina && s[3].time == "2005-08-28_21:00:00" && s[3].time_index == 3);
    CHECK(s[4].file == tibet && s[4].time_index == 0);
  }
  CHECK(!sl::series_build({katrina, katrina}, &s, &error));  // the same times twice
  CHECK(error.find("also in") != std::string::npos);
  CHECK(!sl::series_build({data + "/no_such_file.nc"}, &s, &error));
}

}  // namespace

int main(int argc, char **argv)
{
  if (argc < 2) {
    std::fprintf(stderr, "usage: series_unit_test SHARED_WRF_DIR\n");
    return 2;
  }
  test_uniform_motion_is_reproduced();
  test_fixed_target_stays_fixed();
  test_orbit_takes_the_short_way_round();
  test_keys_by_date();
  test_bad_keys_are_refused();
  test_times_and_patterns();
  test_series_in_time_order(argv[1]);
  return sl_test_finish("series_unit");
}
