// A time series of storm frames over one or more files: which file and time index each frame
// comes from, in time order (io/sl_series.h orders them; this adds what the app needs).
#pragma once

#include <string>
#include <vector>

namespace sl {

struct SeriesFrame {
  std::string file;     // the storm file holding this time
  int time_index = 0;   // 0-based index of the time inside that file
  std::string time;     // the file's "YYYY-MM-DD_hh:mm:ss", empty when the file has no times
  double julian_day = 0; // UT, when time is set
};

// Every time of every file (glob patterns expanded), in time order (by the files' own times when
// all have them, else in the order given, each file's times in order). Fails with one line naming
// the file for an unreadable file, a file with no time records, or the same time in two places.
bool series_build(const std::vector<std::string> &files, std::vector<SeriesFrame> *series, std::string *error);

// The frames chosen by --times: "all" or a Python-like slice "I:J:K" (J exclusive; each part may
// be empty: "2:", ":3", "::2"; a lone "I" is one frame). Returns indices into the series.
bool series_select(const std::string &spec, int count, std::vector<int> *chosen, std::string *error);

// Checks that pattern holds exactly one printf-style integer field (%d, %4d or %04d) and no other
// '%' (write %% for a literal one). With count == 1 a pattern without a field is accepted.
bool frame_pattern_check(const std::string &pattern, int count, std::string *error);
// The pattern with its integer field replaced by number.
std::string frame_pattern_expand(const std::string &pattern, int number);

}  // namespace sl
