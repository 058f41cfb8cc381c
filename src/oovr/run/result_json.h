// Results as JSON: one document shape for `oovr simulate --json`, `oovr
// compare --json` and `oovr paper`'s results.json (docs/results.md). Every
// document says what it is and what made it: schema and version, oovr's
// version and commit, the command line, and the configuration with each
// value readable, in base units and with its source.
#pragma once

#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "oovr/core/config.h"
#include "oovr/run/result_metrics.h"
#include "oovr/scene/stereo.h"
#include "oovr/schemes/i_scheme.h"

namespace oovr {

// Bumped when a field changes meaning or goes; new fields do not bump it.
inline constexpr int kResultsSchemaVersion = 1;

// {"schema": "oovr.results", "schema_version", "oovr": {version, commit},
// "command"}: the start of every results document.
nlohmann::ordered_json results_header(const std::string& command);

// A configuration value as results store it: the number in base units, or
// the readable value for keys without a number (strings, choices).
nlohmann::ordered_json base_value(const Config::Entry& e);

// {key: {"value", "base", "unit", "source"}}; "base" and "unit" only for
// numbers ("base" is the value in "unit": bytes, bytes per second, seconds,
// hertz; no unit for counts and ratios).
nlohmann::ordered_json to_json(const std::map<std::string, Config::Entry>& config);

// One scheme's run: its figures and the configuration it ran with (the
// machine's, after the scheme's own overrides such as baseline-1tb's links).
nlohmann::ordered_json to_json(const SchemeResult& r);

// A run back from its JSON (a results database's `result`): every figure
// to_json writes, exactly (not the per-tile bytes or tile owners, which it
// does not write; configuration entries without their default and kind).
// Throws Error on JSON that is not a run's.
// Numbers read back from JSON, strictly: a whole number in [lo, hi] (not a
// fraction, not narrowed, not wrapped), a count (a whole number >= 0), a
// finite number. Each throws Error naming `what`.
int64_t json_whole(const nlohmann::ordered_json& v, int64_t lo, int64_t hi, const std::string& what);
uint64_t json_count(const nlohmann::ordered_json& v, const std::string& what);
double json_finite(const nlohmann::ordered_json& v, const std::string& what);

// The result is checked as check_scheme_result does.
SchemeResult scheme_result_from_json(const nlohmann::ordered_json& j);

// A run as a results database stores it (`runs.result`): to_json without
// its statistics and what is derived from them (`stats`, `memory`,
// `scheme_metrics`), which the run's metrics rows hold, so that each
// figure is stored once.
nlohmann::ordered_json stored_result_json(const SchemeResult& r);
// A stored run back from its result and its metrics rows, in the order
// they were written (metrics_of's): the statistics are the rows that are
// statistics (is_stat_row). A result that carries its statistics (written
// before the database stored them once) is read from itself. Throws Error
// as scheme_result_from_json does.
SchemeResult scheme_result_from_stored(const nlohmann::ordered_json& result, const std::vector<Metric>& rows);
// Throws Error when a result read back cannot be one of oovr's: GPMs out
// of range, latencies, frequency or throughput not positive and finite,
// per-GPM figures of the wrong count (what is divided or drawn later).
void check_scheme_result(const SchemeResult& r);

// The document simulate and compare write: the header, what was rendered
// (scene, first frame, frames in the window, the stereo frame's size), the
// machine as given (`config`, every key read and described), a run per
// scheme with ratios against the baseline when it ran, and the trace
// cache's notes.
nlohmann::ordered_json results_document(const std::string& command, const std::string& scene, int frame, int frames,
                                        const StereoRig& rig, const Config& config, const std::vector<SchemeResult>& results,
                                        const std::vector<std::string>& trace_notes);

}  // namespace oovr
