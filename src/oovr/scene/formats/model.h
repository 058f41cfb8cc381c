// Model files (OBJ, glTF 2, GLB through assimp; PLY and AC3D through oovr's
// own readers, model_checks.h and ac3d.h). Each (node, mesh) instance
// becomes one object (one draw) in node order.
//
// assimp reads only what oovr has checked (model_checks.h): the model file
// itself comes from memory after its checks, and the files it names (an
// OBJ's material libraries, a glTF's buffers) through an IO system that
// opens regular files within InputLimits file_bytes only, so that a FIFO
// cannot block it and /dev/zero cannot fill its memory.
#pragma once

#include <string>

#include "oovr/scene/scene.h"

namespace oovr {

// Whether `path` names a model file by its extension.
bool is_model_path(const std::string& path);

// Loads a model file, with the files it names. Throws Error.
Scene load_model_file(const std::string& path);

// Loads model bytes as if from a file called `name`, with no other file
// (its material libraries, buffers and textures are missing): for fuzzing.
Scene load_model_bytes(const std::string& bytes, const std::string& name);

}  // namespace oovr
