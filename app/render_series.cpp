#include "render_series.h"

#include <cjson/cJSON.h>
#include <sys/stat.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "camera_path.h"
#include "movie.h"
#include "ranks.h"
#include "series.h"
#include "sl_storm.h"
#include "sl_tempfile.h"

namespace sl {

namespace {

bool ends_with(const std::string &s, const std::string &suffix)
{
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

bool is_file(const std::string &path)
{
  struct stat st;
  return stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

std::string number_text(double v)
{
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string vec_text(const double v[3])
{
  return number_text(v[0]) + "," + number_text(v[1]) + "," + number_text(v[2]);
}

// The options a frame's own render gets: the series' options less those the series decides per
// frame (file, time, outputs, camera from the path) or owns (progress, JSON, movie).
std::vector<std::string> frame_options(const Options &o, int argc, char **argv, const CameraPath &path,
                                       bool set_threads)
{
  std::vector<std::string> skip = {"times", "movie", "fps", "overwrite", "out", "time", "json", "quiet", "help"};
  if (!path.keys.empty()) {
    if (path.absolute) skip.insert(skip.end(), {"camera-position", "camera-target"});
    else skip.insert(skip.end(), {"view-azimuth", "view-elevation"});
    if (path.has_fov) skip.push_back("fov");
  }
  if (set_threads) skip.push_back("threads");
  std::vector<std::string> kept;
  for (int i = 1; i < argc; ++i) {
    const std::string &a = argv[i];
    if (a.size() <= 2 || a[0] != '-' || a[1] != '-') continue;  // positional: the series' files
    const size_t eq = a.find('=');
    const std::string name = a.substr(2, eq == std::string::npos ? std::string::npos : eq - 2);
    const bool takes_next = eq == std::string::npos && !o.is_flag(name);
    bool dropped = false;
    for (const std::string &s : skip) dropped = dropped || s == name;
    if (!dropped) {
      kept.push_back(a);
      if (takes_next && i + 1 < argc) kept.push_back(argv[i + 1]);
    }
    if (takes_next) ++i;
  }
  return kept;
}

}  // namespace

void declare_series_options(Options &o)
{
  o.option("times", "all|I:J:K", "render a series: all times of all FILES in time order, or a slice of them (J\n"
           "exclusive); --out then takes a numbered pattern such as frames/storm_%04d.exr (numbered by series index)");
  o.flag("overwrite", "series: render frames whose files exist already (default: skip them, so a series resumes)");
  o.option("movie", "OUT.mp4", "series: also encode the PNG frames (give a .png pattern in --out) with ffmpeg");
  o.option("fps", "N", "series: movie frame rate", "12");
  o.flag("series-frame", "(internal) one frame of a series: never a series itself");
}

int render_series(Options &o, int argc, char **argv, int (*render_frame)(int argc, char **argv, FrameKeep *keep))
{
  const std::string cmd = "render";
  if (o.has("series-frame")) return -1;
  const std::vector<std::string> files = o.positional();
  CameraPath path;
  std::string error;
  if (!camera_path_read(o.has("scene-text") ? o.str("scene-text") : "", &path, &error)) return fail(cmd, error, 2);
  const bool numbered = o.str("out").find('%') != std::string::npos;
  if (!(o.has("times") || o.has("movie") || files.size() > 1 || numbered || !path.keys.empty())) return -1;

  if (files.empty()) return fail(cmd, "give the storm FILES of the series", 2);
  if (!o.has("out")) return fail(cmd, "missing --out PATTERN.exr or PATTERN.png (e.g. frames/storm_%04d.exr)", 2);
  std::vector<std::string> patterns;
  {
    std::stringstream ss(o.str("out"));
    std::string item;
    while (std::getline(ss, item, ','))
      if (!item.empty()) patterns.push_back(item);
  }
  std::string png_pattern;
  for (const std::string &p : patterns) {
    if (!ends_with(p, ".exr") && !ends_with(p, ".png")) return fail(cmd, p + ": output must end in .exr or .png", 2);
    if (ends_with(p, ".png")) png_pattern = p;
  }
  double fps = 12;
  if (!o.number("fps", &fps) || !(fps > 0 && fps <= 240)) return fail(cmd, "--fps must be in (0, 240]", 2);
  if (o.has("movie")) {
    if (!ends_with(o.str("movie"), ".mp4")) return fail(cmd, o.str("movie") + ": the movie must end in .mp4", 2);
    if (png_pattern.empty())
      return fail(cmd, "--movie is made from PNG frames: add a .png pattern to --out (e.g. f_%04d.exr,f_%04d.png)", 2);
    if (!ffmpeg_available(&error)) return fail(cmd, error, 2);
  }

  std::vector<SeriesFrame> series;
  if (!series_build(files, &series, &error)) return fail(cmd, error);
  std::string spec = o.has("times") ? o.str("times") : "all";
  if (!o.has("times") && files.size() == 1 && !numbered) spec = o.str("time");
  std::vector<int> chosen;
  if (!series_select(spec, (int)series.size(), &chosen, &error)) return fail(cmd, error, 2);
  for (const std::string &p : patterns)
    if (!frame_pattern_check(p, (int)chosen.size(), &error)) return fail(cmd, error, 2);
  if (path.by_date)
    for (int i : chosen)
      if (series[i].time.empty())
        return fail(cmd, series[i].file + ": the camera keys give dates but the file has no times", 2);

  Ranks ranks;
  const bool lead = ranks.rank() == 0;
  const bool json = o.has("json"), quiet = o.has("quiet") || json;

  // A frame is complete when all its files exist: each was renamed into place only when whole.
  std::vector<int> pending;
  std::vector<bool> complete(series.size(), false);
  for (int i : chosen) {
    bool all = true;
    for (const std::string &p : patterns) all = all && is_file(frame_pattern_expand(p, i));
    complete[i] = all && !o.has("overwrite");
    if (!complete[i]) pending.push_back(i);
  }
  for (const std::string &p : patterns) {
    const std::filesystem::path dir = std::filesystem::path(frame_pattern_expand(p, 0)).parent_path();
    std::error_code ec;
    if (!dir.empty()) std::filesystem::create_directories(dir, ec);
  }
  // A killed run's temporary frames (their writer is gone) are neither frames nor kept.
  int stale = 0;
  if (lead)
    for (int i : chosen)
      for (const std::string &p : patterns) {
        int n = 0;
        sl_error err{};
        if (sl_temp_remove_stale(frame_pattern_expand(p, i).c_str(), &n, &err)) return fail(cmd, err.message);
        stale += n;
      }
  // Nobody writes a frame before every rank has decided what is pending.
  ranks.barrier();

  // One world frame for the whole series, so a moving nest moves across it and a camera path
  // stays put: the ENU frame of the first frame's grid centre, unless --origin sets it (where the
  // reader offers the option).
  std::string origin;
  double origin_ll[3] = {0, 0, 1};
  if (o.declared("origin") && !o.has("origin")) {
    std::string load_error;
    if (lead) {
      const SeriesFrame &first = series[chosen.front()];
      sl_load_options lo{};
      lo.time_index = first.time_index;
      sl_storm_frame frame{};
      sl_error err{};
      if (sl_storm_load(first.file.c_str(), &lo, &frame, &err) == SL_OK) {
        origin_ll[0] = frame.center_lat, origin_ll[1] = frame.center_lon, origin_ll[2] = 0;
        sl_storm_frame_free(&frame);
      } else {
        load_error = err.message;
      }
    }
    ranks.broadcast(origin_ll, 3);
    if (origin_ll[2] != 0) return lead ? fail(cmd, load_error) : 1;
    // A grid with no place (CM1's flat plane) has no centre to keep: its frames share the grid's
    // own axes already, and the sun comes from its angles.
    if (std::isfinite(origin_ll[0]) && std::isfinite(origin_ll[1]))
      origin = number_text(origin_ll[0]) + "," + number_text(origin_ll[1]);
  }

  const bool set_threads = ranks.parallel() && !o.has("threads");
  const int threads = ranks.thread_share();
  const std::vector<std::string> common = frame_options(o, argc, argv, path, set_threads);
  if (lead && !quiet) {
    std::printf("series: %zu frames, %zu already complete, %zu to render", chosen.size(), chosen.size() - pending.size(),
                pending.size());
    if (stale) std::printf(" (%d stale temporary file%s of a killed run removed)", stale, stale == 1 ? "" : "s");
    if (ranks.parallel()) std::printf(" on %d ranks (%d thread%s each)", ranks.size(), threads, threads == 1 ? "" : "s");
    std::printf("\n");
    std::fflush(stdout);
  }

  Progress progress("series", lead && !quiet);
  const bool log_frames = !quiet && !stderr_is_tty();
  int finished = 0, failed = 0, own_failed = 0;
  double frame_seconds = 0;
  const double t_start = now_seconds();
  const auto drain = [&](bool wait) {
    int n, bad, ms;
    while (ranks.poll(&n, &bad, &ms, wait && finished < (int)pending.size())) {
      finished += n, failed += bad, frame_seconds += 1e-3 * ms;
      progress.update((double)finished / pending.size());
      if (!wait) continue;
      if (finished >= (int)pending.size()) break;
    }
  };
  std::vector<int> mine;
  for (size_t j = ranks.rank(); j < pending.size(); j += ranks.size()) mine.push_back(pending[j]);
  // Kept from frame to frame: VTK's compositing window; each frame's stages come back in it.
  FrameKeep keep;
  std::vector<FrameTimes> stages(series.size());
  std::vector<double> walls(series.size(), 0.0);  // > 0: rendered here, with its stages
  for (size_t m = 0; m < mine.size(); ++m) {
    const int i = mine[m];
    const SeriesFrame &f = series[i];
    std::vector<std::string> args = {"render", f.file, "--series-frame", "--quiet", "--time",
                                     std::to_string(f.time_index)};
    std::string outs;
    for (const std::string &p : patterns) outs += (outs.empty() ? "" : ",") + frame_pattern_expand(p, i);
    args.insert(args.end(), {"--out", outs});
    if (set_threads) args.insert(args.end(), {"--threads", std::to_string(threads)});
    if (!origin.empty()) args.insert(args.end(), {"--origin", origin});
    if (!path.keys.empty()) {
      const CameraAt c = camera_path_at(path, path.by_date ? f.julian_day : (double)i);
      if (c.absolute)
        args.insert(args.end(), {"--camera-position", vec_text(c.position), "--camera-target", vec_text(c.look_at)});
      else
        args.insert(args.end(), {"--view-azimuth", number_text(c.azimuth), "--view-elevation", number_text(c.elevation)});
      if (c.has_fov) args.insert(args.end(), {"--fov", number_text(c.fov)});
    }
    args.insert(args.end(), common.begin(), common.end());
    std::vector<char *> frame_argv;
    for (std::string &s : args) frame_argv.push_back(&s[0]);
    keep.times = FrameTimes{};
    const double t0 = now_seconds();
    const int rc = render_frame((int)frame_argv.size(), frame_argv.data(), &keep);
    const double seconds = now_seconds() - t0;
    const FrameTimes &t = keep.times;
    // What the frame cost beyond its stages: its set-up and whatever else each frame pays again.
    const double other = seconds - (t.load + t.draw + t.composite + t.write);
    if (!rc) stages[i] = t, walls[i] = seconds;
    if (log_frames) {
      std::printf("%sframe %d (%s time %d%s%s): %s %.2f s", ranks.parallel() ? ("[rank " + std::to_string(ranks.rank()) + "] ").c_str() : "",
                  i, f.file.c_str(), f.time_index, f.time.empty() ? "" : ", ", f.time.c_str(), rc ? "FAILED" : outs.c_str(),
                  seconds);
      if (!rc)
        std::printf(" (load %.2f, draw %.2f, composite %.2f, write %.2f, other %.2f s of which set-up %.2f)", t.load,
                    t.draw, t.composite, t.write, other, t.setup);
      std::printf("\n");
      std::fflush(stdout);
    }
    if (rc) {
      // The first failure ends this rank's share; the rest of it counts as failed.
      own_failed = (int)(mine.size() - m);
      if (lead) finished += own_failed, failed += own_failed;
      else ranks.report(own_failed, own_failed, (int)(1e3 * seconds));
      break;
    }
    if (lead) {
      ++finished, frame_seconds += seconds;
      progress.update((double)finished / pending.size());
      drain(false);
    } else {
      ranks.report(1, 0, (int)(1e3 * seconds));
    }
  }
  if (!lead) return own_failed ? 1 : 0;
  drain(true);
  progress.done();
  const double wall = now_seconds() - t_start;

  int rc = failed ? 1 : 0;
  std::string movie_note;
  if (!failed && o.has("movie")) {
    std::vector<std::string> pngs;
    for (int i : chosen) pngs.push_back(frame_pattern_expand(png_pattern, i));
    const double t0 = now_seconds();
    if (!write_movie(pngs, o.str("movie"), fps, &error)) rc = fail(cmd, error);
    else movie_note = o.str("movie");
    if (!quiet && rc == 0)
      std::printf("movie %s: %zu frames at %g fps, %.2f s\n", o.str("movie").c_str(), pngs.size(), fps,
                  now_seconds() - t0);
  }
  const int rendered = finished - failed;
  if (failed) fail(cmd, std::to_string(failed) + " of " + std::to_string(pending.size()) + " frames failed");
  // Per frame, over the frames rendered here: the draw (its passes, the resolve and the sky)
  // against all else a frame paid besides its load, composite and write.
  FrameTimes sum;
  double sum_wall = 0;
  int timed = 0;
  for (size_t i = 0; i < series.size(); ++i)
    if (walls[i] > 0) {
      const FrameTimes &t = stages[i];
      sum_wall += walls[i], ++timed;
      sum.load += t.load, sum.setup += t.setup, sum.draw += t.draw, sum.composite += t.composite, sum.write += t.write;
    }
  const double other = timed ? (sum_wall - sum.load - sum.draw - sum.composite - sum.write) / timed : 0.0;
  const double per_draw = timed ? sum.draw / timed : 0.0;
  if (!quiet) {
    std::printf("series: rendered %d frames in %.2f s (%.2f s per frame on one rank, %.1f frames per minute)\n",
                rendered, wall, rendered ? frame_seconds / rendered : 0.0, wall > 0 ? 60.0 * rendered / wall : 0.0);
    if (timed)
      std::printf("series: per frame load %.3f s, draw %.3f s, composite %.3f s, write %.3f s, other %.3f s "
                  "(set-up %.3f s): %.0f %% of the draw besides load, composite and write\n",
                  sum.load / timed, per_draw, sum.composite / timed, sum.write / timed, other, sum.setup / timed,
                  per_draw > 0 ? 100.0 * other / per_draw : 0.0);
  }
  if (json) {
    cJSON *root = cJSON_CreateObject();
    cJSON_AddNumberToObject(root, "frames", (double)chosen.size());
    cJSON_AddNumberToObject(root, "skipped", (double)(chosen.size() - pending.size()));
    cJSON_AddNumberToObject(root, "stale_temporary_removed", stale);
    cJSON_AddNumberToObject(root, "rendered", rendered);
    cJSON_AddNumberToObject(root, "failed", failed);
    cJSON_AddNumberToObject(root, "ranks", ranks.size());
    cJSON_AddNumberToObject(root, "threads_per_rank", ranks.parallel() && set_threads ? threads : 0);
    cJSON_AddNumberToObject(root, "seconds", wall);
    cJSON_AddNumberToObject(root, "seconds_per_frame", rendered ? frame_seconds / rendered : 0.0);
    cJSON_AddNumberToObject(root, "frames_per_minute", wall > 0 ? 60.0 * rendered / wall : 0.0);
    if (!movie_note.empty()) cJSON_AddStringToObject(root, "movie", movie_note.c_str());
    if (!origin.empty()) cJSON_AddItemToObject(root, "origin", cJSON_CreateDoubleArray(origin_ll, 2));
    cJSON *list = cJSON_AddArrayToObject(root, "series");
    for (int i : chosen) {
      cJSON *f = cJSON_CreateObject();
      cJSON_AddNumberToObject(f, "index", i);
      cJSON_AddStringToObject(f, "file", series[i].file.c_str());
      cJSON_AddNumberToObject(f, "time_index", series[i].time_index);
      cJSON_AddStringToObject(f, "time", series[i].time.c_str());
      cJSON_AddBoolToObject(f, "skipped", complete[i]);
      if (walls[i] > 0) {  // rendered here (on the lead rank), with its stages
        const FrameTimes &t = stages[i];
        cJSON *st = cJSON_AddObjectToObject(f, "seconds");
        cJSON_AddNumberToObject(st, "frame", walls[i]);
        cJSON_AddNumberToObject(st, "load", t.load);
        cJSON_AddNumberToObject(st, "setup", t.setup);
        cJSON_AddNumberToObject(st, "draw", t.draw);
        cJSON_AddNumberToObject(st, "composite", t.composite);
        cJSON_AddNumberToObject(st, "write", t.write);
      }
      if (!path.keys.empty()) {
        const CameraAt c = camera_path_at(path, path.by_date ? series[i].julian_day : (double)i);
        cJSON *cam = cJSON_AddObjectToObject(f, "camera");
        if (c.absolute) {
          cJSON_AddItemToObject(cam, "position", cJSON_CreateDoubleArray(c.position, 3));
          cJSON_AddItemToObject(cam, "look_at", cJSON_CreateDoubleArray(c.look_at, 3));
        } else {
          cJSON_AddNumberToObject(cam, "view_azimuth", c.azimuth);
          cJSON_AddNumberToObject(cam, "view_elevation", c.elevation);
        }
        if (c.has_fov) cJSON_AddNumberToObject(cam, "fov", c.fov);
      }
      cJSON_AddItemToArray(list, f);
    }
    char *text = cJSON_PrintUnformatted(root);
    std::printf("%s\n", text);
    std::free(text);
    cJSON_Delete(root);
  }
  return rc;
}

}  // namespace sl
