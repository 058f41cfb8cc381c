// libFuzzer target: what `oovr sweep` reads that a user or a cluster wrote.
// The first byte picks the input: 0, a sweep file (parsed, and resolved when
// it expands to at most 200 points); 1, a line of a SLURM task's results
// file (a run record, as --collect reads it). Bad input must be an Error,
// never a crash, a hang or an unbounded allocation.
#include <cstddef>
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "oovr/core/error.h"
#include "oovr/experiments/results_db.h"
#include "oovr/experiments/sweep.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    if (data[0] == 0) {
      oovr::Sweep s = oovr::parse_sweep(text, "fuzz.toml", "");
      if (s.points.size() <= 200) oovr::resolve_all(s);
    } else if (data[0] == 1) {
      nlohmann::ordered_json j;
      try {
        j = nlohmann::ordered_json::parse(text);
      } catch (const nlohmann::json::exception&) {
        return 0;  // collect names the line and leaves it out
      }
      const oovr::RunRecord r = oovr::run_record_from_json(j);
      // What it read writes back to the same record.
      if (oovr::run_record_from_json(oovr::to_json(r)).id != r.id) __builtin_trap();
    }
  } catch (const oovr::Error&) {
  }
  return 0;
}
