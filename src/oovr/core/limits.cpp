#include "oovr/core/limits.h"

#include <cstdlib>

#include "oovr/core/error.h"
#include "oovr/core/text.h"
#include "oovr/core/units.h"

namespace oovr {

InputLimits InputLimits::parse(const std::string& text) {
  InputLimits l;
  for (const std::string& pair : split_list(text)) {
    const size_t eq = pair.find('=');
    const std::string name = pair.substr(0, eq), value = eq == std::string::npos ? "" : pair.substr(eq + 1);
    const std::string what = "OOVR_LIMITS " + name;
    const auto whole = [&](uint64_t lo, uint64_t hi) {
      const auto v = parse_whole_number(value, lo, hi);
      if (!v)
        throw Error(what + " must be a whole number from " + std::to_string(lo) + " to " + std::to_string(hi) + ", not '" +
                    value + "'");
      return *v;
    };
    const auto bytes = [&] {
      const Bytes b = parse_bytes(value, what);
      if (b.value < 1) throw Error(what + " must be at least 1 byte");
      return b.value;
    };
    if (name == "image_side") l.image_side = int(whole(1, 1 << 20));
    else if (name == "image_texels") l.image_texels = whole(1, uint64_t(1) << 40);
    else if (name == "file_bytes") l.file_bytes = bytes();
    else if (name == "elements") l.elements = whole(1, uint64_t(1) << 40);
    else if (name == "scene_bytes") l.scene_bytes = bytes();
    else if (name == "nesting") l.nesting = int(whole(1, 100000));
    else if (name == "draws") l.draws = whole(1, uint64_t(1) << 32);
    else
      throw Error("OOVR_LIMITS: unknown limit '" + name +
                  "' (limits: image_side, image_texels, file_bytes, elements, scene_bytes, nesting, draws)");
  }
  return l;
}

const InputLimits& InputLimits::get() {
  static const InputLimits limits = [] {
    const char* env = std::getenv("OOVR_LIMITS");
    return env ? parse(env) : InputLimits{};
  }();
  return limits;
}

void check_limit(uint64_t count, uint64_t limit, const char* name, const std::string& what, const char* things) {
  if (count > limit)
    throw Error(what + ": " + std::to_string(count) + " " + things + ", more than the limit of " + std::to_string(limit) +
                " ($OOVR_LIMITS " + name + ")");
}

void exceeded_limit(uint64_t limit, const char* name, const std::string& what, const char* things) {
  throw Error(what + ": more than " + std::to_string(limit) + " " + things + " ($OOVR_LIMITS " + name + ")");
}

}  // namespace oovr
