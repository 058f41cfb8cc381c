// The simulated machine, typed: read from the configuration once per run at
// the entry points (`oovr simulate`/`compare`, a sweep's point, Python) and
// carried by every scheme input, so that no setting is parsed twice in a
// run. A scheme's configure() edits its typed fields (baseline-1tb's links,
// ideal's GPM) and says so with set_entry, which is what its results
// record; a scheme's own section (ConfigSection::scheme_section, OO-VR's
// `oo`) is read here too, into own().
#pragma once

#include <any>
#include <map>
#include <optional>
#include <string>

#include "oovr/core/config.h"
#include "oovr/memory/memory_spec.h"
#include "oovr/pipeline/pipeline.h"
#include "oovr/schemes/composition_spec.h"
#include "oovr/timing/gpm_model.h"

namespace oovr {

struct MachineSpec {
  MemorySpec memory;
  TimingSpec timing;
  CompositionSpec composition;
  PipelineSettings pipeline;  // its texture_format; line size and filtering are the trace's
  // Every key read, described (Config::entries), with the scheme's own
  // overrides once configure() has run: what a result records.
  std::map<std::string, Config::Entry> entries;
  // The configuration it was read from (a scheme written in Python edits a
  // copy of it in its configure()).
  Config config;
  // Record every unit's time into SchemeResult::timeline (oovr simulate
  // --timeline). Not configuration: it changes what a run keeps, never its
  // numbers or its id.
  bool timeline = false;

  // Reads every key of `c` once: the machine's sections into the fields
  // above, each scheme's own section into own() (or, for a section without
  // a reader, its check), then refuses keys nobody read (check_config).
  // Throws Error as check_config does.
  static MachineSpec from_config(const Config& c);

  // A scheme's own section's settings, as its reader made them
  // (ConfigSection::read); throws Error when the section has none.
  template <class T>
  const T& own(const std::string& section) const {
    const auto it = m_own.find(section);
    if (it == m_own.end()) throw_missing(section);
    return std::any_cast<const T&>(it->second);
  }

  // Who is configuring now ("scheme baseline-1tb"): the source set_entry
  // records.
  void set_source(std::string source) { m_source = std::move(source); }
  const std::string& source() const { return m_source; }
  // Records that the scheme set `key` to `value` (readable, as Config
  // writes it: "1 TB/s") and `base` (in the key's base unit); the key's
  // default, kind and unit stay as read.
  void set_entry(const std::string& key, std::string value, std::optional<double> base);

 private:
  [[noreturn]] static void throw_missing(const std::string& section);
  std::map<std::string, std::any> m_own;
  std::string m_source = "scheme";
};

}  // namespace oovr
