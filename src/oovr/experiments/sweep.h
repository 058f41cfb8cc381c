// Sweep definitions (`oovr sweep FILE.toml`, docs/sweeps.md): scenes,
// schemes, resolutions, frames and any configuration keys with lists of
// values, crossed, plus explicit points. Each point is resolved against the
// machine configuration (preset, fixed settings, swept values, defaults)
// and named by a stable id: a hash of everything that determines its
// result, so the same point in another sweep, on another host or after a
// restart has the same id.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "oovr/core/config.h"
#include "oovr/schemes/machine_spec.h"

namespace oovr {

// A sweep of more points than this is refused before it is expanded: a
// resolved point holds its whole configuration (docs/reliability.md), and a
// typo'd list should not allocate gigabytes of points. Larger studies are
// several sweeps into one database.
inline constexpr size_t kMaxPoints = 100000;

// The longest name or value a sweep file may give (a scene's path, a
// setting), and so the longest a run record keeps (results_db.h).
inline constexpr size_t kMaxNameChars = 4096;

// Whether `name` is a sweep name oovr takes: 1 to 64 letters, digits, '_',
// '-' and '.', not starting with '.' or '-'. A sweep's name reaches a SLURM
// job script, file names, the report's HTML and the terminal.
bool is_sweep_name(const std::string& name);

struct SweepPoint {
  std::string scene;
  std::string scheme;
  std::string resolution = "1280x1024";  // the whole stereo frame, WxH
  int frame = 0;                         // first frame of the camera path
  int frames = 0;                        // measured frames; 0: one per GPM (as oovr compare)
  int aniso = 16;
  // Configuration overrides in the order applied: the file's fixed [set]
  // table, then the swept values.
  std::vector<std::pair<std::string, std::string>> settings;
  // The swept keys' values of this point ("link.bandwidth" -> "32GBps"),
  // which the database keeps as columns.
  std::map<std::string, std::string> swept;

  // Filled by resolve():
  std::string id;  // 16 hex digits
  int window = 0;  // frames actually measured
  // The machine: preset + settings, every key read once (its config and
  // entries within), what the point's run is given.
  MachineSpec machine;
  std::string canonical;  // the JSON the id hashes
};

struct Sweep {
  std::string name;                     // "name" in the file, else the file's stem
  std::string file;                     // as given
  std::string definition;               // the file's text, kept with the results
  std::string preset;                   // machine preset (resolved against the file's folder), "" for Table 1
  bool images = false;                  // store each point's GPM image and tile traffic (images = true)
  std::vector<std::string> swept_keys;  // in file order: the columns
  std::vector<SweepPoint> points;       // in file order, unresolved
  // The file's top-level [set], in file order: the first settings of every
  // point (sweep_machine's machine, for resolve_on_machine).
  std::vector<std::pair<std::string, std::string>> base_settings;
  // Filled by resolve_all and resolve_on_machine: the points that were the
  // same run as an earlier point, in words. They are not run again: the
  // earlier point's run is theirs, so they are left out of `points`.
  std::vector<std::string> shared;
};

// Reads and expands a sweep file. Throws Error naming the file and what is
// wrong (an unknown key, a list where one value is wanted, an empty list,
// a point that names no scene, two points with the same id).
// `settings`: --set's overrides of the file's [set] (sweep_with_settings).
Sweep read_sweep(const std::string& path, const std::vector<std::string>& settings = {});
Sweep parse_sweep(const std::string& text, const std::string& name, const std::string& base_dir);

// The sweep file's text with `settings` ("key=value", as --set takes them)
// in its top-level [set] table, replacing the file's own value of a key,
// each value as the text given (what a configuration key reads): the text
// the sweep then is, kept with its results and copied to a SLURM job, so
// that a resume or a task reads the same points. A key the file sweeps, or
// that a point sets or sweeps, is refused (overriding it would silently
// change what the file says it varies), as is a setting without '='.
// Throws Error naming the setting.
std::string sweep_with_settings(const std::string& text, const std::string& name, const std::vector<std::string>& settings);

// A sweep definition given as data (the Python module's dicts, as JSON) as
// the TOML text of a sweep file with the same keys, for parse_sweep. Throws
// Error naming a value TOML cannot hold (null) or nesting too deep.
std::string sweep_toml(const nlohmann::json& definition);

// Resolves a point against `machine` (the preset with its keys): applies
// its settings, checks every key and the scheme, fixes the frame window and
// computes the id. Throws Error naming the point on a bad value.
void resolve(SweepPoint& p, const Config& machine);

// Resolves every point of `s` and returns the machine preset they start
// from. A point that is the same run as an earlier one (the same id) is not
// run twice: it is left out of s.points, said in s.shared, and the earlier
// point takes the swept values it lacks (its row in the database has them).
Config resolve_all(Sweep& s);

// A sweep file's text with the machine its points run on written out whole
// in its top-level [set] (`oovr paper --config/--set`): the values of the
// preset `preset` (else of the file's `config`, relative to `base_dir`),
// then the file's own [set], then `settings` ("key=value", as --set takes
// them), a later value of a key replacing an earlier one; `config` is
// dropped, so that the text alone says what the machine was (it is kept with
// the results). Unlike sweep_with_settings, a key the points set or sweep may
// be given: it is the machine's, and the points that set it keep their own
// (resolve_on_machine). `sources` receives where each [set] key came from
// ("FILE.toml:LINE", "--set", "FILE [set]"). `frames` (0: the file's)
// replaces the file's top-level `frames`, the window every point measures (a
// machine of 8 GPMs needs 8 for AFR), refused where a point sets its own.
// Returns `text` itself when there is nothing to write. Throws Error naming
// a bad setting or preset.
std::string sweep_on_machine(const std::string& text, const std::string& name, const std::string& base_dir,
                             const std::string& preset, const std::vector<std::string>& settings, int frames = 0,
                             std::map<std::string, std::string>* sources = nullptr);

// The machine a sweep's [set] describes: its preset, then s.base_settings,
// each key's source `sources`' label for it, else "FILE [set]". Throws
// Error naming a key no part of oovr reads.
Config sweep_machine(const Sweep& s, const std::map<std::string, std::string>& sources = {});

// Resolves every point of `s` on sweep_machine(s, sources), its own
// settings (its point's set and sweep, not the file's [set]) on top: a
// machine key its scheme does not read is simply not its (`oo.*` for the
// baseline). Points that are the same run are shared as by resolve_all.
// Returns the machine.
Config resolve_on_machine(Sweep& s, const std::map<std::string, std::string>& sources = {});

// The trace group a point's traces come from: points with the same scene,
// resolution, first frame, filtering and line size replay the same traces.
std::string trace_group(const SweepPoint& p);

// "ab12...": FNV-1a 64 of `text` as 16 lower-case hex digits.
std::string stable_id(const std::string& text);

// The JSON a point's id hashes: what determines its result, numbers in base
// units ("64GBps" and 64e9 are one point). `config`: every key's base value
// (or its text, for keys without a unit), keys in order. resolve() and
// results_db's check of a stored run both make it here, so that they agree.
std::string canonical_point(const std::string& scene, const std::string& scheme, const std::string& resolution, int frame,
                            int frames, int aniso, const nlohmann::ordered_json& config);

}  // namespace oovr
