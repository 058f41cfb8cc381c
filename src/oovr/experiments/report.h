// `oovr report RESULTS.db --out DIR` (docs/report.md): plots (PNG and SVG)
// and one HTML page from a results database, drawn by matplotlib through
// Debian's Python. oovr writes the plotting script it carries (report.py,
// beside this file) and the paper's claims, resolved (claims.json), into
// DIR and runs the script there; both stay, so the page can be drawn again
// or changed without oovr.
#pragma once

#include <string>
#include <vector>

namespace oovr {

struct ReportOptions {
  std::string db;   // an oovr results database
  std::string out;  // the folder written (created)
  // The Python with matplotlib: $OOVR_PYTHON, else /usr/bin/python3 (a
  // python3 earlier on PATH may be one that cannot import Debian's packages).
  std::string python;
  // How the study's figures are drawn (docs/report.md, "Options"), checked
  // against the database before anything is written: the rows of each
  // figure (latency, speedup, throughput, traffic, energy; empty: the
  // default rows the database can fill), the swept keys to plot against
  // (empty: all), panels per "scene" or per "scheme", the scheme speed-ups
  // are over, and whether absolute rows keep each panel's own y axis.
  std::vector<std::string> plots;
  std::vector<std::string> x;
  std::string group = "scene";
  std::string normalise = "baseline";
  bool own_y = false;
};

// Writes the report; returns the page's path. Throws Error when the
// database is missing or not oovr's, an option names a plot, key or
// scheme the database does not have, the folder cannot be written, or the
// script fails (matplotlib missing: named with the package to install).
std::string write_report(const ReportOptions& o);

}  // namespace oovr
