// Checks a model file before assimp reads it (docs/reliability.md): assimp
// trusts the sizes a file declares, so a 214-byte PLY claiming 2e9
// vertices grows past 14 GB, a truncated one can loop for ever, and a 2 KB
// GLB whose chunk says 2 GB allocates 2 GB. The counts and lengths a PLY
// header, a GLB container or a glTF document declares are checked against
// the bytes that are there and against InputLimits first.
#pragma once

#include <string>

namespace oovr {

// Throws Error naming the file and the declared size that cannot be.
void precheck_model_file(const std::string& path);

// The same on bytes in memory (`name` for messages; a .gltf's external
// buffers are looked up beside `name`), for tests and fuzzing.
void precheck_model_bytes(const std::string& bytes, const std::string& name);

}  // namespace oovr
