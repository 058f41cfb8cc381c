// What a pass costs a fragment lane, in scalar instructions.
//
// GPUs since NVIDIA's G80 run shaders on scalar lanes (SIMT): a vec4
// multiply is four instructions, an interpolated attribute one per
// component, a texture lookup one issued instruction whatever its filter
// (the texture unit does the filtering; the timing model charges it as
// samples). The counts below follow the SASS a GLSL fragment shader
// becomes on those GPUs (NVIDIA's CUDA Binary Utilities, "Instruction Set
// Reference": IPA interpolates one component, MUFU.RCP gives 1/w, FMUL and
// FFMA one component, TEX one lookup, KIL a discard); blending is done by
// the ROPs and costs no shader instruction. docs/model.md lists them.
#pragma once

#include <cstdint>

#include "oovr/scene/material.h"

namespace oovr {

struct FragmentCosts {
  static constexpr uint32_t setup = 2;         // IPA 1/w, MUFU.RCP
  static constexpr uint32_t output = 4;        // RGBA to the ROPs
  static constexpr uint32_t coordinates = 4;   // per layer: IPA u, v and two FMUL by w
  static constexpr uint32_t transform = 4;     // per transformed layer: two FFMA per coordinate
  static constexpr uint32_t lookup = 1;        // per layer: TEX
  static constexpr uint32_t scale = 3;         // a layer's RGB scale: FMUL per channel
  static constexpr uint32_t colour = 4;        // the pass colour, when not white: FMUL per channel
  static constexpr uint32_t combine = 4;       // modulate (FMUL) or add (FFMA x3, FMUL alpha) per layer after the first
  static constexpr uint32_t alpha_test = 2;    // FSETP, KIL
};

// Scalar instructions one fragment lane runs for `pass`.
uint32_t fragment_instructions(const Pass& pass);

}  // namespace oovr
