#include "series.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <memory>

#include "sl_sky.h"
#include "sl_series.h"
#include "sl_storm.h"

bool sl_parse_iso8601_utc(const std::string &text, sl_utc *out, std::string *why);  // cmd_sun.cpp

namespace sl {

bool series_build(const std::vector<std::string> &files, std::vector<SeriesFrame> *series, std::string *error)
{
  // io/ orders the files' times (and expands glob patterns); the app adds the Julian day.
  series->clear();
  std::vector<const char *> paths;
  for (const std::string &f : files) paths.push_back(f.c_str());
  sl_series s{};
  sl_error err{};
  if (sl_series_open(paths.data(), (int)paths.size(), &s, &err) != SL_OK) {
    *error = err.message;
    return false;
  }
  bool ok = true;
  for (int i = 0; i < s.count && ok; ++i) {
    SeriesFrame f;
    f.file = s.frames[i].path;
    f.time_index = s.frames[i].time_index;
    f.time = s.frames[i].time;
    if (!f.time.empty()) {
      std::string iso = f.time, why;
      for (char &ch : iso)
        if (ch == '_') ch = 'T';
      sl_utc utc{};
      if (!sl_parse_iso8601_utc(iso + "Z", &utc, &why)) {
        *error = f.file + ": time '" + f.time + "' is not a date-time";
        ok = false;
      }
      f.julian_day = sl_julian_day(&utc);
    }
    series->push_back(f);
  }
  sl_series_free(&s);
  return ok;
}

namespace {

bool parse_int(const std::string &s, long *out)
{
  if (s.empty()) return false;
  char *end = nullptr;
  *out = std::strtol(s.c_str(), &end, 10);
  return *end == '\0';
}

}  // namespace

bool series_select(const std::string &spec, int count, std::vector<int> *chosen, std::string *error)
{
  chosen->clear();
  if (spec == "all") {
    for (int i = 0; i < count; ++i) chosen->push_back(i);
    return true;
  }
  std::vector<std::string> parts;
  size_t start = 0;
  for (size_t c; (c = spec.find(':', start)) != std::string::npos; start = c + 1) parts.push_back(spec.substr(start, c - start));
  parts.push_back(spec.substr(start));
  const std::string bad = "--times '" + spec + "': give all or I:J:K with 0 <= I < J <= " + std::to_string(count) +
                          " (J exclusive) and K >= 1";
  long i = 0, j = count, k = 1;
  if (parts.size() > 3 || (!parts[0].empty() && !parse_int(parts[0], &i)) ||
      (parts.size() > 1 && !parts[1].empty() && !parse_int(parts[1], &j)) ||
      (parts.size() > 2 && !parts[2].empty() && !parse_int(parts[2], &k))) {
    *error = bad;
    return false;
  }
  if (parts.size() == 1) j = i + 1;
  if (i < 0 || j > count || i >= j || k < 1) {
    *error = bad;
    return false;
  }
  for (long n = i; n < j; n += k) chosen->push_back((int)n);
  return true;
}

namespace {

// Counts the integer fields and notes the last one's position and length; false on a malformed '%'.
bool find_field(const std::string &p, size_t *pos, size_t *len, int *fields)
{
  *fields = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    if (p[i] != '%') continue;
    if (i + 1 < p.size() && p[i + 1] == '%') {
      ++i;
      continue;
    }
    size_t j = i + 1;
    while (j < p.size() && std::isdigit((unsigned char)p[j])) ++j;
    if (j >= p.size() || p[j] != 'd' || j - i - 1 > 2) return false;
    *pos = i;
    *len = j - i + 1;
    ++*fields;
    i = j;
  }
  return true;
}

}  // namespace

bool frame_pattern_check(const std::string &pattern, int count, std::string *error)
{
  size_t pos = 0, len = 0;
  int fields = 0;
  if (!find_field(pattern, &pos, &len, &fields) || fields > 1) {
    *error = pattern + ": a frame pattern holds one %d, %4d or %04d field (and %% for a literal %)";
    return false;
  }
  if (fields == 0 && count > 1) {
    *error = pattern + ": several frames need a numbered pattern such as frames/storm_%04d.exr";
    return false;
  }
  return true;
}

std::string frame_pattern_expand(const std::string &pattern, int number)
{
  std::string out;
  for (size_t i = 0; i < pattern.size(); ++i) {
    if (pattern[i] != '%') {
      out += pattern[i];
      continue;
    }
    if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
      out += '%';
      ++i;
      continue;
    }
    size_t j = i + 1;
    const bool zero = j < pattern.size() && pattern[j] == '0';
    int width = 0;
    while (j < pattern.size() && std::isdigit((unsigned char)pattern[j])) width = 10 * width + (pattern[j++] - '0');
    std::string digits = std::to_string(number);
    if ((int)digits.size() < width) digits.insert(0, width - digits.size(), zero ? '0' : ' ');
    out += digits;
    i = j;  // the 'd'
  }
  return out;
}

}  // namespace sl
