// libFuzzer target: a sweep's name, and any text oovr writes to a terminal.
// The input is the name, as a TOML basic string holds it (escaped); a name
// parse_sweep accepts must be safe in every place a name goes: a file name
// (no '/', not "." or ".."), an sbatch script's #SBATCH line and its
// comment (no control character), HTML (no '<', '&' or quote) and a
// terminal. printable() of the raw bytes must hold no control character.
#include <cstddef>
#include <cstdint>
#include <string>

#include "oovr/core/error.h"
#include "oovr/core/text.h"
#include "oovr/experiments/sweep.h"

namespace {

bool has_control(const std::string& s) {
  for (size_t i = 0; i < s.size(); ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c < 0x20 || c == 0x7f) return true;
    if (c == 0xc2 && i + 1 < s.size() && static_cast<unsigned char>(s[i + 1]) >= 0x80 &&
        static_cast<unsigned char>(s[i + 1]) <= 0x9f)
      return true;
  }
  return false;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string raw(reinterpret_cast<const char*>(data), size);
  if (has_control(oovr::printable(raw))) __builtin_trap();
  std::string quoted;
  for (const unsigned char c : raw) {
    static const char* hex = "0123456789abcdef";
    if (c == '"' || c == '\\' || c < 0x20 || c == 0x7f) {
      quoted += "\\u00";
      quoted += hex[c >> 4];
      quoted += hex[c & 15];
    } else {
      quoted += char(c);
    }
  }
  try {
    const oovr::Sweep s =
        oovr::parse_sweep("name = \"" + quoted + "\"\nscenes = [\"crowd\"]\nschemes = [\"baseline\"]\n", "f.toml", "");
    const std::string& n = s.name;
    if (!oovr::is_sweep_name(n) || n.empty() || n.size() > 64) __builtin_trap();
    if (n.find_first_of("/<>&\"' \\$`;|*?()[]{}") != std::string::npos || n == "." || n == ".." || n[0] == '-') __builtin_trap();
    if (has_control(n)) __builtin_trap();
  } catch (const oovr::Error&) {
  }
  return 0;
}
