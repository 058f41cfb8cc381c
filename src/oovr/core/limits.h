// Bounds on what an input may ask for (docs/reliability.md): a reader
// checks the sizes a file declares against these before it allocates, so
// that an 18-byte header claiming a 23000x23000 image, or a model claiming
// two billion vertices, is an error naming the file, not gigabytes of
// memory or std::bad_alloc.
//
// The defaults hold every scene oovr ships or installs with a wide margin.
// $OOVR_LIMITS overrides them: comma-separated name=value pairs, e.g.
// OOVR_LIMITS=image_side=32768,scene_bytes=16GB; an unknown name or a bad
// value is an Error.
#pragma once

#include <cstdint>
#include <string>

namespace oovr {

struct InputLimits {
  int image_side = 16384;                     // texels on an image's side
  uint64_t image_texels = uint64_t(1) << 26;  // texels in one image (256 MiB as RGBA8)
  uint64_t file_bytes = uint64_t(2) << 30;    // bytes of one input file (a model, an archive entry)
  uint64_t elements = uint64_t(1) << 27;      // vertices, faces, indices or records one file declares or makes
  uint64_t scene_bytes = uint64_t(8) << 30;   // a loaded scene's geometry and textures (mip chains included)
  int nesting = 256;                          // depth of a model's node tree (glTF)
  // Draws one scene makes, and the node instances or groups a model file
  // expands to on the way: each costs the simulator about 18 KB, so that
  // 200,000 one-triangle draws from a 10 MB file took 3.6 GB. The largest
  // installed level draws 1,806 (TORCS alpine-1).
  uint64_t draws = uint64_t(1) << 16;

  // The limits in force ($OOVR_LIMITS over the defaults), read once.
  static const InputLimits& get();
  // Parses "name=value,...": throws Error naming a bad pair.
  static InputLimits parse(const std::string& text);
};

// Throws Error("<what>: <count> <things>, more than the limit of <limit>
// ($OOVR_LIMITS <name>)") when count > limit.
void check_limit(uint64_t count, uint64_t limit, const char* name, const std::string& what, const char* things);
// The same where counting stopped past the limit: "<what>: more than
// <limit> <things> ($OOVR_LIMITS <name>)".
[[noreturn]] void exceeded_limit(uint64_t limit, const char* name, const std::string& what, const char* things);

}  // namespace oovr
